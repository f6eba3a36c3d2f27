#ifndef OPENMMDPD_REFERENCEPAIRLIST_H_
#define OPENMMDPD_REFERENCEPAIRLIST_H_

#include "openmm/Vec3.h"
#include <vector>

namespace DPDPlugin {

/** A pair of particles closer than the cutoff, with d = r_i - r_j for the nearest image. */
struct ReferencePair {
    int i, j;
    OpenMM::Vec3 d;
};

/**
 * Every pair of active particles closer than a cutoff, found with a plain cell list, in
 * the order in which the sequential schemes sweep them on every platform:
 *
 *   cells: n_k = floor(1 / R_k) along each axis k, R_k the fractional width that the cutoff
 *          spans, lowered on a periodic axis to a multiple of cellMultiple (3 lets the
 *          sweeps colour the cells);
 *   order: colour by colour (colour (x mod 3, y mod 3, z mod 3), 27 colours, when every
 *          periodic axis has a multiple of 3 cells), cell by cell in index order, each
 *          particle i of the cell in index order, its neighbour cells in the order below,
 *          and their particles j in index order (in i's own cell only those after i).
 *   neighbour cells of a cell: with 3 or more cells along every axis the cell itself and
 *          the half shell of offsets after (0, 0, 0) in (dz, dy, dx) order; otherwise every
 *          distinct cell of the full shell not below the cell, in index order.
 */
class ReferencePairList {
public:
    ReferencePairList(const std::vector<bool>& active, double cutoff, bool periodic, int cellMultiple);
    std::vector<ReferencePair> find(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box) const;

private:
    /** The grid: cells per axis, each active particle's cell, whether the cells are coloured. */
    void bin(const std::vector<OpenMM::Vec3>& positions, const OpenMM::Vec3* box, int* numCells, std::vector<int>& cellOf,
             bool& coloured) const;
    /** The neighbour cells of `cell` (see the class comment). */
    std::vector<int> neighbourCells(int cell, const int* numCells) const;
    std::vector<bool> active;
    double cutoff;
    bool periodic;
    int cellMultiple;
};

} // namespace DPDPlugin

#endif
