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
        for (int n = 0; n < NEIGHBOUR_SLOTS; n++) {
            const int cell = neighbourCell(atomCell[k], n, numCells);
            if (cell < 0)
                continue;
            for (int s = cellStart[cell]; s < cellStart[cell+1]; s++) {
                const int k2 = cellAtoms[s];
                const int b = atomIndex[k2];
                if (k2 == k)
                    continue;
                const mixed4 rb = loadPosition(posq, posqCorrection, k2);
                const bool aIsLo = (a < b);
                const mixed4 d = (aIsLo ? nearestDisplacement(ra, rb, boxSize, invBoxSize, boxC)
                                        : nearestDisplacement(rb, ra, boxSize, invBoxSize, boxC));
                const mixed dx = d.x, dy = d.y, dz = d.z;
                const mixed4 p = typeParams[atomType[aIsLo ? a : b]*numTypes+atomType[aIsLo ? b : a]];
                const mixed r2 = dx*dx+dy*dy+dz*dz;
                if (r2 >= p.w || r2 == 0)
                    continue;
                bool excluded = false;
                for (int e = exclusionStart[a]; e < exclusionStart[a+1]; e++)
                    excluded = excluded || (exclusions[e] == b);
                if (excluded)
                    continue;
                const mixed r = sqrt(r2);
                const mixed scale = softRepulsionAlongE(r, p.x, p.z)/r;
                const mm_long sign = (aIsLo ? 1 : -1);
                f[0] += sign*toFixed(dx*scale);
                f[1] += sign*toFixed(dy*scale);
                f[2] += sign*toFixed(dz*scale);
                if (aIsLo) {
                    energy += softRepulsionEnergy(r, p.x, p.y);
                    addVirialAlong(w, dx, dy, dz, scale);
                }
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
