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
 * the group's next plane, and a group's planes can be shared out over the workers.  Within a
 * plane the same holds along y: a cell's pairs reach one row of cells either side, so rows
 * three apart share no particle, and y mod 3 is the colour's next digit: the 3 colours of one
 * y mod 3 can run strip by strip (a strip: some of the plane's rows of that y mod 3), all 3 in
 * a strip before the next strip.  A plane of more than stripCells cells runs in strips of as
 * many rows as keep a strip within stripCells (one at least), so that the velocities a
 * strip's colours touch stay in cache (README, "At scale").  With too few planes to share,
 * each colour's cells are shared out instead.
 */
class PairSweep {
public:
    /** The cells of a plane a strip spans at most (unless one row takes more), by default: its velocities and those it reaches fit a core's cache. */
    static constexpr int STRIP_CELLS = 1728;
    PairSweep(ParallelExecutor& executor, bool oneThread = false, int stripCells = STRIP_CELLS) :
            executor(executor), oneThread(oneThread), stripCells(stripCells) {}
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
    /** run() over the list's entries of one kind, each cell's where cellPairs says (null uniformRule: PairGeometry). */
    template <class Entry, class Rule, class Random>
    void runOver(const DPDThermostatForces& pairs, const std::vector<const Entry*>& cellPairs, const UniformPairRule* uniformRule,
                 std::vector<OpenMM::Vec3>& velocities, const Rule& rule, const std::vector<Random>& random, bool reverse) {
        runColours([&](const std::vector<int>& cells, size_t begin, size_t end) {
            sweepCells(rule, random, velocities,
                       SweepCells<Entry>{cells, pairs.getCellPairStart(), cellPairs, begin, end, reverse, independentCells, uniformRule});
        }, reverse);
    }
    /** visit(cells, begin, end) for runs of a colour's cells [begin, end) that cover all pairs, in the sweep order or its reverse (SweepCells). */
    template <class Visit>
    void runColours(const Visit& visit, bool reverse);
    /** The planes [begin, end) of a group, each by y mod 3, strip by strip, a strip's colours (x mod 3) in turn (or all in reverse). */
    template <class Visit>
    void runPlanes(int group, int begin, int end, const Visit& visit, bool reverse) const;
    /**
     * Worker w's items [begin, end) (a colour's cells, or a group's planes) given the pairs
     * before each item (`before`, one longer than the items): equal shares of the pairs.
     */
    void workerShare(const std::vector<int>& before, int w, size_t& begin, size_t& end) const;
    /** prepare()'s first part: each colour's cells with pairs, in cell order, and where each strip of each plane starts among them. */
    void placeCells(const PairSearch& search, const std::vector<int>& start);
    /** The planes of cells in group g (z mod 3 = g). */
    static int groupPlanes(const PairSearch& search, int g) { return (search.getNumCellsAlong(2) - g + 2) / 3; }
    ParallelExecutor& executor;
    const bool oneThread;
    const int stripCells;
    bool independentCells = false;
    static constexpr int GROUPS = 3, GROUP_COLOURS = 9;  // of the 27 colours, by z mod 3
    std::vector<std::vector<int>> colourCells;           // by colour, in cell order (so plane by plane, row by row)
    std::vector<std::vector<int>> colourPairsBefore;     // pairs in the colour's cells before each
    int strips = 1;                                      // strips per plane
    std::vector<std::vector<int>> colourStripStart;      // where strip s of plane k of the colour's group starts in colourCells: k * strips + s
    std::vector<std::vector<int>> groupPairsBefore;      // pairs in the group's planes before each (3 groups)
};

inline void PairSweep::prepare(const DPDThermostatForces& pairs) {
    const PairSearch& search = pairs.getSearch();
    independentCells = !oneThread && search.isColourable();
    const int colours = search.isColourable() ? 27 : 1;
    const std::vector<int>& start = pairs.getCellPairStart();
    placeCells(search, start);
    colourPairsBefore.resize(colours);
    for (int c = 0; c < colours; c++) {
        std::vector<int>& before = colourPairsBefore[c];
        before.assign(1, 0);
        for (int cell : colourCells[c])
            before.push_back(before.back() + start[cell + 1] - start[cell]);
    }
    groupPairsBefore.assign(colours == 27 ? GROUPS : 0, std::vector<int>());
    for (int g = 0; g < (int) groupPairsBefore.size(); g++) {
        groupPairsBefore[g].assign(groupPlanes(search, g) + 1, 0);
        for (int k = 0; k <= groupPlanes(search, g); k++)
            for (int c = g * GROUP_COLOURS; c < (g + 1) * GROUP_COLOURS; c++)
                groupPairsBefore[g][k] += colourPairsBefore[c][colourStripStart[c][k * strips]];
    }
}

inline void PairSweep::placeCells(const PairSearch& search, const std::vector<int>& start) {
    // Plane k of group g (z mod 3) is z = g + 3k; row y of a plane is row m = y / 3 of the
    // rows of its y mod 3, and strip s holds the rows m * strips / rows = s (strips as equal
    // as can be).  A cell's colour and strip come from where it lies along the axes (found
    // by dividing its number, they took most of prepare's time).
    const bool coloured = search.isColourable();
    const int nx = search.getNumCellsAlong(0), ny = search.getNumCellsAlong(1), nz = search.getNumCellsAlong(2);
    const auto rows = [&](int y) { return (ny - y % 3 + 2) / 3; };  // of the y mod 3 of row y
    const int stripRows = (coloured ? std::max(1, stripCells / (3 * nx)) : 1);
    strips = (coloured ? (rows(0) + stripRows - 1) / stripRows : 1);
    colourCells.assign(coloured ? 27 : 1, std::vector<int>());
    colourStripStart.assign(coloured ? 27 : 0, std::vector<int>());
    for (int c = 0; c < (int) colourStripStart.size(); c++)
        colourStripStart[c].assign(groupPlanes(search, c / GROUP_COLOURS) * strips + 1, 0);
    for (int z = 0, cell = 0; z < nz; z++)
        for (int y = 0; y < ny; y++) {
            const int strip = z / 3 * strips + y / 3 * strips / rows(y);
            for (int x = 0; x < nx; x++, cell++) {
                if (start[cell + 1] == start[cell])
                    continue;
                const int c = (coloured ? PairSearch::getColour(x, y, z) : 0);
                colourCells[c].push_back(cell);
                if (coloured)
                    colourStripStart[c][strip + 1]++;  // made where the strips start below
            }
        }
    for (std::vector<int>& stripStart : colourStripStart)
        for (size_t k = 1; k < stripStart.size(); k++)
            stripStart[k] += stripStart[k - 1];
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
    if (pairs.arePairsUniform())
        runOver(pairs, pairs.getCellUniformPairs(), &pairs.getUniformRule(), velocities, rule, random, reverse);
    else
        runOver(pairs, pairs.getCellPairs(), nullptr, velocities, rule, random, reverse);
}

template <class Visit>
void PairSweep::runPlanes(int group, int begin, int end, const Visit& visit, bool reverse) const {
    const auto inOrder = [&](int i, int n) { return reverse ? n - 1 - i : i; };
    for (int p = begin; p < end; p++) {
        const int k = inOrder(p - begin, end - begin) + begin;
        for (int b = 0; b < 3; b++)  // y mod 3
            for (int s = 0; s < strips; s++)
                for (int x = 0; x < 3; x++) {  // x mod 3
                    const int colour = group * GROUP_COLOURS + 3 * inOrder(b, 3) + inOrder(x, 3), strip = k * strips + inOrder(s, strips);
                    const std::vector<int>& stripStart = colourStripStart[colour];
                    visit(colourCells[colour], stripStart[strip], stripStart[strip + 1]);
                }
    }
}

template <class Visit>
void PairSweep::runColours(const Visit& visit, bool reverse) {
    const int colours = (int) colourCells.size();
    if (!independentCells) {
        // Colour by colour, exactly: without colours, or where an impulse reaches beyond its
        // pair (constraints) and planes do not bound which particles a cell touches.
        for (int c = 0; c < colours; c++) {
            const std::vector<int>& cells = colourCells[reverse ? colours - 1 - c : c];
            visit(cells, 0, cells.size());
        }
        return;
    }
    const int workers = executor.getNumWorkers(), fewestPlanes = (int) groupPairsBefore.back().size() - 1;
    if (workers == 1 || fewestPlanes >= 2 * workers) {
        // Plane by plane, each group's planes shared out: one wait per group.
        executor.executePhases(GROUPS, [&](int w, int g) {
            const int group = reverse ? GROUPS - 1 - g : g;
            size_t begin, end;
            workerShare(groupPairsBefore[group], w, begin, end);
            runPlanes(group, (int) begin, (int) end, visit, reverse);
        });
        return;
    }
    // Too few planes to share: colour by colour, each colour's cells shared out.
    executor.executePhases(colours, [&](int w, int c) {
        const int colour = reverse ? colours - 1 - c : c;
        size_t begin, end;
        workerShare(colourPairsBefore[colour], w, begin, end);
        visit(colourCells[colour], begin, end);
    });
}

} // namespace DPDPlugin

#endif
