#include "openmmdpd/ReferencePairList.h"
#include "openmmdpd/BoxGeometry.h"
#include <algorithm>
#include <cmath>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

/** r_i - r_j reduced to the nearest periodic image, as OpenMM reduces it. */
Vec3 nearestImage(Vec3 d, const Vec3* box, bool periodic) {
    if (periodic) {
        d -= box[2] * std::round(d[2] / box[2][2]);
        d -= box[1] * std::round(d[1] / box[1][1]);
        d -= box[0] * std::round(d[0] / box[0][0]);
    }
    return d;
}

int colourOf(int cell, const int* n) {
    return cell % n[0] % 3 + 3 * (cell / n[0] % n[1] % 3) + 9 * (cell / (n[0] * n[1]) % 3);
}

} // namespace

ReferencePairList::ReferencePairList(const std::vector<bool>& active, double cutoff, bool periodic, int cellMultiple) :
        active(active), cutoff(cutoff), periodic(periodic), cellMultiple(cellMultiple) {
}

void ReferencePairList::bin(const std::vector<Vec3>& positions, const Vec3* box, int* numCells, std::vector<int>& cellOf,
                            bool& coloured) const {
    // Fractional coordinates s (in [0, 1) per axis) and the fractional reach of the cutoff.
    const int n = (int) positions.size();
    std::vector<Vec3> s(n);
    double reach[3];
    if (periodic) {
        Vec3 rows[3];
        inverseBoxRows(box, rows);
        for (int k = 0; k < 3; k++) {
            reach[k] = cutoff * std::sqrt(rows[k].dot(rows[k]));
            for (int i = 0; i < n; i++)
                s[i][k] = rows[k].dot(positions[i]) - std::floor(rows[k].dot(positions[i]));
        }
    }
    else {
        Vec3 lo, hi;
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
            const double extent = std::max(hi[k] - lo[k], cutoff) * (1 + 1e-12);
            reach[k] = cutoff / extent;
            for (int i = 0; i < n; i++)
                s[i][k] = (positions[i][k] - lo[k]) / extent;
        }
    }
    coloured = true;
    for (int k = 0; k < 3; k++) {
        numCells[k] = std::max(1, (int) std::floor(1.0 / reach[k]));
        if (periodic && numCells[k] >= cellMultiple)
            numCells[k] -= numCells[k] % cellMultiple;
        if (periodic && numCells[k] % 3 != 0)
            coloured = false;
    }
    cellOf.assign(n, -1);
    for (int i = 0; i < n; i++)
        if (active[i]) {
            int c[3];
            for (int k = 0; k < 3; k++)
                c[k] = std::min(numCells[k] - 1, std::max(0, (int) (s[i][k] * numCells[k])));
            cellOf[i] = (c[2] * numCells[1] + c[1]) * numCells[0] + c[0];
        }
}

std::vector<int> ReferencePairList::neighbourCells(int cell, const int* n) const {
    const int c[3] = {cell % n[0], cell / n[0] % n[1], cell / (n[0] * n[1])};
    // The cell at offset d, or -1 beyond a non-periodic edge.
    auto at = [&](int dx, int dy, int dz) {
        int idx[3] = {c[0] + dx, c[1] + dy, c[2] + dz};
        for (int k = 0; k < 3; k++) {
            if (!periodic && (idx[k] < 0 || idx[k] >= n[k]))
                return -1;
            idx[k] = (idx[k] + n[k]) % n[k];
        }
        return (idx[2] * n[1] + idx[1]) * n[0] + idx[0];
    };
    std::vector<int> cells;
    const bool halfShell = (n[0] >= 3 && n[1] >= 3 && n[2] >= 3);
    for (int dz = (halfShell ? 0 : -1); dz <= 1; dz++)
        for (int dy = (halfShell && dz == 0 ? 0 : -1); dy <= 1; dy++)
            for (int dx = (halfShell && dz == 0 && dy == 0 ? 0 : -1); dx <= 1; dx++) {
                const int other = at(dx, dy, dz);
                if (other >= 0 && (halfShell || other >= cell))
                    cells.push_back(other);
            }
    if (!halfShell) {
        std::sort(cells.begin(), cells.end());
        cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
    }
    return cells;
}

std::vector<ReferencePair> ReferencePairList::find(const std::vector<Vec3>& positions, const Vec3* box) const {
    int numCells[3];
    std::vector<int> cellOf;
    bool coloured;
    bin(positions, box, numCells, cellOf, coloured);
    const int totalCells = numCells[0] * numCells[1] * numCells[2];
    std::vector<std::vector<int>> members(totalCells);
    for (int i = 0; i < (int) positions.size(); i++)
        if (cellOf[i] >= 0)
            members[cellOf[i]].push_back(i);
    std::vector<ReferencePair> pairs;
    for (int colour = 0; colour < (coloured ? 27 : 1); colour++)
        for (int cell = 0; cell < totalCells; cell++) {
            if (coloured && colourOf(cell, numCells) != colour)
                continue;
            const std::vector<int> neighbours = neighbourCells(cell, numCells);
            for (size_t a = 0; a < members[cell].size(); a++) {
                const int i = members[cell][a];
                for (int other : neighbours)
                    for (size_t b = (other == cell ? a + 1 : 0); b < members[other].size(); b++) {
                        const int j = members[other][b];
                        const Vec3 d = nearestImage(positions[i] - positions[j], box, periodic);
                        if (d.dot(d) < cutoff * cutoff)
                            pairs.push_back(ReferencePair{i, j, d});
                    }
            }
        }
    return pairs;
}
