/*
 * What every openmm-dpd device program shares: positions (with the mixed-precision
 * correction), forces in 64-bit fixed point (OpenMM's scale, 2^32 per kJ/mol/nm), and the
 * nearest image in a rectangular box, or in one whose b is tilted along x (Lees-Edwards).
 */

inline DEVICE mixed4 loadPosition(GLOBAL const real4* RESTRICT posq, GLOBAL const real4* RESTRICT posqCorrection, int k) {
    const real4 a = posq[k];
#ifdef OPENMMDPD_MIXED
    const real4 b = posqCorrection[k];
    return make_mixed4(a.x+(mixed) b.x, a.y+(mixed) b.y, a.z+(mixed) b.z, 0);
#else
    return make_mixed4(a.x, a.y, a.z, 0);
#endif
}

inline DEVICE void storePosition(GLOBAL real4* RESTRICT posq, GLOBAL real4* RESTRICT posqCorrection, int k, mixed4 r) {
    const real w = posq[k].w;
#ifdef OPENMMDPD_MIXED
    posq[k] = make_real4((real) r.x, (real) r.y, (real) r.z, w);
    posqCorrection[k] = make_real4((real) (r.x-(real) r.x), (real) (r.y-(real) r.y), (real) (r.z-(real) r.z), 0);
#else
    posq[k] = make_real4(r.x, r.y, r.z, w);
#endif
}

/* Conversion truncates toward zero, so toFixed(-x) == -toFixed(x): a pair adds exactly opposite numbers. */
inline DEVICE mm_long toFixed(mixed x) {
    return (mm_long) (x*(mixed) 4294967296.0f);
}

inline DEVICE mixed fromFixed(mm_long x) {
    return ((mixed) x)*(mixed) 2.3283064365386963e-10f;
}

/* v + scale F, F an atom's fixed-point force in an array laid out by component (x, y, z numAtoms apart). */
inline DEVICE mixed4 addScaledForce(mixed4 v, GLOBAL const mm_long* RESTRICT force, int a, int numAtoms, mixed scale) {
    v.x += fromFixed(force[a])*scale;
    v.y += fromFixed(force[a+numAtoms])*scale;
    v.z += fromFixed(force[a+2*numAtoms])*scale;
    return v;
}

inline DEVICE mixed nearestImage(mixed d, mixed size, mixed invSize) {
    return d-floor(d*invSize+(mixed) 0.5f)*size;
}

/*
 * r_a - r_b at its nearest image in a box of OpenMM's reduced form: a = (Lx, 0, 0), b = (tilt,
 * Ly, 0), c = boxC.xyz, where (Lx, Ly, Lz) = boxSize.xyz and tilt = boxSize.w (Lees-Edwards
 * shear tilts b; c is (0, 0, Lz) but in a triclinic box).  Images are taken off along c, then
 * b, then a, as minimumImage on the host.  w = the number of b taken off, whose image moves at
 * w U along x under shear (docs/theory/lees-edwards.md).
 */
inline DEVICE mixed4 nearestDisplacement(mixed4 ra, mixed4 rb, mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC) {
    const mixed cImages = floor((ra.z-rb.z)*invBoxSize.z+(mixed) 0.5f);
    const mixed dz = ra.z-rb.z-cImages*boxSize.z;
    const mixed y = ra.y-rb.y-cImages*boxC.y;
    const mixed images = floor(y*invBoxSize.y+(mixed) 0.5f);
    const mixed dy = y-images*boxSize.y;
    const mixed dx = nearestImage(ra.x-rb.x-cImages*boxC.x-images*boxSize.w, boxSize.x, invBoxSize.x);
    return make_mixed4(dx, dy, dz, images);
}

/*
 * The displacement of a pair seen from either of its particles (a at ra, b at rb) as from the
 * lower index, r_lo - r_hi: both particles then take the same rounding.
 */
inline DEVICE mixed4 loHiDisplacement(bool aIsLo, mixed4 ra, mixed4 rb, mixed4 boxSize, mixed4 invBoxSize, mixed4 boxC) {
    return (aIsLo ? nearestDisplacement(ra, rb, boxSize, invBoxSize, boxC) : nearestDisplacement(rb, ra, boxSize, invBoxSize, boxC));
}

/* f += sign d scale in fixed point: with sign +1 on the lower index and -1 on the higher, a pair adds exactly opposite forces. */
inline DEVICE void addFixedAlong(mm_long* f, mm_long sign, mixed4 d, mixed scale) {
    f[0] += sign*toFixed(d.x*scale);
    f[1] += sign*toFixed(d.y*scale);
    f[2] += sign*toFixed(d.z*scale);
}

/*
 * Finite and below `bound` (also false for NaN).  Written as one ordered comparison because
 * OpenMM compiles with fast math, under which isnan() and isinf() may be folded away.
 */
inline DEVICE bool withinBound(mixed x, mixed bound) {
    return x <= bound;
}

/*
 * t += c d d^T, t a symmetric tensor as (xx, yy, zz, xy, xz, yz): the virial r F e e^T of a
 * central pair force F e at d = r e, with c = F/r.
 */
inline DEVICE void addVirialAlong(mixed* t, mixed dx, mixed dy, mixed dz, mixed c) {
    t[0] += c*dx*dx;
    t[1] += c*dy*dy;
    t[2] += c*dz*dz;
    t[3] += c*dx*dy;
    t[4] += c*dx*dz;
    t[5] += c*dy*dz;
}

/*
 * t += the virial r F^T of a pair force F not along r (transverse friction), in the order the
 * host's addOuter writes it (PressureTensor.h): the diagonal r_a F_a, and r_b F_a for a < b.
 */
inline DEVICE void addVirialOuter(mixed* t, mixed dx, mixed dy, mixed dz, mixed fx, mixed fy, mixed fz) {
    t[0] += dx*fx;
    t[1] += dy*fy;
    t[2] += dz*fz;
    t[3] += dy*fx;
    t[4] += dz*fx;
    t[5] += dz*fy;
}

/* The part of (x, y, z) perpendicular to the unit vector e (PairGeometry::perpendicular), in place. */
inline DEVICE void perpendicularInPlace(mixed* x, mixed ex, mixed ey, mixed ez) {
    const mixed eDotX = ex*x[0]+ey*x[1]+ez*x[2];
    x[0] = perpendicularPart(x[0], eDotX, ex);
    x[1] = perpendicularPart(x[1], eDotX, ey);
    x[2] = perpendicularPart(x[2], eDotX, ez);
}

/* rows[k + c stride] += t[c]: a thread's tensor into its own row of a tensor array laid out by component. */
inline DEVICE void addVirialRow(GLOBAL mixed* RESTRICT rows, int k, int stride, const mixed* t) {
    for (int c = 0; c < 6; c++)
        rows[k+c*stride] += t[c];
}

/* The thermostat factor f of the pair of atoms (a, b): its exception's, else 1 (exceptions listed by the lower atom index). */
inline DEVICE mixed thermostatFactor(int a, int b, GLOBAL const int* RESTRICT exceptionStart, GLOBAL const int* RESTRICT exceptionPartner,
        GLOBAL const mixed* RESTRICT exceptionFactor) {
    const int lo = min(a, b), hi = max(a, b);
    for (int k = exceptionStart[lo]; k < exceptionStart[lo+1]; k++)
        if (exceptionPartner[k] == hi)
            return exceptionFactor[k];
    return 1;
}
