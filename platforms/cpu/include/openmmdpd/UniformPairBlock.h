#ifndef OPENMMDPD_UNIFORMPAIRBLOCK_H_
#define OPENMMDPD_UNIFORMPAIRBLOCK_H_

#include "openmmdpd/PairParameters.h"

namespace DPDPlugin {

/**
 * What every pair shares when the thermostat has one type pair and every particle one mass,
 * there is no shear, and the soft force (if any) has one type pair and no exclusions (the
 * usual DPD fluid): constants instead of per-pair lookups.
 */
struct UniformPairRule {
    double cutoff, cutoff2, gamma, sigma, rate;
    bool soft;
    double softA, softInverseCutoff, softCutoff;
};

/**
 * The pair list's work for one block of hits of slot p (PairSearch::forEachSortedPairBlock),
 * four hits at a time where the processor has AVX2: the hits within the cutoff as
 * out[0, n) (i and j left for the caller to set) with their partners' slots in acceptedQ,
 * and, with the soft force, its pair forces added to softForce by slot, pair by pair in hit
 * order.  Bit for bit what DPDPairParameters::pairGeometry and SoftRepulsionKernel::pairForce
 * give pair by pair: the same operations in the same order, each rounded alike in a lane.
 * Returns n; returns -1 where the processor has no AVX2 (the caller goes pair by pair).
 */
int uniformPairBlock(const UniformPairRule& rule, int p, const int* qs, const OpenMM::Vec3* ds, int hits, int* acceptedQ,
                     PairGeometry* out, OpenMM::Vec3* softForce);

} // namespace DPDPlugin

#endif
