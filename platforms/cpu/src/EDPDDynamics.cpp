#include "openmmdpd/EDPDDynamics.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

EDPDDynamics::EDPDDynamics(const OpenMM::System& system, const EDPDIntegrator& integrator, ParallelExecutor& executor) :
        PairDynamics(system, integrator, executor, 1), memory(thermostat.getParameters(), thermostat.getRandom(), executor),
        auxiliary(system.getNumParticles()) {
}

void EDPDDynamics::computeAuxiliaryForce() {
    // dp_i = -grad_i h_k s_k dt with grad_i h_k = wR e_ij.
    const std::vector<PairGeometry>& pairs = thermostat.getPairs();
    coefficient.resize(pairs.size());
    forEachParticle(pairs.size(), [&](size_t k) { coefficient[k] = -pairs[k].wR * pairS[k]; });
    thermostat.sumAlongPairs(coefficient, auxiliary);
}

void EDPDDynamics::step(OpenMM::ContextImpl& context, const EDPDIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& r = *data.positions;
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const double dt = integrator.getStepSize();
    const long long current = data.stepCount, next = current + 1;
    const AuxiliaryRecurrence recurrence(integrator.getAlpha(), dt, thermostat.getParameters().getKT(),
                                         integrator.getScheme() == EDPDIntegrator::Symmetric);
    memory.renumberSteps(current);
    if (!carriedForceValid(r, v)) {
        // A start, or positions set from outside: the pairs in range and their h are the
        // current ones; the s they carry are kept.
        computeConservativeAndPairs(context, integrator.getIntegrationForceGroups(), current);
        memory.bind(thermostat.getPairs(), current, recurrence, pairS);
        computeAuxiliaryForce();
        forEachParticle(r.size(), [&](size_t i) { force[i] = conservative[i] + auxiliary[i]; });
        setCarriedForceValid();
    }
    // p += dt/2 F ; r += dt p/m
    movePositions(context, next, dt, [&](size_t i) {
        v[i] += force[i] * (0.5 * dt * invMass[i]);
        return v[i] * dt;
    });
    // s^{n+1} from s^n and h(r^{n+1}) - h(r^n), then F(r^{n+1}, s^{n+1})
    computeConservativeAndPairs(context, integrator.getIntegrationForceGroups(), next);
    memory.advance(thermostat.getPairs(), current, recurrence, pairS);
    computeAuxiliaryForce();
    if (thermostatVirial != nullptr)
        addPairVirial(thermostat.getPairs(), coefficient, thermostat.getParameters(), *thermostatVirial);
    forEachParticle(r.size(), [&](size_t i) {
        force[i] = conservative[i] + auxiliary[i];
        v[i] += force[i] * (0.5 * dt * invMass[i]);
    });
    constrainVelocities(context);
    finishStep(data, dt);
}
