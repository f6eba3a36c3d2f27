/*
 * A sweep's pair impulse in a System with constraints, as ConstrainedPairImpulse on the host
 * (docs/theory/shardlow.md): J along e at i and -J at j with the constraint forces it calls
 * up, d = M^-1 (g - C^T lambda), lambda solving K lambda = C M^-1 g with K = C M^-1 C^T, over
 * the constraint clusters of i and j; the pair's 1/mu_eff = g.M^-1 g - (C M^-1 g).lambda.
 *
 * A cluster c holds the constraints [clusterStart[c], clusterStart[c+1]), each with its atoms
 * (a, b) and unit direction from b to a at the sweep's positions, and W = K^+ (row-major,
 * from matrixStart[c]): K_SS^-1 on a set S of independent constraints, 0 on the redundant ones
 * (any solution of K lambda = b gives the same C^T lambda, since b lies in K's range).  A
 * direction's w notes whether its constraint is in S.
 */

typedef struct {
    int active;
    GLOBAL const int* clusterOf;
    GLOBAL const int* clusterStart;
    GLOBAL const int2* atoms;
    GLOBAL const mixed4* direction;
    GLOBAL const int* matrixStart;
    GLOBAL const mixed* matrix;
} SweepConstraints;

/*
 * Each cluster's directions and W at the positions of the sweep (position, velocity by atom:
 * (v, 1/m)).  W by Goodnight's sweep operator on K with the largest remaining pivot first;
 * a pivot below 1e-12 of the largest diagonal marks the rest redundant, as the host's LDLT.
 */
KERNEL void factorConstraintClusters(int numClusters, GLOBAL const int* RESTRICT clusterStart, GLOBAL const int2* RESTRICT atoms,
        GLOBAL const mixed4* RESTRICT position, GLOBAL const mixed4* RESTRICT velocity, GLOBAL const int* RESTRICT matrixStart,
        GLOBAL mixed4* RESTRICT direction, GLOBAL mixed* RESTRICT matrix) {
    for (int c = GLOBAL_ID; c < numClusters; c += GLOBAL_SIZE) {
        const int first = clusterStart[c], n = clusterStart[c+1]-first;
        GLOBAL mixed* A = matrix+matrixStart[c];
        for (int k = 0; k < n; k++) {
            const mixed4 ra = position[atoms[first+k].x], rb = position[atoms[first+k].y];
            const mixed dx = ra.x-rb.x, dy = ra.y-rb.y, dz = ra.z-rb.z;
            const mixed inverseLength = 1/sqrt(dx*dx+dy*dy+dz*dz);
            direction[first+k] = make_mixed4(dx*inverseLength, dy*inverseLength, dz*inverseLength, 0);
        }
        mixed largest = 0;
        for (int k = 0; k < n; k++)
            for (int l = 0; l < n; l++) {
                const int2 p = atoms[first+k], q = atoms[first+l];
                const mixed shared = (p.x == q.x ? velocity[p.x].w : 0)+(p.y == q.y ? velocity[p.y].w : 0)-
                                     (p.x == q.y ? velocity[p.x].w : 0)-(p.y == q.x ? velocity[p.y].w : 0);
                const mixed4 u = direction[first+k], v = direction[first+l];
                A[k*n+l] = shared*(u.x*v.x+u.y*v.y+u.z*v.z);
                largest = (k == l && A[k*n+l] > largest ? A[k*n+l] : largest);
            }
        GLOBAL mixed4* swept = direction+first;  // .w: 1 once swept
        for (int step = 0; step < n; step++) {
            int k = -1;
            for (int m = 0; m < n; m++)
                if (swept[m].w == 0 && (k < 0 || A[m*n+m] > A[k*n+k]))
                    k = m;
            const mixed d = A[k*n+k];
            if (!(d > (mixed) 1e-12f*largest))
                break;
            for (int i = 0; i < n; i++)
                for (int j = 0; j < n; j++)
                    if (i != k && j != k)
                        A[i*n+j] -= A[i*n+k]*A[k*n+j]/d;
            for (int i = 0; i < n; i++)
                if (i != k) {
                    A[i*n+k] /= d;
                    A[k*n+i] /= d;
                }
            A[k*n+k] = -1/d;
            swept[k].w = 1;
        }
        // The swept block holds -K_SS^-1.
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++)
                A[i*n+j] = (swept[i].w != 0 && swept[j].w != 0 ? -A[i*n+j] : 0);
    }
}

/* b_l = c_l . (g_a/m_a - g_b/m_b) of constraint l for the impulse g (e at i, -e at j). */
inline DEVICE mixed clusterImpulseTerm(SweepConstraints c, int l, int i, int j, mixed ex, mixed ey, mixed ez,
        GLOBAL const mixed4* RESTRICT velocity) {
    const int2 p = c.atoms[l];
    const mixed ga = (p.x == i ? velocity[i].w : p.x == j ? -velocity[j].w : 0);
    const mixed gb = (p.y == i ? velocity[i].w : p.y == j ? -velocity[j].w : 0);
    const mixed4 u = c.direction[l];
    return (ga-gb)*(u.x*ex+u.y*ey+u.z*ez);
}

/* lambda_k of constraint k (in cluster cluster's numbering) for a unit impulse on the pair: (W b)_k. */
inline DEVICE mixed clusterLambda(SweepConstraints c, int cluster, int k, int i, int j, mixed ex, mixed ey, mixed ez,
        GLOBAL const mixed4* RESTRICT velocity) {
    const int first = c.clusterStart[cluster], n = c.clusterStart[cluster+1]-first;
    GLOBAL const mixed* W = c.matrix+c.matrixStart[cluster];
    mixed lambda = 0;
    for (int l = 0; l < n; l++)
        lambda += W[k*n+l]*clusterImpulseTerm(c, first+l, i, j, ex, ey, ez, velocity);
    return lambda;
}

/* b.lambda of a cluster: what its constraints take off the pair's 1/mu. */
inline DEVICE mixed clusterResponse(SweepConstraints c, int cluster, int i, int j, mixed ex, mixed ey, mixed ez,
        GLOBAL const mixed4* RESTRICT velocity) {
    const int first = c.clusterStart[cluster], n = c.clusterStart[cluster+1]-first;
    mixed sum = 0;
    for (int k = 0; k < n; k++)
        sum += clusterImpulseTerm(c, first+k, i, j, ex, ey, ez, velocity)*clusterLambda(c, cluster, k, i, j, ex, ey, ez, velocity);
    return sum;
}

/* The constraint forces of a cluster for the impulse J on the pair: v_a -= lambda_k J/m_a c_k, v_b += lambda_k J/m_b c_k. */
inline DEVICE void spreadOverCluster(SweepConstraints c, int cluster, int i, int j, mixed ex, mixed ey, mixed ez, mixed J,
        GLOBAL mixed4* RESTRICT velocity) {
    const int first = c.clusterStart[cluster], n = c.clusterStart[cluster+1]-first;
    for (int k = 0; k < n; k++) {
        const mixed scale = clusterLambda(c, cluster, k, i, j, ex, ey, ez, velocity)*J;
        const int2 p = c.atoms[first+k];
        const mixed4 u = c.direction[first+k];
        mixed4 va = velocity[p.x];
        va.x -= u.x*scale*va.w;
        va.y -= u.y*scale*va.w;
        va.z -= u.z*scale*va.w;
        velocity[p.x] = va;
        mixed4 vb = velocity[p.y];
        vb.x += u.x*scale*vb.w;
        vb.y += u.y*scale*vb.w;
        vb.z += u.z*scale*vb.w;
        velocity[p.y] = vb;
    }
}

/*
 * 1/mu_eff of the pair (i, j) along e (its free 1/mu less its clusters' responses); 0 where the
 * constraints hold it rigid: below 1e-9 of the free 1/mu as on the host, or in single
 * precision 1e-5, since a rigid pair's rounding there leaves ~1e-7, and an impulse scaled by
 * that mu_eff would spread rounding errors of the order of the velocities themselves.
 */
inline DEVICE mixed constrainedInverseMu(SweepConstraints c, int i, int j, mixed ex, mixed ey, mixed ez, GLOBAL const mixed4* RESTRICT velocity) {
    const mixed free = velocity[i].w+velocity[j].w;
    mixed inverse = free;
    const int ci = c.clusterOf[i], cj = c.clusterOf[j];
    if (ci >= 0)
        inverse -= clusterResponse(c, ci, i, j, ex, ey, ez, velocity);
    if (cj >= 0 && cj != ci)
        inverse -= clusterResponse(c, cj, i, j, ex, ey, ez, velocity);
    const mixed rigid = (sizeof(mixed) == 8 ? (mixed) 1e-9f : (mixed) 1e-5f);
    return (inverse > rigid*free ? inverse : 0);
}

/*
 * After the free kick J along e on the pair (vi and vj its velocities in hand): where i or j is
 * constrained, the constraint forces over its clusters, in velocity (one work item sweeps a
 * System with constraints), and vi, vj read back.
 */
inline DEVICE void addConstraintForces(SweepConstraints c, int i, int j, mixed4* vi, mixed4* vj, mixed ex, mixed ey, mixed ez, mixed J,
        GLOBAL mixed4* RESTRICT velocity) {
    if (!c.active)
        return;
    const int ci = c.clusterOf[i], cj = c.clusterOf[j];
    if (ci < 0 && cj < 0)
        return;
    velocity[i] = *vi;
    velocity[j] = *vj;
    if (ci >= 0)
        spreadOverCluster(c, ci, i, j, ex, ey, ez, J, velocity);
    if (cj >= 0 && cj != ci)
        spreadOverCluster(c, cj, i, j, ex, ey, ez, J, velocity);
    *vi = velocity[i];
    *vj = velocity[j];
}
