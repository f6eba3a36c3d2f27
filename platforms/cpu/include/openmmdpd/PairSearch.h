#ifndef OPENMMDPD_PAIRSEARCH_H_
#define OPENMMDPD_PAIRSEARCH_H_

#include "openmmdpd/BoxGeometry.h"
#include "openmmdpd/ParallelExecutor.h"
#include "openmm/Vec3.h"
#include <algorithm>
#include <cmath>
#include <vector>

namespace DPDPlugin {

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
 * Asks the processor for `data`'s entry of the particle that a loop over slots in order
 * reaches a few dozen slots on.  Such loops read or write by particle index, and where the
 * particles' order is not the cells' (a million particles placed at random) that is all over
 * memory, at addresses the hardware cannot see coming.
 */
template <class T>
inline void prefetchSlotParticle(const T* data, const std::vector<int>& sortedIndex, size_t slot) {
    constexpr size_t AHEAD = 32;
    if (slot + AHEAD < sortedIndex.size()) {
        const char* entry = (const char*) (data + sortedIndex[slot + AHEAD]);
        __builtin_prefetch(entry);
        __builtin_prefetch(entry + sizeof(T) - 1);
    }
}

/**
 * Finds every pair of particles closer than a cutoff: a cell list over the box in its own
 * (fractional) coordinates, so rectangular and triclinic periodic boxes and non-periodic
 * systems are handled alike, in O(N).  Rebuilt at every evaluation, so pairs are found at
 * the positions where they are used (a Verlet list with a skin measured slower; README).
 *
 * Pairs are visited cell by cell in a fixed order, and ranges of cells can be visited
 * independently: visiting [0, n) in consecutive ranges and concatenating the results in
 * range order gives the same sequence whatever the number of ranges.  That is how the CPU
 * platform searches in parallel and still gets the Reference platform's pair order.
 */
class PairSearch {
public:
    /** The most pairs forEachSortedPairBlock() hands over in one block. */
    static constexpr int MAX_BLOCK = 256;
    /** Candidate slots [first, last), seen from r (the particle moved to their image). */
    struct ScanRun {
        int first, last;
        OpenMM::Vec3 r;
    };

    /**
     * @param active        particles that take part (e.g. those with non-zero mass)
     * @param cellMultiple  make the number of cells along each periodic axis a multiple of
     *                      this (3 lets sequential sweeps colour the cells; see getColour)
     */
    PairSearch(const std::vector<bool>& active, double cutoff, bool periodic, int cellMultiple = 1);
    /**
     * Bin the particles into cells, O(N): the per-particle passes, the counting sort's
     * included, over `executor`'s workers where one is given and N is large (the same
     * values and slots either way).
     */
    void build(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, ParallelExecutor* executor = nullptr);
    int getNumCells() const { return (int) cellStart.size() - 1; }
    /** The number of cells along axis k (cell = (z ny + y) nx + x). */
    int getNumCellsAlong(int k) const { return numCells[k]; }
    /**
     * The cells [begin, end) that worker w of `workers` visits: consecutive ranges holding
     * equal shares of the particles (cells hold unequal numbers, and the slowest worker
     * sets the pace).
     */
    void workerCells(int w, int workers, size_t& begin, size_t& end) const {
        auto boundary = [&](int k) {
            const int target = (int) ((long long) cellStart.back() * k / workers);
            return (size_t) (std::lower_bound(cellStart.begin(), cellStart.end() - 1, target) - cellStart.begin());
        };
        begin = (w == 0 ? 0 : boundary(w));
        end = (w == workers - 1 ? (size_t) getNumCells() : boundary(w + 1));
    }
    /**
     * Slots [first, first + count) taken cyclically among `slots`: a worker's reach (see
     * workerSlotReach).
     */
    struct SlotReach {
        size_t first, count, slots;
        bool contains(size_t k) const { return (k >= first ? k - first : k + slots - first) < count; }
        /** buffer[k] = 0 for the slots k of the reach. */
        template <class T>
        void zero(std::vector<T>& buffer) const {
            const size_t end = first + count;
            std::fill(buffer.begin() + first, buffer.begin() + std::min(end, slots), T());
            if (end > slots)
                std::fill(buffer.begin(), buffer.begin() + (end - slots), T());
        }
    };
    /**
     * The slots that the pairs found from worker w's cells (workerCells) can touch: those of
     * its cells, of the plane of cells before them and of the two after, cyclically (a
     * cell's neighbours lie less than two planes ahead of it, or, across the box's edge along
     * x or y, up to a plane behind; past the last plane they are in the first).  A worker's
     * buffer by slot need be zeroed and read only there: every worker's everywhere would be
     * work that does not shrink with more workers.
     */
    SlotReach workerSlotReach(int w, int workers) const {
        size_t begin, end;
        workerCells(w, workers, begin, end);
        const size_t total = getNumCells(), plane = (size_t) numCells[0] * numCells[1];
        const size_t cells = std::min(total, end - begin + 3 * plane);
        const size_t start = (cells == total ? 0 : (begin + total - plane) % total), last = start + cells;
        const size_t first = cellStart[start];
        const size_t count = (last <= total ? cellStart[last] - first : cellStart[total] - first + cellStart[last - total]);
        return SlotReach{first, count, (size_t) cellStart[total]};
    }
    /** workerSlotReach of every worker of `workers`. */
    std::vector<SlotReach> workerSlotReaches(int workers) const {
        std::vector<SlotReach> reaches;
        for (int w = 0; w < workers; w++)
            reaches.push_back(workerSlotReach(w, workers));
        return reaches;
    }
    bool isPeriodic() const { return periodic; }
    /**
     * Whether candidates are tested four at a time (AVX2; on by default where the processor
     * has it).  Both ways find the same pairs in the same order; this is for testing that.
     * Returns whether the vector version is now in use.
     */
    bool setVectorScan(bool enabled);
    /**
     * Whether the cells can be given 27 colours such that the pairs found from two cells of
     * one colour share no particle: the pairs of a cell touch only it and its neighbours,
     * so colour (x mod 3, y mod 3, z mod 3) works when every periodic axis has a multiple
     * of 3 cells.
     */
    bool isColourable() const { return colourable; }
    /** The colour, in [0, 27), of the cell at (x, y, z) along the axes, when isColourable(). */
    static int getColour(int x, int y, int z) { return x % 3 + 3 * (y % 3) + 9 * (z % 3); }
    /**
     * Call visit(i, j, d) for every pair closer than the cutoff whose lower cell is in
     * [begin, end); d = r_i - r_j for the nearest image.  Thread safe.
     */
    template <class Visitor>
    void forEachPair(int begin, int end, Visitor&& visit) const {
        forEachSortedPair(begin, end, [&](int p, int q, const OpenMM::Vec3& d) { visit(sortedIndex[p], sortedIndex[q], d); });
    }
    /**
     * The same pairs in the same order, named by their slots in the cell-sorted order
     * (particle getSortedIndex()[p]): per-slot arrays are read and written close together,
     * where per-particle arrays would be hit at random.
     */
    template <class Visitor>
    void forEachSortedPair(int begin, int end, Visitor&& visit) const;
    /**
     * The same pairs in the same order, in blocks sharing their first slot p:
     * visit(p, q, d, count) with the other slots q[k] and displacements d[k], for
     * k < count <= MAX_BLOCK (usually all of p's pairs in one block).
     */
    template <class BlockVisitor>
    void forEachSortedPairBlock(int begin, int end, BlockVisitor&& visit) const {
        forEachSortedPairBlock(begin, end, visit, [](int) {});
    }
    /** The same, calling startCell(cell) before each cell's blocks (empty cells too). */
    template <class BlockVisitor, class CellVisitor>
    void forEachSortedPairBlock(int begin, int end, BlockVisitor&& visit, CellVisitor&& startCell) const;
    /** The particle in each sorted slot (active particles only, cell by cell). */
    const std::vector<int>& getSortedIndex() const { return sortedIndex; }

private:
    /**
     * A run of cells [firstCell, lastCell] whose particles are contiguous in the sorted
     * arrays and share one image shift: up to three cells along x, so a particle's
     * candidates come in ~5 runs of ~12 rather than 14 cells of ~4.
     */
    struct Neighbour {
        int firstCell, lastCell;
        bool exactShift;     // shift gives the image (else each pair gets a minimum-image test)
        OpenMM::Vec3 shift;  // the other cells' images lie at their positions + shift
        int wrap[3];         // shift = sum_k wrap[k] box[k]: kept so a new box only moves the shifts
    };
    void neighbourCells(int cell, std::vector<Neighbour>& out) const;
    /** A particle's hits: their slots, the runs they came from (read by gatherInOneCall only), and their displacements. */
    struct HitBlock {
        int hits[MAX_BLOCK + 4], hitRun[MAX_BLOCK + 4];
        OpenMM::Vec3 d[MAX_BLOCK];
        ScanRun runs[27];
    };
    /**
     * All hits of slot p (in cell) in one gatherWithinCutoff call, the usual case; -1 if its
     * neighbour cells need minimum-image tests or hold more than a block of candidates.
     */
    int gatherInOneCall(int cell, int p, HitBlock& block) const;
    /** The other case: in chunks, visiting each full block; returns the hits left in block. */
    template <class BlockVisitor>
    int gatherInChunks(int cell, int p, HitBlock& block, BlockVisitor& visit) const;
    /** build()'s steps: frac and the fractional reach of the cutoff per axis; the cells; the sort. */
    void fractionalCoordinates(const std::vector<OpenMM::Vec3>& positions, double* reach, ParallelExecutor& executor);
    void chooseGrid(const double* reach);
    void sortIntoCells(ParallelExecutor& executor);
    /** The cell of fractional coordinates s. */
    int cellIndex(const OpenMM::Vec3& s) const;
    /** sortIntoCells' serial step: cellStart from the workers' counts per cell (workerFill). */
    void startCells();
    /** sortIntoCells' last step for worker w of `workers`: the particles of its cells into sortedIndex, in index order. */
    void placeInCells(int w, int workers);
    void storeSortedPositions(const std::vector<OpenMM::Vec3>& positions, ParallelExecutor& executor);
    /**
     * The neighbour cells of every cell, for the current grid: rebuilt when the grid changes;
     * when only the box does (a sliding Lees-Edwards box, every step) only the shifts move.
     */
    void updateNeighbourTable();
    std::vector<bool> active;
    double cutoff;
    bool periodic, colourable;
    int cellMultiple, numCells[3];
    OpenMM::Vec3 box[3];
    std::vector<int> cellStart, sortedIndex;
    std::vector<OpenMM::Vec3> frac;   // build()'s work space, kept to save allocations
    std::vector<int> cellOf;
    std::vector<std::vector<int>> workerFill;  // sortIntoCells' counts per cell, then the next slot of each cell placed, per worker
    std::vector<OpenMM::Vec3> sortedPositions;
    std::vector<double> sortedX, sortedY, sortedZ;  // the same, by coordinate (read four at a time)
    /**
     * Appends to hits, run by run, every slot q of the runs with |r - position q|^2 <
     * cutoff2 (computed as Vec3::dot does), and to hitRun the index of each hit's run, and
     * returns the number of hits.  Four slots at a time where the processor has AVX2,
     * with exactly the scalar arithmetic; it reads up to 3 slots past a run (the coordinate
     * arrays are padded) and may write 3 entries past its last hit.
     */
    int (*gatherWithinCutoff)(const double* x, const double* y, const double* z, const ScanRun* runs, int numRuns,
                              double cutoff2, int* hits, int* hitRun);
    std::vector<int> neighbourStart;
    std::vector<Neighbour> neighbourTable;
    int tableCells[3] = {0, 0, 0};
    OpenMM::Vec3 tableBox[3];
};

template <class BlockVisitor, class CellVisitor>
void PairSearch::forEachSortedPairBlock(int begin, int end, BlockVisitor&& visit, CellVisitor&& startCell) const {
    // About one candidate in seven is within the cutoff, so a branch per candidate would be
    // mispredicted often: the hits are gathered without branches (gatherWithinCutoff), and
    // a particle's hits from all its neighbour cells are visited together.  Callers should
    // cover many cells per call: each call zeroes a 6 kB HitBlock (a Vec3 zeroes itself).
    HitBlock block;
    for (int cell = begin; cell < end; cell++) {
        startCell(cell);
        for (int p = cellStart[cell]; p < cellStart[cell + 1]; p++) {
            int count = gatherInOneCall(cell, p, block);
            if (count < 0)
                count = gatherInChunks(cell, p, block, visit);
            if (count > 0)
                visit(p, (const int*) block.hits, (const OpenMM::Vec3*) block.d, count);
        }
    }
}

template <class BlockVisitor>
int PairSearch::gatherInChunks(int cell, int p, HitBlock& block, BlockVisitor& visit) const {
    // Crowded cells, and grids too small for one image per neighbour cell: in chunks, each
    // full block visited as it fills.
    constexpr int CHUNK = 64;
    const double cutoff2 = cutoff * cutoff;
    const OpenMM::Vec3 rp = sortedPositions[p];
    int count = 0;
    for (int k = neighbourStart[cell]; k < neighbourStart[cell + 1]; k++) {
        const Neighbour& other = neighbourTable[k];
        ScanRun run;
        run.r = rp - other.shift;
        const int first = (other.firstCell == cell ? p + 1 : cellStart[other.firstCell]);
        const int last = cellStart[other.lastCell + 1];
        for (int chunkStart = first; chunkStart < last; chunkStart += CHUNK) {
            if (count + CHUNK > MAX_BLOCK) {
                visit(p, (const int*) block.hits, (const OpenMM::Vec3*) block.d, count);
                count = 0;
            }
            const int chunkEnd = std::min(last, chunkStart + CHUNK), chunkHits = count;
            if (other.exactShift) {
                run.first = chunkStart;
                run.last = chunkEnd;
                count += gatherWithinCutoff(sortedX.data(), sortedY.data(), sortedZ.data(), &run, 1, cutoff2, block.hits + count,
                                            block.hitRun + count);
                for (int h = chunkHits; h < count; h++)
                    block.d[h] = run.r - sortedPositions[block.hits[h]];
                continue;
            }
            for (int q = chunkStart; q < chunkEnd; q++) {
                const OpenMM::Vec3 dq = minimumImage(rp - sortedPositions[q], box, periodic);
                block.hits[count] = q;
                count += (dq.dot(dq) < cutoff2);
            }
            for (int h = chunkHits; h < count; h++)
                block.d[h] = minimumImage(rp - sortedPositions[block.hits[h]], box, periodic);
        }
    }
    return count;
}

template <class Visitor>
void PairSearch::forEachSortedPair(int begin, int end, Visitor&& visit) const {
    forEachSortedPairBlock(begin, end, [&](int p, const int* q, const OpenMM::Vec3* d, int count) {
        for (int k = 0; k < count; k++)
            visit(p, q[k], d[k]);
    });
}

} // namespace DPDPlugin

#endif
