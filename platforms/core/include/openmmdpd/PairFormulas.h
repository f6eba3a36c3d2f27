/*
 * The formulas of one DPD pair, written once for every platform (docs/theory/dpd.md,
 * docs/theory/shardlow.md, docs/theory/lowe-andersen.md, docs/theory/forces.md).
 *
 * The host compiles this file as C++: each formula is a function template of Real (double,
 * or a vector of doubles whose lanes are pairs) and Scalar (double: a value common to the
 * lanes).  The GPU platforms compile the same text as device code, prepended to their kernel
 * sources with OPENMMDPD_DEVICE_CODE defined: Real and Scalar are then OpenMM's `mixed`.
 * So the code in this file is the subset both languages share: no namespaces (but the
 * host's, below), overloads, references or double literals (0.5f is exact in float and
 * double).  The platforms differ only in how they find the pairs and loop over them.
 */
#ifndef OPENMMDPD_PAIRFORMULAS_H_
#define OPENMMDPD_PAIRFORMULAS_H_

#ifdef OPENMMDPD_DEVICE_CODE
#define Real mixed
#define Scalar mixed
#define OPENMMDPD_FORMULA inline DEVICE mixed
#define OPENMMDPD_PREDICATE inline DEVICE bool
#else
#include <cmath>
#if defined(__GNUC__) || defined(__clang__)
// Always inlined: a vector passed by value crosses a call between code built for different
// vector units differently on each side.
#define OPENMMDPD_FORMULA template <class Real> __attribute__((always_inline)) inline Real
#else
#define OPENMMDPD_FORMULA template <class Real> inline Real
#endif
#define OPENMMDPD_PREDICATE inline bool
namespace DPDPlugin {
typedef double Scalar;
using std::pow;
using std::sqrt;
#endif

/* The linear weight w(r) = 1 - r/rc of a pair inside its cutoff rc. */
OPENMMDPD_FORMULA pairLinearWeight(Real r, Scalar cutoff) {
    return 1 - r / cutoff;
}

/*
 * The random weight wR = w^(s/2) of a pair with weight exponent s (Fan et al. 2006); the
 * standard s = 2 gives w itself, without pow, as the vector paths compute it.
 */
OPENMMDPD_FORMULA pairRandomWeight(Real w, Scalar s) {
    return s == 2 ? w : pow(w, 0.5f * s);
}

/* The dissipative weight wD = wR^2 = w^s: the fluctuation-dissipation theorem's partner of wR. */
OPENMMDPD_FORMULA pairDissipativeWeight(Real wR) {
    return wR * wR;
}

/* The noise amplitude sigma = sqrt(2 gamma kT) that balances a friction gamma. */
OPENMMDPD_FORMULA pairNoiseAmplitude(Real gamma, Scalar kT) {
    return sqrt(2 * gamma * kT);
}

/*
 * The dissipative force on i along e: F_D = -gamma wD (e . v_ij).  Transverse friction
 * applies the same formula to each axis of v_ij's part perpendicular to e
 * (perpendicularPart), with its own gamma and weight.
 */
OPENMMDPD_FORMULA dissipativeAlongE(Real gammaWD, Real eDotVij) {
    return -gammaWD * eDotVij;
}

/* The random force on i along e: F_R = sigma wR xi / sqrt(dt) (and across e, as dissipativeAlongE). */
OPENMMDPD_FORMULA randomAlongE(Real sigmaWR, Real xi, Scalar invSqrtDt) {
    return sigmaWR * xi * invSqrtDt;
}

/*
 * One axis a of the part of a vector x perpendicular to the pair's e, x_a - (e . x) e_a:
 * what transverse friction acts on (the relative velocity) and draws (its noise).
 */
OPENMMDPD_FORMULA perpendicularPart(Real x, Real eDotX, Real e) {
    return x - eDotX * e;
}

/*
 * Shardlow's splitting of a pair's fluctuation-dissipation part over a time h, with
 * noise = sigma wR xi sqrt(h), friction = gamma wD h, mu the pair's reduced mass and u its
 * relative normal velocity.  The explicit half's impulse along e, from u before it:
 */
OPENMMDPD_FORMULA shardlowExplicitHalf(Real noise, Real friction, Real u) {
    return 0.5f * (noise - friction * u);
}

/* The implicit half's impulse, from u after the explicit half. */
OPENMMDPD_FORMULA shardlowImplicitHalf(Real noise, Real friction, Scalar mu, Real u) {
    return 0.5f * (noise - friction * u) / (1 + friction / (2 * mu));
}

/* Both halves as the one impulse they add up to, (noise - friction u) / (1 + friction/2mu), from u before them. */
OPENMMDPD_FORMULA shardlowOneKick(Real noise, Real friction, Scalar mu, Real u) {
    const Real scale = 1 / (1 + friction * (0.5f / mu));
    return noise * scale - (friction * scale) * u;
}

/* Lowe-Andersen: whether a pair with collision rate Gamma collides in a time h, given a uniform number in [0, 1). */
OPENMMDPD_PREDICATE loweCollides(Scalar uniform, Scalar rate, Scalar h) {
    return uniform < rate * h;
}

/* The impulse along e that draws a colliding pair's relative normal velocity u anew from the Maxwell distribution: mu (xi sqrt(kT/mu) - u). */
OPENMMDPD_FORMULA loweImpulse(Real u, Real xi, Scalar mu, Scalar kTOverMu) {
    return mu * (xi * sqrt(kTOverMu) - u);
}

/*
 * The exact solution over h of the pair's Ornstein-Uhlenbeck equation for u,
 * du = -(gamma wD/mu) u dt + noise: the new u, from u, decay = exp(-gamma wD h/mu) and
 * spread = sqrt(kT/mu (1 - decay^2)) (each platform takes exp and sqrt with its own
 * functions of Real).
 */
OPENMMDPD_FORMULA pairOUVelocity(Real u, Real decay, Real spread, Real xi) {
    return u * decay + spread * xi;
}

/* The soft repulsion's force on i along e, a (1 - r/rc), for r < rc. */
OPENMMDPD_FORMULA softRepulsionAlongE(Real r, Scalar a, Scalar inverseCutoff) {
    return a * (1 - r * inverseCutoff);
}

/* The soft repulsion's energy a rc (1 - r/rc)^2 / 2, for r < rc. */
OPENMMDPD_FORMULA softRepulsionEnergy(Real r, Scalar a, Scalar cutoff) {
    const Real x = 1 - r / cutoff;
    return 0.5f * a * cutoff * x * x;
}

/* Many-body DPD's density weight norm (1 - r/rd)^2, norm = 15/(2 pi rd^3), for r < rd (docs/theory/mdpd.md). */
OPENMMDPD_FORMULA mdpdDensityWeight(Real r, Scalar norm, Scalar inverseDensityCutoff) {
    const Real x = 1 - r * inverseDensityCutoff;
    return norm * x * x;
}

/* Many-body DPD's density repulsion on i along e, (B_i rho_i + B_j rho_j)(1 - r/rd), for r < rd. */
OPENMMDPD_FORMULA mdpdRepulsionAlongE(Real r, Real densityRepulsion, Scalar inverseDensityCutoff) {
    return densityRepulsion * (1 - r * inverseDensityCutoff);
}

/* Many-body DPD's energy of one particle, pi rd^4 B rho^2 / 30 = energyFactor B rho^2. */
OPENMMDPD_FORMULA mdpdDensityEnergy(Real density, Scalar b, Scalar energyFactor) {
    return energyFactor * b * density * density;
}

/*
 * Extended DPD (docs/theory/edpd.md): the change of a pair's potential h = rc/2 (1 - w^2)
 * (rc/2 beyond the cutoff, h' = w) between two states, from its w^2 in each (0 out of range).
 */
OPENMMDPD_FORMULA edpdPotentialChange(Scalar cutoff, Real w2Old, Real w2New) {
    return -0.5f * cutoff * (w2New - w2Old);
}

/*
 * One step of a pair variable's recurrence: s' = rho s + (lambda dh + sqrt(lambda) c w) / d,
 * with invD = 1/d, c = noisePerLambda and w the step's normal number (the scheme sets rho and d).
 */
OPENMMDPD_FORMULA edpdNextValue(Real s, Scalar rho, Scalar invD, Real lambda, Real dh, Scalar noisePerLambda, Real w) {
    return rho * s + (lambda * dh + sqrt(lambda) * noisePerLambda * w) * invD;
}

/*
 * A pair variable after steps with h constant, exact in distribution: decay = rho^steps,
 * variance the stationary one, xi a normal number (decay 0: a fresh draw).
 */
OPENMMDPD_FORMULA edpdCaughtUp(Real s, Real decay, Real variance, Real xi) {
    return decay * s + sqrt(variance * (1 - decay * decay)) * xi;
}

#ifdef OPENMMDPD_DEVICE_CODE
#undef Real
#undef Scalar
#else
} // namespace DPDPlugin
#endif
#undef OPENMMDPD_FORMULA
#undef OPENMMDPD_PREDICATE

#endif
