#ifndef OPENMMDPD_UNIFORMPAIRBLOCK_H_
#define OPENMMDPD_UNIFORMPAIRBLOCK_H_

#include "openmmdpd/PairParameters.h"

namespace DPDPlugin {

/**
 * What every pair shares when the thermostat has one type pair with the standard weight
 * exponent 2 and no exceptions, every particle has one mass, there is no shear, and the soft force (if any) has one type pair and no exclusions (the
 * usual DPD fluid): constants instead of per-pair lookups.
 */
struct UniformPairRule {
    double cutoff, cutoff2, gamma, sigma, rate;
    bool soft;
    double softA, softInverseCutoff, softCutoff;
};

/**
 * A pair of a list whose pairs all share their parameters (a UniformPairRule), as the
 * sweeps read it: what its PairGeometry holds beyond the rule's constants, in 40 bytes
 * where a PairGeometry takes 72 (at a million particles the sweeps wait for their list to
 * come in from memory).
 */
struct UniformPair {
    int i, j;
    OpenMM::Vec3 e;
    double wR;
};
static_assert(sizeof(UniformPair) == 40, "a UniformPair is the 40 bytes its readers count on");

/** A uniform pair's PairGeometry: what DPDPairParameters::pairGeometry gives it (the same operations on the same values). */
inline PairGeometry pairGeometry(const UniformPair& pair, const UniformPairRule& rule) {
    PairGeometry g;
    g.i = pair.i;
    g.j = pair.j;
    g.e = pair.e;
    g.wR = pair.wR;
    g.gammaWD = rule.gamma * pairDissipativeWeight(pair.wR);
    g.sigmaWR = rule.sigma * pair.wR;
    g.rate = rule.rate;
    g.imageVx = 0;
    return g;
}

/** Whether uniformPairBlock runs on this processor (it needs AVX2). */
bool canRunUniformPairBlock();

/**
 * The pair list's work for one block of hits of slot p (PairSearch::forEachSortedPairBlock),
 * four hits at a time where the processor has AVX2: the hits within the cutoff as
 * out[0, n) (i and j left for the caller to set) with their partners' slots in acceptedQ,
 * and, with the soft force, its pair forces added to softForce by slot, pair by pair in hit
 * order, or, given softPairForce, each accepted pair's soft force along e to
 * softPairForce[0, n) (the caller adds it where it adds the pair's other forces; softForce
 * is then not touched and may be null).  Bit for bit what DPDPairParameters::pairGeometry
 * and SoftRepulsionKernel::pairForce give pair by pair: the same operations in the same
 * order, each rounded alike in a lane.  Returns n; returns -1 where the processor has no
 * AVX2 (the caller goes pair by pair).
 */
int uniformPairBlock(const UniformPairRule& rule, int p, const int* qs, const OpenMM::Vec3* ds, int hits, int* acceptedQ,
                     PairGeometry* out, OpenMM::Vec3* softForce, double* softPairForce = nullptr);
/** The same with the accepted pairs as UniformPair (i and j left for the caller to set). */
int uniformPairBlock(const UniformPairRule& rule, int p, const int* qs, const OpenMM::Vec3* ds, int hits, int* acceptedQ,
                     UniformPair* out, OpenMM::Vec3* softForce);

} // namespace DPDPlugin

#endif
