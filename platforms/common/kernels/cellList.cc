/*
 * A cell list in a rectangular periodic box: cells at least the cutoff wide, each particle
 * slot listed in its cell (the order within a cell does not matter: every sum over a cell
 * is taken in fixed point).  An axis with fewer than three cells visits each cell once.
 */

KERNEL void clearCells(int numCells, GLOBAL int* RESTRICT cellCount) {
    for (int c = GLOBAL_ID; c < numCells; c += GLOBAL_SIZE)
        cellCount[c] = 0;
}

inline DEVICE int cellAlong(mixed x, mixed invSize, int n) {
    mixed f = x*invSize;
    f -= floor(f);
    const int c = (int) (f*n);
    return (c < 0 ? 0 : (c >= n ? n-1 : c));  // also keeps a non-finite position inside the arrays
}

KERNEL void assignCells(int numAtoms, GLOBAL const real4* RESTRICT posq, mixed4 invBoxSize, int4 numCells,
        GLOBAL int* RESTRICT atomCell, GLOBAL int* RESTRICT cellCount) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const real4 r = posq[k];
        const int c = cellAlong(r.x, invBoxSize.x, numCells.x) +
                numCells.x*(cellAlong(r.y, invBoxSize.y, numCells.y) + numCells.y*cellAlong(r.z, invBoxSize.z, numCells.z));
        atomCell[k] = c;
        ATOMIC_ADD(&cellCount[c], 1);
    }
}

/* One thread: the start of every cell (cellStart[numCells] = numAtoms); the counts are zeroed for fillCells. */
KERNEL void scanCells(int numCells, GLOBAL int* RESTRICT cellCount, GLOBAL int* RESTRICT cellStart) {
    if (GLOBAL_ID != 0)
        return;
    int sum = 0;
    for (int c = 0; c < numCells; c++) {
        cellStart[c] = sum;
        sum += cellCount[c];
        cellCount[c] = 0;
    }
    cellStart[numCells] = sum;
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

/* The n-th (0..26) neighbour of a cell, itself included; -1 where an axis has too few cells to have it. */
inline DEVICE int neighbourCell(int cell, int n, int4 numCells) {
    const int x = shiftCell(cell%numCells.x, n%3-1, numCells.x);
    const int y = shiftCell((cell/numCells.x)%numCells.y, (n/3)%3-1, numCells.y);
    const int z = shiftCell(cell/(numCells.x*numCells.y), n/9-1, numCells.z);
    return (x < 0 || y < 0 || z < 0 ? -1 : x+numCells.x*(y+numCells.y*z));
}
