#ifndef OPENMMDPD_COMMONSTAGGEREDDYNAMICS_H_
#define OPENMMDPD_COMMONSTAGGEREDDYNAMICS_H_

#include "openmmdpd/CommonSweepDynamics.h"
#include "openmmdpd/PolymerSelection.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"

namespace DPDPlugin {

/**
 * The time-staggered schemes on the device, step for step as ReferenceStaggeredDynamics
 * (kernels/staggered.cc): per outer step Dt one slow evaluation for every particle (OpenMM's
 * slow force groups, with the velocity-Verlet base the pair forces at the predicted
 * velocities), K sub-steps of the polymer alone with OpenMM's fast groups evaluated on the
 * device, and with the Lowe base the sweep over the end-of-step pairs.  Carried (and in
 * checkpoints): the slow force on every particle and the fast force on the polymer.  Unlike
 * the Reference, a non-finite fast force is not named as such: the velocity and position
 * checks at the end of the step stop the run.
 */
class CommonStaggeredDynamics : public CommonSweepDynamics {
public:
    CommonStaggeredDynamics(OpenMM::ComputeContext& cc, const OpenMM::System& system, const StaggeredDPDIntegrator& integrator,
                            const std::string& platform);
    void step(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);

protected:
    void saveExtraState(std::ostream& stream) const override;
    void loadExtraState(CheckpointReader& reader) override;
    void commitExtraState() override;

private:
    /** The polymer for the integrator's fast groups and explicit list, on the device. */
    void updatePolymer(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator);
    /** `out` <- the slow force at the current positions, FD from `velocity` (velocity-Verlet base), the numbers keyed by step. */
    void slowForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step, OpenMM::ComputeArray& out);
    /** `out` <- the fast force on the polymer at the current positions. */
    void fastForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step, OpenMM::ComputeArray& out);
    /** Moves r to (r_s, r^^_p), `velocity` <- the predicted velocities, with the sliding boundaries. */
    void predict(const StaggeredDPDIntegrator& integrator);
    /** The polymer from the start of the step through K sub-steps (the box too, under shear). */
    void subCycle(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, const OpenMM::Vec3* startBox, long long next);
    void subStep(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, int s, long long next);

    const StaggeredDPDIntegrator::BaseScheme baseScheme;
    PolymerSelection polymer;
    OpenMM::ComputeArray polymerFlag, newSlow, fast, newFast, startPosition, startVelocity;
    OpenMM::ComputeKernel takeForceKernel, predictKernel, kickSolventKernel, restoreKernel, driftKernel, kickKernel;
    std::vector<OpenMM::Vec3> loadedFast;  // read from a checkpoint, until all of it is read
};

} // namespace DPDPlugin

#endif
