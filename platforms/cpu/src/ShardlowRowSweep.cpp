// A RowReal passed or returned by value is passed differently by code built for different
// vector units (the compiler warns of it).  Here none crosses a call between such code: the
// functions that take or return one are always inlined, and ShardlowPairUpdate::apply takes
// them by reference.
#pragma GCC diagnostic ignored "-Wpsabi"

#include "openmmdpd/ShardlowRowSweep.h"
#include "openmmdpd/CpuFeatures.h"

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

typedef double RowReal __attribute__((vector_size(SWEEP_LANES * sizeof(double))));
typedef ShardlowPairUpdate<const EqualMassPairImpulse&> EqualMassShardlow;

/** The velocities of a row of pairs with no particle in common, as PairVelocities (equal masses). */
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
    const PairGeometry* p[SWEEP_LANES];
    for (int l = 0; l < SWEEP_LANES; l++)
        p[l] = &list[row[l]];
    auto lanes = [&](auto value) __attribute__((always_inline)) {
        RowReal x;
        for (int l = 0; l < SWEEP_LANES; l++)
            x[l] = value(*p[l]);
        return x;
    };
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
    RowReal xi;
    for (int l = 0; l < SWEEP_LANES; l++)
        xi[l] = random[row[l]];
    rule.apply(pair, lanes([](const PairGeometry& q) { return q.sigmaWR; }), lanes([](const PairGeometry& q) { return q.gammaWD; }), xi);
    // The lanes' particles are distinct, except where a lane repeats lane 0's pair: it stores
    // the same values again, after lane 0.
    for (int l = 0; l < SWEEP_LANES; l++) {
        v[p[l]->i] = Vec3(pair.vix[l], pair.viy[l], pair.viz[l]);
        v[p[l]->j] = Vec3(pair.vjx[l], pair.vjy[l], pair.vjz[l]);
    }
}

__attribute__((always_inline)) inline void sweepRows(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list,
                                                     const std::vector<double>& random, std::vector<Vec3>& v, const SweepCells& run) {
    // always inlined, as the row's other functions, so that it is compiled for the caller's vector unit
    forEachPairRow(run, [&](const int* row, int n) __attribute__((always_inline)) {
        prefetchAhead(list, random, row, n, run.reverse);
        updateRow(rule, list, random, row, v);
    });
}

void sweepRowsBase(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list, const std::vector<double>& random,
                   std::vector<Vec3>& v, const SweepCells& run) {
    sweepRows(rule, list, random, v, run);
}

#ifdef OPENMMDPD_X86_VECTORS
// The same code, compiled for 4-wide vectors where the processor has them.
__attribute__((target("avx2"))) void sweepRowsAVX2(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list,
                                                   const std::vector<double>& random, std::vector<Vec3>& v, const SweepCells& run) {
    sweepRows(rule, list, random, v, run);
}

#endif

} // namespace

void DPDPlugin::sweepCells(const EqualMassShardlow& rule, const std::vector<PairGeometry>& list, const std::vector<double>& random,
                           std::vector<Vec3>& v, const SweepCells& run, RowVectorUnit unit) {
    if (!run.independent || rule.impulse.invMass == 0)
        sweepCells<EqualMassShardlow, double>(rule, list, random, v, run);
#ifdef OPENMMDPD_X86_VECTORS
    else if (unit == RowVectorUnit::Best && haveAVX2())
        sweepRowsAVX2(rule, list, random, v, run);
#endif
    else
        sweepRowsBase(rule, list, random, v, run);
}
