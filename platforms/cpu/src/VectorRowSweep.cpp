// A RowReal passed or returned by value is passed differently by code built for different
// vector units (the compiler warns of it).  Here none crosses a call between such code: the
// functions that take or return one are always inlined, and the rules' apply take them by
// reference.
#pragma GCC diagnostic ignored "-Wpsabi"

#include "openmmdpd/VectorRowSweep.h"
#include "openmmdpd/CpuFeatures.h"
#include <cmath>

#if defined(OPENMMDPD_X86_VECTORS) && defined(OPENMMDPD_HAVE_LIBMVEC)
#include <immintrin.h>
// glibc's vector math library (libmvec): exp of four doubles at once, AVX2 variant.
extern "C" __m256d _ZGVdN4v_exp(__m256d);
#define OPENMMDPD_ROW_EXP_AVX2
#endif

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

typedef double RowReal __attribute__((vector_size(SWEEP_LANES * sizeof(double))));
typedef PairOrnsteinUhlenbeckUpdate<const EqualMassPairImpulse&, RowConsistentMath> EqualMassOU;

/** The row of value(l) for each lane l.  (Made from zero, where lane by lane into nothing would read the unset lanes.) */
template <class Value>
__attribute__((always_inline)) inline RowReal laneValues(Value value) {
    RowReal x = {};
    for (int l = 0; l < SWEEP_LANES; l++)
        x[l] = value(l);
    return x;
}

/** A row's functions of its lanes' values: the scalar ones, lane by lane. */
struct LaneByLaneMath {
    __attribute__((always_inline)) static RowReal exp(const RowReal& x) {
        RowReal y;
        for (int l = 0; l < SWEEP_LANES; l++)
            y[l] = std::exp(x[l]);
        return y;
    }
    __attribute__((always_inline)) static RowReal sqrt(const RowReal& x) {
        RowReal y;
        for (int l = 0; l < SWEEP_LANES; l++)
            y[l] = std::sqrt(x[l]);
        return y;
    }
};

#ifdef OPENMMDPD_ROW_EXP_AVX2
static_assert(SWEEP_LANES == 4, "libmvec's AVX2 exp takes four doubles");

// Called, not inlined: the rules' apply need not be inlined into code built for AVX2.
__attribute__((target("avx2"))) void expAVX2(const RowReal& x, RowReal& y) {
    y = (RowReal) _ZGVdN4v_exp((__m256d) x);
}

/** With AVX2 and libmvec: exp four at a time (the scalar one to rounding). */
struct AVX2RowMath : LaneByLaneMath {
    __attribute__((always_inline)) static RowReal exp(const RowReal& x) {
        RowReal y;
        expAVX2(x, y);
        return y;
    }
};
#else
typedef LaneByLaneMath AVX2RowMath;
#endif

/** The velocities of a row of pairs with no particle in common, as PairVelocities (equal masses). */
template <class Functions>
struct PairRowVelocities {
    typedef Functions Math;
    RowReal ex, ey, ez, imageVx, vix, viy, viz, vjx, vjy, vjz;
    double invMass, mu;

    __attribute__((always_inline)) RowReal normalVelocity() const { return ex * (vix - vjx - imageVx) + ey * (viy - vjy) + ez * (viz - vjz); }
    /** EqualMassPairImpulse::apply, lane by lane. */
    __attribute__((always_inline)) void kick(RowReal impulseAlongE) {
        const RowReal k = impulseAlongE * invMass;
        vix += ex * k;
        viy += ey * k;
        viz += ez * k;
        vjx -= ex * k;
        vjy -= ey * k;
        vjz -= ez * k;
    }
};

/** A row's pairs: their geometry, random numbers and velocities, loaded lane by lane, and stored back. */
template <class Math>
struct PairRow {
    int i[SWEEP_LANES], j[SWEEP_LANES];
    PairRowVelocities<Math> pair;
    RowReal sigmaWR, gammaWD, xi;

    template <class Entry>
    __attribute__((always_inline)) PairRow(const Entry* const* rowPairs, const SweepCells<Entry>& run, const std::vector<double>& random,
                                           const int* row, const std::vector<Vec3>& v, double invMass, double mu) {
        for (int l = 0; l < SWEEP_LANES; l++) {
            i[l] = rowPairs[l]->i;
            j[l] = rowPairs[l]->j;
        }
        loadGeometry(rowPairs, run);
        pair.vix = laneValues([&](int l) { return v[i[l]][0]; });
        pair.viy = laneValues([&](int l) { return v[i[l]][1]; });
        pair.viz = laneValues([&](int l) { return v[i[l]][2]; });
        pair.vjx = laneValues([&](int l) { return v[j[l]][0]; });
        pair.vjy = laneValues([&](int l) { return v[j[l]][1]; });
        pair.vjz = laneValues([&](int l) { return v[j[l]][2]; });
        pair.invMass = invMass;
        pair.mu = mu;
        xi = laneValues([&](int l) { return random[row[l]]; });
    }
    __attribute__((always_inline)) void loadGeometry(const PairGeometry* const* q, const SweepCells<PairGeometry>&) {
        pair.ex = laneValues([&](int l) { return q[l]->e[0]; });
        pair.ey = laneValues([&](int l) { return q[l]->e[1]; });
        pair.ez = laneValues([&](int l) { return q[l]->e[2]; });
        pair.imageVx = laneValues([&](int l) { return q[l]->imageVx; });
        sigmaWR = laneValues([&](int l) { return q[l]->sigmaWR; });
        gammaWD = laneValues([&](int l) { return q[l]->gammaWD; });
    }
    /** As pairGeometry(UniformPair, rule) makes them, lane by lane. */
    __attribute__((always_inline)) void loadGeometry(const UniformPair* const* q, const SweepCells<UniformPair>& run) {
        pair.ex = laneValues([&](int l) { return q[l]->e[0]; });
        pair.ey = laneValues([&](int l) { return q[l]->e[1]; });
        pair.ez = laneValues([&](int l) { return q[l]->e[2]; });
        pair.imageVx = RowReal{};
        const RowReal wR = laneValues([&](int l) { return q[l]->wR; });
        gammaWD = run.uniformRule->gamma * pairDissipativeWeight(wR);
        sigmaWR = run.uniformRule->sigma * wR;
    }
    __attribute__((always_inline)) void store(std::vector<Vec3>& v) const {
        // The lanes' particles are distinct, except where a lane repeats lane 0's pair: it
        // stores the same values again, after lane 0.
        for (int l = 0; l < SWEEP_LANES; l++) {
            v[i[l]] = Vec3(pair.vix[l], pair.viy[l], pair.viz[l]);
            v[j[l]] = Vec3(pair.vjx[l], pair.vjy[l], pair.vjz[l]);
        }
    }
};

template <class Math>
__attribute__((always_inline)) inline void updateRow(const RowShardlowUpdate& rule, PairRow<Math>& row) {
    rule.apply(row.pair, row.sigmaWR, row.gammaWD, row.xi);
}

template <class Math>
__attribute__((always_inline)) inline void updateRow(const EqualMassOU& rule, PairRow<Math>& row) {
    rule.apply(row.pair, row.gammaWD, row.xi, rule.commonKTOverMu);
}

template <class Math, class Rule, class Entry>
__attribute__((always_inline)) inline void sweepRows(const Rule& rule, const std::vector<double>& random, std::vector<Vec3>& v,
                                                     const SweepCells<Entry>& run) {
    // always inlined, as the row's other functions, so that it is compiled for the caller's vector unit
    const double invMass = rule.impulse.invMass, mu = rule.reducedMass(invMass + invMass);
    forEachPairRow(run, [&](const int* rowIndex, const Entry* const* rowPairs, int n) __attribute__((always_inline)) {
        prefetchAhead(rowPairs, random, rowIndex, n, run.reverse);
        PairRow<Math> row(rowPairs, run, random, rowIndex, v, invMass, mu);
        updateRow(rule, row);
        row.store(v);
    });
}

template <class Rule, class Entry>
void sweepRowsBase(const Rule& rule, const std::vector<double>& random, std::vector<Vec3>& v, const SweepCells<Entry>& run) {
    sweepRows<LaneByLaneMath>(rule, random, v, run);
}

#ifdef OPENMMDPD_X86_VECTORS
// The same code, compiled for 4-wide vectors where the processor has them.
template <class Rule, class Entry>
__attribute__((target("avx2"))) void sweepRowsAVX2(const Rule& rule, const std::vector<double>& random, std::vector<Vec3>& v,
                                                   const SweepCells<Entry>& run) {
    sweepRows<AVX2RowMath>(rule, random, v, run);
}
#endif

/** sweepCells of either rule: rows of pairs where the cells are independent and masses nonzero, else pair by pair. */
template <class Rule, class Entry>
void sweepCellsInRows(const Rule& rule, const std::vector<double>& random, std::vector<Vec3>& v, const SweepCells<Entry>& run,
                      RowVectorUnit unit) {
    if (!run.independent || rule.impulse.invMass == 0)
        sweepCells<Rule, double, Entry>(rule, random, v, run);
#ifdef OPENMMDPD_X86_VECTORS
    else if (unit == RowVectorUnit::Best && haveAVX2())
        sweepRowsAVX2(rule, random, v, run);
#endif
    else
        sweepRowsBase(rule, random, v, run);
}

} // namespace

double RowConsistentMath::exp(double x) {
#ifdef OPENMMDPD_ROW_EXP_AVX2
    if (haveAVX2()) {
        RowReal y;
        expAVX2(RowReal{x, x, x, x}, y);
        return y[0];
    }
#endif
    return std::exp(x);
}

void DPDPlugin::sweepCells(const RowShardlowUpdate& rule, const std::vector<double>& random, std::vector<Vec3>& v,
                           const SweepCells<PairGeometry>& run, RowVectorUnit unit) {
    sweepCellsInRows(rule, random, v, run, unit);
}

void DPDPlugin::sweepCells(const RowShardlowUpdate& rule, const std::vector<double>& random, std::vector<Vec3>& v,
                           const SweepCells<UniformPair>& run, RowVectorUnit unit) {
    sweepCellsInRows(rule, random, v, run, unit);
}

void DPDPlugin::sweepCells(const EqualMassOU& rule, const std::vector<double>& random, std::vector<Vec3>& v,
                           const SweepCells<PairGeometry>& run, RowVectorUnit unit) {
    sweepCellsInRows(rule, random, v, run, unit);
}

void DPDPlugin::sweepCells(const EqualMassOU& rule, const std::vector<double>& random, std::vector<Vec3>& v,
                           const SweepCells<UniformPair>& run, RowVectorUnit unit) {
    sweepCellsInRows(rule, random, v, run, unit);
}
