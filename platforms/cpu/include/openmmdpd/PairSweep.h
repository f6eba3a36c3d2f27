#ifndef OPENMMDPD_PAIRSWEEP_H_
#define OPENMMDPD_PAIRSWEEP_H_

#include "openmmdpd/DPDThermostatForces.h"
#include "openmmdpd/ParallelExecutor.h"
#include <algorithm>
#include <vector>

namespace DPDPlugin {

/**
 * Applies a pair rule (PairEvaluators.h) to every pair of a DPDThermostatForces list, with
 * the pair's random input drawn ahead, sequentially: each pair sees the velocities the
 * pairs before it changed.  The order is fixed by the geometry alone:
 * colour by colour (27 colours of cells, see PairSearch::isColourable), cell by cell,
 * pair by pair.  Cells of one colour share no particle, so a colour's cells are split
 * over the workers, and the result is bit for bit the same for any number of workers.
 * Without a colouring (a box fewer than 3 cells wide), or where a pair's impulse reaches
 * beyond the pair (oneThread: constraint forces), the sweep runs in one thread, in the same
 * order.
 */
class PairSweep {
public:
    PairSweep(ParallelExecutor& executor, bool oneThread = false) : executor(executor), oneThread(oneThread) {}
    /** Group the current pair list's cells by colour (call after every pair update). */
    void prepare(const DPDThermostatForces& pairs);
    /**
     * Run the rule over all pairs, pair k with random[k] (drawNormals or drawBits order);
     * `reverse` runs exactly the opposite order.
     */
    template <class Rule, class Random>
    void run(const DPDThermostatForces& pairs, std::vector<OpenMM::Vec3>& velocities, const Rule& rule,
             const std::vector<Random>& random, bool reverse);

private:
    /** visit(k) for every pair k, in the sweep order or its reverse. */
    template <class Visit>
    void runColours(const DPDThermostatForces& pairs, const Visit& visit, bool reverse);
    template <class Visit>
    void runCells(const DPDThermostatForces& pairs, const std::vector<int>& cells, size_t begin, size_t end, const Visit& visit,
                  bool reverse) const;
    /** The cells [begin, end) of a colour that worker w sweeps: equal shares of its pairs. */
    void workerCells(int colour, int w, size_t& begin, size_t& end) const;
    ParallelExecutor& executor;
    const bool oneThread;
    bool parallel = false, independentCells = false;
    std::vector<std::vector<int>> colourCells;
    std::vector<std::vector<int>> colourPairsBefore;  // pairs in the colour's cells before each
};

inline void PairSweep::prepare(const DPDThermostatForces& pairs) {
    const PairSearch& search = pairs.getSearch();
    independentCells = !oneThread && search.isColourable();
    parallel = independentCells && executor.getNumWorkers() > 1;
    const int colours = search.isColourable() ? 27 : 1;
    colourCells.assign(colours, std::vector<int>());
    const std::vector<int>& start = pairs.getCellPairStart();
    for (int cell = 0; cell < search.getNumCells(); cell++)
        if (start[cell + 1] > start[cell])
            colourCells[colours == 27 ? search.getColour(cell) : 0].push_back(cell);
    colourPairsBefore.resize(colours);
    for (int c = 0; c < colours; c++) {
        std::vector<int>& before = colourPairsBefore[c];
        before.assign(1, 0);
        for (int cell : colourCells[c])
            before.push_back(before.back() + start[cell + 1] - start[cell]);
    }
}

inline void PairSweep::workerCells(int colour, int w, size_t& begin, size_t& end) const {
    // Split by pairs, not cells: a colour's cells hold unequal numbers of pairs, and each of
    // the 27 colours ends with all workers waiting for the slowest.
    const std::vector<int>& before = colourPairsBefore[colour];
    const long long total = before.back(), workers = executor.getNumWorkers();
    auto boundary = [&](long long k) {
        return (size_t) (std::lower_bound(before.begin(), before.end(), (int) (total * k / workers)) - before.begin());
    };
    begin = (w == 0 ? 0 : boundary(w));
    end = (w == workers - 1 ? colourCells[colour].size() : boundary(w + 1));
}

template <class Visit>
void PairSweep::runCells(const DPDThermostatForces& pairs, const std::vector<int>& cells, size_t begin, size_t end, const Visit& visit,
                         bool reverse) const {
    const std::vector<int>& start = pairs.getCellPairStart();
    if (independentCells) {
        // Cells of one colour share no particle, so interleaving their pairs changes no
        // result; LANES cells at a time, pair by pair, give the processor that many
        // independent chains of velocity updates to overlap (one cell's pairs each depend
        // on the one before, through the velocities they share).
        constexpr size_t LANES = 4;
        const int direction = reverse ? -1 : 1;
        for (size_t k = begin; k < end; k += LANES) {
            int next[LANES], last[LANES];
            const size_t lanes = std::min(LANES, end - k);
            for (size_t l = 0; l < lanes; l++) {
                const int cell = cells[reverse ? begin + end - 1 - (k + l) : k + l];
                next[l] = reverse ? start[cell + 1] - 1 : start[cell];
                last[l] = reverse ? start[cell] - 1 : start[cell + 1];
            }
            for (bool any = true; any;) {
                any = false;
                for (size_t l = 0; l < lanes; l++)
                    if (next[l] != last[l]) {
                        visit(next[l]);
                        next[l] += direction;
                        any = true;
                    }
            }
        }
        return;
    }
    for (size_t k = begin; k < end; k++) {
        const int cell = cells[reverse ? begin + end - 1 - k : k];
        if (reverse)
            for (int p = start[cell + 1] - 1; p >= start[cell]; p--)
                visit(p);
        else
            for (int p = start[cell]; p < start[cell + 1]; p++)
                visit(p);
    }
}

template <class Rule, class Random>
void PairSweep::run(const DPDThermostatForces& pairs, std::vector<OpenMM::Vec3>& velocities, const Rule& rule,
                    const std::vector<Random>& random, bool reverse) {
    const std::vector<PairGeometry>& list = pairs.getPairs();
    runColours(pairs, [&](int k) { rule(list[k], random[k], velocities); }, reverse);
}

template <class Visit>
void PairSweep::runColours(const DPDThermostatForces& pairs, const Visit& visit, bool reverse) {
    const int colours = (int) colourCells.size();
    if (!parallel) {
        for (int c = 0; c < colours; c++) {
            const std::vector<int>& cells = colourCells[reverse ? colours - 1 - c : c];
            runCells(pairs, cells, 0, cells.size(), visit, reverse);
        }
        return;
    }
    executor.executePhases(colours, [&](int w, int c) {
        const int colour = reverse ? colours - 1 - c : c;
        size_t begin, end;
        workerCells(colour, w, begin, end);
        runCells(pairs, colourCells[colour], begin, end, visit, reverse);
    });
}

} // namespace DPDPlugin

#endif
