#ifndef OPENMMDPD_REFERENCESWEEPDYNAMICS_H_
#define OPENMMDPD_REFERENCESWEEPDYNAMICS_H_

#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ReferenceDynamics.h"
#include "openmmdpd/ShardlowIntegrator.h"

namespace DPDPlugin {

/**
 * Velocity Verlet with the conservative force, split with pairwise-sequential sweeps
 * (docs/theory/shardlow.md, docs/theory/lowe-andersen.md).  The carried force is the
 * conservative force FC at the current positions.  The sweeps visit the pairs in ReferencePairList's order (cellMultiple
 * 3), the order every platform sweeps in, so that all of them follow the same trajectory.
 */
class ReferenceSweepDynamics : public ReferenceDynamics {
protected:
    ReferenceSweepDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) :
            ReferenceDynamics(system, integrator, 3), constrainedImpulse(system) {}
    /** At the start of a step: make sure the carried force is FC at the current positions. */
    void ensureCarriedForce(OpenMM::ContextImpl& context, int forceGroups);
    /** v += dt/2m F ; r += dt v ; F <- FC(r) ; v += dt/2m F. */
    void velocityVerlet(OpenMM::ContextImpl& context, int forceGroups, double dt);
    /**
     * body(impulse) with the pair impulse of a sweep over these pairs at the current positions,
     * in a step of length dt (see withRecordedPairImpulse in core).
     */
    template <class Body>
    void withPairImpulse(OpenMM::ContextImpl& context, const std::vector<PairGeometry>& pairs, double dt, Body body) {
        withRecordedPairImpulse(constrainedImpulse, parameters, *data(context).positions, pairs, dt, thermostatVirial, impulses, body);
    }

private:
    ConstrainedPairImpulse constrainedImpulse;
    PairImpulseRecord impulses;
};

/** Shardlow's S1 and S2 (ShardlowIntegrator, docs/theory/shardlow.md). */
class ReferenceShardlowDynamics : public ReferenceSweepDynamics {
public:
    ReferenceShardlowDynamics(const OpenMM::System& system, const ShardlowIntegrator& integrator) :
            ReferenceSweepDynamics(system, integrator) {}
    void step(OpenMM::ContextImpl& context, const ShardlowIntegrator& integrator);
};

/**
 * Lowe-Andersen and the exact pair Ornstein-Uhlenbeck update (LoweAndersenIntegrator,
 * section 3), after the velocity-Verlet step or between its half drifts (section 11).
 */
class ReferenceLoweAndersenDynamics : public ReferenceSweepDynamics {
public:
    ReferenceLoweAndersenDynamics(const OpenMM::System& system, const LoweAndersenIntegrator& integrator) :
            ReferenceSweepDynamics(system, integrator) {}
    void step(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator);

private:
    /**
     * B A O A B with the velocities kept at O, as LangevinMiddleIntegrator keeps them:
     * v += dt/m F ; r += dt/2 v ; O ; r += dt/2 v ; F <- FC(r).
     */
    void middleStep(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator);
    /** O: the pair thermostat over dt, over the pairs at the current positions, its numbers keyed by step. */
    void applyThermostat(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator, long long step);
};

} // namespace DPDPlugin

#endif
