#include "openmmdpd/DPDPairCore.h"
#include "openmm/OpenMMException.h"
#include <algorithm>
#include <map>

using namespace DPDPlugin;
using OpenMM::Vec3;

DPDPairParameters::DPDPairParameters(const OpenMM::System& system, const DPDThermostatIntegrator& integrator) {
    const int n = system.getNumParticles();
    kT = BOLTZMANN_KJ_PER_MOL_K * integrator.getTemperature();
    // Dense indices for the types in use (type 0 always exists: it is everyone's default).
    std::map<int, int> dense = {{0, 0}};
    for (auto& entry : integrator.getParticleTypes())
        dense.emplace(entry.second, 0);
    int next = 0;
    for (auto& entry : dense)
        entry.second = next++;
    numTypes = next;
    typeIndex.resize(n);
    for (int i = 0; i < n; i++)
        typeIndex[i] = dense[integrator.getParticleType(i)];
    friction.assign(numTypes * numTypes, integrator.getDefaultFriction());
    cutoff.assign(numTypes * numTypes, integrator.getDefaultCutoff());
    for (int k = 0; k < integrator.getNumTypePairs(); k++) {
        int t1, t2;
        double f, c;
        integrator.getTypePairParameters(k, t1, t2, f, c);
        const int a = dense.at(t1), b = dense.at(t2);
        friction[a * numTypes + b] = friction[b * numTypes + a] = f;
        cutoff[a * numTypes + b] = cutoff[b * numTypes + a] = c;
    }
    maxCutoff = *std::max_element(cutoff.begin(), cutoff.end());
    cutoff2.resize(cutoff.size());
    for (size_t k = 0; k < cutoff.size(); k++)
        cutoff2[k] = cutoff[k] * cutoff[k];
    mass.resize(n);
    invMass.resize(n);
    active.resize(n);
    for (int i = 0; i < n; i++) {
        mass[i] = system.getParticleMass(i);
        active[i] = (mass[i] > 0);
        invMass[i] = active[i] ? 1 / mass[i] : 0;
    }
}

namespace {

template <bool Dissipative, bool Random, bool Sum>
void accumulate(const std::vector<PairGeometry>& pairs, size_t begin, size_t end, const std::vector<Vec3>& velocities,
                const PairRandom& random, long long step, double invSqrtDt, std::vector<Vec3>& dissipative,
                std::vector<Vec3>& randomForce) {
    for (size_t k = begin; k < end; k++) {
        const PairGeometry& p = pairs[k];
        Vec3 fd, fr;
        if (Dissipative)
            fd = DPDPairForce::dissipative(p, velocities[p.i] - velocities[p.j]);
        if (Random)
            fr = DPDPairForce::random(p, random.gaussian(PairRandom::RandomForce, step, p.i, p.j), invSqrtDt);
        if (Sum) {
            const Vec3 f = fd + fr;
            dissipative[p.i] += f;
            dissipative[p.j] -= f;
            continue;
        }
        if (Dissipative) {
            dissipative[p.i] += fd;
            dissipative[p.j] -= fd;
        }
        if (Random) {
            randomForce[p.i] += fr;
            randomForce[p.j] -= fr;
        }
    }
}

} // namespace

void DPDPlugin::accumulateDPDForces(const std::vector<PairGeometry>& pairs, size_t begin, size_t end, int terms,
                                    const std::vector<Vec3>& velocities, const PairRandom& random, long long step,
                                    double dt, std::vector<Vec3>& dissipative, std::vector<Vec3>& randomForce) {
    const double invSqrtDt = 1 / std::sqrt(dt);
    const bool both = (terms & DissipativeTerm) && (terms & RandomTerm);
    if (both && &dissipative == &randomForce)
        accumulate<true, true, true>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
    else if (both)
        accumulate<true, true, false>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
    else if (terms & DissipativeTerm)
        accumulate<true, false, false>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
    else if (terms & RandomTerm)
        accumulate<false, true, false>(pairs, begin, end, velocities, random, step, invSqrtDt, dissipative, randomForce);
}
