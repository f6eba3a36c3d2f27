#include "openmmdpd/DenOtterClarkeDynamics.h"
#include "ReferencePlatform.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

DenOtterClarkeDynamics::DenOtterClarkeDynamics(const OpenMM::System& system, const DenOtterClarkeIntegrator& integrator,
                                               ParallelExecutor& executor) :
        PairDynamics(system, integrator, executor, 1), dissipative(system.getNumParticles()), random(system.getNumParticles()),
        workerTerms(executor.getNumWorkers()) {
}

void DenOtterClarkeDynamics::measure(const std::vector<Vec3>& velocities, double dt) {
    const std::vector<bool>& active = thermostat.getParameters().getActive();
    executor.execute([&](int w) {
        size_t begin, end;
        executor.range(w, velocities.size(), begin, end);
        DenOtterClarkeSums terms;
        for (size_t i = begin; i < end; i++)
            if (active[i])
                terms.add(dissipative[i], random[i], velocities[i], dt);
        workerTerms[w] = terms;
    });
    for (const DenOtterClarkeSums& terms : workerTerms)
        sums.add(terms);
}

void DenOtterClarkeDynamics::step(OpenMM::ContextImpl& context, const DenOtterClarkeIntegrator& integrator) {
    OpenMM::ReferencePlatform::PlatformData& data = platformData(context);
    std::vector<Vec3>& v = *data.velocities;
    const std::vector<double>& invMass = thermostat.getParameters().getInverseMasses();
    const double dt = integrator.getStepSize();
    const long long now = data.stepCount;
    // (3) of the step before: FC(r), FD(r, v), FR(r), the random numbers keyed by this step
    computeConservativeAndPairs(context, integrator.getIntegrationForceGroups(), now);
    thermostat.compute(DissipativeTerm | RandomTerm, v, now, dt, dissipative, random);
    measure(v, dt);
    double alpha, beta;
    integrator.getPrefactors(DenOtterClarkeSums::thermostatMass(thermostat.getParameters()), alpha, beta);
    // (1) v += alpha dt/m (FC + FD) + beta dt/m FR ; (2) r += dt v
    movePositions(context, now + 1, dt, [&](size_t i) {
        v[i] += ((conservative[i] + dissipative[i]) * alpha + random[i] * beta) * (dt * invMass[i]);
        return v[i] * dt;
    });
    // The next step's FD sees only velocities the constraints allow, as in every other update rule here.
    constrainVelocities(context);
    finishStep(data, dt);
}
