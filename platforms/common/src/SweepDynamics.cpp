#include "openmmdpd/SweepDynamics.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/PairRules.h"
#include "openmmdpd/ShardlowIntegrator.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

SweepDynamics::SweepDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor) :
        PairDynamics(system, integrator, executor, 3), pairSweep(executor), pairsStep(-1) {
}

void SweepDynamics::updatePairs(OpenMM::ContextImpl& context) {
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    thermostat.updatePairs(*platformData(context).positions, box);
    pairSweep.prepare(thermostat);
    pairsStep = platformData(context).stepCount;
}

void SweepDynamics::sweep(const DPDThermostatIntegrator& integrator, std::vector<Vec3>& v, long long step, double h,
                          PairRandom::Stream stream, bool reverse) {
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const double kT = thermostat.getParameters().getKT();
    const PairRandom& random = thermostat.getRandom();
    const LoweAndersenIntegrator* lowe = dynamic_cast<const LoweAndersenIntegrator*>(&integrator);
    if (lowe == nullptr)
        pairSweep.run(thermostat, v, ShardlowPairUpdate{random, stream, step, h, invMass}, reverse);
    else if (lowe->getMethod() == LoweAndersenIntegrator::Lowe)
        pairSweep.run(thermostat, v, LowePairUpdate{random, step, h, kT, invMass}, reverse);
    else
        pairSweep.run(thermostat, v, PairOrnsteinUhlenbeckUpdate{random, step, h, kT, invMass}, reverse);
}

void SweepDynamics::step(OpenMM::ContextImpl& context, const DPDThermostatIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& r = *data.positions;
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const size_t n = r.size();
    const double dt = integrator.getStepSize();
    const long long current = data.stepCount, next = current + 1;
    const int forceGroups = integrator.getIntegrationForceGroups();
    if (!carriedForceValid(r, v)) {
        computeConservativeAndPairs(context, forceGroups, current);
        force = conservative;
        pairSweep.prepare(thermostat);
        pairsStep = current;
        setCarriedForceValid();
    }
    else if (pairsStep != current)
        updatePairs(context);

    const ShardlowIntegrator* shardlow = dynamic_cast<const ShardlowIntegrator*>(&integrator);
    const bool secondOrder = (shardlow != nullptr && shardlow->getOrder() == 2);
    // Shardlow: the pair sweep (S1: dt; S2: dt/2) comes before the conservative step.
    if (shardlow != nullptr)
        sweep(integrator, v, current, secondOrder ? 0.5 * dt : dt, PairRandom::RandomForce, false);

    // Velocity Verlet with the conservative force.
    movePositions(r, next, [&](size_t i) {
        v[i] += force[i] * (0.5 * dt * invMass[i]);
        return v[i] * dt;
    });
    computeConservativeAndPairs(context, forceGroups, next);
    pairSweep.prepare(thermostat);
    pairsStep = next;
    forEachParticle(n, [&](size_t i) {
        force[i] = conservative[i];
        v[i] += force[i] * (0.5 * dt * invMass[i]);
    });

    // S2: the second half sweep, in the reverse order; Lowe-Andersen: the thermostat.
    if (secondOrder)
        sweep(integrator, v, current, 0.5 * dt, PairRandom::SecondSweep, true);
    else if (shardlow == nullptr)
        sweep(integrator, v, current, dt, PairRandom::PairThermalisation, false);
    finishStep(data, dt);
}
