// A Lane4 passed or returned by value is passed differently by code built for different
// vector units (the compiler warns of it); none crosses a call between such code here (the
// helpers and DPDPairForce's along-e forms are always inlined).
#pragma GCC diagnostic ignored "-Wpsabi"

#include "openmmdpd/DPDPairRows.h"
#include "openmmdpd/CpuFeatures.h"
#include "openmmdpd/PairEvaluators.h"
#include <cstddef>
#include <cstdint>

#ifdef OPENMMDPD_X86_VECTORS
#include <immintrin.h>
#endif

using namespace DPDPlugin;
using OpenMM::Vec3;

#ifdef OPENMMDPD_X86_VECTORS
namespace {

// The rows read e and wR, and gammaWD and sigmaWR, as one load each per pair.
static_assert(offsetof(PairGeometry, wR) == offsetof(PairGeometry, e) + 3 * sizeof(double), "e is followed by wR");
static_assert(offsetof(PairGeometry, sigmaWR) == offsetof(PairGeometry, gammaWD) + sizeof(double), "gammaWD by sigmaWR");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "a Vec3 is its three doubles");
static_assert(offsetof(DPDThermostatForces::KeptPair, gammaWD) == offsetof(DPDThermostatForces::KeptPair, e) + sizeof(Vec3),
              "a kept pair's e is followed by gammaWD");

inline const double* components(const Vec3& v) {
    return reinterpret_cast<const double*>(&v);
}

inline double* components(Vec3& v) {
    return reinterpret_cast<double*>(&v);
}

/** How far ahead (in pairs) the kept pairs' list is fetched. */
const int PREFETCH_PAIRS = 64;

/** The 160 bytes of four kept pairs PREFETCH_PAIRS ahead, as three lines (maybe past the list: a prefetch does not fault). */
template <bool ForWriting>
__attribute__((target("avx2,prfchw"), always_inline)) inline void prefetchFourPairsAhead(const DPDThermostatForces::KeptPair* pairs) {
    const uintptr_t ahead = reinterpret_cast<uintptr_t>(pairs) + PREFETCH_PAIRS * sizeof(*pairs);
    for (int line = 0; line < 3; line++)
        __builtin_prefetch(reinterpret_cast<const void*>(ahead + 64 * line), ForWriting ? 1 : 0);
}

/** Four rows of four as four columns: column c lane l is row l's element c. */
__attribute__((target("avx2"), always_inline)) inline void transpose(__m256d r0, __m256d r1, __m256d r2, __m256d r3, Lane4& c0,
                                                                     Lane4& c1, Lane4& c2, Lane4& c3) {
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
    c0 = (Lane4) _mm256_permute2f128_pd(t0, t2, 0x20);
    c1 = (Lane4) _mm256_permute2f128_pd(t1, t3, 0x20);
    c2 = (Lane4) _mm256_permute2f128_pd(t0, t2, 0x31);
    c3 = (Lane4) _mm256_permute2f128_pd(t1, t3, 0x31);
}

/** Four vectors' x, y and z lanes stored as four Vec3s (96 bytes from out). */
__attribute__((target("avx2"), always_inline)) inline void storeVec3s(const Lane4& x, const Lane4& y, const Lane4& z, Vec3* out) {
    const __m256d xy02 = _mm256_unpacklo_pd((__m256d) x, (__m256d) y);  // x0 y0 x2 y2
    const __m256d xy13 = _mm256_unpackhi_pd((__m256d) x, (__m256d) y);  // x1 y1 x3 y3
    const __m256d zx = _mm256_unpacklo_pd((__m256d) z, xy13);            // z0 x1 z2 x3
    const __m256d yz = _mm256_unpackhi_pd(xy13, (__m256d) z);            // y1 z1 y3 z3
    double* to = reinterpret_cast<double*>(out);
    _mm256_storeu_pd(to, _mm256_permute2f128_pd(xy02, zx, 0x20));
    _mm256_storeu_pd(to + 4, _mm256_permute2f128_pd(yz, xy02, 0x30));
    _mm256_storeu_pd(to + 8, _mm256_permute2f128_pd(zx, yz, 0x31));
}

/** Two doubles from each of a and b, as a0 a1 b0 b1. */
__attribute__((target("avx2"), always_inline)) inline __m256d twoPairs(const double* a, const double* b) {
    return _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(a)), _mm_loadu_pd(b), 1);
}

/** v_p - v_q of four pairs of slots (p[l], q[l]) as x, y, z lanes. */
__attribute__((target("avx2"), always_inline)) inline void relativeVelocities(const Vec3* v, const int* p, const int* q, Lane4& x,
                                                                              Lane4& y, Lane4& z) {
    const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);  // a Vec3's three doubles, not the next one's x
    __m256d row[4];
    for (int l = 0; l < 4; l++)
        row[l] = _mm256_sub_pd(_mm256_maskload_pd(components(v[p[l]]), xyz), _mm256_maskload_pd(components(v[q[l]]), xyz));
    Lane4 unused;
    transpose(row[0], row[1], row[2], row[3], x, y, z, unused);
}

/**
 * Pairs k to k + 3 to kept (e with gammaWD where wR was), each line of the list fetched for
 * writing ahead (a processor without PREFETCHW runs it as a no-op).
 */
__attribute__((target("avx2,prfchw"), always_inline)) inline void keep(const DPDBatchPairs& pairs, int k, const __m256d* eAndWR) {
    prefetchFourPairsAhead<true>(pairs.kept + k);
    for (int l = 0; l < 4; l++) {
        DPDThermostatForces::KeptPair& kept = pairs.kept[k + l];
        kept.p = pairs.slotP[k + l];
        kept.q = pairs.slotQ[k + l];
        _mm256_storeu_pd(components(kept.e), _mm256_blend_pd(eAndWR[l], _mm256_broadcast_sd(&pairs.geometry[k + l].gammaWD), 0x8));
    }
}

__attribute__((target("avx2,prfchw"))) int pairForceRowsAVX2(const DPDBatchPairs& pairs, int n, const Vec3* v, double invSqrtDt,
                                                             Vec3* forces, Vec3* dissipative) {
    const int rows = n & ~3;
    for (int k = 0; k < rows; k += 4) {
        const PairGeometry* g = pairs.geometry + k;
        __m256d eAndWR[4];
        for (int l = 0; l < 4; l++)
            eAndWR[l] = _mm256_loadu_pd(components(g[l].e));
        Lane4 ex, ey, ez, unused;
        transpose(eAndWR[0], eAndWR[1], eAndWR[2], eAndWR[3], ex, ey, ez, unused);
        if (pairs.kept != nullptr)
            keep(pairs, k, eAndWR);
        const __m256d frictionNoise02 = twoPairs(&g[0].gammaWD, &g[2].gammaWD), frictionNoise13 = twoPairs(&g[1].gammaWD, &g[3].gammaWD);
        const Lane4 gammaWD = (Lane4) _mm256_unpacklo_pd(frictionNoise02, frictionNoise13);
        const Lane4 sigmaWR = (Lane4) _mm256_unpackhi_pd(frictionNoise02, frictionNoise13);
        Lane4 vx, vy, vz;
        relativeVelocities(v, pairs.slotP + k, pairs.slotQ + k, vx, vy, vz);
        if (pairs.sheared)  // j moves as its image does
            vx -= Lane4{g[0].imageVx, g[1].imageVx, g[2].imageVx, g[3].imageVx};
        const Lane4 fd = dissipativeAlongE(gammaWD, ex * vx + ey * vy + ez * vz);
        const Lane4 fr = randomAlongE(sigmaWR, (Lane4) _mm256_loadu_pd(pairs.xi + k), invSqrtDt);
        Lane4 fx = ex * fr, fy = ey * fr, fz = ez * fr;
        if (dissipative != nullptr)
            storeVec3s(ex * fd, ey * fd, ez * fd, dissipative + k);
        else {
            fx = ex * fd + fx;
            fy = ey * fd + fy;
            fz = ez * fd + fz;
        }
        if (pairs.softAlongE != nullptr) {
            const Lane4 soft = (Lane4) _mm256_loadu_pd(pairs.softAlongE + k);
            fx += ex * soft;
            fy += ey * soft;
            fz += ez * soft;
        }
        storeVec3s(fx, fy, fz, forces + k);
    }
    return rows;
}

__attribute__((target("avx2,prfchw"))) int keptDissipativeRowsAVX2(const DPDThermostatForces::KeptPair* kept, const double* imageVx,
                                                                   int n, const Vec3* v, Vec3* forces) {
    const int rows = n & ~3;
    for (int k = 0; k < rows; k += 4) {
        const DPDThermostatForces::KeptPair* pair = kept + k;
        prefetchFourPairsAhead<false>(pair);
        Lane4 ex, ey, ez, gammaWD;
        transpose(_mm256_loadu_pd(components(pair[0].e)), _mm256_loadu_pd(components(pair[1].e)), _mm256_loadu_pd(components(pair[2].e)),
                  _mm256_loadu_pd(components(pair[3].e)), ex, ey, ez, gammaWD);
        const int p[4] = {pair[0].p, pair[1].p, pair[2].p, pair[3].p}, q[4] = {pair[0].q, pair[1].q, pair[2].q, pair[3].q};
        Lane4 vx, vy, vz;
        relativeVelocities(v, p, q, vx, vy, vz);
        if (imageVx != nullptr)
            vx -= (Lane4) _mm256_loadu_pd(imageVx + k);
        const Lane4 fd = dissipativeAlongE(gammaWD, ex * vx + ey * vy + ez * vz);
        storeVec3s(ex * fd, ey * fd, ez * fd, forces + k);
    }
    return rows;
}

} // namespace
#endif

int DPDPlugin::dpdPairForceRows(const DPDBatchPairs& pairs, int n, const Vec3* velocities, double invSqrtDt, Vec3* forces,
                                Vec3* dissipative) {
#ifdef OPENMMDPD_X86_VECTORS
    if (haveAVX2())
        return pairForceRowsAVX2(pairs, n, velocities, invSqrtDt, forces, dissipative);
#endif
    return 0;
}

int DPDPlugin::dpdKeptDissipativeRows(const DPDThermostatForces::KeptPair* kept, const double* imageVx, int n, const Vec3* velocities,
                                      Vec3* forces) {
#ifdef OPENMMDPD_X86_VECTORS
    if (haveAVX2())
        return keptDissipativeRowsAVX2(kept, imageVx, n, velocities, forces);
#endif
    return 0;
}
