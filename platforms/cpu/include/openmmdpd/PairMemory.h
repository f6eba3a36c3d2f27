#ifndef OPENMMDPD_PAIRMEMORY_H_
#define OPENMMDPD_PAIRMEMORY_H_

#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/DPDPairCore.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/ParallelExecutor.h"
#include <iosfwd>
#include <vector>

namespace DPDPlugin {

/**
 * The auxiliary variables s_k of EDPD, one per pair, as state that outlives a step.
 *
 * Pairs within their cutoff are held per lower particle index, sorted by the other index,
 * with their s and wR^2 (h_k = -rc wR^2 / 2 up to a constant) at the current step.  A pair
 * that leaves its cutoff moves to a per-particle archive with the step of its last update;
 * while away, h is constant and the recurrence is linear, so when the pair returns after m
 * steps its s is caught up exactly in distribution: rho^m s + sqrt(V (1 - rho^(2m))) xi.
 * A pair away for forgetSteps or more steps (or never seen) is drawn from the stationary
 * law N(0, V).  Archived pairs are dropped every forgetSteps/4 steps once forgotten; until
 * then they cost 24 bytes each.
 *
 * Every pair's update depends only on its own state and on random numbers keyed by
 * (seed, step, i, j), and the work is split by particle ranges, so results are the same
 * for any number of workers.
 */
class PairMemory {
public:
    PairMemory(const DPDPairParameters& parameters, const PairRandom& random, ParallelExecutor& executor);
    /**
     * Make the pairs of `pairs` (found at the current positions, step `step`) the ones in
     * range, each with its s at that step (kept, caught up or drawn); pairs no longer in
     * range are archived unchanged.  Writes each pair's s to pairS (pair list order).
     */
    void bind(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence,
              std::vector<double>& pairS);
    /**
     * Advance every pair in range at step `step` or at step + 1 (`pairs`, found at the new
     * positions) by one step of the recurrence.  Writes s at step + 1 to pairS.
     */
    void advance(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence,
                 std::vector<double>& pairS);
    /** The s of the pair (i, j) and its step; false if the pair is not remembered. */
    bool find(int i, int j, double& s, long long& step) const;
    /** The number of pair variables held (in range and archived). */
    long long size() const;
    /**
     * The Context's step count was set from outside to `step`: the pair variables keep
     * their values and move to the new step numbering.
     */
    void renumberSteps(long long step);
    /** Forget every pair (as a new Context). */
    void clear();

private:
    struct InRange {
        int j;
        double s, wR2;
    };
    struct Archived {
        int j;
        double s;
        long long step;
    };

public:
    /** The pair variables as a checkpoint holds them. */
    struct Saved {
        long long inRangeStep = -1;
        std::vector<int> inRangeStart;
        std::vector<InRange> inRange;
        std::vector<std::vector<Archived>> archived;
    };
    /** Binary, field by field, so that a continuation is bit-exact. */
    void write(std::ostream& stream) const;
    /** Reads and checks what write() wrote, without using it. */
    Saved read(CheckpointReader& reader) const;
    void restore(Saved&& saved);

private:
    /** Reads and checks saved.inRangeStart and saved.inRange. */
    void readInRange(CheckpointReader& reader, Saved& saved) const;
    /** Reads and checks saved.archived. */
    void readArchived(CheckpointReader& reader, Saved& saved) const;
    template <class PairUpdate>
    void merge(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence,
               std::vector<double>& pairS, PairUpdate update);
    /** s at `step` of the pair (i, j) last updated to s at `last`; draws when forgotten. */
    double recall(int i, int j, bool known, double s, long long last, long long step, const AuxiliaryRecurrence& recurrence) const;
    const Archived* findArchived(int i, int j) const;
    void archive(int i, int j, double s, long long step);
    const DPDPairParameters& parameters;
    const PairRandom& random;
    ParallelExecutor& executor;
    long long inRangeStep;
    std::vector<int> inRangeStart;
    std::vector<InRange> inRange;
    std::vector<std::vector<Archived>> archived;
    // The new pair list grouped by lower particle index (a counting sort), and the new
    // in-range table being built.
    std::vector<int> groupStart, groupPairs, fill;
    std::vector<InRange> nextInRange;
};

} // namespace DPDPlugin

#endif
