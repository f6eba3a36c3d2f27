/*
 * The DPD thermostat's pair forces (PairFormulas.h), gathered per particle: each
 * particle slot sums over its neighbours.  A pair is always evaluated as (lo, hi) by atom
 * index, so both of its particles compute the same numbers and add exactly opposite fixed
 * point values: F_ij = -F_ji to the bit, and the sums do not depend on any order.
 *
 * velocity[atom] holds (v, 1/m) by atom index; outD / outR[atom + d numAtoms] get the
 * dissipative / random force (terms: 1 = dissipative, 2 = random, 3 = both).  The virial
 * r F e e^T of the terms in virialTerms (a subset of terms) is added to the slot's row of
 * virial (6 components paddedNumAtoms apart), each pair counted by its lo particle.
 * With transverse friction (transverse != 0), transverseParams holds each type pair's
 * (friction rate across e, its weight exponent, unused, unused), and the forces across e
 * (DPDPairForce::transverseDissipative, transverseRandom) are added, their virial r F^T.
 */
/* A slot's sums: its atom's forces into outD / outR (the terms computed), its virial into the slot's row (if any). */
inline DEVICE void storeSums(int a, int k, int numAtoms, int paddedNumAtoms, int terms, int virialTerms, const mm_long* fd,
        const mm_long* fr, const mixed* w, GLOBAL mm_long* RESTRICT outD, GLOBAL mm_long* RESTRICT outR, GLOBAL mixed* RESTRICT virial) {
    for (int d = 0; d < 3; d++) {
        if (terms & 1)
            outD[a+d*numAtoms] = fd[d];
        if (terms & 2)
            outR[a+d*numAtoms] = fr[d];
    }
    if (virialTerms != 0)
        addVirialRow(virial, k, paddedNumAtoms, w);
}

/*
 * The forces along e of a pair on lo for the terms asked (DPDPairForce::dissipative, random),
 * added to the slot's fd / fr with its sign: gamma = 2 mu f times the friction rate, wR the
 * random weight, eDotV e . (v_lo - v_hi), xi the pair's normal number (read with the random
 * term).  Returns the sum of those of virialTerms, along e.
 */
inline DEVICE mixed addForcesAlong(int terms, int virialTerms, mixed gamma, mixed wR, mixed kT, mixed invSqrtDt, mixed ex, mixed ey,
        mixed ez, mixed eDotV, mixed xi, mm_long sign, mm_long* fd, mm_long* fr) {
    mixed virialForce = 0;
    if (terms & 1) {
        const mixed f = dissipativeAlongE(gamma*pairDissipativeWeight(wR), eDotV);
        fd[0] += sign*toFixed(ex*f);
        fd[1] += sign*toFixed(ey*f);
        fd[2] += sign*toFixed(ez*f);
        virialForce += (virialTerms & 1 ? f : 0);
    }
    if (terms & 2) {
        const mixed f = randomAlongE(pairNoiseAmplitude(gamma, kT)*wR, xi, invSqrtDt);
        fr[0] += sign*toFixed(ex*f);
        fr[1] += sign*toFixed(ey*f);
        fr[2] += sign*toFixed(ez*f);
        virialForce += (virialTerms & 2 ? f : 0);
    }
    return virialForce;
}

/*
 * The forces across e of a pair with transverse friction on lo (DPDPairForce::transverseDissipative,
 * transverseRandom) for the terms asked, added to the slot's fd / fr with its sign, and those of
 * virialTerms to `across`: gamma = 2 mu f times the transverse rate, wR its random weight, u the
 * relative velocity v_lo - v_hi (hi's image), zeta lo's noise vector (read with the random term).
 */
inline DEVICE void addForcesAcross(int terms, int virialTerms, mixed gamma, mixed wR, mixed kT, mixed invSqrtDt, mixed ex, mixed ey,
        mixed ez, mixed* u, mixed* zeta, mm_long sign, mm_long* fd, mm_long* fr, mixed* across) {
    if (terms & 1) {
        perpendicularInPlace(u, ex, ey, ez);
        for (int c = 0; c < 3; c++) {
            const mixed f = dissipativeAlongE(gamma*pairDissipativeWeight(wR), u[c]);
            fd[c] += sign*toFixed(f);
            across[c] += (virialTerms & 1 ? f : 0);
        }
    }
    if (terms & 2) {
        perpendicularInPlace(zeta, ex, ey, ez);
        for (int c = 0; c < 3; c++) {
            const mixed f = randomAlongE(pairNoiseAmplitude(gamma, kT)*wR, zeta[c], invSqrtDt);
            fr[c] += sign*toFixed(f);
            across[c] += (virialTerms & 2 ? f : 0);
        }
    }
}

KERNEL void dpdPairForces(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT atomType,
        int numTypes, GLOBAL const mixed4* RESTRICT typeParams, GLOBAL const int* RESTRICT exceptionStart,
        GLOBAL const int* RESTRICT exceptionPartner, GLOBAL const mixed* RESTRICT exceptionFactor, mixed kT, mixed invSqrtDt, unsigned int seed,
        unsigned int stepLow, unsigned int stepHigh, int terms, GLOBAL mm_long* RESTRICT outD, GLOBAL mm_long* RESTRICT outR,
        mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC, int4 numCells, GLOBAL const int* RESTRICT atomCell,
        GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms, int virialTerms, int paddedNumAtoms,
        GLOBAL mixed* RESTRICT virial, mixed imageVelocity, int transverse, GLOBAL const mixed4* RESTRICT transverseParams) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 va = velocity[a];
        const mixed4 ra = loadPosition(posq, posqCorrection, k);
        mm_long fd[3] = {0, 0, 0}, fr[3] = {0, 0, 0};
        mixed w[6] = {0, 0, 0, 0, 0, 0};
        if (va.w != 0)
            FOR_EACH_NEIGHBOUR_SLOT(s, atomCell[k], numCells, cellStart) {
                const int k2 = cellAtoms[s];
                const int b = atomIndex[k2];
                const mixed4 vb = velocity[b];
                if (k2 == k || vb.w == 0)
                    continue;
                const mixed4 rb = loadPosition(posq, posqCorrection, k2);
                const bool aIsLo = (a < b);
                const mixed4 rLo = (aIsLo ? ra : rb), rHi = (aIsLo ? rb : ra);
                const mixed4 vLo = (aIsLo ? va : vb), vHi = (aIsLo ? vb : va);
                const mixed4 d = nearestDisplacement(rLo, rHi, boxSize, invBoxSize, boxC);
                const mixed dx = d.x, dy = d.y, dz = d.z;
                const int typePair = atomType[aIsLo ? a : b]*numTypes+atomType[aIsLo ? b : a];
                const mixed4 p = typeParams[typePair];  // friction, rc, s, rc^2
                const mixed r2 = dx*dx+dy*dy+dz*dz;
                if (r2 >= p.w || r2 == 0)
                    continue;
                const mixed r = sqrt(r2);
                const mixed wR = pairRandomWeight(pairLinearWeight(r, p.y), p.z);
                const mixed ex = dx/r, ey = dy/r, ez = dz/r;
                // 2 mu friction f, f the pair's thermostat factor (sigma follows as sqrt(2 gamma kT))
                const mixed factor = thermostatFactor(a, b, exceptionStart, exceptionPartner, exceptionFactor);
                const mixed gamma = 2*p.x/(vLo.w+vHi.w)*factor;
                const mm_long sign = (aIsLo ? 1 : -1);
                // Under shear, hi's image moves at d.w U along x.
                const mixed vx = vLo.x-vHi.x-d.w*imageVelocity;
                const mixed xi = (terms & 2 ? boxMuller(pairWords(seed, 0, stepLow, stepHigh, a, b)) : 0);
                const mixed virialForce = addForcesAlong(terms, virialTerms, gamma, wR, kT, invSqrtDt, ex, ey, ez,
                                                         ex*vx+ey*(vLo.y-vHi.y)+ez*(vLo.z-vHi.z), xi, sign, fd, fr);
                mixed across[3] = {0, 0, 0};  // the forces across e of the virial's terms
                const mixed4 tp = (transverse ? transverseParams[typePair] : make_mixed4(0, 0, 0, 0));
                if (tp.x != 0) {
                    mixed u[3] = {vx, vLo.y-vHi.y, vLo.z-vHi.z}, zeta[3];
                    if (terms & 2)  // PairRandom::TransverseNoise, on lo
                        normalVector(pairWords(seed, 5, stepLow, stepHigh, a, b), aIsLo ? a : b, aIsLo ? b : a, zeta);
                    addForcesAcross(terms, virialTerms, 2*tp.x/(vLo.w+vHi.w)*factor, pairRandomWeight(pairLinearWeight(r, p.y), tp.y),
                                    kT, invSqrtDt, ex, ey, ez, u, zeta, sign, fd, fr, across);
                }
                if (aIsLo && virialTerms != 0) {
                    addVirialAlong(w, dx, dy, dz, virialForce/r);
                    addVirialOuter(w, dx, dy, dz, across[0], across[1], across[2]);
                }
            }
        storeSums(a, k, numAtoms, paddedNumAtoms, terms, virialTerms, fd, fr, w, outD, outR, virial);
    }
}
