/*
 * The update rules of DPDVVIntegrator (platforms/reference/src/ReferenceDPDVVDynamics.cpp
 * is the definition).  Particle data of OpenMM (posq, velm, its force buffer) is indexed by
 * slot, which OpenMM may reorder inside a force evaluation; what a step carries (the force,
 * by-atom velocities, the pair sums) is indexed by atom.  status: [0] a position is not
 * finite, [1] a particle moved too far (its square move in moveValue[0]), [2] a velocity is
 * not finite or above the instability bound on m v^2.
 */

KERNEL void gatherVelocities(int numAtoms, GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL mixed4* RESTRICT velocity) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE)
        velocity[atomIndex[k]] = velm[k];
}

/* out[atom] = FC[slot] + FD[atom] + FR[atom], or FC + FR (withDissipative = 0). */
KERNEL void sumForces(int numAtoms, int paddedNumAtoms, GLOBAL const int* RESTRICT atomIndex, GLOBAL const mm_long* RESTRICT conservative,
        GLOBAL const mm_long* RESTRICT fd, GLOBAL const mm_long* RESTRICT fr, int withDissipative, GLOBAL mm_long* RESTRICT out) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        for (int d = 0; d < 3; d++)
            out[a+d*numAtoms] = conservative[k+d*paddedNumAtoms]+fr[a+d*numAtoms]+(withDissipative ? fd[a+d*numAtoms] : 0);
    }
}

inline DEVICE void checkVelocity(mixed4 v, mixed bound, GLOBAL int* RESTRICT status) {
    const mixed v2 = v.x*v.x+v.y*v.y+v.z*v.z;
    if (!withinBound(v2, (mixed) 1e30f) || (v.w != 0 && !withinBound(v2/v.w, bound)))
        status[2] = 1;
}

inline DEVICE void movePosition(GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, int k, mixed4 move,
        mixed maxMove2, GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue) {
    mixed4 r = loadPosition(posq, posqCorrection, k);
    r.x += move.x;
    r.y += move.y;
    r.z += move.z;
    storePosition(posq, posqCorrection, k, r);
    const mixed move2 = move.x*move.x+move.y*move.y+move.z*move.z;
    if (!withinBound(r.x*r.x+r.y*r.y+r.z*r.z, (mixed) 1e30f))
        status[0] = 1;
    // Also past 1e15 nm, where the host finds the position finite and reports the move.
    if (!withinBound(move2, maxMove2)) {
        status[1] = 1;
        moveValue[0] = (float) move2;
    }
}

/*
 * A drift: with constraints, the move goes to posDelta for OpenMM's constraints to correct
 * (and is kept in driftMove: see applyConstrainedDrift); without, the position moves now.
 */
inline DEVICE void drift(GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, int k, mixed4 move, mixed maxMove2,
        GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue, int constrained, GLOBAL mixed4* RESTRICT posDelta,
        GLOBAL mixed4* RESTRICT driftMove) {
    if (constrained) {
        posDelta[k] = move;
        driftMove[k] = move;
    }
    else
        movePosition(posq, posqCorrection, k, move, maxMove2, status, moveValue);
}

/*
 * After OpenMM's constraints corrected posDelta: r += posDelta, and each particle with mass
 * has its velocity (and its by-atom copy, or predicted velocity) corrected by (posDelta - move)/dt.
 */
KERNEL void applyConstrainedDrift(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex, GLOBAL const mixed4* RESTRICT posDelta,
        GLOBAL const mixed4* RESTRICT driftMove, GLOBAL mixed4* RESTRICT velocity, mixed invDt, mixed maxMove2,
        GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const mixed4 delta = posDelta[k];
        movePosition(posq, posqCorrection, k, delta, maxMove2, status, moveValue);
        mixed4 v = velm[k];
        if (v.w == 0)
            continue;
        const mixed4 move = driftMove[k];
        const mixed cx = (delta.x-move.x)*invDt, cy = (delta.y-move.y)*invDt, cz = (delta.z-move.z)*invDt;
        v.x += cx;
        v.y += cy;
        v.z += cz;
        velm[k] = v;
        const int a = atomIndex[k];
        mixed4 u = velocity[a];
        u.x += cx;
        u.y += cy;
        u.z += cz;
        velocity[a] = u;
    }
}

/* Groot-Warren: r += dt v + dt^2/(2m) F;  velocity[atom] = v + lambda dt F/m (the predicted velocity). */
KERNEL void grootWarrenPart1(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex, GLOBAL const mm_long* RESTRICT carried,
        GLOBAL mixed4* RESTRICT velocity, mixed dt, mixed lambda, mixed maxMove2, GLOBAL int* RESTRICT status,
        GLOBAL float* RESTRICT moveValue, int constrained, GLOBAL mixed4* RESTRICT posDelta, GLOBAL mixed4* RESTRICT driftMove) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 v = velm[k];
        const mixed fx = fromFixed(carried[a]), fy = fromFixed(carried[a+numAtoms]), fz = fromFixed(carried[a+2*numAtoms]);
        const mixed moveScale = (mixed) 0.5f*dt*dt*v.w, kick = lambda*dt*v.w;
        drift(posq, posqCorrection, k, make_mixed4(v.x*dt+fx*moveScale, v.y*dt+fy*moveScale, v.z*dt+fz*moveScale, 0),
              maxMove2, status, moveValue, constrained, posDelta, driftMove);
        velocity[a] = make_mixed4(v.x+fx*kick, v.y+fy*kick, v.z+fz*kick, v.w);
    }
}

/* Groot-Warren: F' = FC + FD(predicted) + FR;  v += dt/(2m) (F + F');  F <- F'. */
KERNEL void grootWarrenPart2(int numAtoms, int paddedNumAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mm_long* RESTRICT conservative, GLOBAL const mm_long* RESTRICT fd, GLOBAL const mm_long* RESTRICT fr,
        GLOBAL mm_long* RESTRICT carried, mixed dt, mixed bound, GLOBAL int* RESTRICT status) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        mixed4 v = velm[k];
        const mixed scale = (mixed) 0.5f*dt*v.w;
        mixed f[3];
        for (int d = 0; d < 3; d++) {
            const mm_long next = conservative[k+d*paddedNumAtoms]+fd[a+d*numAtoms]+fr[a+d*numAtoms];
            f[d] = fromFixed(carried[a+d*numAtoms]+next)*scale;
            carried[a+d*numAtoms] = next;
        }
        v.x += f[0];
        v.y += f[1];
        v.z += f[2];
        velm[k] = v;
        checkVelocity(v, bound, status);
    }
}

/* DPD-VV (1), (2): v += dt/(2m) F;  r += dt v;  velocity[atom] = v. */
KERNEL void dpdvvPart1(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex, GLOBAL const mm_long* RESTRICT carried,
        GLOBAL mixed4* RESTRICT velocity, mixed dt, mixed maxMove2, GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue,
        int constrained, GLOBAL mixed4* RESTRICT posDelta, GLOBAL mixed4* RESTRICT driftMove) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        mixed4 v = velm[k];
        v = addScaledForce(v, carried, a, numAtoms, (mixed) 0.5f*dt*v.w);
        velm[k] = v;
        velocity[a] = v;
        drift(posq, posqCorrection, k, make_mixed4(v.x*dt, v.y*dt, v.z*dt, 0), maxMove2, status, moveValue, constrained, posDelta,
              driftMove);
    }
}

/* DPD-VV (4a): noDissipative[atom] = v + dt/(2m) (FC + FR), with carried[atom] = FC + FR already summed. */
KERNEL void dpdvvPart2(int numAtoms, GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mm_long* RESTRICT carried, GLOBAL mixed4* RESTRICT noDissipative, mixed dt) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 v = velm[k];
        noDissipative[a] = addScaledForce(v, carried, a, numAtoms, (mixed) 0.5f*dt*v.w);
    }
}

/* DPD-VV (4b), and each iteration of SC-VV's: v <- noDissipative + dt/(2m) FD. */
KERNEL void dpdvvDissipativeKick(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mixed4* RESTRICT noDissipative, GLOBAL const mm_long* RESTRICT fd, GLOBAL mixed4* RESTRICT velocity, mixed dt) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        const mixed4 v = addScaledForce(noDissipative[a], fd, a, numAtoms, (mixed) 0.5f*dt*velm[k].w);
        velm[k] = v;
        velocity[a] = v;
    }
}

/* DPD-VV (5): the carried force becomes FC + FR + FD(r, v); the step's velocity check. */
KERNEL void dpdvvPart3(int numAtoms, GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mm_long* RESTRICT fd, GLOBAL mm_long* RESTRICT carried, mixed bound, GLOBAL int* RESTRICT status) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        for (int d = 0; d < 3; d++)
            carried[a+d*numAtoms] += fd[a+d*numAtoms];
        checkVelocity(velm[k], bound, status);
    }
}
