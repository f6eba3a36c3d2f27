/*
 * The update rule of DenOtterClarkeIntegrator (platforms/reference/src/ReferenceDenOtterClarkeDynamics.cpp
 * is the definition): the step's measured terms, then the leap-frog with the fitted
 * prefactors.  Indexing and status flags as in dpdvv.cc.
 */

/*
 * Each work item's sums over its atoms with mass of FD.v, FD.FD and FR.FR dt (FR with its
 * 1/sqrt(dt)) at rows[item + c threads], c = 0, 1, 2: added on the host in double.
 */
KERNEL void denOtterClarkeTerms(int numAtoms, int threads, GLOBAL const mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex,
        GLOBAL const mm_long* RESTRICT fd, GLOBAL const mm_long* RESTRICT fr, mixed dt, GLOBAL mixed* RESTRICT rows) {
    if (GLOBAL_ID >= threads)
        return;
    mixed fdDotV = 0, fdDotFD = 0, frDotFR = 0;
    for (int k = GLOBAL_ID; k < numAtoms; k += threads) {
        const mixed4 v = velm[k];
        if (v.w == 0)
            continue;
        const int a = atomIndex[k];
        const mixed dx = fromFixed(fd[a]), dy = fromFixed(fd[a+numAtoms]), dz = fromFixed(fd[a+2*numAtoms]);
        const mixed rx = fromFixed(fr[a]), ry = fromFixed(fr[a+numAtoms]), rz = fromFixed(fr[a+2*numAtoms]);
        fdDotV += dx*v.x+dy*v.y+dz*v.z;
        fdDotFD += dx*dx+dy*dy+dz*dz;
        frDotFR += (rx*rx+ry*ry+rz*rz)*dt;
    }
    rows[GLOBAL_ID] = fdDotV;
    rows[GLOBAL_ID+threads] = fdDotFD;
    rows[GLOBAL_ID+2*threads] = frDotFR;
}

/* v += alpha dt/m (FC + FD) + beta dt/m FR;  r += dt v. */
KERNEL void denOtterClarkeStep(int numAtoms, int paddedNumAtoms, GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection,
        GLOBAL mixed4* RESTRICT velm, GLOBAL const int* RESTRICT atomIndex, GLOBAL const mm_long* RESTRICT conservative,
        GLOBAL const mm_long* RESTRICT fd, GLOBAL const mm_long* RESTRICT fr, mixed dt, mixed alpha, mixed beta, mixed maxMove2,
        mixed bound, GLOBAL int* RESTRICT status, GLOBAL float* RESTRICT moveValue, int constrained, GLOBAL mixed4* RESTRICT posDelta,
        GLOBAL mixed4* RESTRICT driftMove) {
    for (int k = GLOBAL_ID; k < numAtoms; k += GLOBAL_SIZE) {
        const int a = atomIndex[k];
        mixed4 v = velm[k];
        const mixed scale = dt*v.w;
        mixed f[3];
        for (int d = 0; d < 3; d++)
            f[d] = ((fromFixed(conservative[k+d*paddedNumAtoms])+fromFixed(fd[a+d*numAtoms]))*alpha+fromFixed(fr[a+d*numAtoms])*beta)*scale;
        v.x += f[0];
        v.y += f[1];
        v.z += f[2];
        velm[k] = v;
        checkVelocity(v, bound, status);
        drift(posq, posqCorrection, k, make_mixed4(v.x*dt, v.y*dt, v.z*dt, 0), maxMove2, status, moveValue, constrained, posDelta,
              driftMove);
    }
}
