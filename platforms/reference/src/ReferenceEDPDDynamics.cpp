#include "openmmdpd/ReferenceEDPDDynamics.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

AuxiliaryRecurrence ReferenceEDPDDynamics::recurrence(const EDPDIntegrator& integrator) const {
    return AuxiliaryRecurrence(integrator.getAlpha(), integrator.getStepSize(), parameters.getKT(),
                               integrator.getScheme() == EDPDIntegrator::Symmetric);
}

std::vector<Vec3> ReferenceEDPDDynamics::totalForce(const std::vector<Vec3>& FC, const std::vector<PairGeometry>& pairs,
                                                     SymmetricTensor* virial) const {
    // -grad h_k s_k, with grad_i h_k = wR e and grad_j h_k = -wR e: the pair force c_k e, c_k = -wR s_k.
    std::vector<Vec3> auxiliary(FC.size());
    std::vector<double> c(pairs.size());
    for (size_t k = 0; k < pairs.size(); k++) {
        const PairGeometry& p = pairs[k];
        c[k] = -p.wR * memory.inRangeValue(p.i, p.j);
        auxiliary[p.i] += p.e * c[k];
        auxiliary[p.j] -= p.e * c[k];
    }
    if (virial != nullptr)
        addPairVirial(pairs, c, parameters, *virial);
    std::vector<Vec3> F(FC.size());
    for (size_t i = 0; i < F.size(); i++)
        F[i] = FC[i] + auxiliary[i];
    return F;
}

void ReferenceEDPDDynamics::halfKick(std::vector<Vec3>& v, const std::vector<Vec3>& F, double dt) const {
    const std::vector<double>& invMass = parameters.getInverseMasses();
    for (size_t i = 0; i < v.size(); i++)
        v[i] += F[i] * (0.5 * dt * invMass[i]);
}

void ReferenceEDPDDynamics::step(OpenMM::ContextImpl& context, const EDPDIntegrator& integrator) {
    std::vector<Vec3>& r = *data(context).positions;
    std::vector<Vec3>& v = *data(context).velocities;
    const double dt = integrator.getStepSize();
    const int groups = integrator.getIntegrationForceGroups();
    const long long current = data(context).stepCount, next = current + 1;
    const AuxiliaryRecurrence rec = recurrence(integrator);
    memory.renumberSteps(current);
    if (!carried.isValid(r, v)) {
        // A start, or a state set from outside: the pairs in range are those at the current
        // positions, with the s they carry (kept, caught up, or drawn if new).
        const std::vector<Vec3> FC = conservativeForce(context, groups, current);
        const std::vector<PairGeometry> pairs = findPairs(context);
        memory.bind(pairs, current, rec);
        carried.force = totalForce(FC, pairs);
        carried.setValid();
    }
    // p^{n+1/2} = p^n + dt/2 F(r^n, s^n) ;  r^{n+1} = r^n + dt M^-1 p^{n+1/2}
    halfKick(v, carried.force, dt);
    std::vector<Vec3> move(r.size());
    for (size_t i = 0; i < r.size(); i++)
        move[i] = v[i] * dt;
    movePositions(context, move, next, dt);
    // s^{n+1} from s^n and h(r^{n+1}) - h(r^n), over the pairs in range at r^n or r^{n+1}
    const std::vector<Vec3> FC = conservativeForce(context, groups, next);
    const std::vector<PairGeometry> pairs = findPairs(context);
    memory.advance(pairs, current, rec);
    // p^{n+1} = p^{n+1/2} + dt/2 F(r^{n+1}, s^{n+1})
    carried.force = totalForce(FC, pairs, thermostatVirial);
    halfKick(v, carried.force, dt);
    constrainVelocities(context);
    finishStep(context, dt);
}

bool ReferenceEDPDDynamics::getPairVariable(int i, int j, double& value, long long& step) const {
    if (i == j || i < 0 || j < 0 || i >= parameters.getNumParticles() || j >= parameters.getNumParticles())
        return false;
    return memory.find(i, j, value, step);
}
