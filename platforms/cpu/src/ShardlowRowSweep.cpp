// The row's vector type is this file's own, so the calling convention for it that the
// compiler warns about never meets code built with other options.
#pragma GCC diagnostic ignored "-Wpsabi"

#include "openmmdpd/ShardlowRowSweep.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

typedef double RowReal __attribute__((vector_size(32)));
typedef ShardlowPairUpdate<const EqualMassPairImpulse&> EqualMassShardlow;

/** The velocities of a row of 4 pairs with no particle in common, as PairVelocities (equal masses). */
struct PairRowVelocities {
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

__attribute__((always_inline)) inline void updateRow(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list,
                                                     const std::vector<double>& random, const int* row, std::vector<Vec3>& v) {
    const PairGeometry* p[4] = {&list[row[0]], &list[row[1]], &list[row[2]], &list[row[3]]};
    auto lanes = [&](auto value) __attribute__((always_inline)) { return RowReal{value(*p[0]), value(*p[1]), value(*p[2]), value(*p[3])}; };
    const double invMass = rule.impulse.invMass;
    PairRowVelocities pair{lanes([](const PairGeometry& q) { return q.e[0]; }),
                           lanes([](const PairGeometry& q) { return q.e[1]; }),
                           lanes([](const PairGeometry& q) { return q.e[2]; }),
                           lanes([](const PairGeometry& q) { return q.imageVx; }),
                           lanes([&](const PairGeometry& q) { return v[q.i][0]; }),
                           lanes([&](const PairGeometry& q) { return v[q.i][1]; }),
                           lanes([&](const PairGeometry& q) { return v[q.i][2]; }),
                           lanes([&](const PairGeometry& q) { return v[q.j][0]; }),
                           lanes([&](const PairGeometry& q) { return v[q.j][1]; }),
                           lanes([&](const PairGeometry& q) { return v[q.j][2]; }),
                           invMass, rule.reducedMass(invMass + invMass)};
    const RowReal xi = {random[row[0]], random[row[1]], random[row[2]], random[row[3]]};
    rule.apply(pair, lanes([](const PairGeometry& q) { return q.sigmaWR; }), lanes([](const PairGeometry& q) { return q.gammaWD; }), xi);
    // A lane that repeats another's pair stores the same values again.
    for (int l = 0; l < 4; l++) {
        v[p[l]->i] = Vec3(pair.vix[l], pair.viy[l], pair.viz[l]);
        v[p[l]->j] = Vec3(pair.vjx[l], pair.vjy[l], pair.vjz[l]);
    }
}

__attribute__((always_inline)) inline void sweepRows(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list,
                                                     const std::vector<double>& random, std::vector<Vec3>& v, const SweepCells& run) {
    // always inlined, as everything here, so that it is compiled for the caller's vectors
    forEachPairRow(run, [&](const int* row, int n) __attribute__((always_inline)) {
        prefetchAhead(list, random, row, n, run.reverse);
        updateRow(rule, list, random, row, v);
    });
}

void sweepRowsBase(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list, const std::vector<double>& random,
                   std::vector<Vec3>& v, const SweepCells& run) {
    sweepRows(rule, list, random, v, run);
}

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
// The same code, compiled for 4-wide vectors where the processor has them.
__attribute__((target("avx2"))) void sweepRowsAVX2(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list,
                                                   const std::vector<double>& random, std::vector<Vec3>& v, const SweepCells& run) {
    sweepRows(rule, list, random, v, run);
}

const auto sweepRowsHere = __builtin_cpu_supports("avx2") ? sweepRowsAVX2 : sweepRowsBase;
#else
const auto sweepRowsHere = sweepRowsBase;
#endif

} // namespace

void DPDPlugin::sweepCells(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list, const std::vector<double>& random,
                           std::vector<Vec3>& v, const SweepCells& run) {
    if (!run.independent || rule.impulse.invMass == 0)
        sweepCells<EqualMassShardlow, double>(rule, list, random, v, run);
    else
        sweepRowsHere(rule, list, random, v, run);
}
