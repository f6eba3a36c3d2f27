#ifndef OPENMMDPD_SHARDLOWROWSWEEP_H_
#define OPENMMDPD_SHARDLOWROWSWEEP_H_

#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/PairRowSweep.h"

namespace DPDPlugin {

/** The code a row sweep runs: the best the processor has, or the baseline target's (what runs where AVX2 is missing; for tests). */
enum class RowVectorUnit { Best, Baseline };

/**
 * sweepCells for Shardlow's update where all masses are equal (the common case): the pairs
 * of a row of independent cells (forEachPairRow) are updated as one, a vector lane each, with
 * the arithmetic of ShardlowPairUpdate::apply in every lane (the same result bit for bit).
 * Cells that are not independent, and massless particles, go pair by pair as before.
 */
void sweepCells(const ShardlowPairUpdate<const EqualMassPairImpulse&>& rule, const std::vector<PairGeometry>& list,
                const std::vector<double>& random, std::vector<OpenMM::Vec3>& v, const SweepCells& run,
                RowVectorUnit unit = RowVectorUnit::Best);

} // namespace DPDPlugin

#endif
