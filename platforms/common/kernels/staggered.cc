/*
 * The steps of StaggeredDPDIntegrator (platforms/reference/src/ReferenceStaggeredDynamics.cpp
 * is the definition, docs/theory/staggered.md the notation).  By atom, in fixed point: slow the
 * slow force F carried from the step before, newSlow F^ of this one, fast and newFast the fast
 * force Fp on the polymer particles (polymer[a] != 0).  Dt is the outer step, dt = Dt/K.
 */

/* The force of each slot (OpenMM's buffer) by atom: every atom's, or the polymer's alone. */
KERNEL void staggeredTakeForce(int numAtoms, int paddedNumAtoms, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mm_long* RESTRICT force, GLOBAL const int* RESTRICT polymer, int polymerOnly, GLOBAL mm_long* RESTRICT out) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        if (polymerOnly && !polymer[a])
            continue;
        for (int d = 0; d < 3; d++)
            out[a+d*numAtoms] = force[k+d*paddedNumAtoms];
    }
}

/*
 * r_s += Dt u_s + Dt^2/(2m) F_s ;  r^^_p = r_p + (1 - mu) [Dt u_p + Dt^2/(2m) (F_p + Fp_p)] ;
 * predicted: u^_s = u_s + lambda Dt F_s/m, u^^_p = a u_p + (1 - a) [u_p + lambda Dt (F_p + Fp_p)/m].
 * The polymer's positions and velocities at the start are kept for the sub-cycle.
 */
KERNEL void staggeredPredict(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT polymer,
        GLOBAL const mm_long* RESTRICT slow, GLOBAL const mm_long* RESTRICT fast, GLOBAL mixed4* RESTRICT predicted,
        GLOBAL mixed4* RESTRICT startPosition, GLOBAL mixed4* RESTRICT startVelocity, mixed Dt, mixed lambda, mixed mu, mixed a,
        mixed maxMove2, GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int atom = atomIndex[k];
        const int inPolymer = polymer[atom];
        const mixed4 v = velm[k];
        mixed f[3];
        for (int d = 0; d < 3; d++)
            f[d] = fromFixed(slow[atom+d*numAtoms])+(inPolymer ? fromFixed(fast[atom+d*numAtoms]) : 0);
        const mixed square = 0.5f*Dt*Dt*v.w, kick = lambda*Dt*v.w;
        mixed4 move = make_mixed4(v.x*Dt+f[0]*square, v.y*Dt+f[1]*square, v.z*Dt+f[2]*square, 0);
        mixed4 u = make_mixed4(v.x+f[0]*kick, v.y+f[1]*kick, v.z+f[2]*kick, v.w);
        if (inPolymer) {
            startPosition[atom] = loadPosition(posq, posqCorrection, k);
            startVelocity[atom] = v;
            move.x *= 1-mu;
            move.y *= 1-mu;
            move.z *= 1-mu;
            u.x = v.x*a+u.x*(1-a);
            u.y = v.y*a+u.y*(1-a);
            u.z = v.z*a+u.z*(1-a);
        }
        predicted[atom] = u;
        movePosition(posq, posqCorrection, k, move, maxMove2, status, moveValue);
    }
}

/* u_s += Dt/(2m) (F_s + F^_s). */
KERNEL void staggeredKickSolvent(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const int* RESTRICT polymer, GLOBAL const mm_long* RESTRICT slow, GLOBAL const mm_long* RESTRICT newSlow, mixed Dt,
        mixed bound, GLOBAL int* RESTRICT status) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        if (polymer[a])
            continue;
        mixed4 v = velm[k];
        const mixed scale = 0.5f*Dt*v.w;
        v.x += (fromFixed(slow[a])+fromFixed(newSlow[a]))*scale;
        v.y += (fromFixed(slow[a+numAtoms])+fromFixed(newSlow[a+numAtoms]))*scale;
        v.z += (fromFixed(slow[a+2*numAtoms])+fromFixed(newSlow[a+2*numAtoms]))*scale;
        velm[k] = v;
        checkVelocity(v, bound, status);
    }
}

/* The polymer back to its positions and velocities at the start of the outer step. */
KERNEL void staggeredRestorePolymer(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT polymer,
        GLOBAL const mixed4* RESTRICT startPosition, GLOBAL const mixed4* RESTRICT startVelocity) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        if (!polymer[a])
            continue;
        storePosition(posq, posqCorrection, k, startPosition[a]);
        velm[k] = startVelocity[a];
    }
}

/* A sub-step's drift: r_p += dt u_p + dt^2/(2m) (F^^_p + Fp_p), F^^ = b F + (1 - b) F^. */
KERNEL void staggeredSubStepDrift(int numAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex, GLOBAL const int* RESTRICT polymer,
        GLOBAL const mm_long* RESTRICT slow, GLOBAL const mm_long* RESTRICT newSlow, GLOBAL const mm_long* RESTRICT fast, mixed dt,
        mixed b, mixed maxMove2, GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        if (!polymer[a])
            continue;
        const mixed4 v = velm[k];
        const mixed square = 0.5f*dt*dt*v.w;
        mixed f[3];
        for (int d = 0; d < 3; d++)
            f[d] = fromFixed(slow[a+d*numAtoms])*b+fromFixed(newSlow[a+d*numAtoms])*(1-b)+fromFixed(fast[a+d*numAtoms]);
        movePosition(posq, posqCorrection, k, make_mixed4(v.x*dt+f[0]*square, v.y*dt+f[1]*square, v.z*dt+f[2]*square, 0), maxMove2,
                     status, moveValue);
    }
}

/*
 * A sub-step's kick: u_p += dt/(2m) [(Fold + Fp_p) + (Fnew + Fp*_p)], the slow force at the
 * sub-step's two ends Fold = oldOfF F + oldOfNewF F^, Fnew = newOfF F + newOfNewF F^; then Fp <- Fp*.
 */
KERNEL void staggeredSubStepKick(int numAtoms, GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const int* RESTRICT polymer, GLOBAL const mm_long* RESTRICT slow, GLOBAL const mm_long* RESTRICT newSlow,
        GLOBAL mm_long* RESTRICT fast, GLOBAL const mm_long* RESTRICT newFast, mixed dt, mixed4 weights, mixed bound,
        GLOBAL int* RESTRICT status) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        if (!polymer[a])
            continue;
        mixed4 v = velm[k];
        const mixed scale = 0.5f*dt*v.w;
        mixed kick[3];
        for (int d = 0; d < 3; d++) {
            const int i = a+d*numAtoms;
            const mixed F = fromFixed(slow[i]), newF = fromFixed(newSlow[i]);
            const mixed oldSlow = F*weights.x+newF*weights.y, nextSlow = F*weights.z+newF*weights.w;
            kick[d] = ((oldSlow+fromFixed(fast[i]))+(nextSlow+fromFixed(newFast[i])))*scale;
            fast[i] = newFast[i];
        }
        v.x += kick[0];
        v.y += kick[1];
        v.z += kick[2];
        velm[k] = v;
        checkVelocity(v, bound, status);
    }
}
