/*
 * MDPDForce (docs/theory/mdpd.md) in two gathers per particle slot over the cell list, as
 * softRepulsion.cc: mdpdDensity sums each slot's local density over its pairs within rd;
 * mdpdForce then gives each pair F = [A (1 - r/rc) + (B_lo rho_lo + B_hi rho_hi)(1 - r/rd)] e,
 * computed in lo/hi order so that both particles of a pair add the exact opposite fixed-point
 * value.  Each particle's density energy, and each pair's A energy (by its lo particle), go to
 * the energy buffer of the thread.  typeParams: (A, rc, 1/rc, rc^2) per type pair; typeB: B
 * per type; densityParams: (norm, 1/rd, rd^2, energyFactor).
 */

KERNEL void mdpdDensity(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT exclusionStart, GLOBAL const int* RESTRICT exclusions,
        mixed4 densityParams, GLOBAL mixed* RESTRICT density, mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC, int4 numCells,
        GLOBAL const int* RESTRICT atomCell, GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 ra = loadPosition(posq, posqCorrection, k);
        mixed rho = 0;
        FOR_EACH_NEIGHBOUR_SLOT(s, atomCell[k], numCells, cellStart) {
            const int k2 = cellAtoms[s];
            if (k2 == k)
                continue;
            const mixed4 d = nearestDisplacement(ra, loadPosition(posq, posqCorrection, k2), boxSize, invBoxSize, boxC);
            const mixed r2 = d.x*d.x+d.y*d.y+d.z*d.z;
            if (r2 < densityParams.z && !isExcluded(a, atomIndex[k2], exclusionStart, exclusions))
                rho += mdpdDensityWeight(sqrt(r2), densityParams.x, densityParams.y);
        }
        density[k] = rho;
    }
}

KERNEL void mdpdForce(int numAtoms, int paddedNumAtoms, int energyThreads, GLOBAL const real4* RESTRICT posq,
        GLOBAL const real4* RESTRICT posqCorrection, GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT atomType,
        int numTypes, GLOBAL const mixed4* RESTRICT typeParams, GLOBAL const mixed* RESTRICT typeB, mixed4 densityParams,
        GLOBAL const mixed* RESTRICT density, GLOBAL const int* RESTRICT exclusionStart, GLOBAL const int* RESTRICT exclusions,
        GLOBAL mm_long* RESTRICT forceBuffer, GLOBAL mixed* RESTRICT energyBuffer, mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC,
        int4 numCells, GLOBAL const int* RESTRICT atomCell, GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms,
        int virialOnly, GLOBAL mixed* RESTRICT virial) {
    const int threads = min((int) GLOBAL_SIZE, energyThreads);
    if (GLOBAL_ID >= threads)
        return;
    mixed energy = 0;
    mixed w[6] = {0, 0, 0, 0, 0, 0};
    for (int k = GLOBAL_ID; k < numAtoms; k += threads) {
        const int a = atomIndex[k];
        const mixed4 ra = loadPosition(posq, posqCorrection, k);
        const mixed repulsionA = typeB[atomType[a]]*density[k];
        energy += mdpdDensityEnergy(density[k], typeB[atomType[a]], densityParams.w);
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
            const mixed repulsionB = typeB[atomType[b]]*density[k2];
            mixed along = softRepulsionAlongE(r, p.x, p.z);
            if (r2 < densityParams.z)
                along += mdpdRepulsionAlongE(r, aIsLo ? repulsionA+repulsionB : repulsionB+repulsionA, densityParams.y);
            const mixed scale = along/r;
            addFixedAlong(f, aIsLo ? 1 : -1, d, scale);
            if (aIsLo) {
                energy += softRepulsionEnergy(r, p.x, p.y);
                addVirialAlong(w, d.x, d.y, d.z, scale);
            }
        }
        for (int c = 0; c < 3 && !virialOnly; c++)
            forceBuffer[k+c*paddedNumAtoms] += f[c];
    }
    if (virialOnly)
        addVirialRow(virial, GLOBAL_ID, energyThreads, w);
    else
        energyBuffer[GLOBAL_ID] += energy;
}
