#ifndef OPENMMDPD_PAIRRULES_H_
#define OPENMMDPD_PAIRRULES_H_

#include "openmmdpd/DPDPairCore.h"
#include <cmath>
#include <vector>

namespace DPDPlugin {

/**
 * Pairwise-sequential velocity updates (algorithms.md sections 2 and 3): each acts on one
 * pair in place, with an impulse J along e (v_i += J/m_i e, v_j -= J/m_j e), so momentum is
 * conserved pair by pair.  A sweep applies one of them to every pair in a fixed order.
 */
struct PairImpulse {
    static void apply(const PairGeometry& p, double impulse, const std::vector<double>& invMass, std::vector<OpenMM::Vec3>& v) {
        v[p.i] += p.e * (impulse * invMass[p.i]);
        v[p.j] -= p.e * (impulse * invMass[p.j]);
    }
    static double reducedMass(const PairGeometry& p, const std::vector<double>& invMass) {
        return 1 / (invMass[p.i] + invMass[p.j]);
    }
};

/** Shardlow's splitting of the fluctuation-dissipation part over a time h (Table IV, general masses). */
struct ShardlowPairUpdate {
    const PairRandom& random;
    PairRandom::Stream stream;
    long long step;
    double h;
    const std::vector<double>& invMass;

    void operator()(const PairGeometry& p, std::vector<OpenMM::Vec3>& v) const {
        const double noise = p.sigmaWR * random.gaussian(stream, step, p.i, p.j) * std::sqrt(h);
        const double friction = p.gammaWD * h;
        // explicit half
        double u = p.e.dot(v[p.i] - v[p.j]);
        PairImpulse::apply(p, 0.5 * (noise - friction * u), invMass, v);
        // implicit half, with u after the explicit one
        u = p.e.dot(v[p.i] - v[p.j]);
        const double mu = PairImpulse::reducedMass(p, invMass);
        PairImpulse::apply(p, 0.5 * (noise - friction * u) / (1 + friction / (2 * mu)), invMass, v);
    }
};

/** Lowe-Andersen: with probability Gamma h, the pair's relative normal velocity is drawn anew. */
struct LowePairUpdate {
    const PairRandom& random;
    long long step;
    double h, kT;
    const std::vector<double>& invMass;

    void operator()(const PairGeometry& p, std::vector<OpenMM::Vec3>& v) const {
        // One draw gives both numbers; the Gaussian is only made for the pairs that collide.
        const r123::Philox4x32::ctr_type bits = random.bits(PairRandom::PairThermalisation, step, p.i, p.j);
        if (PairRandom::toUniform(bits[2]) >= p.rate * h)
            return;
        const double xi = PairRandom::boxMuller(bits);
        const double mu = PairImpulse::reducedMass(p, invMass);
        const double u = p.e.dot(v[p.i] - v[p.j]);
        PairImpulse::apply(p, mu * (xi * std::sqrt(kT / mu) - u), invMass, v);
    }
};

/**
 * The exact solution over h of the pair's Ornstein-Uhlenbeck equation for its relative
 * normal velocity, du = -(gamma wD/mu) u dt + noise: exact for the ideal gas at any h.
 */
struct PairOrnsteinUhlenbeckUpdate {
    const PairRandom& random;
    long long step;
    double h, kT;
    const std::vector<double>& invMass;

    void operator()(const PairGeometry& p, std::vector<OpenMM::Vec3>& v) const {
        const double mu = PairImpulse::reducedMass(p, invMass);
        const double decay = std::exp(-p.gammaWD * h / mu);
        const double u = p.e.dot(v[p.i] - v[p.j]);
        const double xi = random.gaussian(PairRandom::PairThermalisation, step, p.i, p.j);
        const double target = u * decay + std::sqrt(kT / mu * (1 - decay * decay)) * xi;
        PairImpulse::apply(p, mu * (target - u), invMass, v);
    }
};

} // namespace DPDPlugin

#endif
