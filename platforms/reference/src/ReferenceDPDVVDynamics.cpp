#include "openmmdpd/ReferenceDPDVVDynamics.h"
#include <cmath>

using namespace DPDPlugin;
using OpenMM::Vec3;

std::vector<Vec3> ReferenceDPDVVDynamics::totalForce(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator,
                                                     const std::vector<Vec3>& v, long long step, SymmetricTensor* virial) {
    std::vector<Vec3> f = conservativeForce(context, integrator.getIntegrationForceGroups(), step);
    const std::vector<PairGeometry> pairs = findPairs(context);
    addDissipative(pairs, v, f, virial);
    addRandom(pairs, step, integrator.getStepSize(), f, virial);
    return f;
}

void ReferenceDPDVVDynamics::step(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& v = *data(context).velocities;
    if (!carried.isValid(r, v)) {
        carried.force = totalForce(context, integrator, v, data(context).stepCount);
        carried.setValid();
    }
    if (integrator.getVariant() == DPDVVIntegrator::GrootWarren)
        grootWarrenStep(context, integrator);
    else
        dpdvvStep(context, integrator);
    finishStep(context, integrator.getStepSize());
}

void ReferenceDPDVVDynamics::grootWarrenStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& v = *data(context).velocities;
    std::vector<Vec3>& F = carried.force;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const double dt = integrator.getStepSize(), lambda = integrator.getLambda();
    const long long next = data(context).stepCount + 1;
    const size_t n = r.size();
    // r(t+dt) = r + dt v + dt^2/(2m) F ;  v~ = v + lambda dt F/m (both corrected by the constraints)
    std::vector<Vec3> move(n), predicted(n);
    for (size_t i = 0; i < n; i++) {
        move[i] = v[i] * dt + F[i] * (0.5 * dt * dt * invMass[i]);
        predicted[i] = v[i] + F[i] * (lambda * dt * invMass[i]);
    }
    movePositions(context, move, next, dt, &predicted);
    // F(t+dt) = FC(r) + FD(r, v~) + FR(r)
    const std::vector<Vec3> newF = totalForce(context, integrator, predicted, next, thermostatVirial);
    // v(t+dt) = v + dt/(2m) [F + F(t+dt)]
    for (size_t i = 0; i < n; i++)
        v[i] += (F[i] + newF[i]) * (0.5 * dt * invMass[i]);
    constrainVelocities(context);
    F = newF;
}

void ReferenceDPDVVDynamics::dpdvvStep(OpenMM::ContextImpl& context, const DPDVVIntegrator& integrator) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& v = *data(context).velocities;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const double dt = integrator.getStepSize();
    const long long next = data(context).stepCount + 1;
    const size_t n = r.size();
    // (1) v <- v + dt/(2m) (FC + FD + FR) ; (2) r <- r + dt v
    std::vector<Vec3> move(n);
    for (size_t i = 0; i < n; i++) {
        v[i] += carried.force[i] * (0.5 * dt * invMass[i]);
        move[i] = v[i] * dt;
    }
    movePositions(context, move, next, dt);
    // (3) FC(r), FD(r, v), FR(r), v the half-step velocity
    const std::vector<Vec3> FC = conservativeForce(context, integrator.getIntegrationForceGroups(), next);
    const std::vector<PairGeometry> pairs = findPairs(context);
    std::vector<Vec3> FD(n), FR(n);
    addDissipative(pairs, v, FD);
    addRandom(pairs, next, dt, FR, thermostatVirial);
    // (4a) v° <- v + dt/(2m) (FC + FR)
    std::vector<Vec3> vNoFD(n);
    for (size_t i = 0; i < n; i++)
        vNoFD[i] = v[i] + (FC[i] + FR[i]) * (0.5 * dt * invMass[i]);
    // (4b) v <- v° + dt/(2m) FD ; (5) FD <- FD(r, v).  SC-VV repeats both until the kinetic
    // energy changes by less than the tolerance (relative), at most maxIterations times.
    const bool selfConsistent = (integrator.getVariant() == DPDVVIntegrator::SelfConsistent);
    const int iterations = selfConsistent ? integrator.getMaxIterations() : 1;
    double previousKinetic = 0;
    for (int it = 0; it < iterations; it++) {
        for (size_t i = 0; i < n; i++)
            v[i] = vNoFD[i] + FD[i] * (0.5 * dt * invMass[i]);
        constrainVelocities(context);
        FD.assign(n, Vec3());
        addDissipative(pairs, v, FD);
        if (!selfConsistent)
            break;
        const double kinetic = sumMV2(v);
        if (it > 0 && std::fabs(kinetic - previousKinetic) <= integrator.getTolerance() * kinetic)
            break;
        previousKinetic = kinetic;
    }
    if (thermostatVirial != nullptr) {
        std::vector<Vec3> unused(n);
        addDissipative(pairs, v, unused, thermostatVirial);  // the FD carried into the next step
    }
    for (size_t i = 0; i < n; i++)
        carried.force[i] = FC[i] + FR[i] + FD[i];
}
