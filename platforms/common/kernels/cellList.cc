/*
 * A cell list binned as the Reference bins (ReferencePairList.h), in fractional coordinates
 * s_k = rows[k] . (r - origin).  In a periodic box of OpenMM's reduced form (a along x, b in
 * the xy plane, c tilted or not: rectangular, sheared by Lees-Edwards, or triclinic) the rows
 * are those of the inverse box matrix, the origin 0 and s taken modulo 1, so that the box's
 * faces, tilted or not, are the grid's.  In an open System (numCells.w = 0) the grid spans
 * the particles' bounding box from its lower corner, and has no cells beyond its edges.
 * Cells are at least the cutoff wide across, so a particle's partners lie in its cell and
 * the 26 around it; an axis with fewer than three cells visits each cell once.  The rows come
 * as rowX = rows[0] and rowYZ = (rows[1][1], rows[1][2], rows[2][2], unused).
 */

KERNEL void clearCells(int numCells, GLOBAL int* RESTRICT cellCount) {
    for (int c = GLOBAL_ID; c < numCells; c += GLOBAL_SIZE)
        cellCount[c] = 0;
}

/* The cell of n along an axis that holds the fractional coordinate f (taken modulo 1 if periodic). */
inline DEVICE int cellOfFraction(mixed f, int n, int periodic) {
    if (periodic)
        f -= floor(f);
    const int c = (int) (f*n);
    return (c < 0 ? 0 : (c >= n ? n-1 : c));  // also keeps a non-finite position inside the arrays
}

/* The cell of position r in a grid of numCells along the fractional axes. */
inline DEVICE int fractionalCell(mixed4 r, mixed4 origin, mixed4 rowX, mixed4 rowYZ, int4 numCells) {
    const mixed x = r.x-origin.x, y = r.y-origin.y, z = r.z-origin.z;
    const mixed sx = rowX.x*x+rowX.y*y+rowX.z*z, sy = rowYZ.x*y+rowYZ.y*z, sz = rowYZ.z*z;
    return cellOfFraction(sx, numCells.x, numCells.w) +
           numCells.x*(cellOfFraction(sy, numCells.y, numCells.w) + numCells.y*cellOfFraction(sz, numCells.z, numCells.w));
}

/*
 * The lowest and highest x, y, z of each of numSlots shares of the particles (those that
 * move, 1/m != 0, if movingOnly), share t as bounds[6 t ...]; the host takes the extremes.  A
 * share with no particle leaves +-huge.  (Shares, not work items: OpenMM may launch fewer.)
 */
KERNEL void findBounds(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const mixed4* RESTRICT velm, int movingOnly, int numSlots, GLOBAL mixed* RESTRICT bounds) {
    for (int t = GLOBAL_ID; t < numSlots; t += GLOBAL_SIZE) {
        mixed lo[3] = {1e30f, 1e30f, 1e30f}, hi[3] = {-1e30f, -1e30f, -1e30f};
        for (int k = t; k < numAtoms; k += numSlots) {
            if (movingOnly && velm[k].w == 0)
                continue;
            const mixed4 r = loadPosition(posq, posqCorrection, k);
            const mixed x[3] = {r.x, r.y, r.z};
            for (int d = 0; d < 3; d++) {
                lo[d] = min(lo[d], x[d]);
                hi[d] = max(hi[d], x[d]);
            }
        }
        for (int d = 0; d < 3; d++) {
            bounds[6*t+d] = lo[d];
            bounds[6*t+3+d] = hi[d];
        }
    }
}

KERNEL void assignCells(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection, mixed4 origin,
        mixed4 rowX, mixed4 rowYZ, int4 numCells, GLOBAL int* RESTRICT atomCell, GLOBAL int* RESTRICT cellCount) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int c = fractionalCell(loadPosition(posq, posqCorrection, k), origin, rowX, rowYZ, numCells);
        atomCell[k] = c;
        ATOMIC_ADD(&cellCount[c], 1);
    }
}

/*
 * cellStart = the exclusive prefix sum of cellCount (cellStart[numCells] = numAtoms), in
 * three launches of CELL_SCAN_BLOCK-item work groups: scanCellBlocks scans each block of
 * cells and keeps its total, scanBlockSums (one work group) turns the totals into the
 * blocks' starts, addBlockStarts adds them.  Integer sums: the same starts as one loop.
 * The counts are zeroed for fillCells.
 */

/* The inclusive prefix sum of `value` over the work group (Hillis-Steele, in `buffer`). */
inline DEVICE int scanWorkGroup(int value, LOCAL_ARG int* buffer) {
    SYNC_THREADS;  // the last call's buffer may still be read
    buffer[LOCAL_ID] = value;
    SYNC_THREADS;
    for (int offset = 1; offset < CELL_SCAN_BLOCK; offset *= 2) {
        const int add = (LOCAL_ID >= offset ? buffer[LOCAL_ID-offset] : 0);
        SYNC_THREADS;
        buffer[LOCAL_ID] += add;
        SYNC_THREADS;
    }
    return buffer[LOCAL_ID];
}

KERNEL void scanCellBlocks(int numCells, GLOBAL int* RESTRICT cellCount, GLOBAL int* RESTRICT cellStart,
        GLOBAL int* RESTRICT blockSums) {
    LOCAL int buffer[CELL_SCAN_BLOCK];
    for (int block = GROUP_ID; block*CELL_SCAN_BLOCK < numCells; block += NUM_GROUPS) {
        const int c = block*CELL_SCAN_BLOCK+LOCAL_ID;
        const int count = (c < numCells ? cellCount[c] : 0);
        const int inclusive = scanWorkGroup(count, buffer);
        if (c < numCells) {
            cellStart[c] = inclusive-count;
            cellCount[c] = 0;
        }
        if (LOCAL_ID == CELL_SCAN_BLOCK-1)
            blockSums[block] = inclusive;
    }
}

/* One work group: blockSums[b] becomes the start of block b, in chunks of CELL_SCAN_BLOCK blocks. */
KERNEL void scanBlockSums(int numBlocks, int numCells, GLOBAL int* RESTRICT blockSums, GLOBAL int* RESTRICT cellStart) {
    LOCAL int buffer[CELL_SCAN_BLOCK];
    int total = 0;
    for (int first = 0; first < numBlocks; first += CELL_SCAN_BLOCK) {
        const int b = first+LOCAL_ID;
        const int sum = (b < numBlocks ? blockSums[b] : 0);
        const int inclusive = scanWorkGroup(sum, buffer);
        if (b < numBlocks)
            blockSums[b] = total+inclusive-sum;
        total += buffer[CELL_SCAN_BLOCK-1];
    }
    if (LOCAL_ID == 0)
        cellStart[numCells] = total;
}

KERNEL void addBlockStarts(int numCells, GLOBAL const int* RESTRICT blockSums, GLOBAL int* RESTRICT cellStart) {
    for (int c = GLOBAL_ID; c < numCells; c += GLOBAL_SIZE)
        cellStart[c] += blockSums[c/CELL_SCAN_BLOCK];
}

KERNEL void fillCells(int numAtoms, GLOBAL const int* RESTRICT atomCell, GLOBAL const int* RESTRICT cellStart,
        GLOBAL int* RESTRICT cellCount, GLOBAL int* RESTRICT cellAtoms) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int c = atomCell[k];
        cellAtoms[cellStart[c]+ATOMIC_ADD(&cellCount[c], 1)] = k;
    }
}

/* The cell `offset` (-1..1) on from c of n along an axis; -1 for none (beyond an open edge, or one already visited). */
inline DEVICE int shiftCell(int c, int offset, int n, int periodic) {
    if (!periodic)
        return (c+offset < 0 || c+offset >= n ? -1 : c+offset);
    if (n < 3 && (offset < 0 || (n == 1 && offset > 0)))
        return -1;
    return (c+offset+n)%n;
}

/* How many neighbour slots a cell has: the offsets -1..1 along each axis. */
#define NEIGHBOUR_SLOTS 27

/* The n-th (0..NEIGHBOUR_SLOTS-1) neighbour of a cell, itself included; -1 where there is none. */
inline DEVICE int neighbourCell(int cell, int n, int4 numCells) {
    const int x = shiftCell(cell%numCells.x, n%3-1, numCells.x, numCells.w);
    const int y = shiftCell((cell/numCells.x)%numCells.y, (n/3)%3-1, numCells.y, numCells.w);
    const int z = shiftCell(cell/(numCells.x*numCells.y), n/9-1, numCells.z, numCells.w);
    return (x < 0 || y < 0 || z < 0 ? -1 : x+numCells.x*(y+numCells.y*z));
}

/*
 * Every slot s of cellAtoms in the cells around `cell`, itself included, for the statement
 * that follows: a particle's partners within the cutoff lie among them.
 */
#define FOR_EACH_NEIGHBOUR_SLOT(s, cell, numCells, cellStart) \
    for (int neighbour_ = 0; neighbour_ < NEIGHBOUR_SLOTS; neighbour_++) \
        for (int cell_ = neighbourCell(cell, neighbour_, numCells), s = (cell_ < 0 ? 0 : cellStart[cell_]), \
                 end_ = (cell_ < 0 ? 0 : cellStart[cell_+1]); s < end_; s++)

/* Whether the pair (a, b) is in a's exclusions (exclusions[exclusionStart[a] .. exclusionStart[a+1]-1]). */
inline DEVICE bool isExcluded(int a, int b, GLOBAL const int* RESTRICT exclusionStart, GLOBAL const int* RESTRICT exclusions) {
    bool excluded = false;
    for (int e = exclusionStart[a]; e < exclusionStart[a+1]; e++)
        excluded = excluded || (exclusions[e] == b);
    return excluded;
}
