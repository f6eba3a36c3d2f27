/*
 * A cell list in a periodic box of OpenMM's reduced form (a along x, b in the xy plane,
 * c tilted or not: rectangular, sheared by Lees-Edwards, or triclinic), binned as the Reference
 * bins (ReferencePairList.h): in fractional coordinates s_k = rows[k] . r, taken modulo 1,
 * so that the box's faces, tilted or not, are the grid's.  Cells are at least the cutoff wide
 * across, so a particle's partners lie in its cell and the 26 around it; an axis with fewer
 * than three cells visits each cell once.  The rows of the inverse box matrix come as
 * rowX = rows[0] and rowYZ = (rows[1][1], rows[1][2], rows[2][2], unused).
 */

KERNEL void clearCells(int numCells, GLOBAL int* RESTRICT cellCount) {
    for (int c = GLOBAL_ID; c < numCells; c += GLOBAL_SIZE)
        cellCount[c] = 0;
}

/* The cell of n along an axis that holds the fractional coordinate f (taken modulo 1). */
inline DEVICE int cellOfFraction(mixed f, int n) {
    f -= floor(f);
    const int c = (int) (f*n);
    return (c < 0 ? 0 : (c >= n ? n-1 : c));  // also keeps a non-finite position inside the arrays
}

/* The cell of position r in a grid of numCells along the fractional axes. */
inline DEVICE int fractionalCell(mixed4 r, mixed4 rowX, mixed4 rowYZ, int4 numCells) {
    const mixed sx = rowX.x*r.x+rowX.y*r.y+rowX.z*r.z, sy = rowYZ.x*r.y+rowYZ.y*r.z, sz = rowYZ.z*r.z;
    return cellOfFraction(sx, numCells.x) + numCells.x*(cellOfFraction(sy, numCells.y) + numCells.y*cellOfFraction(sz, numCells.z));
}

KERNEL void assignCells(int numAtoms, GLOBAL const real4* RESTRICT posq, mixed4 rowX, mixed4 rowYZ, int4 numCells,
        GLOBAL int* RESTRICT atomCell, GLOBAL int* RESTRICT cellCount) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const real4 r = posq[k];
        const int c = fractionalCell(make_mixed4(r.x, r.y, r.z, 0), rowX, rowYZ, numCells);
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

inline DEVICE int shiftCell(int c, int offset, int n) {
    if (n < 3 && (offset < 0 || (n == 1 && offset > 0)))
        return -1;
    return (c+offset+n)%n;
}

/* How many neighbour slots a cell has: the offsets -1..1 along each axis. */
#define NEIGHBOUR_SLOTS 27

/* The n-th (0..NEIGHBOUR_SLOTS-1) neighbour of a cell, itself included; -1 where there is none. */
inline DEVICE int neighbourCell(int cell, int n, int4 numCells) {
    const int x = shiftCell(cell%numCells.x, n%3-1, numCells.x);
    const int y = shiftCell((cell/numCells.x)%numCells.y, (n/3)%3-1, numCells.y);
    const int z = shiftCell(cell/(numCells.x*numCells.y), n/9-1, numCells.z);
    return (x < 0 || y < 0 || z < 0 ? -1 : x+numCells.x*(y+numCells.y*z));
}
