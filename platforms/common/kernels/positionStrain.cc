/*
 * The pressure tensor's strain of the positions (PositionStrain, CommonPositionStrain): the
 * positions are kept by atom index, exactly as stored, so that they come back to the bit
 * whatever OpenMM does with its slots in between.
 */

KERNEL void savePositions(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL real4* RESTRICT savedPosq, GLOBAL real4* RESTRICT savedCorrection) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        savedPosq[a] = posq[k];
        savedCorrection[a] = posqCorrection[k];
    }
}

/* Each slot's position: its atom's saved position with x_axis += strain x_along. */
KERNEL void strainPositions(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const real4* RESTRICT savedPosq, GLOBAL const real4* RESTRICT savedCorrection,
        int axis, int along, mixed strain) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 r = loadPosition(savedPosq, savedCorrection, a);
        mixed x[3] = {r.x, r.y, r.z};
        x[axis] += strain*x[along];
        storePosition(posq, posqCorrection, k, make_mixed4(x[0], x[1], x[2], 0));
    }
}

KERNEL void restorePositions(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const real4* RESTRICT savedPosq, GLOBAL const real4* RESTRICT savedCorrection) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        posq[k] = savedPosq[a];
        posqCorrection[k] = savedCorrection[a];
    }
}
