#ifndef OPENMMDPD_REFERENCESTAGGEREDDYNAMICS_H_
#define OPENMMDPD_REFERENCESTAGGEREDDYNAMICS_H_

#include "openmmdpd/PolymerSelection.h"
#include "openmmdpd/ReferenceDynamics.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"

namespace DPDPlugin {

/**
 * The time-staggered schemes (docs/theory/staggered.md; Symeonidis and
 * Karniadakis 2006, Tables 1 and 2), written
 * plainly: every force comes from the Context itself (the fast force groups for Fp, the
 * other integration groups for the slow conservative force), the thermostat pairs from
 * findPairs() wherever they are used.
 *
 * Carried from one outer step to the next (and saved in checkpoints, in the CPU
 * platform's layout): the slow force F (FC slow + FD + FR for the velocity-Verlet base,
 * FC slow for the Lowe base) on every particle in `carried.force`, and the fast force Fp
 * on each polymer particle.
 */
class ReferenceStaggeredDynamics : public ReferenceDynamics {
public:
    ReferenceStaggeredDynamics(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator);
    void step(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);

protected:
    /** After the slow force: the number of polymer particles and the fast force on each. */
    void saveExtraState(std::ostream& stream) const override;
    void loadExtraState(CheckpointReader& reader) override;
    void commitExtraState() override { Fp.swap(loadedFp); }

private:
    /** The state at the start of the outer step, where the polymer's sub-cycle starts from. */
    struct StepStart {
        StepStart(OpenMM::ContextImpl& context, const std::vector<OpenMM::Vec3>& r, const std::vector<OpenMM::Vec3>& v) :
                positions(r), velocities(v) {
            context.getPeriodicBoxVectors(box[0], box[1], box[2]);
        }
        const std::vector<OpenMM::Vec3> positions, velocities;
        OpenMM::Vec3 box[3];
    };
    /** The polymer particles for the integrator's current fast groups and explicit list. */
    void updatePolymer(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator);
    bool isPolymer(int i) const { return polymer.index[i] >= 0; }
    /**
     * The slow force at the current positions: FC slow + FD(u) + FR (random numbers keyed by
     * `step`, over the outer step Dt) for the velocity-Verlet base, FC slow for the Lowe base.
     */
    std::vector<OpenMM::Vec3> slowForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator,
                                        const std::vector<OpenMM::Vec3>& u, long long step);
    /**
     * Fp on each polymer particle (index k of polymer[k]) at the current positions.  With
     * checkFastForceOutside, the fast forces must leave every other particle alone.
     */
    std::vector<OpenMM::Vec3> fastForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step);
    /** The first lines of Tables 1-2: moves r to (r_s, r^^_p), returns (u^_s, u^^_p) (vV base). */
    std::vector<OpenMM::Vec3> predict(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);
    /** u_s <- u_s + Dt/(2m) (F_s + F^_s). */
    void kickSolvent(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, const std::vector<OpenMM::Vec3>& newF);
    /** The K polymer sub-steps from `start` (positions, velocities, box), driven by F^^ = b F + (1 - b) F^ and Fp. */
    void subCycle(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, const StepStart& start,
                  const std::vector<OpenMM::Vec3>& newF);
    /** Sub-step s of K: r_p, then Fp at the new r_p, then u_p. */
    void subStep(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, int s,
                 const std::vector<OpenMM::Vec3>& driving, const std::vector<OpenMM::Vec3>& newF);
    /** Lowe base: Lowe's pair thermalisation (probability Gamma Dt) at the end-of-step positions. */
    void thermalise(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step);

    const StaggeredDPDIntegrator::BaseScheme baseScheme;
    PolymerSelection polymer;
    std::vector<OpenMM::Vec3> Fp;   // the fast force on polymer[k], carried
    std::vector<OpenMM::Vec3> loadedFp;  // Fp read from a checkpoint, until all of it is read
};

} // namespace DPDPlugin

#endif
