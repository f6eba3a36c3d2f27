#include "openmmdpd/DPDVVDynamics.h"
#include "ReferencePlatform.h"
#include <cmath>

using namespace DPDPlugin;
using OpenMM::Vec3;

DPDVVDynamics::DPDVVDynamics(const OpenMM::System& system, const DPDVVIntegrator& integrator, ParallelExecutor& executor) :
        PairDynamics(system, integrator, executor, 1) {
    const int n = system.getNumParticles();
    for (auto* v : {&dissipative, &conservativeAndRandom, &predicted, &velocityNoFD, &newForce})
        v->resize(n);
}

void DPDVVDynamics::computeInitialForce(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    computeForceInOnePass(context, integrator.getIntegrationForceGroups(), *data.velocities, data.stepCount,
                          integrator.getStepSize(), force);
    setCarriedForceValid();
}

void DPDVVDynamics::step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    if (!carriedForceValid(*data.positions, *data.velocities))
        computeInitialForce(context, integrator);
    if (integrator.getVariant() == DPDVVIntegrator::GrootWarren)
        grootWarrenStep(context, integrator);
    else
        dpdvvStep(context, integrator);
    finishStep(data, integrator.getStepSize());
}

void DPDVVDynamics::grootWarrenStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& r = *data.positions;
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const double dt = integrator.getStepSize(), lambda = integrator.getLambda();
    const long long next = data.stepCount + 1;
    // r += dt v + dt^2/(2m) F ;  v~ = v + lambda dt F/m (both corrected by the constraints)
    movePositions(context, next, dt, [&](size_t i) {
        predicted[i] = v[i] + force[i] * (lambda * dt * invMass[i]);
        return v[i] * dt + force[i] * (0.5 * dt * dt * invMass[i]);
    }, &predicted);
    // F(t+dt) = FC(r) + FD(r, v~) + FR(r)
    computeForceInOnePass(context, integrator.getIntegrationForceGroups(), predicted, next, dt, newForce);
    if (thermostatVirial != nullptr) {
        // The one pass left the pair list stale: find the same pairs again for the virial.
        Vec3 box[3];
        context.getPeriodicBoxVectors(box[0], box[1], box[2]);
        thermostat.updatePairs(r, box);
        thermostat.addVirial(DissipativeTerm | RandomTerm, predicted, next, dt, *thermostatVirial);
    }
    // v += dt/(2m) [F + F(t+dt)]
    forEachParticle(r.size(), [&](size_t i) {
        v[i] += (force[i] + newForce[i]) * (0.5 * dt * invMass[i]);
        force[i] = newForce[i];
    });
    constrainVelocities(context);
}

void DPDVVDynamics::dpdvvStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const double dt = integrator.getStepSize();
    const long long next = data.stepCount + 1;
    // (1) v += dt/(2m) (FC + FD + FR) ; (2) r += dt v
    movePositions(context, next, dt, [&](size_t i) {
        v[i] += force[i] * (0.5 * dt * invMass[i]);
        return v[i] * dt;
    });
    // (3) FC(r), FD(r, v), FR(r) with the half-step v: FC + FR and FD in one pass over
    // the pairs, which keeps them for (5), each FD at new velocities.
    const FusedPairForce* fused;
    const std::vector<Vec3>* base = prepareSlotPasses(context, integrator.getIntegrationForceGroups(), next, fused);
    const bool bySlot = canStayInSlotOrder();
    thermostat.sumBySlot(DissipativeTerm | RandomTerm, v, next, dt, fused, base, conservativeAndRandom, &dissipative,
                         DPDThermostatForces::FindAndKeepPairs, DPDThermostatForces::ByParticle,
                         bySlot ? DPDThermostatForces::BySlot : DPDThermostatForces::ByParticle);
    const std::vector<Vec3>& u = updateVelocities(context, integrator, bySlot);
    // F = FC + FR + FD, the FD at the final velocities: carried into the next step.
    const std::vector<int>& particle = thermostat.getSearch().getSortedIndex();
    forEachParticle(u.size(), [&](size_t k) {
        const size_t i = (bySlot ? particle[k] : k);
        if (bySlot) {
            prefetchSlotParticle(v.data(), particle, k);
            prefetchSlotParticle(force.data(), particle, k);
            v[i] = u[k];
        }
        force[i] = conservativeAndRandom[k] + dissipative[k];
    });
    if (thermostatVirial != nullptr) {
        // The slot passes left the pair list stale: find the same pairs again for the virial.
        Vec3 box[3];
        context.getPeriodicBoxVectors(box[0], box[1], box[2]);
        thermostat.updatePairs(*data.positions, box);
        thermostat.addVirial(DissipativeTerm | RandomTerm, v, next, dt, *thermostatVirial);
    }
}

bool DPDVVDynamics::canStayInSlotOrder() const {
    // The constraints act in particle order; particles outside the thermostat have no slot.
    return !motion.hasConstraints() && thermostat.getSearch().getSortedIndex().size() == force.size();
}

void DPDVVDynamics::sortMasses(bool withMasses) {
    const std::vector<int>& particle = thermostat.getSearch().getSortedIndex();
    const DPDPairParameters& parameters = thermostat.getParameters();
    const size_t n = particle.size();
    slotMasses.resize(withMasses ? n : 0);
    if (parameters.hasUniformMass() && n > 0) {
        // the same in every order: filled once
        if (slotInverseMasses.size() != n || slotInverseMasses[0] != parameters.getInverseMasses()[0])
            slotInverseMasses.assign(n, parameters.getInverseMasses()[0]);
        std::fill(slotMasses.begin(), slotMasses.end(), parameters.getMasses()[0]);
        return;
    }
    slotInverseMasses.resize(n);
    forEachParticle(n, [&](size_t k) {
        slotInverseMasses[k] = parameters.getInverseMasses()[particle[k]];
        if (withMasses)
            slotMasses[k] = parameters.getMasses()[particle[k]];
    });
}

const std::vector<Vec3>& DPDVVDynamics::updateVelocities(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator, bool bySlot) {
    std::vector<Vec3>& v = *platformData(context).velocities;
    const double dt = integrator.getStepSize();
    const long long next = platformData(context).stepCount + 1;
    const int iterations = (integrator.getVariant() == DPDVVIntegrator::SelfConsistent ? integrator.getMaxIterations() : 1);
    const DPDThermostatForces::Indexing indexing = (bySlot ? DPDThermostatForces::BySlot : DPDThermostatForces::ByParticle);
    if (bySlot)
        sortMasses(iterations > 1);
    const std::vector<double>& w = (bySlot ? slotInverseMasses : thermostat.getParameters().getInverseMasses());
    const std::vector<Vec3>& halfStep = (bySlot ? thermostat.getSlotVelocities() : v);
    std::vector<Vec3>& u = (bySlot ? slotVelocities : v);
    const size_t n = halfStep.size();
    slotVelocities.resize(bySlot ? n : 0);
    // (4a) v° = v + dt/(2m) (FC + FR)
    forEachParticle(n, [&](size_t k) { velocityNoFD[k] = halfStep[k] + conservativeAndRandom[k] * (0.5 * dt * w[k]); });
    // (4b) v = v° + dt/(2m) FD ; (5) FD <- FD(r, v).  SC-VV repeats both until the
    // kinetic energy settles; DPD-VV does them once.
    double previous = 0;
    for (int it = 0; it < iterations; it++) {
        forEachParticle(n, [&](size_t k) { u[k] = velocityNoFD[k] + dissipative[k] * (0.5 * dt * w[k]); });
        if (!bySlot)
            constrainVelocities(context);
        thermostat.sumBySlot(DissipativeTerm, u, next, dt, nullptr, nullptr, dissipative, nullptr, DPDThermostatForces::KeptPairs,
                             indexing, indexing);
        if (iterations > 1) {
            const double kinetic = sumMV2(u, bySlot ? slotMasses : thermostat.getParameters().getMasses());
            if (it > 0 && std::fabs(kinetic - previous) <= integrator.getTolerance() * kinetic)
                break;
            previous = kinetic;
        }
    }
    return u;
}
