/*
 * DPDSoftRepulsionForce (docs/theory/forces.md), gathered per particle slot over the cell
 * list: F = a (1 - r/rc) e on lo, the exact opposite fixed-point value on hi (see
 * dpdPairs.cc), added to OpenMM's force buffer; each pair's energy counted once (by its lo
 * particle) in the energy buffer of the thread.  typeParams: (a, rc, 1/rc, rc^2).
 * exclusionStart/exclusions: the excluded partners of each atom (by atom index).  With
 * virialOnly, nothing else is written: each thread adds the virial r F e e^T of its pairs
 * to its row of virial (6 components energyThreads apart).
 */
KERNEL void softRepulsion(int numAtoms, int paddedNumAtoms, int energyThreads, GLOBAL const real4* RESTRICT posq,
        GLOBAL const real4* RESTRICT posqCorrection, GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT atomType,
        int numTypes, GLOBAL const mixed4* RESTRICT typeParams, GLOBAL const int* RESTRICT exclusionStart,
        GLOBAL const int* RESTRICT exclusions, GLOBAL mm_long* RESTRICT forceBuffer, GLOBAL mixed* RESTRICT energyBuffer,
        mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC, int4 numCells, GLOBAL const int* RESTRICT atomCell,
        GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms, int virialOnly,
        GLOBAL mixed* RESTRICT virial) {
    // Threads beyond the energy slots return; a launch that a platform capped below them has
    // fewer, and each strides by the number that run.
    const int threads = min((int) GLOBAL_SIZE, energyThreads);
    if (GLOBAL_ID >= threads)
        return;
    mixed energy = 0;
    mixed w[6] = {0, 0, 0, 0, 0, 0};
    for (int k = GLOBAL_ID; k < numAtoms; k += threads) {
        const int a = atomIndex[k];
        const mixed4 ra = loadPosition(posq, posqCorrection, k);
        mm_long f[3] = {0, 0, 0};
        FOR_EACH_NEIGHBOUR_SLOT(s, atomCell[k], numCells, cellStart) {
            const int k2 = cellAtoms[s];
            const int b = atomIndex[k2];
            if (k2 == k)
                continue;
            const mixed4 rb = loadPosition(posq, posqCorrection, k2);
            const bool aIsLo = (a < b);
            const mixed4 d = loHiDisplacement(aIsLo, ra, rb, boxSize, invBoxSize, boxC);
            const mixed4 p = typeParams[atomType[aIsLo ? a : b]*numTypes+atomType[aIsLo ? b : a]];
            const mixed r2 = d.x*d.x+d.y*d.y+d.z*d.z;
            if (r2 >= p.w || r2 == 0 || isExcluded(a, b, exclusionStart, exclusions))
                continue;
            const mixed r = sqrt(r2);
            const mixed scale = softRepulsionAlongE(r, p.x, p.z)/r;
            addFixedAlong(f, aIsLo ? 1 : -1, d, scale);
            if (aIsLo) {
                energy += softRepulsionEnergy(r, p.x, p.y);
                addVirialAlong(w, d.x, d.y, d.z, scale);
            }
        }
        for (int d = 0; d < 3 && !virialOnly; d++)
            forceBuffer[k+d*paddedNumAtoms] += f[d];
    }
    if (virialOnly)
        addVirialRow(virial, GLOBAL_ID, energyThreads, w);
    else
        energyBuffer[GLOBAL_ID] += energy;
}
