#include "openmmdpd/SweepDynamics.h"
#include "openmmdpd/PairEvaluators.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

SweepDynamics::SweepDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor) :
        PairDynamics(system, integrator, executor, 3), constrainedImpulse(system),
        pairSweep(executor, constrainedImpulse.hasConstraints()), pairsStep(-1) {
}

void SweepDynamics::updatePairs(OpenMM::ContextImpl& context) {
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    thermostat.updatePairs(*platformData(context).positions, box);
    pairSweep.prepare(thermostat);
    pairsStep = platformData(context).stepCount;
}

void SweepDynamics::startStep(OpenMM::ContextImpl& context, int forceGroups) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    if (!carriedForceValid(*data.positions, *data.velocities)) {
        computeConservativeAndPairs(context, forceGroups, data.stepCount);
        force = conservative;
        pairSweep.prepare(thermostat);
        pairsStep = data.stepCount;
        setCarriedForceValid();
    }
    else if (pairsStep != data.stepCount)
        updatePairs(context);
}

void SweepDynamics::velocityVerlet(OpenMM::ContextImpl& context, int forceGroups, double dt) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const long long next = data.stepCount + 1;
    movePositions(context, next, dt, [&](size_t i) {
        v[i] += force[i] * (0.5 * dt * invMass[i]);
        return v[i] * dt;
    });
    computeConservativeAndPairs(context, forceGroups, next);
    pairSweep.prepare(thermostat);
    pairsStep = next;
    forEachParticle(v.size(), [&](size_t i) {
        force[i] = conservative[i];
        v[i] += force[i] * (0.5 * dt * invMass[i]);
    });
    constrainVelocities(context);
}

SweepDynamics::BatchNormals SweepDynamics::normals(PairRandom::Stream stream, long long step) {
    thermostat.drawNormals(stream, step, pairNormals);
    return BatchNormals{pairNormals, thermostat.getPairs().data()};
}

void ShardlowDynamics::step(OpenMM::ContextImpl& context, const ShardlowIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const double dt = integrator.getStepSize();
    const long long current = data.stepCount;
    startStep(context, integrator.getIntegrationForceGroups());
    // S1: sweep (dt) ; VV.  S2: sweep (dt/2) ; VV ; sweep (dt/2) in the reverse order.
    const bool secondOrder = (integrator.getOrder() == 2);
    const double h = secondOrder ? 0.5 * dt : dt;
    withPairImpulse(context, [&](const auto& impulse) {
        sweep(*data.velocities, ShardlowPairUpdate<BatchNormals, decltype(impulse)>{normals(PairRandom::RandomForce, current), h, impulse},
              false);
    });
    constrainVelocities(context);
    velocityVerlet(context, integrator.getIntegrationForceGroups(), dt);
    if (secondOrder) {
        withPairImpulse(context, [&](const auto& impulse) {
            sweep(*data.velocities, ShardlowPairUpdate<BatchNormals, decltype(impulse)>{normals(PairRandom::SecondSweep, current), h, impulse},
                  true);
        });
        constrainVelocities(context);
    }
    finishStep(data, dt);
}

void LoweAndersenDynamics::step(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const double dt = integrator.getStepSize(), kT = thermostat.getParameters().getKT();
    const long long current = data.stepCount;
    const PairRandom& random = thermostat.getRandom();
    startStep(context, integrator.getIntegrationForceGroups());
    // VV ; the pair thermostat over the pairs at the new positions.
    velocityVerlet(context, integrator.getIntegrationForceGroups(), dt);
    withPairImpulse(context, [&](const auto& impulse) {
        using Impulse = decltype(impulse);
        if (integrator.getMethod() == LoweAndersenIntegrator::Lowe)
            sweep(*data.velocities, LowePairUpdate<Impulse>{random, current, dt, kT, impulse}, false);
        else
            sweep(*data.velocities,
                  PairOrnsteinUhlenbeckUpdate<BatchNormals, Impulse>{normals(PairRandom::PairThermalisation, current), dt, kT, impulse},
                  false);
    });
    constrainVelocities(context);
    finishStep(data, dt);
}
