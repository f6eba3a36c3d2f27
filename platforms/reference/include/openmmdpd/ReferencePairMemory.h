#ifndef OPENMMDPD_REFERENCEPAIRMEMORY_H_
#define OPENMMDPD_REFERENCEPAIRMEMORY_H_

#include "openmmdpd/CheckpointIO.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmmdpd/PairParameters.h"
#include "openmmdpd/PairRandom.h"
#include <iosfwd>
#include <map>
#include <utility>
#include <vector>

namespace DPDPlugin {

/**
 * The auxiliary variables s_k of EDPD (docs/theory/edpd.md), one per pair k = (i, j),
 * as state that outlives a step: two plain maps keyed by (min(i, j), max(i, j)).
 *
 *   inRange:  the pairs within their cutoff at step inRangeStep, each with s and wR^2 there
 *             (h_k = phi(r) = rc/2 (1 - wR^2), so wR^2 is all that dh needs);
 *   archived: the pairs that left their cutoff, each with s at the step of its last update.
 *
 * A pair seen for the first time is drawn from the stationary law N(0, lambda V), with
 * lambda = alpha gamma_ij and V the recurrence's variancePerLambda.  While a pair is away h
 * is constant, so when it comes back its s is caught up in closed form (recall); after
 * forgetSteps away it is drawn anew, as if never seen.  A returning pair's archived entry
 * is left where it is (it is never read again: the in-range entry comes first, and leaving
 * again overwrites it) until the periodic clean-up drops it; getNumPairVariables() counts
 * both maps, as the CPU platform's PairMemory does.
 *
 * Random numbers (PairRandom, keyed by (seed, stream, step, i, j)):
 *   AuxiliaryRecall at step n: a pair's s drawn or caught up to step n;
 *   AuxiliaryNoise at step n + 1: the noise w of the recurrence step from n to n + 1.
 */
class ReferencePairMemory {
public:
    ReferencePairMemory(const DPDPairParameters& parameters, const PairRandom& random) :
            parameters(parameters), random(random) {}
    /**
     * At a (re)start, at step `step`: make `pairs` (found at the current positions) the pairs
     * in range, each with its s at `step` (kept, caught up or drawn) and its current wR^2.
     * Pairs that were in range and no longer are archived with the s they have.
     */
    void bind(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence);
    /**
     * One step of the recurrence from step `step` to step + 1, with `pairs` found at the new
     * positions: every pair in range before or after takes one step.
     */
    void advance(const std::vector<PairGeometry>& pairs, long long step, const AuxiliaryRecurrence& recurrence);
    /** The s of a pair in range (bind or advance made it so). */
    double inRangeValue(int i, int j) const;
    /** The s of the pair (i, j) and the step it belongs to; false if the pair is not remembered. */
    bool find(int i, int j, double& s, long long& step) const;
    /** The number of entries held, in range and archived. */
    long long size() const { return (long long) (inRange.size() + archived.size()); }
    /**
     * The Context's step count was set from outside to `step`: the pair variables keep
     * their values and move to the new step numbering.
     */
    void renumberSteps(long long step);
    /** Forget every pair (as a new Context). */
    void clear();

private:
    typedef std::pair<int, int> Key;
    struct InRange {
        double s, wR2;
    };
    struct Archived {
        double s;
        long long step;
    };

public:
    /** The pair variables as a checkpoint holds them. */
    struct Saved {
        long long inRangeStep = -1;
        std::map<Key, InRange> inRange;
        std::map<Key, Archived> archived;
    };
    /** Binary, field by field, so that a continuation is bit-exact. */
    void write(std::ostream& stream) const;
    /** Reads and checks what write() wrote, without using it. */
    Saved read(CheckpointReader& reader) const;
    void restore(Saved&& saved);

private:
    static Key key(int i, int j) { return i < j ? Key(i, j) : Key(j, i); }
    /** lambda_ij = alpha gamma_ij. */
    double lambda(const Key& k, const AuxiliaryRecurrence& recurrence) const;
    /** s at `step` of a pair last updated to s at step `last` (known), or never seen (!known). */
    double catchUp(const Key& k, bool known, double s, long long last, long long step, const AuxiliaryRecurrence& recurrence) const;
    /** s at `step` of a pair that was not in range: its archived value caught up, or a fresh draw. */
    double recallArchived(const Key& k, long long step, const AuxiliaryRecurrence& recurrence) const;
    /** s^{n+1} from s^n and wR^2 at r^n and r^{n+1} (0 out of range), n = step. */
    double nextValue(const Key& k, double s, double wR2Old, double wR2New, long long step, const AuxiliaryRecurrence& recurrence) const;
    /** Drop the archived pairs away for forgetSteps or more at step `now`, every forgetSteps/4 steps. */
    void forget(long long now, const AuxiliaryRecurrence& recurrence);

    const DPDPairParameters& parameters;
    const PairRandom& random;
    long long inRangeStep = -1;
    std::map<Key, InRange> inRange;
    std::map<Key, Archived> archived;
};

} // namespace DPDPlugin

#endif
