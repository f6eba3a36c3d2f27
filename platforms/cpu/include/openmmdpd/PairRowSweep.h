#ifndef OPENMMDPD_PAIRROWSWEEP_H_
#define OPENMMDPD_PAIRROWSWEEP_H_

#include "openmmdpd/PairParameters.h"
#include <algorithm>
#include <vector>

namespace DPDPlugin {

/**
 * A run of cells a sweep visits in turn (PairSweep): cells[begin, end) in that order or its
 * reverse, cell c's pairs the list's [start[c], start[c + 1]).  `independent`: the cells
 * share no particle (one colour), so their pairs may be interleaved.
 */
struct SweepCells {
    const std::vector<int>& cells;
    const std::vector<int>& start;
    size_t begin, end;
    bool reverse, independent;
};

/** The cells a sweep interleaves (forEachPairRow): the width of a row of pairs. */
constexpr int SWEEP_LANES = 4;

/**
 * visitRow(row, n) for the pairs of a run of independent cells, SWEEP_LANES cells at a time,
 * pair by pair: row[l] is the next pair of the l-th of n cells in progress (the lanes past n
 * repeat row[0]), and a cell that ends is followed in its lane by the run's next one.  Each
 * cell's pairs keep their order (or its reverse), which is all that decides the result; the
 * lanes are independent chains of velocity updates for the processor to overlap.
 */
template <class VisitRow>
__attribute__((always_inline)) inline void forEachPairRow(const SweepCells& run, VisitRow&& visitRow) {
    constexpr int LANES = SWEEP_LANES;
    const int direction = run.reverse ? -1 : 1;
    int next[LANES], last[LANES], active = 0;
    size_t taken = run.begin;
    auto takeCell = [&](int l) {
        while (taken < run.end) {
            const int cell = run.cells[run.reverse ? run.begin + run.end - 1 - taken : taken];
            taken++;
            if (run.start[cell + 1] > run.start[cell]) {  // (PairSweep lists no empty cell; a lane must not start on one)
                next[l] = run.reverse ? run.start[cell + 1] - 1 : run.start[cell];
                last[l] = run.reverse ? run.start[cell] - 1 : run.start[cell + 1];
                return true;
            }
        }
        return false;
    };
    while (active < LANES && takeCell(active))
        active++;
    while (active > 0) {
        int row[LANES];
        for (int l = 0; l < LANES; l++)
            row[l] = next[l < active ? l : 0];
        visitRow(row, active);
        for (int l = 0; l < active; l++) {
            next[l] += direction;
            if (next[l] == last[l] && !takeCell(l)) {
                // the last lane moves into this one and takes its turn here
                active--;
                next[l] = next[active];
                last[l] = last[active];
                l--;
            }
        }
    }
}

/**
 * A cell's pairs are a run of the list, but the sweep hops between cells (and lanes) too
 * often for the hardware to see the runs: each pair asks for the one 8 further on.
 */
template <class Random>
__attribute__((always_inline)) inline void prefetchAhead(const std::vector<PairGeometry>& list, const std::vector<Random>& random,
                                                         const int* row, int n, bool reverse) {
    const int ahead = reverse ? -8 : 8, last = (int) list.size() - 1;
    for (int l = 0; l < n; l++) {
        const int k = std::max(0, std::min(last, row[l] + ahead));
        __builtin_prefetch(&list[k]);
        __builtin_prefetch((const char*) &list[k] + sizeof(PairGeometry) - 1);  // 72 bytes: it spans two lines
        __builtin_prefetch(&random[k]);
    }
}

/** Apply a pair rule (PairEvaluators.h) to the pairs of a run of cells, pair k with random[k]. */
template <class Rule, class Random>
void sweepCells(const Rule& rule, const std::vector<PairGeometry>& list, const std::vector<Random>& random,
                std::vector<OpenMM::Vec3>& v, const SweepCells& run) {
    if (run.independent) {
        forEachPairRow(run, [&](const int* row, int n) {
            prefetchAhead(list, random, row, n, run.reverse);
            for (int l = 0; l < n; l++)
                rule(list[row[l]], random[row[l]], v);
        });
        return;
    }
    for (size_t k = run.begin; k < run.end; k++) {
        const int cell = run.cells[run.reverse ? run.begin + run.end - 1 - k : k];
        const int first = run.reverse ? run.start[cell + 1] - 1 : run.start[cell], last = run.reverse ? run.start[cell] - 1 : run.start[cell + 1];
        for (int p = first; p != last; p += (run.reverse ? -1 : 1)) {
            prefetchAhead(list, random, &p, 1, run.reverse);
            rule(list[p], random[p], v);
        }
    }
}

} // namespace DPDPlugin

#endif
