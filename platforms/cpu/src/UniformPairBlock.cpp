// A Lane4 passed or returned by value is passed differently by code built for different
// vector units (the compiler warns of it); none crosses a call between such code here.
#pragma GCC diagnostic ignored "-Wpsabi"

#include "openmmdpd/UniformPairBlock.h"
#include "openmmdpd/CpuFeatures.h"

#ifdef OPENMMDPD_X86_VECTORS
#include <immintrin.h>
#endif

using namespace DPDPlugin;
using OpenMM::Vec3;

#ifdef OPENMMDPD_X86_VECTORS
namespace {

/** Four hits' geometry, lane by lane as pairGeometry computes it (no FMA: the target has none). */
struct HitRow {
    Lane4 dx, dy, dz, r2, wR, ex, ey, ez, gammaWD, sigmaWR, softForce;

    __attribute__((target("avx2"))) HitRow(const Vec3* ds, int first, int hits) {
        // lanes past the last hit repeat the first (and are not accepted)
        const Vec3 &a = ds[first], &b = ds[first + 1 < hits ? first + 1 : first], &c = ds[first + 2 < hits ? first + 2 : first],
                   &d = ds[first + 3 < hits ? first + 3 : first];
        dx = Lane4{a[0], b[0], c[0], d[0]};
        dy = Lane4{a[1], b[1], c[1], d[1]};
        dz = Lane4{a[2], b[2], c[2], d[2]};
        r2 = dx * dx + dy * dy + dz * dz;
    }
    __attribute__((target("avx2"))) void finish(const UniformPairRule& rule) {
        const Lane4 r = (Lane4) _mm256_sqrt_pd((__m256d) r2);
        wR = pairLinearWeight(r, rule.cutoff);
        const Lane4 scale = 1.0 / r;
        ex = dx * scale;
        ey = dy * scale;
        ez = dz * scale;
        gammaWD = rule.gamma * pairDissipativeWeight(wR);
        sigmaWR = rule.sigma * wR;
        if (rule.soft) {
            const Lane4 softR = rule.cutoff * (1 - wR);
            const Lane4 force = softRepulsionAlongE(softR, rule.softA, rule.softInverseCutoff);
            // pairForce's test, NaN included: 0 where r >= the soft cutoff
            softForce = (Lane4) _mm256_andnot_pd((__m256d) (softR >= rule.softCutoff), (__m256d) force);
        }
        else
            softForce = Lane4{0, 0, 0, 0};  // read by no one: set for -Wmaybe-uninitialized, which cannot tell
    }
};

/** Lane l of a row as a list entry. */
inline void setEntry(PairGeometry& g, const HitRow& row, int l, const UniformPairRule& rule) {
    g.e = Vec3(row.ex[l], row.ey[l], row.ez[l]);
    g.wR = row.wR[l];
    g.gammaWD = row.gammaWD[l];
    g.sigmaWR = row.sigmaWR[l];
    g.rate = rule.rate;
    g.imageVx = 0;
    g.transverseGammaWD = g.transverseSigmaWR = 0;
}

inline void setEntry(UniformPair& pair, const HitRow& row, int l, const UniformPairRule&) {
    pair.e = Vec3(row.ex[l], row.ey[l], row.ez[l]);
    pair.wR = row.wR[l];
}

template <class Entry>
__attribute__((target("avx2"))) int uniformPairBlockAVX2(const UniformPairRule& rule, int p, const int* qs, const Vec3* ds, int hits,
                                                         int* acceptedQ, Entry* out, Vec3* softForce, double* softPairForce) {
    int n = 0;
    const bool bySlot = rule.soft && softPairForce == nullptr, perPair = rule.soft && softPairForce != nullptr;
    Vec3 forceOnP = (bySlot ? softForce[p] : Vec3());
    for (int first = 0; first < hits; first += 4) {
        HitRow row(ds, first, hits);
        // pairGeometry's test, NaN included: a pair is out where r2 >= cutoff2 or r2 == 0
        int accept = 0;
        for (int l = 0; l < 4 && first + l < hits; l++)
            accept |= (!(row.r2[l] >= rule.cutoff2) && row.r2[l] != 0) << l;
        if (accept == 0)
            continue;
        row.finish(rule);
        for (int l = 0; l < 4; l++) {
            if (!(accept & (1 << l)))
                continue;
            setEntry(out[n], row, l, rule);
            if (perPair)
                softPairForce[n] = row.softForce[l];
            const int q = acceptedQ[n++] = qs[first + l];
            if (bySlot) {
                // e * force, as SoftRepulsionKernel::pairForce's caller makes it (0 beyond the soft cutoff)
                const Vec3 f = Vec3(row.ex[l], row.ey[l], row.ez[l]) * row.softForce[l];
                forceOnP += f;
                softForce[q] -= f;
            }
        }
    }
    if (bySlot)
        softForce[p] = forceOnP;
    return n;
}

} // namespace
#endif

bool DPDPlugin::canRunUniformPairBlock() {
#ifdef OPENMMDPD_X86_VECTORS
    return haveAVX2();
#else
    return false;
#endif
}

namespace {

template <class Entry>
int uniformPairBlockOn(const UniformPairRule& rule, int p, const int* qs, const Vec3* ds, int hits, int* acceptedQ, Entry* out,
                       Vec3* softForce, double* softPairForce) {
#ifdef OPENMMDPD_X86_VECTORS
    if (haveAVX2())
        return uniformPairBlockAVX2(rule, p, qs, ds, hits, acceptedQ, out, softForce, softPairForce);
#endif
    return -1;
}

} // namespace

int DPDPlugin::uniformPairBlock(const UniformPairRule& rule, int p, const int* qs, const Vec3* ds, int hits, int* acceptedQ,
                                PairGeometry* out, Vec3* softForce, double* softPairForce) {
    return uniformPairBlockOn(rule, p, qs, ds, hits, acceptedQ, out, softForce, softPairForce);
}

int DPDPlugin::uniformPairBlock(const UniformPairRule& rule, int p, const int* qs, const Vec3* ds, int hits, int* acceptedQ,
                                UniformPair* out, Vec3* softForce) {
    return uniformPairBlockOn(rule, p, qs, ds, hits, acceptedQ, out, softForce, nullptr);
}
