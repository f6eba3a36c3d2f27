#include "openmmdpd/SweepDynamics.h"
#include "openmmdpd/PairEvaluators.h"
#include <type_traits>
#include <utility>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

/** Shardlow's halves as the one kick they add up to (PairEvaluators.h), with every impulse. */
template <class Impulse>
using CpuShardlowUpdate = ShardlowPairUpdate<Impulse, ShardlowForm::OneKick>;

// The rule for equal masses must be the one VectorRowSweep's rows take, or the sweep would go pair by pair.
static_assert(std::is_same<CpuShardlowUpdate<const EqualMassPairImpulse&>, RowShardlowUpdate>::value,
              "the equal-mass Shardlow update is the row sweep's");

} // namespace

SweepDynamics::SweepDynamics(const OpenMM::System& system, const DPDThermostatIntegrator& integrator, ParallelExecutor& executor) :
        PairDynamics(system, integrator, executor, 3), constrainedImpulse(system),
        pairSweep(executor, constrainedImpulse.hasConstraints()), pairsStep(-1) {
}

void SweepDynamics::updatePairs(OpenMM::ContextImpl& context, long long step) {
    Vec3 box[3];
    context.getPeriodicBoxVectors(box[0], box[1], box[2]);
    findPairs(step, [&] { thermostat.updatePairs(*platformData(context).positions, box, nullptr, nullptr, wantsPairsBySlot()); });
}

void SweepDynamics::startStep(OpenMM::ContextImpl& context, int forceGroups) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    if (!carriedForceValid(*data.positions, *data.velocities)) {
        findPairs(data.stepCount, [&] { computeConservativeAndPairs(context, forceGroups, data.stepCount); });
        force = conservative;
        setCarriedForceValid();
    }
    else if (pairsStep != data.stepCount || thermostat.arePairsBySlot() != wantsPairsBySlot())
        updatePairs(context, data.stepCount);
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
    carryForce(context, forceGroups, next);
    forEachParticle(v.size(), [&](size_t i) { v[i] += force[i] * (0.5 * dt * invMass[i]); });
    constrainVelocities(context);
}

void SweepDynamics::carryForce(OpenMM::ContextImpl& context, int forceGroups, long long step) {
    findPairs(step, [&] { computeConservativeAndPairs(context, forceGroups, step); });
    // Swapped, not copied: `conservative` is made anew before it is next read.
    std::swap(force, conservative);
}

const std::vector<double>& SweepDynamics::normals(PairRandom::Stream stream, long long step) {
    thermostat.drawNormals(stream, step, pairNormals);
    return pairNormals;
}

const std::vector<double>& SweepDynamics::firstSweepNormals(long long step) {
    const bool kept = (normalsKept && nextNormalsStep == step && nextNormalsSeed == thermostat.getSeed());
    return (kept ? nextNormals : normals(PairRandom::RandomForce, step));
}

const std::vector<double>& SweepDynamics::secondSweepNormals(long long next) {
    thermostat.drawNormalsAndPartners(PairRandom::RandomForce, next, nextNormals, pairNormals);
    normalsKept = true;
    nextNormalsStep = next;
    nextNormalsSeed = thermostat.getSeed();
    return pairNormals;
}

const std::vector<PairNoise>& SweepDynamics::pairNoise(const std::vector<double>& normals, PairRandom::Stream transverseStream,
                                                        long long step) {
    thermostat.drawNormalVectors(transverseStream, step, pairNoiseVectors);
    pairNoises.resize(normals.size());
    forEachParticle(normals.size(), [&](size_t k) {
        pairNoises[k].xi = normals[k];
        std::copy(&pairNoiseVectors[3 * k], &pairNoiseVectors[3 * k] + 3, pairNoises[k].zeta);
    });
    return pairNoises;
}

const std::vector<r123::Philox4x32::ctr_type>& SweepDynamics::bits(PairRandom::Stream stream, long long step) {
    thermostat.drawBits(stream, step, pairBits);
    return pairBits;
}

void ShardlowDynamics::step(OpenMM::ContextImpl& context, const ShardlowIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const double dt = integrator.getStepSize();
    const long long current = data.stepCount;
    startStep(context, integrator.getIntegrationForceGroups());
    // S1: sweep (dt) ; VV.  S2: sweep (dt/2) ; VV ; sweep (dt/2) in the reverse order, with
    // the partners of the next step's first sweep's numbers.
    const bool secondOrder = (integrator.getOrder() == 2);
    const double h = secondOrder ? 0.5 * dt : dt;
    withPairImpulse(context, dt, [&](const auto& impulse) {
        sweepWith(*data.velocities, CpuShardlowUpdate<decltype(impulse)>{h, impulse}, firstSweepNormals(current), PairRandom::TransverseNoise,
                  current, false);
    });
    constrainVelocities(context);
    velocityVerlet(context, integrator.getIntegrationForceGroups(), dt);
    if (secondOrder) {
        withPairImpulse(context, dt, [&](const auto& impulse) {
            sweepWith(*data.velocities, CpuShardlowUpdate<decltype(impulse)>{h, impulse}, secondSweepNormals(current + 1),
                      PairRandom::TransverseSecondSweep, current + 1, true);
        });
        constrainVelocities(context);
    }
    finishStep(data, dt);
}

void LoweAndersenDynamics::step(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    const double dt = integrator.getStepSize();
    const long long current = data.stepCount;
    startStep(context, integrator.getIntegrationForceGroups());
    if (integrator.getSplitting() == LoweAndersenIntegrator::Middle)
        middleStep(context, integrator);
    else {
        // VV ; the pair thermostat over the pairs at the new positions.
        velocityVerlet(context, integrator.getIntegrationForceGroups(), dt);
        applyThermostat(context, integrator, current);
    }
    finishStep(data, dt);
}

void LoweAndersenDynamics::middleStep(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const double dt = integrator.getStepSize();
    const long long current = data.stepCount, next = current + 1;
    // B B (the last step's closing half kick and this step's opening one) A
    movePositions(context, next, 0.5 * dt, [&](size_t i) {
        v[i] += force[i] * (dt * invMass[i]);
        return v[i] * (0.5 * dt);
    });
    // O over the pairs where it acts (positions of no step)
    updatePairs(context, -1);
    applyThermostat(context, integrator, current);
    // A ; F <- FC(r)
    movePositions(context, next, 0.5 * dt, [&](size_t i) { return v[i] * (0.5 * dt); });
    carryForce(context, integrator.getIntegrationForceGroups(), next);
}

void LoweAndersenDynamics::applyThermostat(OpenMM::ContextImpl& context, const LoweAndersenIntegrator& integrator, long long step) {
    std::vector<Vec3>& v = *platformData(context).velocities;
    const double dt = integrator.getStepSize(), kT = thermostat.getParameters().getKT();
    withPairImpulse(context, dt, [&](const auto& impulse) {
        using Impulse = decltype(impulse);
        if (integrator.getMethod() == LoweAndersenIntegrator::Lowe) {
            sweep(v, LowePairUpdate<Impulse>{dt, kT, impulse}, bits(PairRandom::PairThermalisation, step), false);
            return;
        }
        sweepWith(v, PairOrnsteinUhlenbeckUpdate<Impulse, RowConsistentMath>{dt, kT, impulse}, normals(PairRandom::PairThermalisation, step),
                  PairRandom::TransverseNoise, step, false);
    });
    constrainVelocities(context);
}
