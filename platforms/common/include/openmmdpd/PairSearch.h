#ifndef OPENMMDPD_PAIRSEARCH_H_
#define OPENMMDPD_PAIRSEARCH_H_

#include "openmm/Vec3.h"
#include <cmath>
#include <vector>

namespace DPDPlugin {

/**
 * Nearest integer, for |x| far below 2^63.  std::round is a library call on baseline
 * x86-64 and dominated the pair search; a truncating conversion is one instruction.
 */
inline double roundToInteger(double x) {
    return (double) (long long) (x + (x >= 0 ? 0.5 : -0.5));
}

/** The displacement r_i - r_j, reduced to the nearest periodic image (OpenMM's reduced box form). */
inline OpenMM::Vec3 minimumImage(OpenMM::Vec3 d, const OpenMM::Vec3* box, bool periodic) {
    if (periodic) {
        d -= box[2] * roundToInteger(d[2] / box[2][2]);
        d -= box[1] * roundToInteger(d[1] / box[1][1]);
        d -= box[0] * roundToInteger(d[0] / box[0][0]);
    }
    return d;
}

/**
 * Finds every pair of particles closer than a search radius: a cell list over the box in
 * its own (fractional) coordinates, so rectangular and triclinic periodic boxes and
 * non-periodic systems are handled alike, in O(N).
 *
 * With a skin > 0 this is a Verlet list: pairs within cutoff + skin are kept and the list
 * is rebuilt only once some particle has moved more than skin/2 since the last build (or
 * the box changed).  Callers must still test each pair's distance at the positions they
 * evaluate it at.
 *
 * The pair order is fixed by the geometry (cell by cell), and the cells can be searched
 * in independent ranges (findPairsInCells) whose outputs, concatenated in range order,
 * give the same list whatever the number of ranges: this is how the CPU platform builds
 * it in parallel and still gets the Reference platform's list.
 */
class PairSearch {
public:
    struct Pair {
        int i, j;
    };
    /**
     * @param active  particles that take part (e.g. those with non-zero mass)
     */
    PairSearch(const std::vector<bool>& active, double cutoff, double skin, bool periodic);
    /**
     * Prepare a search at these positions.  Returns false if the current list is still
     * valid (nothing to do); otherwise the cells are rebuilt and the caller must refill the
     * pair list with findPairsInCells over [0, getNumCells()) followed by setPairs().
     */
    bool needsRebuild(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box);
    /** Bin the particles into cells (serial, O(N)); call after needsRebuild() returned true. */
    void buildCells(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box);
    int getNumCells() const { return (int) cellStart.size() - 1; }
    /** Append the pairs whose lower cell is in [begin, end) to out (thread safe). */
    void findPairsInCells(int begin, int end, std::vector<Pair>& out) const;
    /** Serial convenience: needsRebuild + buildCells + findPairsInCells over all cells. */
    void update(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box);
    std::vector<Pair>& getPairs() { return pairs; }
    const std::vector<Pair>& getPairs() const { return pairs; }
    double getSearchRadius() const { return cutoff + skin; }
    bool isPeriodic() const { return periodic; }
    int getNumBuilds() const { return numBuilds; }
    /** Whether a list was built, and at which positions and box (for checkpoints). */
    bool hasList() const { return numBuilds > 0; }
    const std::vector<OpenMM::Vec3>& getBuildPositions() const { return positionsAtBuild; }
    const OpenMM::Vec3* getBuildBox() const { return box; }

private:
    struct Neighbour {
        int cell;
        bool exactShift;     // shift is the image (else test every pair by minimum image)
        OpenMM::Vec3 shift;  // added to this cell's positions to meet the other cell's
    };
    void neighbourCells(int cell, std::vector<Neighbour>& out) const;
    std::vector<bool> active;
    double cutoff, skin;
    bool periodic;
    int numBuilds;
    int numCells[3];
    OpenMM::Vec3 box[3], origin, cellScale;
    std::vector<int> cellStart, sortedIndex;
    std::vector<OpenMM::Vec3> sortedPositions, positionsAtBuild;
    std::vector<Pair> pairs;
};

} // namespace DPDPlugin

#endif
