#ifndef OPENMMDPD_PAIRSWEEP_H_
#define OPENMMDPD_PAIRSWEEP_H_

#include "openmmdpd/DPDThermostatForces.h"
#include "openmmdpd/ParallelExecutor.h"
#include "openmmdpd/VectorRowSweep.h"
#include <algorithm>
#include <vector>

namespace DPDPlugin {

/**
 * Applies a pair rule (PairEvaluators.h) to every pair of a DPDThermostatForces list, with
 * the pair's random input drawn ahead, sequentially: each pair sees the velocities the
 * pairs before it changed.  The order is fixed by the geometry alone:
 * colour by colour (27 colours of cells, see PairSearch::isColourable), cell by cell,
 * pair by pair.  Without a colouring (a box fewer than 3 cells wide), or where a pair's
 * impulse reaches beyond the pair (oneThread: constraint forces), it runs in that order in
 * one thread.
 *
 * Otherwise it runs in an order of the same result bit for bit, for any number of workers:
 * only the order of pairs that share a particle decides the result, and cells of one colour
 * share none.  Each colour touches cells all over the box, so colour by colour would bring
 * every velocity in from memory 27 times a sweep; the sweep goes plane by plane instead.  A
 * cell's pairs reach the next plane of cells along z and no further, so cells in planes more
 * than one apart share no particle, and the colour's z mod 3 is its most significant digit:
 * the 9 colours of a group (one z mod 3) can run plane by plane, all 9 in a plane before
 * the group's next plane, and a group's planes can be shared out over the workers.  Two
 * planes' velocities stay in cache through a plane's 9 colours.  With too few planes to
 * share, each colour's cells are shared out instead.
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
    /** visit(run) for runs of cells that cover all pairs, in the sweep order or its reverse (SweepCells). */
    template <class Visit>
    void runColours(const DPDThermostatForces& pairs, const Visit& visit, bool reverse);
    /** The planes [begin, end) of a group, each with its colours in turn (or in reverse). */
    template <class Visit>
    void runPlanes(const DPDThermostatForces& pairs, int group, int begin, int end, const Visit& visit, bool reverse) const;
    /** visit(run) for a colour's cells [begin, end). */
    template <class Visit>
    void runCells(const DPDThermostatForces& pairs, const std::vector<int>& cells, size_t begin, size_t end, const Visit& visit,
                  bool reverse) const {
        visit(SweepCells{cells, pairs.getCellPairStart(), pairs.getCellPairs(), begin, end, reverse, independentCells});
    }
    /**
     * Worker w's items [begin, end) (a colour's cells, or a group's planes) given the pairs
     * before each item (`before`, one longer than the items): equal shares of the pairs.
     */
    void workerShare(const std::vector<int>& before, int w, size_t& begin, size_t& end) const;
    /** prepare()'s second half: where each plane starts in each colour's cells, and the pairs before it. */
    void preparePlanes(const PairSearch& search);
    ParallelExecutor& executor;
    const bool oneThread;
    bool independentCells = false;
    static constexpr int GROUPS = 3, GROUP_COLOURS = 9;  // of the 27 colours, by z mod 3
    std::vector<std::vector<int>> colourCells;           // by colour, in cell order (so plane by plane)
    std::vector<std::vector<int>> colourPairsBefore;     // pairs in the colour's cells before each
    std::vector<std::vector<int>> colourPlaneStart;      // where each plane of the colour's group starts in colourCells (27 colours)
    std::vector<std::vector<int>> groupPairsBefore;      // pairs in the group's planes before each (3 groups)
};

inline void PairSweep::prepare(const DPDThermostatForces& pairs) {
    const PairSearch& search = pairs.getSearch();
    independentCells = !oneThread && search.isColourable();
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
    preparePlanes(search);
}

inline void PairSweep::preparePlanes(const PairSearch& search) {
    // Plane k of group g (z mod 3) is z = g + 3k.
    const int colours = (int) colourCells.size();
    colourPlaneStart.assign(colours == 27 ? colours : 0, std::vector<int>());
    const int planeCells = search.getNumCellsAlong(0) * search.getNumCellsAlong(1), planes = search.getNumCellsAlong(2);
    for (int c = 0; c < (int) colourPlaneStart.size(); c++) {
        const std::vector<int>& cells = colourCells[c];
        const int groupPlanes = (planes - c / GROUP_COLOURS + 2) / 3;
        std::vector<int>& planeStart = colourPlaneStart[c];
        planeStart.assign(groupPlanes + 1, (int) cells.size());
        for (int k = 0, index = 0; k < groupPlanes; k++) {
            while (index < (int) cells.size() && cells[index] / planeCells / 3 < k)
                index++;
            planeStart[k] = index;
        }
    }
    groupPairsBefore.assign(colourPlaneStart.empty() ? 0 : GROUPS, std::vector<int>());
    for (int g = 0; g < (int) groupPairsBefore.size(); g++) {
        const int groupPlanes = (int) colourPlaneStart[g * GROUP_COLOURS].size() - 1;
        groupPairsBefore[g].assign(groupPlanes + 1, 0);
        for (int k = 0; k <= groupPlanes; k++)
            for (int c = g * GROUP_COLOURS; c < (g + 1) * GROUP_COLOURS; c++)
                groupPairsBefore[g][k] += colourPairsBefore[c][colourPlaneStart[c][k]];
    }
}

inline void PairSweep::workerShare(const std::vector<int>& before, int w, size_t& begin, size_t& end) const {
    // Split by pairs, not items: cells and planes hold unequal numbers of pairs, and each
    // phase ends with all workers waiting for the slowest.
    const long long total = before.back(), workers = executor.getNumWorkers();
    auto boundary = [&](long long k) {
        return (size_t) (std::lower_bound(before.begin(), before.end(), (int) (total * k / workers)) - before.begin());
    };
    begin = (w == 0 ? 0 : boundary(w));
    end = (w == workers - 1 ? before.size() - 1 : boundary(w + 1));
}

template <class Rule, class Random>
void PairSweep::run(const DPDThermostatForces& pairs, std::vector<OpenMM::Vec3>& velocities, const Rule& rule,
                    const std::vector<Random>& random, bool reverse) {
    runColours(pairs, [&](const SweepCells& cells) { sweepCells(rule, random, velocities, cells); }, reverse);
}

template <class Visit>
void PairSweep::runPlanes(const DPDThermostatForces& pairs, int group, int begin, int end, const Visit& visit, bool reverse) const {
    for (int p = begin; p < end; p++) {
        const int k = reverse ? begin + end - 1 - p : p;
        for (int q = 0; q < GROUP_COLOURS; q++) {
            const int colour = group * GROUP_COLOURS + (reverse ? GROUP_COLOURS - 1 - q : q);
            const std::vector<int>& planeStart = colourPlaneStart[colour];
            runCells(pairs, colourCells[colour], planeStart[k], planeStart[k + 1], visit, reverse);
        }
    }
}

template <class Visit>
void PairSweep::runColours(const DPDThermostatForces& pairs, const Visit& visit, bool reverse) {
    const int colours = (int) colourCells.size();
    if (!independentCells) {
        // Colour by colour, exactly: without colours, or where an impulse reaches beyond its
        // pair (constraints) and planes do not bound which particles a cell touches.
        for (int c = 0; c < colours; c++) {
            const std::vector<int>& cells = colourCells[reverse ? colours - 1 - c : c];
            runCells(pairs, cells, 0, cells.size(), visit, reverse);
        }
        return;
    }
    const int workers = executor.getNumWorkers(), fewestPlanes = (int) colourPlaneStart.back().size() - 1;
    if (workers == 1 || fewestPlanes >= 2 * workers) {
        // Plane by plane, each group's planes shared out: one wait per group.
        executor.executePhases(GROUPS, [&](int w, int g) {
            const int group = reverse ? GROUPS - 1 - g : g;
            size_t begin, end;
            workerShare(groupPairsBefore[group], w, begin, end);
            runPlanes(pairs, group, (int) begin, (int) end, visit, reverse);
        });
        return;
    }
    // Too few planes to share: colour by colour, each colour's cells shared out.
    executor.executePhases(colours, [&](int w, int c) {
        const int colour = reverse ? colours - 1 - c : c;
        size_t begin, end;
        workerShare(colourPairsBefore[colour], w, begin, end);
        runCells(pairs, colourCells[colour], begin, end, visit, reverse);
    });
}

} // namespace DPDPlugin

#endif
