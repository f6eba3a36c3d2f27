/*
 * The pairwise-sequential sweeps of ShardlowIntegrator and LoweAndersenIntegrator
 * (platforms/reference/src/ReferenceSweepDynamics.cpp is the definition, and the pair
 * formulas are PairFormulas.h's, shared with the host) in the Reference's pair order
 * (ReferencePairList.h), so that the device follows the Reference's trajectory: colour by colour, cell by cell, each particle i of a
 * cell in index order, its neighbour cells in order, their particles j in index order (in
 * i's own cell those after i).  Cells of one colour touch disjoint particles, so one
 * launch sweeps a colour with a work item per cell; in a periodic grid with fewer than 3
 * cells on an axis there are no colours and one work item sweeps every cell in order (an
 * open grid, without wrap-around, is coloured whatever its size, as the Reference's).
 *
 * Everything here is indexed by atom: position[a] at the sweep, velocity[a] = (v, 1/m)
 * (1/m = 0: a particle the thermostat leaves alone), cellAtoms sorted by atom index.
 *
 * The grid is the Reference's, in fractional coordinates (fractionalCell), in any box of
 * OpenMM's reduced form; under Lees-Edwards shear (b = (tilt, Ly, 0), tilt = boxSize.w) a
 * pair across the y boundary sees its partner's image move at n U.
 *
 * With constraints a pair's impulse also moves the particles its constraints tie to i and j
 * (pairConstraints.cc), so one work item sweeps each colour's cells in order.
 *
 * For the pressure tensor, a sweep can also add the virial r J e e^T of the impulse J each
 * pair receives to the row of the work item that swept it (6 components virialStride apart).
 */

/* Each atom's position and cell in the sweep grid, binned as the Reference bins (fractionalCell). */
KERNEL void sweepAssign(int numAtoms, GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection,
        GLOBAL const int* RESTRICT atomIndex, mixed4 origin, mixed4 rowX, mixed4 rowYZ, int4 numCells, GLOBAL mixed4* RESTRICT position,
        GLOBAL int* RESTRICT atomCell, GLOBAL int* RESTRICT cellCount) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 r = loadPosition(posq, posqCorrection, k);
        const int c = fractionalCell(r, origin, rowX, rowYZ, numCells);
        position[a] = r;
        atomCell[a] = c;
        ATOMIC_ADD(&cellCount[c], 1);
    }
}

/* fillCells lists each cell's atoms in the order the atomics came; the sweep needs index order. */
KERNEL void sweepSortCells(int numCells, GLOBAL const int* RESTRICT cellStart, GLOBAL int* RESTRICT cellAtoms) {
    for (int c = GLOBAL_ID; c < numCells; c += GLOBAL_SIZE)
        for (int s = cellStart[c]+1; s < cellStart[c+1]; s++) {
            const int atom = cellAtoms[s];
            int t = s;
            for (; t > cellStart[c] && cellAtoms[t-1] > atom; t--)
                cellAtoms[t] = cellAtoms[t-1];
            cellAtoms[t] = atom;
        }
}

/* The cell at offset (dx, dy, dz) in the grid; -1 beyond the edge of an open one (n.w = 0). */
inline DEVICE int sweepCellAt(int cell, int dx, int dy, int dz, int4 n) {
    int x = cell%n.x+dx, y = (cell/n.x)%n.y+dy, z = cell/(n.x*n.y)+dz;
    if (!n.w && (x < 0 || x >= n.x || y < 0 || y >= n.y || z < 0 || z >= n.z))
        return -1;
    x = (x+n.x)%n.x;
    y = (y+n.y)%n.y;
    z = (z+n.z)%n.z;
    return x+n.x*(y+n.y*z);
}

/*
 * The neighbour cells of a cell in the Reference's order; returns how many.  With 3 or more
 * cells on every axis: the cell itself, then the offsets after (0, 0, 0) in (dz, dy, dx)
 * order (offsets 13..26 of the 27).  Otherwise every distinct cell of the full shell not
 * below the cell, in index order.
 */
inline DEVICE int sweepNeighbours(int cell, int4 n, bool halfShell, int* out) {
    int count = 0;
    for (int m = (halfShell ? 13 : 0); m < 27; m++) {
        const int other = sweepCellAt(cell, m%3-1, (m/3)%3-1, m/9-1, n);
        if (halfShell) {
            if (other >= 0)
                out[count++] = other;
            continue;
        }
        bool listed = (other < cell);
        for (int t = 0; t < count; t++)
            listed = listed || (out[t] == other);
        if (listed)
            continue;
        int t = count;
        for (; t > 0 && out[t-1] > other; t--)
            out[t] = out[t-1];
        out[t] = other;
        count++;
    }
    return count;
}

#define SWEEP_SHARDLOW 0
#define SWEEP_LOWE 1
#define SWEEP_PAIR_OU 2

typedef struct {
    int rule;
    mixed h, kT, imageVelocity;  /* U under shear */
    unsigned int seed, stream, stepLow, stepHigh;
    int partner;  /* xi the partner of the key's Box-Muller number (boxMullerPartner) */
    int virial;   /* whether to add the pairs' impulse virials */
    unsigned int transverseStream;  /* the stream of transverse friction's noise vectors (same step) */
    int transverse;  /* whether any type pair has transverse friction */
    SweepConstraints constraints;  /* a System's constraints (active = 0 without) */
} SweepRule;

/* The relative velocity along e of i and the image of j, which moves at images U along x. */
inline DEVICE mixed normalVelocity(mixed4 vi, mixed4 vj, mixed ex, mixed ey, mixed ez, mixed imagesU) {
    return ex*(vi.x-vj.x-imagesU)+ey*(vi.y-vj.y)+ez*(vi.z-vj.z);
}

/* The impulse J along e on the pair: v_i += J/m_i e, v_j -= J/m_j e (FreePairImpulse). */
inline DEVICE void applyImpulse(mixed4* vi, mixed4* vj, mixed ex, mixed ey, mixed ez, mixed J) {
    const mixed ji = J*(*vi).w, jj = J*(*vj).w;
    (*vi).x += ex*ji;
    (*vi).y += ey*ji;
    (*vi).z += ez*ji;
    (*vj).x -= ex*jj;
    (*vj).y -= ey*jj;
    (*vj).z -= ez*jj;
}

/* The impulse J along e on the pair, with the constraint forces it calls up (addConstraintForces). */
inline DEVICE void kickPair(SweepRule s, int i, int j, mixed4* vi, mixed4* vj, mixed ex, mixed ey, mixed ez, mixed J,
        GLOBAL mixed4* RESTRICT velocity) {
    applyImpulse(vi, vj, ex, ey, ez, J);
    addConstraintForces(s.constraints, i, j, vi, vj, ex, ey, ez, J, velocity);
}

/* An impulse J in any direction (across e): v_i += J/m_i, v_j -= J/m_j (FreePairImpulse::applyAcross). */
inline DEVICE void applyImpulseAcross(mixed4* vi, mixed4* vj, const mixed* J) {
    (*vi).x += J[0]*(*vi).w;
    (*vi).y += J[1]*(*vi).w;
    (*vi).z += J[2]*(*vi).w;
    (*vj).x -= J[0]*(*vj).w;
    (*vj).y -= J[1]*(*vj).w;
    (*vj).z -= J[2]*(*vj).w;
}

/* The part across e of the relative velocity of i and the image of j, which moves at images U along x. */
inline DEVICE void velocityAcross(mixed4 vi, mixed4 vj, mixed ex, mixed ey, mixed ez, mixed imagesU, mixed* u) {
    u[0] = vi.x-vj.x-imagesU;
    u[1] = vi.y-vj.y;
    u[2] = vi.z-vj.z;
    perpendicularInPlace(u, ex, ey, ez);
}

/*
 * The rule's update across e of a pair with transverse friction (ShardlowPairUpdate::applyAcross,
 * PairOrnsteinUhlenbeckUpdate::applyAcross): each axis of the relative velocity's part across e
 * with gammaPerp wD_perp and the part across e of the pair's noise vector, as one impulse in the
 * plane; returns it in J.  weight: the pair's 1 - r/rc; tp: the type pair's (rate, exponent, -, -).
 */
inline DEVICE void sweepPairAcross(SweepRule s, int i, int j, mixed ex, mixed ey, mixed ez, mixed imagesU, mixed weight, mixed4 tp,
        mixed mu, mixed f, mixed4* vi, mixed4* vj, mixed* J) {
    mixed zeta[3], u[3];
    normalVector(pairWords(s.seed, s.transverseStream, s.stepLow, s.stepHigh, i, j), i, j, zeta);
    perpendicularInPlace(zeta, ex, ey, ez);
    const mixed gamma = 2*tp.x*mu*f, wR = pairRandomWeight(weight, tp.y);
    velocityAcross(*vi, *vj, ex, ey, ez, imagesU, u);
    if (s.rule == SWEEP_SHARDLOW) {
        const mixed noise = pairNoiseAmplitude(gamma, s.kT)*wR*sqrt(s.h), friction = gamma*pairDissipativeWeight(wR)*s.h;
        mixed J2[3];
        for (int c = 0; c < 3; c++)
            J[c] = shardlowExplicitHalf(noise*zeta[c], friction, u[c]);
        applyImpulseAcross(vi, vj, J);
        velocityAcross(*vi, *vj, ex, ey, ez, imagesU, u);
        for (int c = 0; c < 3; c++)
            J2[c] = shardlowImplicitHalf(noise*zeta[c], friction, mu, u[c]);
        applyImpulseAcross(vi, vj, J2);
        for (int c = 0; c < 3; c++)
            J[c] += J2[c];
        return;
    }
    const mixed x = gamma*pairDissipativeWeight(wR)*s.h/mu, decay = exp(-x), spread = sqrt(-s.kT/mu*expm1(-2*x));
    for (int c = 0; c < 3; c++)
        J[c] = mu*(pairOUVelocity(u[c], decay, spread, zeta[c])-u[c]);
    applyImpulseAcross(vi, vj, J);
}

/*
 * One pair (i, j) at d = r_i - r_j (d.w: the images of b taken off): the rule's update of both velocities in place
 * (ShardlowPairUpdate, LowePairUpdate, PairOrnsteinUhlenbeckUpdate).  p: the type pair's
 * (friction or collision rate, rc, weight exponent s, rc^2); tp its transverse friction's
 * (rate, exponent, -, -); f: the pair's thermostat factor (0: the pair is left alone).  The
 * virial of the impulse is added to `virial` (if s.virial).
 */
inline DEVICE void sweepPair(SweepRule s, int i, int j, mixed4 d, mixed4 p, mixed4 tp, mixed f, GLOBAL mixed4* RESTRICT velocity,
        mixed* virial) {
    const mixed dx = d.x, dy = d.y, dz = d.z;
    const mixed r2 = dx*dx+dy*dy+dz*dz;
    if (r2 >= p.w || r2 == 0 || f == 0)
        return;
    mixed4 vi = velocity[i], vj = velocity[j];
    if (vi.w == 0 || vj.w == 0)
        return;
    const PhiloxWords w = pairWords(s.seed, s.stream, s.stepLow, s.stepHigh, i, j);
    if (s.rule == SWEEP_LOWE && !loweCollides(((mixed) w.v[2])*(mixed) 2.3283064365386963e-10f, p.x*f, s.h))
        return;
    const mixed r = sqrt(r2);
    const mixed ex = dx/r, ey = dy/r, ez = dz/r;
    const mixed weight = pairLinearWeight(r, p.y), wR = pairRandomWeight(weight, p.z);
    const mixed freeMu = 1/(vi.w+vj.w);
    const mixed gamma = 2*p.x*freeMu*f;  // 2 mu friction f
    // The reduced mass the impulse sees: mu_eff with constraints (1/mu_eff = 0: they hold the pair rigid).
    const mixed inverseMu = (s.constraints.active ? constrainedInverseMu(s.constraints, i, j, ex, ey, ez, velocity) : vi.w+vj.w);
    if (inverseMu == 0)
        return;
    const mixed mu = (s.constraints.active ? 1/inverseMu : freeMu);
    const mixed xi = (s.partner ? boxMullerPartner(w) : boxMuller(w));
    const mixed imagesU = d.w*s.imageVelocity;
    mixed u = normalVelocity(vi, vj, ex, ey, ez, imagesU);
    mixed J;
    if (s.rule == SWEEP_SHARDLOW) {
        const mixed noise = pairNoiseAmplitude(gamma, s.kT)*wR*xi*sqrt(s.h);
        const mixed friction = gamma*pairDissipativeWeight(wR)*s.h;
        J = shardlowExplicitHalf(noise, friction, u);
        kickPair(s, i, j, &vi, &vj, ex, ey, ez, J, velocity);
        u = normalVelocity(vi, vj, ex, ey, ez, imagesU);
        const mixed J2 = shardlowImplicitHalf(noise, friction, mu, u);
        kickPair(s, i, j, &vi, &vj, ex, ey, ez, J2, velocity);
        J += J2;
    }
    else if (s.rule == SWEEP_LOWE) {
        J = loweImpulse(u, xi, mu, s.kT/mu);
        kickPair(s, i, j, &vi, &vj, ex, ey, ez, J, velocity);
    }
    else {
        // 1 - decay^2 as -expm1(-2x): in float, 1 - decay*decay loses its digits when decay is near 1 (small wR).
        const mixed x = gamma*pairDissipativeWeight(wR)*s.h/mu;
        const mixed target = pairOUVelocity(u, exp(-x), sqrt(-s.kT/mu*expm1(-2*x)), xi);
        J = mu*(target-u);
        kickPair(s, i, j, &vi, &vj, ex, ey, ez, J, velocity);
    }
    mixed across[3] = {0, 0, 0};
    if (tp.x != 0 && s.rule != SWEEP_LOWE)
        sweepPairAcross(s, i, j, ex, ey, ez, imagesU, weight, tp, mu, f, &vi, &vj, across);
    velocity[i] = vi;
    velocity[j] = vj;
    if (s.virial) {
        addVirialAlong(virial, dx, dy, dz, J/r);
        addVirialOuter(virial, dx, dy, dz, across[0], across[1], across[2]);
    }
}

/* Every pair of one cell, in the sweep order or (reverse) exactly the opposite order. */
inline DEVICE void sweepCell(SweepRule s, int cell, bool reverse, bool halfShell, GLOBAL const mixed4* RESTRICT position,
        GLOBAL mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT atomType, int numTypes, GLOBAL const mixed4* RESTRICT typeParams,
        mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC, int4 numCells, GLOBAL const int* RESTRICT cellStart,
        GLOBAL const int* RESTRICT cellAtoms, GLOBAL const int* RESTRICT exceptionStart, GLOBAL const int* RESTRICT exceptionPartner,
        GLOBAL const mixed* RESTRICT exceptionFactor,
        GLOBAL const mixed4* RESTRICT transverseParams, mixed* virial) {
    int neighbours[27];
    const int numNeighbours = sweepNeighbours(cell, numCells, halfShell, neighbours);
    const int first = cellStart[cell], last = cellStart[cell+1];
    for (int m = 0; m < last-first; m++) {
        const int slotI = (reverse ? last-1-m : first+m);
        const int i = cellAtoms[slotI];
        const mixed4 ri = position[i];
        for (int q = 0; q < numNeighbours; q++) {
            const int other = neighbours[reverse ? numNeighbours-1-q : q];
            const int begin = (other == cell ? slotI+1 : cellStart[other]), end = cellStart[other+1];
            for (int t = 0; t < end-begin; t++) {
                const int j = cellAtoms[reverse ? end-1-t : begin+t];
                const mixed4 rj = position[j];
                const int typePair = atomType[i]*numTypes+atomType[j];
                sweepPair(s, i, j, nearestDisplacement(ri, rj, boxSize, invBoxSize, boxC), typeParams[typePair],
                          s.transverse ? transverseParams[typePair] : make_mixed4(0, 0, 0, 0),
                          thermostatFactor(i, j, exceptionStart, exceptionPartner, exceptionFactor), velocity, virial);
            }
        }
    }
}

/*
 * One colour's cells (colour (x mod 3) + 3 (y mod 3) + 9 (z mod 3)), a work item each; or,
 * colour < 0 (fewer than 3 cells on an axis of a periodic grid), every cell in order in one
 * work item.  An open grid is coloured whatever its size, as the Reference colours it.
 */
KERNEL void sweepColour(int colour, int reverse, int rule, mixed h, mixed kT, unsigned int seed, unsigned int stream,
        unsigned int stepLow, unsigned int stepHigh, GLOBAL const mixed4* RESTRICT position, GLOBAL mixed4* RESTRICT velocity,
        GLOBAL const int* RESTRICT atomType, int numTypes, GLOBAL const mixed4* RESTRICT typeParams, mixed4 boxSize,
        mixed4 invBoxSize, mixed4 boxC, int4 numCells, GLOBAL const int* RESTRICT cellStart, GLOBAL const int* RESTRICT cellAtoms,
        int partner,
        GLOBAL const int* RESTRICT exceptionStart, GLOBAL const int* RESTRICT exceptionPartner, GLOBAL const mixed* RESTRICT exceptionFactor,
        int virial, int virialStride, GLOBAL mixed* RESTRICT virialRows, mixed imageVelocity, unsigned int transverseStream,
        int transverse, GLOBAL const mixed4* RESTRICT transverseParams, int constrained, GLOBAL const int* RESTRICT clusterOf,
        GLOBAL const int* RESTRICT clusterStart, GLOBAL const int2* RESTRICT constraintAtoms, GLOBAL const mixed4* RESTRICT constraintDirection,
        GLOBAL const int* RESTRICT matrixStart, GLOBAL const mixed* RESTRICT clusterMatrix) {
    SweepRule s;
    const SweepConstraints constraints = {constrained, clusterOf, clusterStart, constraintAtoms, constraintDirection, matrixStart, clusterMatrix};
    s.constraints = constraints;
    s.rule = rule;
    s.h = h;
    s.kT = kT;
    s.seed = seed;
    s.stream = stream;
    s.stepLow = stepLow;
    s.stepHigh = stepHigh;
    s.partner = partner;
    s.virial = virial;
    s.imageVelocity = imageVelocity;
    s.transverseStream = transverseStream;
    s.transverse = transverse;
    mixed w[6] = {0, 0, 0, 0, 0, 0};
    if (colour < 0) {
        const int total = numCells.x*numCells.y*numCells.z;
        if (GLOBAL_ID == 0) {
            for (int c = 0; c < total; c++)
                sweepCell(s, reverse ? total-1-c : c, reverse, false, position, velocity, atomType, numTypes, typeParams,
                          boxSize, invBoxSize, boxC, numCells, cellStart, cellAtoms, exceptionStart, exceptionPartner, exceptionFactor,
                          transverseParams, w);
            if (virial)
                addVirialRow(virialRows, 0, virialStride, w);
        }
        return;
    }
    // The colour's cells along each axis: those of the axis's residue modulo 3.  With
    // constraints an impulse reaches beyond its pair, so one work item sweeps them in order.
    const int px = (numCells.x-colour%3+2)/3, py = (numCells.y-(colour/3)%3+2)/3, pz = (numCells.z-colour/9+2)/3;
    const bool halfShell = (numCells.x >= 3 && numCells.y >= 3 && numCells.z >= 3);
    const int cells = px*py*pz;
    for (int m = (constrained ? 0 : GLOBAL_ID); m < (constrained && GLOBAL_ID > 0 ? 0 : cells); m += (constrained ? 1 : GLOBAL_SIZE)) {
        const int t = (constrained && reverse ? cells-1-m : m);
        const int x = colour%3+3*(t%px), y = (colour/3)%3+3*((t/px)%py), z = colour/9+3*(t/(px*py));
        sweepCell(s, x+numCells.x*(y+numCells.y*z), reverse, halfShell, position, velocity, atomType, numTypes, typeParams,
                  boxSize, invBoxSize, boxC, numCells, cellStart, cellAtoms, exceptionStart, exceptionPartner, exceptionFactor,
                  transverseParams, w);
    }
    if (virial && GLOBAL_ID < (constrained ? 1 : cells))
        addVirialRow(virialRows, GLOBAL_ID, virialStride, w);
}

/* velm[slot] = velocity[atom] after a sweep; the velocity check. */
KERNEL void scatterVelocities(int numAtoms, GLOBAL const mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL mixed4* RESTRICT velm, mixed bound, GLOBAL int* RESTRICT status) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const mixed4 v = velocity[atomIndex[k]];
        velm[k] = v;
        checkVelocity(v, bound, status);
    }
}

/* v += kick/m F ; r += driftTime v, with F the carried force (by atom); with constraints the move goes to posDelta (drift). */
KERNEL void kickDrift(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, GLOBAL mixed4* RESTRICT velm,
        GLOBAL const int* RESTRICT atomIndex, GLOBAL const mm_long* RESTRICT carried, mixed kick, mixed driftTime, mixed maxMove2,
        GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue, int constrained, GLOBAL mixed4* RESTRICT posDelta,
        GLOBAL mixed4* RESTRICT driftMove) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        mixed4 v = velm[k];
        v = addScaledForce(v, carried, a, numAtoms, kick*v.w);
        velm[k] = v;
        drift(posq, posqCorrection, k, make_mixed4(v.x*driftTime, v.y*driftTime, v.z*driftTime, 0), maxMove2, status, moveValue,
              constrained, posDelta, driftMove);
    }
}

/* The carried force becomes OpenMM's conservative force (by atom); then, if kick != 0, v += kick/m F and the velocity check. */
KERNEL void takeConservativeForce(int numAtoms, int paddedNumAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mm_long* RESTRICT conservative, GLOBAL mm_long* RESTRICT carried, mixed kick, mixed bound,
        GLOBAL int* RESTRICT status) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        for (int d = 0; d < 3; d++)
            carried[a+d*numAtoms] = conservative[k+d*paddedNumAtoms];
        if (kick == 0)
            continue;
        mixed4 v = velm[k];
        v = addScaledForce(v, carried, a, numAtoms, kick*v.w);
        velm[k] = v;
        checkVelocity(v, bound, status);
    }
}
