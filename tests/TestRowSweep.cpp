#if OPENMMDPD_HAVE_CPU
#include "TestHelpers.h"
#include "openmmdpd/DPDPairRows.h"
#include "openmmdpd/PairSweep.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/UniformPairBlock.h"
#include "openmmdpd/VectorRowSweep.h"
#include <memory>
#include <gtest/gtest.h>
#include <cmath>
#include <cstring>
#include <random>
#include <string>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

typedef PairOrnsteinUhlenbeckUpdate<const EqualMassPairImpulse&, RowConsistentMath> EqualMassOU;
const EqualMassPairImpulse IMPULSE{0.8};

/**
 * Cells that share no particle, with 0 to 11 pairs each (more cells than a row's lanes, so
 * lanes end and take new cells), pairs in random order with random geometry and numbers.
 */
struct IndependentCells {
    std::vector<int> cells, start;
    std::vector<PairGeometry> list;
    std::vector<double> xi;
    std::vector<Vec3> v;

    /** withImages: some pairs' j images move (a sheared box); without, the geometry is one a UniformPair can hold. */
    explicit IndependentCells(unsigned seed, bool withImages = true) {
        std::mt19937 engine(seed);
        std::uniform_real_distribution<double> uniform(-1.0, 1.0);
        std::uniform_int_distribution<int> pairsInCell(0, 11);
        const int numCells = 13, particlesPerCell = 6;
        v.resize(numCells * particlesPerCell);
        for (Vec3& vi : v)
            vi = Vec3(uniform(engine), uniform(engine), uniform(engine));
        start.push_back(0);
        for (int c = 0; c < numCells; c++) {
            cells.push_back(c);
            const int count = pairsInCell(engine);
            for (int k = 0; k < count; k++) {
                PairGeometry g;
                g.i = c * particlesPerCell + (k + c) % particlesPerCell;
                g.j = c * particlesPerCell + (k + c + 1 + k % 3) % particlesPerCell;
                const Vec3 d(uniform(engine), uniform(engine), uniform(engine));
                g.e = d / std::sqrt(d.dot(d));
                g.wR = 0.5 + 0.5 * uniform(engine);
                g.gammaWD = 4.5 * pairDissipativeWeight(g.wR);  // as pairGeometry computes it
                g.sigmaWR = 3.0 * g.wR;
                g.imageVx = (withImages && k % 2 == 0 ? 0.25 * uniform(engine) : 0.0);
                list.push_back(g);
                xi.push_back(uniform(engine) * 2);
            }
            start.push_back((int) list.size());
        }
    }

    /**
     * The velocities after a sweep over every cell, through sweepCells with this unit, or
     * (unit null) cell by cell and pair by pair.  With `apart`, the even and the odd cells'
     * pairs lie in two lists, as the pair search's workers leave theirs.
     */
    template <class Rule>
    std::vector<Vec3> swept(const Rule& rule, bool reverse, const RowVectorUnit* unit, bool apart) const {
        std::vector<PairGeometry> parts[2];
        for (size_t c = 0; c + 1 < start.size(); c++)
            parts[c % 2].insert(parts[c % 2].end(), list.begin() + start[c], list.begin() + start[c + 1]);
        std::vector<const PairGeometry*> cellPairs;
        size_t placed[2] = {0, 0};
        for (size_t c = 0; c + 1 < start.size(); c++) {
            cellPairs.push_back(apart ? parts[c % 2].data() + placed[c % 2] : list.data() + start[c]);
            placed[c % 2] += start[c + 1] - start[c];
        }
        const SweepCells<PairGeometry> run{cells, start, cellPairs, 0, cells.size(), reverse, unit != nullptr, nullptr};
        std::vector<Vec3> out = v;
        if (unit != nullptr)
            sweepCells(rule, xi, out, run, *unit);
        else
            sweepCells<Rule, double>(rule, xi, out, run);
        return out;
    }

    /** The same over a list of UniformPair whose geometry is `uniform`'s: in rows with this unit, or (null) pair by pair. */
    template <class Rule>
    std::vector<Vec3> sweptUniform(const Rule& rule, bool reverse, const RowVectorUnit* unit, const UniformPairRule& uniform) const {
        std::vector<UniformPair> uniformList;
        for (const PairGeometry& g : list)
            uniformList.push_back({g.i, g.j, g.e, g.wR});
        std::vector<const UniformPair*> cellPairs;
        for (size_t c = 0; c + 1 < start.size(); c++)
            cellPairs.push_back(uniformList.data() + start[c]);
        const SweepCells<UniformPair> run{cells, start, cellPairs, 0, cells.size(), reverse, unit != nullptr, &uniform};
        std::vector<Vec3> out = v;
        sweepCells(rule, xi, out, run, unit != nullptr ? *unit : RowVectorUnit::Best);
        return out;
    }
};

} // namespace

/**
 * Each unit's sweep, and the pair-by-pair one, over cells whose pairs lie in two lists,
 * against the pair-by-pair sweep of one list: bit for bit, the baseline target's within
 * `baselineTolerance`.
 */
template <class Rule>
void expectRowsEqualPairByPair(const Rule& rule, double baselineTolerance) {
    for (unsigned seed : {1u, 2u, 3u})
        for (bool reverse : {false, true}) {
            const IndependentCells cells(seed);
            const std::vector<Vec3> expected = cells.swept(rule, reverse, nullptr, false);
            const RowVectorUnit best = RowVectorUnit::Best, baseline = RowVectorUnit::Baseline;
            for (const RowVectorUnit* unit : {&best, &baseline, (const RowVectorUnit*) nullptr}) {
                const double tolerance = (unit == &baseline ? baselineTolerance : 0.0);
                const std::vector<Vec3> v = cells.swept(rule, reverse, unit, true);
                for (size_t i = 0; i < v.size(); i++)
                    for (int k = 0; k < 3; k++)
                        ASSERT_NEAR(v[i][k], expected[i][k], tolerance) << "seed " << seed << (reverse ? " reverse" : "")
                                                                        << (unit ? " row unit " + std::to_string((int) *unit) : " pair by pair") << " particle " << i;
            }
            size_t moved = 0;
            for (size_t i = 0; i < expected.size(); i++)
                moved += (expected[i][0] != cells.v[i][0]);
            ASSERT_GT(moved, expected.size() / 2);
        }
}

TEST(RowSweep, ShardlowRowsEqualPairByPair) {
    // The row sweep (four pairs of four cells as one vector) gives the pair-by-pair
    // update's velocities bit for bit, whichever code the processor runs; here both.
    expectRowsEqualPairByPair(RowShardlowUpdate(0.05, IMPULSE), 0.0);
}

TEST(RowSweep, PairOrnsteinUhlenbeckRowsEqualPairByPair) {
    // The same with the platform's exp (RowConsistentMath), rows and pairs alone alike;
    // forced onto the baseline target's rows on a processor with AVX2, the rows take the
    // scalar exp while a pair alone keeps libmvec's: the same to rounding (velocities of
    // order 1; 1e-14 is some 100 roundings).
    expectRowsEqualPairByPair(EqualMassOU(0.05, 1.0, IMPULSE), 1e-14);
}

TEST(RowSweep, UniformPairsGiveThePairGeometryOnes) {
    // A list of UniformPair (e and wR, with gamma and sigma the rule's) in rows, by each
    // unit, and pair by pair, against the pair-by-pair sweep of the PairGeometry list the
    // same pairs make (gamma wR^2 and sigma wR as pairGeometry computes them): bit for bit,
    // the baseline target's pair OU rows within 1e-14 (see the test above).
    const UniformPairRule uniform{1.0, 1.0, 4.5, 3.0, 0.0, false, 0.0, 0.0, 0.0};
    const RowShardlowUpdate shardlow(0.05, IMPULSE);
    const EqualMassOU ou(0.05, 1.0, IMPULSE);
    const RowVectorUnit best = RowVectorUnit::Best, baseline = RowVectorUnit::Baseline;
    for (unsigned seed : {1u, 2u, 3u})
        for (bool reverse : {false, true}) {
            const IndependentCells cells(seed, false);
            for (const RowVectorUnit* unit : {&best, &baseline, (const RowVectorUnit*) nullptr}) {
                const std::string where = "seed " + std::to_string(seed) + (reverse ? " reverse" : "") +
                                          (unit ? " row unit " + std::to_string((int) *unit) : " pair by pair");
                const std::vector<Vec3> s = cells.sweptUniform(shardlow, reverse, unit, uniform),
                                        sExpected = cells.swept(shardlow, reverse, nullptr, false);
                const std::vector<Vec3> o = cells.sweptUniform(ou, reverse, unit, uniform), oExpected = cells.swept(ou, reverse, nullptr, false);
                for (size_t i = 0; i < s.size(); i++) {
                    ASSERT_EQ(s[i], sExpected[i]) << "Shardlow, " << where << ", particle " << i;
                    for (int k = 0; k < 3; k++)
                        ASSERT_NEAR(o[i][k], oExpected[i][k], unit == &baseline ? 1e-14 : 0.0) << "pair OU, " << where << ", particle " << i;
                }
            }
        }
}

namespace {

/** The same bits (== takes -0 for +0). */
bool sameBits(const Vec3& a, const Vec3& b) {
    return std::memcmp(&a, &b, sizeof(Vec3)) == 0;
}

const Vec3 UNTOUCHED(12345, -6789, 42);  // what the rows must leave past the pairs they make

/** A batch of n pairs from IndependentCells, as DPDSlotForces holds it. */
struct RowBatch {
    IndependentCells cells;
    std::vector<PairGeometry> g;
    std::vector<int> slotP, slotQ;
    std::vector<double> xi, softAlongE, imageVx;

    RowBatch(int n, bool sheared) : cells(n + 1, sheared) {
        for (size_t k = 0; g.size() < (size_t) n && !cells.list.empty(); k = (k + 1) % cells.list.size()) {
            g.push_back(cells.list[k]);
            slotP.push_back(cells.list[k].i);
            slotQ.push_back(cells.list[k].j);
            xi.push_back(cells.xi[k]);
            softAlongE.push_back(25 * (1 - cells.list[k].wR) - 3);
            imageVx.push_back(cells.list[k].imageVx);
        }
    }
    Vec3 fd(int k) const { return DPDPairForce::dissipative(g[k], g[k].relativeVelocity(cells.v[slotP[k]], cells.v[slotQ[k]])); }
};

} // namespace

/**
 * A thermostat batch's forces in rows (dpdPairForceRows) against DPDPairForce pair by pair,
 * summed as DPDSlotForces sums them: (FD + FR) + e soft in one output, or FD and FR + e soft
 * apart with the pairs kept (as DPD-VV's first pass asks), and the kept pairs' FD
 * (dpdKeptDissipativeRows): bit for bit, and nothing written past the pairs made.
 */
static void expectPairForceRowsEqualPairByPair(int n, bool separate, bool soft, bool sheared) {
    const RowBatch batch(n, sheared);
    ASSERT_EQ(batch.g.size(), (size_t) n);
    std::vector<DPDThermostatForces::KeptPair> kept(n, {-1, -1, UNTOUCHED, 0.0});
    const DPDBatchPairs pairs{batch.g.data(), batch.slotP.data(), batch.slotQ.data(), batch.xi.data(),
                              soft ? batch.softAlongE.data() : nullptr, sheared, separate ? kept.data() : nullptr};
    const double invSqrtDt = 1 / std::sqrt(0.05);
    std::vector<Vec3> forces(n, UNTOUCHED), dissipative(n, UNTOUCHED), keptFD(n, UNTOUCHED);
    const int made = dpdPairForceRows(pairs, n, batch.cells.v.data(), invSqrtDt, forces.data(), separate ? dissipative.data() : nullptr);
    ASSERT_EQ(made, n / 4 * 4);
    const std::string where = "n " + std::to_string(n) + (separate ? " separate" : "") + (soft ? " soft" : "") + (sheared ? " sheared" : "");
    for (int k = 0; k < made; k++) {
        const Vec3 fd = batch.fd(k), fr = DPDPairForce::random(batch.g[k], batch.xi[k], invSqrtDt);
        Vec3 expected = (separate ? fr : fd + fr);
        if (soft)
            expected += batch.g[k].e * batch.softAlongE[k];
        ASSERT_TRUE(sameBits(forces[k], expected)) << where << ", pair " << k << ": " << forces[k] << " against " << expected;
        ASSERT_TRUE(!separate || sameBits(dissipative[k], fd)) << where << ", pair " << k;
        ASSERT_TRUE(!separate || (kept[k].p == batch.slotP[k] && kept[k].q == batch.slotQ[k] && sameBits(kept[k].e, batch.g[k].e) &&
                                  kept[k].gammaWD == batch.g[k].gammaWD))
                << where << ", kept pair " << k;
    }
    for (int k = made; k < n; k++)
        ASSERT_TRUE(forces[k] == UNTOUCHED && dissipative[k] == UNTOUCHED && kept[k].p == -1) << where << ", pair " << k << " written";
    if (!separate)
        return;
    for (int k = made; k < n; k++)  // as DPD-VV's first pass keeps the rest
        kept[k] = {batch.slotP[k], batch.slotQ[k], batch.g[k].e, batch.g[k].gammaWD};
    ASSERT_EQ(dpdKeptDissipativeRows(kept.data(), sheared ? batch.imageVx.data() : nullptr, n, batch.cells.v.data(), keptFD.data()), made);
    for (int k = 0; k < n; k++)
        ASSERT_TRUE(k < made ? sameBits(keptFD[k], batch.fd(k)) : keptFD[k] == UNTOUCHED) << "kept pairs, " << where << ", pair " << k;
}

TEST(DPDPairRows, RowsEqualDPDPairForceBitForBit) {
    if (!canRunUniformPairBlock())
        GTEST_SKIP() << "no AVX2: the rows make no pairs, the batch goes pair by pair";
    for (int n = 0; n <= 13; n++)
        for (bool separate : {false, true})
            for (bool soft : {false, true})
                for (bool sheared : {false, true})
                    expectPairForceRowsEqualPairByPair(n, separate, soft, sheared);
}

/**
 * A sweep over the whole of a fluid's pairs (found by particle) with each strip budget in
 * stripCells, against colour by colour and pair by pair (as for constraints): the same
 * velocities bit for bit, in the sweep order and its reverse.
 */
static void expectStripsGiveTheColourOrder(const System& system, const std::vector<Vec3>& positions, int cellsAlongY,
                                    const std::vector<int>& stripCells) {
    ShardlowIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.05);
    Vec3 box[3];
    system.getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    SerialExecutor executor;
    DPDThermostatForces thermostat(system, integrator, executor, 3);
    thermostat.updatePairs(positions, box);
    ASSERT_EQ(thermostat.getSearch().getNumCellsAlong(1), cellsAlongY);
    ASSERT_TRUE(thermostat.getSearch().isColourable());
    std::vector<double> xi;
    thermostat.drawNormals(PairRandom::RandomForce, 3, xi);
    std::mt19937 engine(7);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    std::vector<Vec3> v0(positions.size());
    for (Vec3& vi : v0)
        vi = Vec3(uniform(engine), uniform(engine), uniform(engine));
    const RowShardlowUpdate rule(0.025, IMPULSE);
    for (bool reverse : {false, true}) {
        auto sweptBy = [&](PairSweep&& sweep) {
            std::vector<Vec3> v = v0;
            sweep.prepare(thermostat);
            sweep.run(thermostat, v, rule, xi, reverse);
            return v;
        };
        const std::vector<Vec3> expected = sweptBy(PairSweep(executor, true));
        size_t moved = 0;
        for (size_t i = 0; i < v0.size(); i++)
            moved += (expected[i][0] != v0[i][0]);
        ASSERT_GT(moved, v0.size() / 2);
        for (int cells : stripCells) {
            const std::vector<Vec3> v = sweptBy(PairSweep(executor, false, cells));
            for (size_t i = 0; i < v.size(); i++)
                ASSERT_EQ(v[i], expected[i]) << "stripCells " << cells << (reverse ? ", reverse" : "") << ", particle " << i;
        }
    }
}

TEST(PairSweep, StripsGiveTheColourOrderBitForBit) {
    // Periodic, 12 cells a side (four rows of each y mod 3): one strip a plane (the default),
    // strips of one row and of two.  Not periodic, 13 cells a side (5, 4 and 4 rows of each
    // y mod 3): strips of one row (a class of 4 rows leaves one of the 5 strips empty), and
    // three strips of 2, 2 and 1 rows, or 2, 1 and 1.
    std::vector<Vec3> positions;
    std::unique_ptr<System> periodic(makeFluid(6912, 0, positions));
    expectStripsGiveTheColourOrder(*periodic, positions, 12, {PairSweep::STRIP_CELLS, 36, 72});
    std::unique_ptr<System> open(makeFluid(9841, 0, positions));
    dynamic_cast<CustomBondForce&>(open->getForce(0)).setUsesPeriodicBoundaryConditions(false);
    ASSERT_FALSE(open->usesPeriodicBoundaryConditions());
    expectStripsGiveTheColourOrder(*open, positions, 13, {39, 78});
}
#endif
