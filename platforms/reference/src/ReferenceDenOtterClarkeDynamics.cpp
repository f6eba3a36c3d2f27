#include "openmmdpd/ReferenceDenOtterClarkeDynamics.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

void ReferenceDenOtterClarkeDynamics::step(OpenMM::ContextImpl& context, const DenOtterClarkeIntegrator& integrator) {
    std::vector<Vec3>& v = *data(context).velocities;
    const std::vector<double>& invMass = parameters.getInverseMasses();
    const double dt = integrator.getStepSize();
    const long long now = data(context).stepCount;
    const size_t n = v.size();
    // (3) of the step before: FC(r), FD(r, v), FR(r), the random numbers keyed by this step
    const std::vector<Vec3> FC = conservativeForce(context, integrator.getIntegrationForceGroups(), now);
    const std::vector<PairGeometry> pairs = findPairs(context);
    std::vector<Vec3> FD(n), FR(n);
    addDissipative(pairs, v, FD);
    addRandom(pairs, now, dt, FR);
    for (size_t i = 0; i < n; i++)
        if (parameters.getActive()[i])
            sums.add(FD[i], FR[i], v[i], dt);
    // (1) v <- v + alpha dt/m (FC + FD) + beta dt/m FR  (beta FR sqrt(dt) with FR's 1/sqrt(dt))
    double alpha, beta;
    integrator.getPrefactors(DenOtterClarkeSums::thermostatMass(parameters), alpha, beta);
    // (2) r <- r + dt v
    std::vector<Vec3> move(n);
    for (size_t i = 0; i < n; i++) {
        v[i] += ((FC[i] + FD[i]) * alpha + FR[i] * beta) * (dt * invMass[i]);
        move[i] = v[i] * dt;
    }
    movePositions(context, move, now + 1, dt);
    // The next step's FD sees only velocities the constraints allow, as in every other update rule here.
    constrainVelocities(context);
    finishStep(context, dt);
}
