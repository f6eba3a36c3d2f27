#ifndef OPENMMDPD_DPDPAIRCORE_H_
#define OPENMMDPD_DPDPAIRCORE_H_

#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/PairSearch.h"
#include <vector>

namespace DPDPlugin {

/** What a pass over the pairs adds to the per-particle forces. */
enum PairTerms { DissipativeTerm = 1, RandomTerm = 2 };

/**
 * Adds the dissipative and/or random pair forces of pairs [begin, end) to `dissipative`
 * and `random` (per-particle arrays).  The random numbers are keyed by `step`.  Passing
 * the same array for both adds their sum (one scattered write per pair instead of two).
 */
void accumulateDPDForces(const std::vector<PairGeometry>& pairs, size_t begin, size_t end, int terms,
                         const std::vector<OpenMM::Vec3>& velocities, const PairRandom& random, long long step,
                         double dt, std::vector<OpenMM::Vec3>& dissipative, std::vector<OpenMM::Vec3>& randomForce);

} // namespace DPDPlugin

#endif
