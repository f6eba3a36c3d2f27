#ifndef OPENMMDPD_SWEEPDYNAMICS_H_
#define OPENMMDPD_SWEEPDYNAMICS_H_

#include "openmmdpd/PairDynamics.h"
#include "openmmdpd/PairSweep.h"

namespace DPDPlugin {

/**
 * Velocity Verlet with the conservative forces, split with pairwise-sequential sweeps
 * (algorithms.md sections 2 and 3): Shardlow S1 and S2 (ShardlowIntegrator), Lowe-Andersen
 * and the exact pair Ornstein-Uhlenbeck update (LoweAndersenIntegrator).  The carried
 * force is the conservative force at the current positions.
 */
class SweepDynamics : public PairDynamics {
public:
    SweepDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor);
    void step(OpenMM::ContextImpl& context, const DPDThermostatIntegrator& integrator) override;

protected:
    void stateRestored() override { pairsStep = -1; }

private:
    /** The pair list (and the sweep's colouring) at the current positions. */
    void updatePairs(OpenMM::ContextImpl& context);
    /** Sweep every pair with the integrator's pair rule over a time h. */
    void sweep(const DPDThermostatIntegrator& integrator, std::vector<OpenMM::Vec3>& v, long long step, double h,
               PairRandom::Stream stream, bool reverse);
    PairSweep pairSweep;
    long long pairsStep;
};

} // namespace DPDPlugin

#endif
