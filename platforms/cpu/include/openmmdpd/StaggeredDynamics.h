#ifndef OPENMMDPD_STAGGEREDDYNAMICS_H_
#define OPENMMDPD_STAGGEREDDYNAMICS_H_

#include "openmmdpd/PairDynamics.h"
#include "openmmdpd/PairSweep.h"
#include "openmmdpd/PolymerForceContext.h"
#include "openmmdpd/PolymerSelection.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/Context.h"
#include "openmm/VerletIntegrator.h"
#include <memory>

namespace DPDPlugin {

/**
 * The time-staggered schemes (docs/theory/staggered.md): one slow-force evaluation (and one
 * pair search; the Lowe base a second one, for its thermalisation at the end-of-step
 * positions) per outer step Dt for every particle, K sub-steps of the polymer alone with
 * only the fast forces re-evaluated.
 *
 * Carried from one outer step to the next (and saved in checkpoints): the slow force
 * `force` (FC slow + FD + FR for the velocity-Verlet base, FC slow for the Lowe base) on
 * every particle, and the fast force on each polymer particle.
 */
class StaggeredDynamics : public PairDynamics {
public:
    StaggeredDynamics(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator, ParallelExecutor& executor);
    void step(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);

protected:
    /** K > 1: the slow forces come from the Context of the System without its fast forces. */
    void computeConservative(OpenMM::ContextImpl& context, int forceGroups) override;
    void saveExtraState(std::ostream& stream) const override;
    void loadExtraState(CheckpointReader& reader) override;
    void commitExtraState() override { fastForce.swap(loadedFastForce); }

private:
    /** The polymer particles for the integrator's current fast groups and explicit list. */
    void updatePolymer(const OpenMM::System& system, const StaggeredDPDIntegrator& integrator);
    int slowGroups(const StaggeredDPDIntegrator& integrator) const {
        return integrator.getIntegrationForceGroups() & ~integrator.getFastForceGroups();
    }
    /**
     * fast[k] <- the fast force on polymer particle k at the current positions.  With
     * checkFastForceOutside, the fast forces must leave every other particle alone.
     */
    void computeFastForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long step,
                          std::vector<OpenMM::Vec3>& fast);
    /**
     * A Context of a copy of the System without the forces of the fast groups.  On the CPU
     * platform a CustomNonbondedForce (e.g. the polymer's WCA) makes every force evaluation
     * maintain a neighbour list of all particles, whichever groups are evaluated; the slow
     * evaluations are made where the fast forces are absent so that they do not pay for it.
     */
    void makeSlowContext(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);
    /** force <- the slow force, fastForce <- the fast one, at the current state. */
    void computeInitialForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);

    // The steps of step(), in order (docs/theory/staggered.md).
    /** Checks, the polymer and side Contexts for the integrator's settings, F and Fp if stale. */
    void prepareStep(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);
    /** K > 1: try the Contexts of the polymer alone and of the slow forces (once). */
    void makeSideContexts(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);
    /** Moves r to (r_s, r^^_p); predicted <- (u^_s, u^^_p) (velocity-Verlet base). */
    void predict(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long next);
    /** newForce <- F^ at (r_s, r^^_p), with the predicted velocities for the velocity-Verlet base. */
    void evaluatePredictedForce(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long next);
    /** u_s <- u_s + Dt/(2m) (F_s + F^_s). */
    void kickSolvent(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator);
    /** The polymer back to the start of the step (positions, velocities, box), then K sub-steps driven by b F + (1 - b) F^ and Fp. */
    void subCycle(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long next);
    /** Sub-step s of K: r_p, Fp at the new r_p, u_p. */
    void subStep(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, int s, long long next);
    /** Lowe base: Lowe's thermalisation over the pairs at the end-of-step positions. */
    void thermalise(OpenMM::ContextImpl& context, const StaggeredDPDIntegrator& integrator, long long current);

    const StaggeredDPDIntegrator::BaseScheme baseScheme;
    PolymerSelection polymer;
    PairSweep pairSweep;
    std::vector<r123::Philox4x32::ctr_type> pairBits;  // the Lowe base's words, drawn ahead in batches
    std::vector<OpenMM::Vec3> predicted, newForce;
    // Per polymer particle (index k of polymer[k]): the fast force, the one at the new
    // sub-step positions, the start of the outer step, the slow force driving the sub-steps.
    std::vector<OpenMM::Vec3> fastForce, newFastForce, startPositions, startVelocities, drivingForce;
    OpenMM::Vec3 startBox[3];  // the box at the start of the outer step (it slides under shear)
    std::vector<OpenMM::Vec3> loadedFastForce;  // read from a checkpoint, until all of it is read
    // The fast forces on the polymer alone (K > 1; null: the Context evaluates the fast groups).
    std::unique_ptr<PolymerForceContext> fastForces;
    OpenMM::Vec3 slowBox[3];
    bool fastContextTried;
    std::unique_ptr<OpenMM::System> slowSystem;
    std::unique_ptr<OpenMM::VerletIntegrator> slowIntegrator;
    std::unique_ptr<OpenMM::Context> slowContext;
    bool slowOmitsFusedForce = false;  // the slow Context leaves the fused force to the thermostat pairs
    int numSubSteps;
};

} // namespace DPDPlugin

#endif
