#ifndef OPENMMDPD_VECTORROWSWEEP_H_
#define OPENMMDPD_VECTORROWSWEEP_H_

#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/PairRowSweep.h"

namespace DPDPlugin {

/** Shardlow's update as the CPU platform's rows apply it: equal masses, the halves as one kick. */
typedef ShardlowPairUpdate<const EqualMassPairImpulse&, ShardlowForm::OneKick> RowShardlowUpdate;

/** The code a row sweep runs: the best the processor has, or the baseline target's (what runs where AVX2 is missing; for tests). */
enum class RowVectorUnit { Best, Baseline };

/**
 * sweepCells for Shardlow's update where all masses are equal (the common case): the pairs
 * of a row of independent cells (forEachPairRow) are updated as one, a vector lane each, with
 * the arithmetic of ShardlowPairUpdate::apply in every lane (the same result bit for bit),
 * over a list of PairGeometry or of UniformPair.  Cells that are not independent, and
 * massless particles, go pair by pair as before.
 */
void sweepCells(const RowShardlowUpdate& rule, const std::vector<double>& random, std::vector<OpenMM::Vec3>& v,
                const SweepCells<PairGeometry>& run, RowVectorUnit unit = RowVectorUnit::Best);
void sweepCells(const RowShardlowUpdate& rule, const std::vector<double>& random, std::vector<OpenMM::Vec3>& v,
                const SweepCells<UniformPair>& run, RowVectorUnit unit = RowVectorUnit::Best);

/**
 * The CPU platform's exp and sqrt for the pair Ornstein-Uhlenbeck update: exp is glibc's
 * vector one (libmvec) where the processor has AVX2 and the library is available (a scalar
 * exp per pair was most of that sweep's time), in the rows below and for a pair alone, so a
 * pair's update is the same whichever way it is swept (and whether the pressure tensor is
 * sampled or not); the standard library's, and the Reference platform's, to rounding.
 */
struct RowConsistentMath {
    static double exp(double x);
    static double sqrt(double x) { return std::sqrt(x); }
};

/** The same for the pair Ornstein-Uhlenbeck update, with RowConsistentMath's functions in every lane. */
void sweepCells(const PairOrnsteinUhlenbeckUpdate<const EqualMassPairImpulse&, RowConsistentMath>& rule,
                const std::vector<double>& random, std::vector<OpenMM::Vec3>& v, const SweepCells<PairGeometry>& run,
                RowVectorUnit unit = RowVectorUnit::Best);
void sweepCells(const PairOrnsteinUhlenbeckUpdate<const EqualMassPairImpulse&, RowConsistentMath>& rule,
                const std::vector<double>& random, std::vector<OpenMM::Vec3>& v, const SweepCells<UniformPair>& run,
                RowVectorUnit unit = RowVectorUnit::Best);

} // namespace DPDPlugin

#endif
