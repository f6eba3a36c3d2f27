#ifndef OPENMMDPD_PAIRROWSWEEP_H_
#define OPENMMDPD_PAIRROWSWEEP_H_

#include "openmmdpd/PairParameters.h"
#include "openmmdpd/UniformPairBlock.h"
#include <algorithm>
#include <cstdint>
#include <vector>

namespace DPDPlugin {

/**
 * A run of cells a sweep visits in turn (PairSweep): cells[begin, end) in that order or its
 * reverse, cell c's pairs numbered [start[c], start[c + 1]) (their index into the random
 * numbers), their entries (PairGeometry, or UniformPair under `uniformRule`) the
 * start[c + 1] - start[c] from pairs[c] on (the workers that found them may keep their
 * parts of the list apart).  `independent`: the cells share no particle (one colour), so
 * their pairs may be interleaved.
 */
template <class Entry>
struct SweepCells {
    const std::vector<int>& cells;
    const std::vector<int>& start;
    const std::vector<const Entry*>& pairs;
    size_t begin, end;
    bool reverse, independent;
    const UniformPairRule* uniformRule;  // with UniformPair entries only
};

/** A list entry's PairGeometry. */
inline const PairGeometry& geometryOf(const PairGeometry& pair, const SweepCells<PairGeometry>&) {
    return pair;
}
inline PairGeometry geometryOf(const UniformPair& pair, const SweepCells<UniformPair>& run) {
    return pairGeometry(pair, *run.uniformRule);
}

/** The cells a sweep interleaves (forEachPairRow): the width of a row of pairs. */
constexpr int SWEEP_LANES = 4;

/**
 * visitRow(row, rowPairs, n) for the pairs of a run of independent cells, SWEEP_LANES cells
 * at a time, pair by pair: row[l] is the number of the next pair of the l-th of n cells in
 * progress and rowPairs[l] its list entry (the lanes past n repeat lane 0), and a cell that
 * ends is followed in its lane by the run's next one.  Each cell's pairs keep their order
 * (or its reverse), which is all that decides the result; the lanes are independent chains
 * of velocity updates for the processor to overlap.
 */
template <class Entry, class VisitRow>
__attribute__((always_inline)) inline void forEachPairRow(const SweepCells<Entry>& run, VisitRow&& visitRow) {
    constexpr int LANES = SWEEP_LANES;
    const int direction = run.reverse ? -1 : 1;
    int next[LANES], last[LANES], first[LANES], active = 0;
    const Entry* cellPairs[LANES];
    size_t taken = run.begin;
    auto takeCell = [&](int l) {
        while (taken < run.end) {
            const int cell = run.cells[run.reverse ? run.begin + run.end - 1 - taken : taken];
            taken++;
            if (run.start[cell + 1] > run.start[cell]) {  // (PairSweep lists no empty cell; a lane must not start on one)
                next[l] = run.reverse ? run.start[cell + 1] - 1 : run.start[cell];
                last[l] = run.reverse ? run.start[cell] - 1 : run.start[cell + 1];
                first[l] = run.start[cell];
                cellPairs[l] = run.pairs[cell];
                return true;
            }
        }
        return false;
    };
    while (active < LANES && takeCell(active))
        active++;
    while (active > 0) {
        int row[LANES];
        const Entry* rowPairs[LANES];
        for (int l = 0; l < LANES; l++) {
            const int from = (l < active ? l : 0);
            row[l] = next[from];
            rowPairs[l] = cellPairs[from] + (next[from] - first[from]);
        }
        visitRow(row, rowPairs, active);
        for (int l = 0; l < active; l++) {
            next[l] += direction;
            if (next[l] == last[l] && !takeCell(l)) {
                // the last lane moves into this one and takes its turn here
                active--;
                next[l] = next[active];
                last[l] = last[active];
                first[l] = first[active];
                cellPairs[l] = cellPairs[active];
                l--;
            }
        }
    }
}

/**
 * A cell's pairs are a run of the list, but the sweep hops between cells (and lanes) too
 * often for the hardware to see the runs: each pair asks for the one 8 further on (an
 * address past its part of the list is only a hint to the processor, never read).
 */
template <class Entry, class Random>
__attribute__((always_inline)) inline void prefetchAhead(const Entry* const* rowPairs, const std::vector<Random>& random,
                                                         const int* row, int n, bool reverse) {
    const int ahead = reverse ? -8 : 8, last = (int) random.size() - 1;
    for (int l = 0; l < n; l++) {
        const uintptr_t pair = (uintptr_t) rowPairs[l] + ahead * (intptr_t) sizeof(Entry);
        __builtin_prefetch((const void*) pair);
        __builtin_prefetch((const void*) (pair + sizeof(Entry) - 1));  // 40 or 72 bytes: it may span two lines
        __builtin_prefetch(&random[std::max(0, std::min(last, row[l] + ahead))]);
    }
}

/** Apply a pair rule (PairEvaluators.h) to the pairs of a run of cells, pair k with random[k]. */
template <class Rule, class Random, class Entry>
void sweepCells(const Rule& rule, const std::vector<Random>& random, std::vector<OpenMM::Vec3>& v, const SweepCells<Entry>& run) {
    if (run.independent) {
        forEachPairRow(run, [&](const int* row, const Entry* const* rowPairs, int n) {
            prefetchAhead(rowPairs, random, row, n, run.reverse);
            for (int l = 0; l < n; l++)
                rule(geometryOf(*rowPairs[l], run), random[row[l]], v);
        });
        return;
    }
    for (size_t k = run.begin; k < run.end; k++) {
        const int cell = run.cells[run.reverse ? run.begin + run.end - 1 - k : k];
        const int first = run.reverse ? run.start[cell + 1] - 1 : run.start[cell], last = run.reverse ? run.start[cell] - 1 : run.start[cell + 1];
        for (int p = first; p != last; p += (run.reverse ? -1 : 1)) {
            const Entry* pair = run.pairs[cell] + (p - run.start[cell]);
            prefetchAhead(&pair, random, &p, 1, run.reverse);
            rule(geometryOf(*pair, run), random[p], v);
        }
    }
}

} // namespace DPDPlugin

#endif
