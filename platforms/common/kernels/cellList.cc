/*
 * A cell list in a periodic box whose b may be tilted along x by boxSize.w (Lees-Edwards
 * shear): cells at least the cutoff wide on the grid of (Lx, Ly, Lz), each particle slot listed
 * in its cell (the order within a cell does not matter: every sum over a cell is taken in
 * fixed point).  A particle outside 0 <= y < Ly is binned at its image inside, shifted along x
 * by the tilt with each b.  An axis with fewer than three cells visits each cell once.
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

inline DEVICE int cellAlong(mixed x, mixed invSize, int n) {
    return cellOfFraction(x*invSize, n);
}

KERNEL void assignCells(int numAtoms, GLOBAL const real4* RESTRICT posq, mixed4 boxSize, mixed4 invBoxSize, int4 numCells,
        GLOBAL int* RESTRICT atomCell, GLOBAL int* RESTRICT cellCount) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const real4 r = posq[k];
        const mixed x = r.x-floor(r.y*invBoxSize.y)*boxSize.w;
        const int c = cellAlong(x, invBoxSize.x, numCells.x) +
                numCells.x*(cellAlong(r.y, invBoxSize.y, numCells.y) + numCells.y*cellAlong(r.z, invBoxSize.z, numCells.z));
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

/* How many neighbour slots a cell has: 4 along x (a row across a tilted boundary needs 4), 3 along y and z. */
#define NEIGHBOUR_SLOTS 36

/*
 * The x cell of slot (0..3) along x of a neighbour row `crossing` b away (-1, 0, 1): the
 * row's own cells x-1..x+1, or across a tilted boundary the 4 cells that hold x-1..x+2 shifted
 * by the tilt (fewer than 4 cells: each once); -1 for a slot with no cell.
 */
inline DEVICE int neighbourColumn(int x, int slot, int crossing, int n, mixed4 boxSize) {
    if (crossing == 0 || boxSize.w == 0)
        return (slot == 3 ? -1 : shiftCell(x, slot-1, n));
    if (n <= 4)
        return (slot < n ? slot : -1);
    const int first = (int) floor(x-1-crossing*boxSize.w*n/boxSize.x);
    return ((first+slot)%n+n)%n;
}

/* The n-th (0..NEIGHBOUR_SLOTS-1) neighbour of a cell, itself included; -1 where there is none. */
inline DEVICE int neighbourCell(int cell, int n, int4 numCells, mixed4 boxSize) {
    const int cy = (cell/numCells.x)%numCells.y, dy = (n/4)%3-1;
    const int y = shiftCell(cy, dy, numCells.y);
    const int z = shiftCell(cell/(numCells.x*numCells.y), n/12-1, numCells.z);
    const int crossing = (cy+dy < 0 ? -1 : (cy+dy >= numCells.y ? 1 : 0));
    const int x = neighbourColumn(cell%numCells.x, n%4, crossing, numCells.x, boxSize);
    return (x < 0 || y < 0 || z < 0 ? -1 : x+numCells.x*(y+numCells.y*z));
}
