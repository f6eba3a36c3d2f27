#ifndef OPENMMDPD_PAIREVALUATORS_H_
#define OPENMMDPD_PAIREVALUATORS_H_

#include "openmmdpd/ConstrainedPairImpulse.h"
#include "openmmdpd/PairFormulas.h"
#include "openmmdpd/PairParameters.h"
#include "openmmdpd/PairRandom.h"
#include <cmath>
#include <vector>

#if defined(__GNUC__) || defined(__clang__)
#define OPENMMDPD_ALWAYS_INLINE __attribute__((always_inline)) inline
#else
#define OPENMMDPD_ALWAYS_INLINE inline
#endif

namespace DPDPlugin {

/*
 * The rules of one pair on the host, built on its formulas (PairFormulas.h, which the GPU
 * platforms compile too): each is a small struct of pure functions of the pair's geometry,
 * velocities and random number; the platforms differ only in how they find the pairs and
 * loop over them.
 */

/** The DPD pair forces (docs/theory/dpd.md): the force on i (j gets the opposite). */
struct DPDPairForce {
    /** FD_ij = -gamma wD(r) (e . v_ij) e, and -gamma_perp wD_perp(r) (I - e e^T) v_ij with transverse friction. */
    static OpenMM::Vec3 dissipative(const PairGeometry& p, const OpenMM::Vec3& vij) {
        const OpenMM::Vec3 along = p.e * dissipativeAlongE(p.gammaWD, p.e.dot(vij));
        return p.hasTransverse() ? along + transverseDissipative(p, vij) : along;
    }
    /** FR_ij along e: sigma wR xi e / sqrt(dt). */
    static OpenMM::Vec3 random(const PairGeometry& p, double xi, double invSqrtDt) {
        return p.e * randomAlongE(p.sigmaWR, xi, invSqrtDt);
    }
    /** The transverse friction's dissipative force, -gamma_perp wD_perp (I - e e^T) v_ij. */
    static OpenMM::Vec3 transverseDissipative(const PairGeometry& p, const OpenMM::Vec3& vij) {
        const OpenMM::Vec3 u = p.perpendicular(vij);
        return OpenMM::Vec3(dissipativeAlongE(p.transverseGammaWD, u[0]), dissipativeAlongE(p.transverseGammaWD, u[1]),
                            dissipativeAlongE(p.transverseGammaWD, u[2]));
    }
    /**
     * The transverse friction's random force, sigma_perp wR_perp (I - e e^T) zeta / sqrt(dt),
     * zeta the pair's three normal numbers (PairRandom::normalVector, stream TransverseNoise).
     */
    static OpenMM::Vec3 transverseRandom(const PairGeometry& p, const double* zeta, double invSqrtDt) {
        const OpenMM::Vec3 z = p.perpendicular(OpenMM::Vec3(zeta[0], zeta[1], zeta[2]));
        return OpenMM::Vec3(randomAlongE(p.transverseSigmaWR, z[0], invSqrtDt), randomAlongE(p.transverseSigmaWR, z[1], invSqrtDt),
                            randomAlongE(p.transverseSigmaWR, z[2], invSqrtDt));
    }
};

/**
 * A pair's random input to a sweep with transverse friction: its normal number xi (along e)
 * and its noise vector zeta (PairRandom::normalVector; across e).
 */
struct PairNoise {
    double xi, zeta[3];
};

/** The soft repulsion of DPDSoftRepulsionForce (docs/theory/forces.md), for r < rc. */
struct SoftRepulsionPair {
    /** The force on i along e = r_ij / r: a (1 - r/rc) (kJ/mol/nm). */
    static double force(double a, double inverseCutoff, double r) { return softRepulsionAlongE(r, a, inverseCutoff); }
    /** The energy a rc (1 - r/rc)^2 / 2 (kJ/mol). */
    static double energy(double a, double cutoff, double r) { return softRepulsionEnergy(r, a, cutoff); }
};

/**
 * One step of an EDPD pair variable's recurrence (docs/theory/edpd.md), for a pair with
 * coupling lambda:  s' = rho s + (lambda dh + sqrt(2 kT lambda alpha dt) w) / d,
 * with d = 1 + alpha dt, rho = 1/d (one-sided) or d = 1 + alpha dt/2,
 * rho = (1 - alpha dt/2)/d (symmetric).  With h constant its stationary variance is
 * lambda * variancePerLambda, and it forgets its state in forgetSteps steps
 * (|rho|^forgetSteps < 1e-8).
 */
struct AuxiliaryRecurrence {
    AuxiliaryRecurrence(double alpha, double dt, double kT, bool symmetric) : alpha(alpha) {
        const double x = alpha * dt;
        const double d = symmetric ? 1 + 0.5 * x : 1 + x;
        invD = 1 / d;
        rho = symmetric ? (1 - 0.5 * x) * invD : invD;
        noisePerLambda = std::sqrt(2 * kT * x);
        // V = (c/d)^2 / (1 - rho^2) with c^2 = 2 kT lambda alpha dt, written so that it stays
        // exact when rho is close to 1.
        variancePerLambda = 2 * kT * x / (d * d - (rho * d) * (rho * d));
        const double decay = std::fabs(rho);
        forgetSteps = (decay == 0 ? 1 : (long long) std::floor(std::log(1e-8) / std::log(decay)) + 1);
    }
    /**
     * h(r') - h(r) for h = phi(r) = rc/2 (1 - wR^2) (rc/2 beyond the cutoff, phi' = wR),
     * from the pair's wR^2 before and after (0 out of range).
     */
    static double dh(double cutoff, double wR2Old, double wR2New) { return edpdPotentialChange(cutoff, wR2Old, wR2New); }
    /** s at the next step from s, lambda, dh = h' - h and the step's normal number w. */
    double next(double s, double lambda, double dh, double w) const {
        return edpdNextValue(s, rho, invD, lambda, dh, noisePerLambda, w);
    }
    /**
     * s after `gap` steps with h constant, from s (exact in distribution), given the
     * stationary variance and a normal number; drawn anew if unknown or forgotten.
     */
    double recall(bool known, double s, long long gap, double variance, double xi) const {
        const bool forgotten = (!known || gap < 0 || gap >= forgetSteps);
        return edpdCaughtUp(s, forgotten ? 0.0 : std::pow(rho, (double) gap), variance, xi);
    }
    double alpha, rho, invD, noisePerLambda, variancePerLambda;
    long long forgetSteps;
};

/*
 * Pairwise-sequential velocity updates (docs/theory/shardlow.md and
 * docs/theory/lowe-andersen.md): each acts on one
 * pair in place, with an impulse J along e, so momentum is conserved pair by pair.  A sweep
 * applies one of them to every pair in a fixed order, giving each pair its random input of
 * the sweep (DrawnNormals, DrawnPartnerNormals or DrawnBits, or the same numbers drawn ahead
 * in batches).  The Impulse is FreePairImpulse (v_i += J/m_i e, v_j -= J/m_j e, reduced mass
 * m_i m_j/(m_i + m_j)) or, in a System with constraints, ConstrainedPairImpulse (the
 * effective reduced mass and the constraint forces the impulse calls up); a pair the
 * constraints hold rigid along e is left alone.
 */

/** A pair's normal number for a sweep, drawn from PairRandom (the definition). */
struct DrawnNormals {
    const PairRandom& random;
    PairRandom::Stream stream;
    long long step;
    double operator()(const PairGeometry& p) const { return random.gaussian(stream, step, p.i, p.j); }
};

/** A pair's normal number for a sweep, the partner of DrawnNormals' for the same key (PairRandom::partnerGaussian). */
struct DrawnPartnerNormals {
    const PairRandom& random;
    PairRandom::Stream stream;
    long long step;
    double operator()(const PairGeometry& p) const { return random.partnerGaussian(stream, step, p.i, p.j); }
};

/**
 * A pair's PairNoise for a sweep with transverse friction: its normal number as DrawnNormals
 * (or DrawnPartnerNormals, `partner`) draws it, and its noise vector of `transverseStream` at
 * the same step.
 */
struct DrawnPairNoise {
    const PairRandom& random;
    PairRandom::Stream stream, transverseStream;
    long long step;
    bool partner;
    PairNoise operator()(const PairGeometry& p) const {
        PairNoise noise;
        noise.xi = (partner ? random.partnerGaussian(stream, step, p.i, p.j) : random.gaussian(stream, step, p.i, p.j));
        random.normalVector(transverseStream, step, p.i, p.j, noise.zeta);
        return noise;
    }
};

/** A pair's random words for a sweep, drawn from PairRandom (the definition). */
struct DrawnBits {
    const PairRandom& random;
    PairRandom::Stream stream;
    long long step;
    r123::Philox4x32::ctr_type operator()(const PairGeometry& p) const { return random.bits(stream, step, p.i, p.j); }
};

/**
 * 1/x, where one value is common to most pairs (equal masses) divided once ahead:
 * the same result bit for bit, without a division per pair.
 */
struct Reciprocal {
    explicit Reciprocal(double common) : common(common), inverse(1 / common) {}
    double operator()(double x) const { return x == common ? inverse : 1 / x; }
    double common, inverse;
};

/** The functions a pair rule takes of its numbers (exp, sqrt): the standard library's. */
struct ScalarMath {
    static double exp(double x) { return std::exp(x); }
    static double sqrt(double x) { return std::sqrt(x); }
};

/**
 * One pair's velocities as ShardlowPairUpdate::apply sees them: u along e, and an impulse
 * along e; and the functions the rule takes (Math: ScalarMath, or a platform's own that agree
 * with its vector ones).
 */
template <class Impulse, class Functions = ScalarMath>
struct PairVelocities {
    typedef Functions Math;
    const PairGeometry& p;
    std::vector<OpenMM::Vec3>& v;
    const Impulse& impulse;
    double mu;  // the reduced mass the impulse sees
    double normalVelocity() const { return p.e.dot(p.relativeVelocity(v[p.i], v[p.j])); }
    void kick(double impulseAlongE) const { impulse.apply(p, impulseAlongE, v); }
};

/**
 * How ShardlowPairUpdate adds its halves.  TwoHalves: as docs/theory/shardlow.md writes them, the
 * explicit half, u found again, the implicit half.  OneKick: as the one impulse they add up
 * to.  With s the noise, f the friction and c = f / 2mu, the explicit half J1 = (s - f u) / 2
 * leaves u1 = u + J1 / mu, so the implicit half is J2 = (s - f u1) / (2 (1 + c)) =
 * J1 (1 - c) / (1 + c), and J1 + J2 = (s - f u) / (1 + c): the same to rounding, with one
 * read of the velocities and no division between it and the kick, where a sweep's chain of
 * dependent updates runs (the CPU platform's rows are bound by it).  It holds for every
 * impulse here: each changes u by J / mu, mu the pair's reduced mass, the effective one
 * mu_eff under constraints (ConstrainedPairImpulse), where one kick also spreads the
 * impulse over the constraint clusters once instead of twice (the constraints are solved
 * once per pair in either form).
 */
enum class ShardlowForm { TwoHalves, OneKick };

/** Shardlow's splitting of the fluctuation-dissipation part over a time h (Table IV, general masses). */
template <class Impulse = FreePairImpulse, ShardlowForm Form = ShardlowForm::TwoHalves>
struct ShardlowPairUpdate {
    ShardlowPairUpdate(double h, Impulse impulse) :
            h(h), sqrtH(std::sqrt(h)), impulse(impulse), reducedMass(impulse.commonInverseReducedMass()) {}
    double h, sqrtH;
    Impulse impulse;
    Reciprocal reducedMass;  // mu from 1/mu

    /** xi: the pair's normal number of the sweep (RandomForce of the step; for S2's second, its partner at the next step). */
    void operator()(const PairGeometry& p, double xi, std::vector<OpenMM::Vec3>& v) const {
        const double inverseMu = impulse.inverseReducedMass(p);
        if (inverseMu == 0)
            return;
        PairVelocities<Impulse> pair{p, v, impulse, reducedMass(inverseMu)};
        apply(pair, p.sigmaWR, p.gammaWD, xi);
    }
    /** With transverse friction: along e with noise.xi, as above, then across e with noise.zeta. */
    void operator()(const PairGeometry& p, const PairNoise& noise, std::vector<OpenMM::Vec3>& v) const {
        const double inverseMu = impulse.inverseReducedMass(p);
        if (inverseMu == 0)
            return;
        PairVelocities<Impulse> pair{p, v, impulse, reducedMass(inverseMu)};
        apply(pair, p.sigmaWR, p.gammaWD, noise.xi);
        if (p.hasTransverse())
            applyAcross(p, noise.zeta, v, pair.mu);
    }
    /**
     * The same splitting across e: each axis of the relative velocity's part perpendicular to
     * e follows the one-dimensional rule with gamma_perp wD_perp and the perpendicular part of
     * the pair's noise vector zeta (docs/theory/shardlow.md), as one impulse in the plane.
     */
    void applyAcross(const PairGeometry& p, const double* zeta, std::vector<OpenMM::Vec3>& v, double mu) const {
        const OpenMM::Vec3 noise = p.perpendicular(OpenMM::Vec3(zeta[0], zeta[1], zeta[2])) * (p.transverseSigmaWR * sqrtH);
        const double friction = p.transverseGammaWD * h;
        const auto across = [&]() { return p.perpendicular(p.relativeVelocity(v[p.i], v[p.j])); };
        OpenMM::Vec3 u = across(), J;
        if (Form == ShardlowForm::OneKick) {
            for (int a = 0; a < 3; a++)
                J[a] = shardlowOneKick(noise[a], friction, mu, u[a]);
            impulse.applyAcross(p, J, v);
            return;
        }
        for (int a = 0; a < 3; a++)
            J[a] = shardlowExplicitHalf(noise[a], friction, u[a]);
        impulse.applyAcross(p, J, v);
        u = across();
        for (int a = 0; a < 3; a++)
            J[a] = shardlowImplicitHalf(noise[a], friction, mu, u[a]);
        impulse.applyAcross(p, J, v);
    }
    /**
     * Both halves on a pair (PairVelocities), given sigma wR, gamma wD and xi; or on a row of
     * pairs with no particle in common at once, Real a vector of their values and Pair the
     * row's velocities, with the same arithmetic in each lane.  (By reference: a vector
     * passed by value is passed differently by code built for different vector units.)
     */
    template <class Pair, class Real>
    void apply(Pair& pair, const Real& sigmaWR, const Real& gammaWD, const Real& xi) const {
        const Real noise = sigmaWR * xi * sqrtH;
        const Real friction = gammaWD * h;
        if (Form == ShardlowForm::OneKick) {
            pair.kick(shardlowOneKick(noise, friction, pair.mu, pair.normalVelocity()));
            return;
        }
        pair.kick(shardlowExplicitHalf(noise, friction, pair.normalVelocity()));
        pair.kick(shardlowImplicitHalf(noise, friction, pair.mu, pair.normalVelocity()));
    }
};

/** Lowe-Andersen: with probability Gamma h, the pair's relative normal velocity is drawn anew. */
template <class Impulse = FreePairImpulse>
struct LowePairUpdate {
    double h, kT;
    Impulse impulse;

    /** bits: the pair's words of stream PairThermalisation; the Gaussian is only made for the pairs that collide. */
    void operator()(const PairGeometry& p, const r123::Philox4x32::ctr_type& bits, std::vector<OpenMM::Vec3>& v) const {
        if (!loweCollides(PairRandom::toUniform(bits[2]), p.rate, h))
            return;
        const double inverseMu = impulse.inverseReducedMass(p);
        if (inverseMu == 0)
            return;
        const double xi = PairRandom::boxMuller(bits);
        const double mu = 1 / inverseMu;
        const double u = p.e.dot(p.relativeVelocity(v[p.i], v[p.j]));
        impulse.apply(p, loweImpulse(u, xi, mu, kT / mu), v);
    }
};

/**
 * The exact solution over h of the pair's Ornstein-Uhlenbeck equation for its relative
 * normal velocity, du = -(gamma wD/mu) u dt + noise: exact for the ideal gas at any h.
 * Math: its exp and sqrt (see PairVelocities).
 */
template <class Impulse = FreePairImpulse, class Math = ScalarMath>
struct PairOrnsteinUhlenbeckUpdate {
    PairOrnsteinUhlenbeckUpdate(double h, double kT, Impulse impulse) :
            h(h), kT(kT), impulse(impulse), reducedMass(impulse.commonInverseReducedMass()),
            commonKTOverMu(kT / reducedMass.inverse) {}
    double h, kT;
    Impulse impulse;
    Reciprocal reducedMass;  // mu from 1/mu
    double commonKTOverMu;   // kT/mu for the common mu

    /** xi: the pair's normal number of stream PairThermalisation. */
    void operator()(const PairGeometry& p, double xi, std::vector<OpenMM::Vec3>& v) const {
        const double inverseMu = impulse.inverseReducedMass(p);
        if (inverseMu == 0)
            return;
        const double mu = reducedMass(inverseMu);
        PairVelocities<Impulse, Math> pair{p, v, impulse, mu};
        apply(pair, p.gammaWD, xi, kTOverMu(inverseMu, mu));
    }
    /**
     * With transverse friction: along e with noise.xi, as above, then across e with noise.zeta;
     * with the standard library's exp and sqrt, as no vector row takes such a sweep.
     */
    void operator()(const PairGeometry& p, const PairNoise& noise, std::vector<OpenMM::Vec3>& v) const {
        const double inverseMu = impulse.inverseReducedMass(p);
        if (inverseMu == 0)
            return;
        const double mu = reducedMass(inverseMu);
        PairVelocities<Impulse, ScalarMath> pair{p, v, impulse, mu};
        apply(pair, p.gammaWD, noise.xi, kTOverMu(inverseMu, mu));
        if (p.hasTransverse())
            applyAcross(p, noise.zeta, v, mu, kTOverMu(inverseMu, mu));
    }
    /** kT/mu of a pair of inverse reduced mass inverseMu = 1/mu. */
    double kTOverMu(double inverseMu, double mu) const { return inverseMu == reducedMass.common ? commonKTOverMu : kT / mu; }
    /**
     * The exact solution across e: each axis of the relative velocity's part perpendicular to
     * e decays with gamma_perp wD_perp and takes the perpendicular part of the pair's noise
     * vector zeta (docs/theory/lowe-andersen.md), as one impulse in the plane.
     */
    void applyAcross(const PairGeometry& p, const double* zeta, std::vector<OpenMM::Vec3>& v, double mu, double pairKTOverMu) const {
        const OpenMM::Vec3 z = p.perpendicular(OpenMM::Vec3(zeta[0], zeta[1], zeta[2]));
        const double decay = std::exp(-p.transverseGammaWD * h / mu), spread = std::sqrt(pairKTOverMu * (1 - decay * decay));
        const OpenMM::Vec3 u = p.perpendicular(p.relativeVelocity(v[p.i], v[p.j]));
        OpenMM::Vec3 J;
        for (int a = 0; a < 3; a++)
            J[a] = mu * (pairOUVelocity(u[a], decay, spread, z[a]) - u[a]);
        impulse.applyAcross(p, J, v);
    }
    /**
     * The update of a pair (PairVelocities) given gamma wD, xi and kT/mu, or of a row of pairs
     * at once, as ShardlowPairUpdate::apply; Pair::Math has exp and sqrt of Real.
     */
    template <class Pair, class Real>
    void apply(Pair& pair, const Real& gammaWD, const Real& xi, double kTOverMu) const {
        const Real decay = Pair::Math::exp(-gammaWD * h / pair.mu);
        const Real u = pair.normalVelocity();
        const Real target = pairOUVelocity(u, decay, Pair::Math::sqrt(kTOverMu * (1 - decay * decay)), xi);
        pair.kick(pair.mu * (target - u));
    }
};

} // namespace DPDPlugin

#endif
