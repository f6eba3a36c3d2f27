#include "openmmdpd/PairSearch.h"
#include "openmmdpd/BoxGeometry.h"
#include "openmmdpd/CpuFeatures.h"
#include <algorithm>
#include <cmath>

#ifdef OPENMMDPD_X86_VECTORS
#include <immintrin.h>
#define OPENMMDPD_GATHER_AVX2
#endif

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

/** std::floor, which is a library call on baseline x86-64 and was a tenth of a force evaluation. */
inline double floorOf(double x) {
    if (!(std::fabs(x) < 4503599627370496.0))  // 2^52: already an integer (or not finite)
        return std::floor(x);
    const double t = (double) (long long) x;
    return t > x ? t - 1 : t;
}

// The separate multiplies and adds of Vec3::dot, in its order (no fused multiply-add), so
// every version finds the same pairs.
int gatherScalar(const double* x, const double* y, const double* z, const PairSearch::ScanRun* runs, int numRuns,
                 double cutoff2, int* hits, int* hitRun) {
    int count = 0;
    for (int k = 0; k < numRuns; k++) {
        const Vec3 r = runs[k].r;
        for (int q = runs[k].first; q < runs[k].last; q++) {
            const double dx = r[0] - x[q], dy = r[1] - y[q], dz = r[2] - z[q];
            hits[count] = q;
            hitRun[count] = k;
            count += (dx * dx + dy * dy + dz * dz < cutoff2);
        }
    }
    return count;
}

#ifdef OPENMMDPD_GATHER_AVX2
// AVX2 without FMA: the compiler cannot contract the products into fused operations.
__attribute__((target("avx2"))) int gatherAVX2(const double* x, const double* y, const double* z,
                                               const PairSearch::ScanRun* runs, int numRuns, double cutoff2, int* hits,
                                               int* hitRun) {
    // For each 4-bit mask of slots within the cutoff: the offsets of its set bits, in order.
    alignas(16) static const int offsets[16][4] = {
        {0, 0, 0, 0}, {0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {2, 0, 0, 0}, {0, 2, 0, 0}, {1, 2, 0, 0}, {0, 1, 2, 0},
        {3, 0, 0, 0}, {0, 3, 0, 0}, {1, 3, 0, 0}, {0, 1, 3, 0}, {2, 3, 0, 0}, {0, 2, 3, 0}, {1, 2, 3, 0}, {0, 1, 2, 3}};
    const __m256d limit = _mm256_set1_pd(cutoff2);
    const __m128i lane = _mm_set_epi32(3, 2, 1, 0);
    int count = 0;
    for (int k = 0; k < numRuns; k++) {
        const __m256d rx = _mm256_set1_pd(runs[k].r[0]), ry = _mm256_set1_pd(runs[k].r[1]), rz = _mm256_set1_pd(runs[k].r[2]);
        const int last = runs[k].last;
        const __m128i run = _mm_set1_epi32(k);
        for (int q = runs[k].first; q < last; q += 4) {
            const __m256d dx = _mm256_sub_pd(rx, _mm256_loadu_pd(x + q));
            const __m256d dy = _mm256_sub_pd(ry, _mm256_loadu_pd(y + q));
            const __m256d dz = _mm256_sub_pd(rz, _mm256_loadu_pd(z + q));
            const __m256d r2 = _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(dx, dx), _mm256_mul_pd(dy, dy)), _mm256_mul_pd(dz, dz));
            // Lanes past the run's end read padding or the next cell: masked off.
            const int inRun = _mm_movemask_ps(_mm_castsi128_ps(_mm_cmplt_epi32(lane, _mm_set1_epi32(last - q))));
            const int mask = _mm256_movemask_pd(_mm256_cmp_pd(r2, limit, _CMP_LT_OQ)) & inRun;
            const __m128i slots = _mm_add_epi32(_mm_set1_epi32(q), _mm_load_si128((const __m128i*) offsets[mask]));
            _mm_storeu_si128((__m128i*) (hits + count), slots);
            _mm_storeu_si128((__m128i*) (hitRun + count), run);
            count += __builtin_popcount(mask);
        }
    }
    return count;
}
#endif

} // namespace

PairSearch::PairSearch(const std::vector<bool>& active, double cutoff, bool periodic, int cellMultiple) :
        active(active), cutoff(cutoff), periodic(periodic), colourable(false), cellMultiple(cellMultiple),
        gatherWithinCutoff(gatherScalar) {
    numCells[0] = numCells[1] = numCells[2] = 0;
    setVectorScan(true);
}

bool PairSearch::setVectorScan(bool enabled) {
    gatherWithinCutoff = gatherScalar;
#ifdef OPENMMDPD_GATHER_AVX2
    if (enabled && haveAVX2())
        gatherWithinCutoff = gatherAVX2;
#endif
    return gatherWithinCutoff != gatherScalar;
}

void PairSearch::build(const std::vector<Vec3>& positions, const Vec3* newBox, ParallelExecutor* executor) {
    for (int k = 0; k < 3; k++)
        box[k] = newBox[k];
    SerialExecutor serial;
    ParallelExecutor& workers = (executor != nullptr ? *executor : serial);
    double reach[3];
    fractionalCoordinates(positions, reach, workers);
    chooseGrid(reach);
    sortIntoCells(workers);
    storeSortedPositions(positions, workers);
    updateNeighbourTable();
}

void PairSearch::fractionalCoordinates(const std::vector<Vec3>& positions, double* reach, ParallelExecutor& executor) {
    // Fractional coordinate s_d of a particle, and the fractional distance R_d that a
    // displacement as long as the cutoff can span along d.  A cell at least R_d wide means
    // that pairs within the cutoff sit in the same or adjacent cells.
    const int n = (int) positions.size();
    frac.resize(n);
    if (periodic) {
        Vec3 rows[3];
        inverseBoxRows(box, rows);
        for (int k = 0; k < 3; k++)
            reach[k] = cutoff * std::sqrt(rows[k].dot(rows[k]));
        executor.forEach(n, [&](size_t i) {
            for (int k = 0; k < 3; k++) {
                double s = rows[k].dot(positions[i]);
                frac[i][k] = s - floorOf(s);
            }
        });
        return;
    }
    Vec3 lo(0, 0, 0), hi(0, 0, 0);
    bool first = true;
    for (int i = 0; i < n; i++) {
        if (!active[i])
            continue;
        for (int k = 0; k < 3; k++) {
            lo[k] = first ? positions[i][k] : std::min(lo[k], positions[i][k]);
            hi[k] = first ? positions[i][k] : std::max(hi[k], positions[i][k]);
        }
        first = false;
    }
    for (int k = 0; k < 3; k++) {
        double extent = std::max(hi[k] - lo[k], cutoff) * (1 + 1e-12);
        reach[k] = cutoff / extent;
        for (int i = 0; i < n; i++)
            frac[i][k] = (positions[i][k] - lo[k]) / extent;
    }
}

void PairSearch::chooseGrid(const double* reach) {
    colourable = true;
    for (int k = 0; k < 3; k++) {
        numCells[k] = std::max(1, (int) std::floor(1.0 / reach[k]));
        // Fewer, wider cells are always valid; a periodic axis needs a multiple of 3 cells
        // for the colouring to hold across the boundary.
        if (periodic && numCells[k] >= cellMultiple)
            numCells[k] -= numCells[k] % cellMultiple;
        if (periodic && (numCells[k] < 3 || numCells[k] % 3 != 0))
            colourable = false;
    }
}

void PairSearch::sortIntoCells(ParallelExecutor& executor) {
    // Counting sort of the active particles by cell; within a cell, by particle index.  Each
    // worker counts a consecutive range of particles, then places the particles of a
    // consecutive range of cells: the same order for any number of workers, and each worker
    // writes only its own part of sortedIndex (placing its own particles, every worker wrote
    // into every cache line of it, and two took as long as one).
    const int n = (int) frac.size(), total = numCells[0] * numCells[1] * numCells[2];
    SerialExecutor serial;
    ParallelExecutor& workers = (n < (int) ParallelExecutor::SERIAL_LOOP_LIMIT ? serial : executor);
    const int numWorkers = workers.getNumWorkers();
    cellStart.resize(total + 1);
    workerFill.resize(numWorkers);
    cellOf.resize(n);
    workers.executePhases(3, [&](int w, int phase) {
        if (phase == 0) {
            size_t begin, end;
            workers.range(w, n, begin, end);
            std::vector<int>& count = workerFill[w];
            count.assign(total, 0);
            for (size_t i = begin; i < end; i++) {
                cellOf[i] = (active[i] ? cellIndex(frac[i]) : -1);
                if (cellOf[i] >= 0)
                    count[cellOf[i]]++;
            }
        }
        else if (phase == 1 && w == 0)
            startCells();
        else if (phase == 2)
            placeInCells(w, numWorkers);
    });
}

void PairSearch::placeInCells(int w, int workers) {
    // Worker w's cells are those of the pair passes (workerCells).  Every particle is looked
    // at; a chunk's particles in those cells are picked out without a branch (taken at
    // random, it cost more than placing them), then placed.
    size_t begin, end;
    workerCells(w, workers, begin, end);
    const int first = (int) begin, cells = (int) (end - begin);
    std::vector<int>& next = workerFill[w];
    std::copy(cellStart.begin() + first, cellStart.begin() + first + cells, next.begin() + first);
    constexpr int CHUNK = 256;
    int picked[CHUNK];
    const int n = (int) cellOf.size();
    for (int start = 0; start < n; start += CHUNK) {
        int count = 0;
        for (int i = start; i < std::min(n, start + CHUNK); i++) {
            picked[count] = i;
            count += ((unsigned) (cellOf[i] - first) < (unsigned) cells);
        }
        for (int k = 0; k < count; k++)
            sortedIndex[next[cellOf[picked[k]]]++] = picked[k];
    }
}

int PairSearch::cellIndex(const Vec3& s) const {
    int idx[3];
    for (int k = 0; k < 3; k++)
        idx[k] = std::min(numCells[k] - 1, std::max(0, (int) (s[k] * numCells[k])));
    return (idx[2] * numCells[1] + idx[1]) * numCells[0] + idx[0];
}

void PairSearch::startCells() {
    const int total = numCells[0] * numCells[1] * numCells[2];
    int slots = 0;
    for (int c = 0; c < total; c++) {
        cellStart[c] = slots;
        for (const std::vector<int>& count : workerFill)
            slots += count[c];
    }
    cellStart[total] = slots;
    sortedIndex.resize(slots);
}

void PairSearch::storeSortedPositions(const std::vector<Vec3>& positions, ParallelExecutor& executor) {
    // Slot by slot, so the four arrays are written in order.
    const size_t slots = sortedIndex.size();
    sortedPositions.resize(slots);
    for (auto* coordinate : {&sortedX, &sortedY, &sortedZ})
        coordinate->resize(slots + 3, 0.0);  // padded for gatherWithinCutoff
    executor.forEach(slots, [&](size_t slot) {
        prefetchSlotParticle(periodic ? frac.data() : positions.data(), sortedIndex, slot);
        const int i = sortedIndex[slot];
        // Periodic: the image inside the box, so a neighbour cell's particles need only
        // that cell's fixed shift (see neighbourCells), not a rounding per pair.
        const Vec3 r = periodic ? box[0] * frac[i][0] + box[1] * frac[i][1] + box[2] * frac[i][2] : positions[i];
        sortedPositions[slot] = r;
        sortedX[slot] = r[0];
        sortedY[slot] = r[1];
        sortedZ[slot] = r[2];
    });
}

int PairSearch::gatherInOneCall(int cell, int p, HitBlock& block) const {
    const Neighbour* first = &neighbourTable[neighbourStart[cell]];
    const int numRuns = neighbourStart[cell + 1] - neighbourStart[cell];
    if (!first->exactShift)  // a cell's neighbours all have exact shifts, or none
        return -1;
    const Vec3 rp = sortedPositions[p];
    int candidates = 0;
    for (int k = 0; k < numRuns; k++) {
        const Neighbour& other = first[k];
        block.runs[k].first = (other.firstCell == cell ? p + 1 : cellStart[other.firstCell]);
        block.runs[k].last = cellStart[other.lastCell + 1];
        block.runs[k].r = rp - other.shift;
        candidates += block.runs[k].last - block.runs[k].first;
    }
    if (candidates > MAX_BLOCK)
        return -1;
    const int count = gatherWithinCutoff(sortedX.data(), sortedY.data(), sortedZ.data(), block.runs, numRuns, cutoff * cutoff,
                                         block.hits, block.hitRun);
    // One flat loop: nested over the runs, its ~5 short loops of unpredictable length cost a
    // mispredicted branch each.
    for (int k = 0; k < count; k++)
        block.d[k] = block.runs[block.hitRun[k]].r - sortedPositions[block.hits[k]];
    return count;
}

void PairSearch::updateNeighbourTable() {
    bool sameGrid = !neighbourStart.empty(), sameBox = true;
    for (int k = 0; k < 3; k++) {
        sameGrid = sameGrid && tableCells[k] == numCells[k];
        sameBox = sameBox && tableBox[k] == box[k];
    }
    if (sameGrid && sameBox)
        return;
    if (sameGrid) {
        for (Neighbour& n : neighbourTable)
            n.shift = box[0] * n.wrap[0] + box[1] * n.wrap[1] + box[2] * n.wrap[2];
        std::copy(box, box + 3, tableBox);
        return;
    }
    const int total = numCells[0] * numCells[1] * numCells[2];
    neighbourStart.assign(1, 0);
    neighbourTable.clear();
    std::vector<Neighbour> cellNeighbours;
    for (int cell = 0; cell < total; cell++) {
        neighbourCells(cell, cellNeighbours);
        neighbourTable.insert(neighbourTable.end(), cellNeighbours.begin(), cellNeighbours.end());
        neighbourStart.push_back((int) neighbourTable.size());
    }
    for (int k = 0; k < 3; k++) {
        tableCells[k] = numCells[k];
        tableBox[k] = box[k];
    }
}

void PairSearch::neighbourCells(int cell, std::vector<Neighbour>& out) const {
    out.clear();
    const int c[3] = {cell % numCells[0], (cell / numCells[0]) % numCells[1], cell / (numCells[0] * numCells[1])};
    // The other cell at offset d from this one, and the image shift that brings it next to it.
    auto locate = [&](const int* d, int& other, Vec3& shift, int* wrap) {
        int idx[3];
        for (int k = 0; k < 3; k++) {
            idx[k] = c[k] + d[k];
            wrap[k] = 0;
            if (idx[k] < 0 || idx[k] >= numCells[k]) {
                if (!periodic)
                    return false;
                wrap[k] = (idx[k] < 0 ? -1 : 1);
                idx[k] -= wrap[k] * numCells[k];
            }
        }
        other = (idx[2] * numCells[1] + idx[1]) * numCells[0] + idx[0];
        shift = box[0] * wrap[0] + box[1] * wrap[1] + box[2] * wrap[2];
        return true;
    };
    if (numCells[0] >= 3 && numCells[1] >= 3 && numCells[2] >= 3) {
        // Every offset reaches a distinct cell through exactly one image: search the half
        // shell of offsets after (0, 0, 0) in (dz, dy, dx) order, plus the cell itself, and
        // merge consecutive cells of one x-row that share a shift into one run.
        for (int dz = 0; dz <= 1; dz++)
            for (int dy = (dz == 0 ? 0 : -1); dy <= 1; dy++)
                for (int dx = (dz == 0 && dy == 0 ? 0 : -1); dx <= 1; dx++) {
                    const int d[3] = {dx, dy, dz};
                    Neighbour n;
                    if (!locate(d, n.firstCell, n.shift, n.wrap))
                        continue;
                    n.lastCell = n.firstCell;
                    n.exactShift = true;
                    if (!out.empty() && out.back().lastCell + 1 == n.firstCell && out.back().shift == n.shift && dx > -1)
                        out.back().lastCell = n.firstCell;
                    else
                        out.push_back(n);
                }
        return;
    }
    // Otherwise several offsets reach one cell, which is then searched once, from the lower
    // of the two cells, with a full minimum-image test.
    for (int dz = -1; dz <= 1; dz++)
        for (int dy = -1; dy <= 1; dy++)
            for (int dx = -1; dx <= 1; dx++) {
                const int d[3] = {dx, dy, dz};
                Neighbour n;
                if (locate(d, n.firstCell, n.shift, n.wrap) && n.firstCell >= cell) {
                    n.lastCell = n.firstCell;
                    n.exactShift = false;
                    out.push_back(n);
                }
            }
    std::sort(out.begin(), out.end(), [](const Neighbour& a, const Neighbour& b) { return a.firstCell < b.firstCell; });
    out.erase(std::unique(out.begin(), out.end(), [](const Neighbour& a, const Neighbour& b) { return a.firstCell == b.firstCell; }),
              out.end());
}
