// Lees-Edwards shear (docs/theory/lees-edwards.md) in every single-rate integrator: a pair across
// the sliding boundary is the same pair as inside the box with its partner's image velocity;
// x momentum changes only by the counted boundary jumps; the box slides at U = rate Ly;
// checkpoints continue bit for bit; the CPU follows the Reference trajectory; combinations
// that cannot work are refused, naming shearRate.  The same for the staggered integrator,
// whose polymer crosses the boundary inside its sub-cycle.

#include "TestHelpers.h"
#include "TestSchemes.h"
#include "openmm/CMAPTorsionForce.h"
#include "openmm/CustomCentroidBondForce.h"
#include "openmm/CustomCompoundBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/PeriodicTorsionForce.h"
#include "openmm/MonteCarloBarostat.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"

using namespace DPDPlugin;

namespace {

constexpr double RATE = 0.5, L = 5.0;

/** n particles at density 4 in an L^3 box with soft repulsion a = 25, random positions and thermal velocities. */
System* makeShearFluid(int n, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) {
    System* system = new System();
    system->setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    DPDSoftRepulsionForce* soft = new DPDSoftRepulsionForce(25.0, 1.0);
    system->addForce(soft);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uniform(0, L);
    std::normal_distribution<double> normal(0, 1);
    for (int i = 0; i < n; i++) {
        system->addParticle(1.0);
        positions.push_back(Vec3(uniform(rng), uniform(rng), uniform(rng)));
        velocities.push_back(Vec3(normal(rng), normal(rng), normal(rng)));
    }
    return system;
}

std::unique_ptr<Context> shearedContext(System& system, DPDThermostatIntegrator& integrator, const std::string& platform,
                                        const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities,
                                        const std::map<std::string, std::string>& properties = {}) {
    integrator.setShearRate(RATE);
    integrator.setRandomNumberSeed(17);
    std::unique_ptr<Context> context(new Context(system, integrator, Platform::getPlatformByName(platform), properties));
    context->setPositions(positions);
    context->setVelocities(velocities);
    return context;
}

class LeesEdwards : public testing::TestWithParam<Scheme> {};

/**
 * Two particles 0.42 apart: once across y = 0 (particle 1 at the top of the box, its image
 * below the box), once inside the box with particle 1 replaced by that image.  The pair's
 * random numbers are keyed by (i, j), so both copies draw the same: they must move alike.
 */
TEST_P(LeesEdwards, PairAcrossTheBoundaryFeelsTheImageVelocity) {
    const double U = RATE * L, offset = 1.7;
    const Vec3 v0(0.3, -0.2, 0.1), v1(-0.5, 0.4, 0.2), lift(0, 0.5 * L, 0);
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    system.addParticle(1.0);
    system.addParticle(1.0);
    CustomBondForce* none = new CustomBondForce("0");  // marks the System periodic
    none->setUsesPeriodicBoundaryConditions(true);
    system.addForce(none);
    // Across: particle 1 at (3.9, L - 0.25), its image at (3.9 - offset, -0.25) = (2.2, -0.25).
    const std::vector<Vec3> across = {Vec3(2.0, 0.1, 3.0), Vec3(3.9, L - 0.25, 3.1)};
    const std::vector<Vec3> inside = {across[0] + lift, Vec3(2.2, -0.25, 3.1) + lift};
    std::vector<State> states;
    for (bool isAcross : {true, false})
        for (const std::string& platform : platforms()) {
            std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
            integrator->setDefaultFriction(20.0);
            // SC-VV stops iterating on the lab-frame kinetic energy, which the image velocity
            // changes: make both copies take the same number of iterations.
            if (DPDVVIntegrator* vv = dynamic_cast<DPDVVIntegrator*>(integrator.get()))
                vv->setTolerance(0);
            std::unique_ptr<Context> context = shearedContext(system, *integrator, platform, isAcross ? across : inside,
                                                              {v0, isAcross ? v1 : v1 - Vec3(U, 0, 0)});
            context->setPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(offset, L, 0), Vec3(0, 0, L));
            integrator->step(3);
            states.push_back(context->getState(State::Positions | State::Velocities));
        }
    const size_t n = platforms().size();
    Vec3 a, b, c;
    states[0].getPeriodicBoxVectors(a, b, c);
    for (size_t k = 0; k < n; k++) {
        const State &acrossState = states[k], &insideState = states[n + k];
        const std::string label = GetParam().name + " on " + platforms()[k];
        const std::vector<Vec3> &r = acrossState.getPositions(), &v = acrossState.getVelocities();
        const std::vector<Vec3> &rIn = insideState.getPositions(), &vIn = insideState.getVelocities();
        EXPECT_GT((v[0] - v0).dot(v[0] - v0), 1e-6) << label << ": the pair did not interact";
        for (int axis = 0; axis < 3; axis++) {
            EXPECT_NEAR(v[0][axis], vIn[0][axis], 1e-12) << label;
            EXPECT_NEAR(v[1][axis] - (axis == 0 ? U : 0), vIn[1][axis], 1e-12) << label;
            EXPECT_NEAR(r[0][axis] + lift[axis], rIn[0][axis], 1e-12) << label;
            EXPECT_NEAR(r[1][axis] - b[axis] + lift[axis], rIn[1][axis], 1e-12) << label;
        }
    }
}

/**
 * `steps` sheared steps of the scheme on each platform: at every step the total x momentum of
 * the unit-mass particles changes by exactly U per boundary crossing (counted from the y
 * jumps) and y and z momentum not at all; at the end the box has slid by U t, reduced to
 * |offset| <= L/2.  crossings[p][i]: the crossings of particle i on platform p.
 */
void expectMomentumChangesOnlyByTheJumps(System& system, const Scheme& scheme, const std::vector<Vec3>& positions,
                                         const std::vector<Vec3>& velocities, int steps, std::vector<std::vector<int>>& crossings) {
    const double U = RATE * L;
    for (const std::string& platform : platforms()) {
        crossings.push_back(std::vector<int>(system.getNumParticles()));
        std::unique_ptr<DPDThermostatIntegrator> integrator(scheme.make());
        std::unique_ptr<Context> context = shearedContext(system, *integrator, platform, positions, velocities);
        const double tolerance = (platform == "Reference" ? 1e-10 : 1e-4);  // the CPU sums forces in float
        State before = context->getState(State::Positions | State::Velocities);
        for (int step = 0; step < steps; step++) {
            integrator->step(1);
            const State after = context->getState(State::Positions | State::Velocities);
            double jump = 0;
            Vec3 p0, p1;
            for (int i = 0; i < system.getNumParticles(); i++) {
                const double n = std::round((after.getPositions()[i][1] - before.getPositions()[i][1]) / L);
                jump += n * U;
                crossings.back()[i] += (n != 0);
                p0 += before.getVelocities()[i];
                p1 += after.getVelocities()[i];
            }
            ASSERT_NEAR(p1[0] - p0[0], jump, tolerance) << scheme.name << " on " << platform << ", step " << step;
            ASSERT_NEAR(p1[1], p0[1], tolerance) << scheme.name << " on " << platform;
            ASSERT_NEAR(p1[2], p0[2], tolerance) << scheme.name << " on " << platform;
            before = after;
        }
        Vec3 a, b, c;
        context->getState(0).getPeriodicBoxVectors(a, b, c);
        const double slid = U * steps * integrator->getStepSize();
        EXPECT_NEAR(b[0], slid - L * std::round(slid / L), 1e-9) << scheme.name;
    }
}

/** Total x momentum changes only by m U per boundary crossing (counted from the y jumps); y and z stay. */
TEST_P(LeesEdwards, MomentumChangesOnlyByTheBoundaryJumps) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearFluid(500, positions, velocities));
    std::vector<std::vector<int>> crossings;
    ASSERT_NO_FATAL_FAILURE(expectMomentumChangesOnlyByTheJumps(*system, GetParam(), positions, velocities, 100, crossings));
    for (size_t p = 0; p < crossings.size(); p++)
        EXPECT_GT(std::accumulate(crossings[p].begin(), crossings[p].end(), 0), 10) << GetParam().name << " on " << platforms()[p];
}

TEST_P(LeesEdwards, CheckpointContinuesBitForBit) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearFluid(300, positions, velocities));
    for (const std::string& platform : platforms()) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
        std::unique_ptr<Context> context = shearedContext(*system, *integrator, platform, positions, velocities);
        expectCheckpointContinuesBitForBit(*context, *integrator, GetParam().name + " on " + platform);
        Vec3 a, b, c;
        context->getState(0).getPeriodicBoxVectors(a, b, c);
        EXPECT_NE(b[0], 0) << "the box did not slide";
    }
}

/** setShearRate on a live Context: the box slides from the next step on, and the trajectory changes. */
TEST_P(LeesEdwards, ShearRateIsLive) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearFluid(300, positions, velocities));
    std::vector<State> states;
    for (bool change : {false, true}) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
        std::unique_ptr<Context> context = shearedContext(*system, *integrator, "Reference", positions, velocities);
        integrator->setShearRate(0);
        integrator->step(3);
        if (change)
            integrator->setShearRate(RATE);
        integrator->step(5);
        states.push_back(context->getState(State::Velocities));
        Vec3 a, b, c;
        states.back().getPeriodicBoxVectors(a, b, c);
        EXPECT_NEAR(b[0], change ? RATE * L * 5 * integrator->getStepSize() : 0.0, 1e-12) << GetParam().name;
    }
    EXPECT_GT(relativeDifference(states[0].getVelocities(), states[1].getVelocities()), 1e-6) << GetParam().name;
}

#if OPENMMDPD_HAVE_CPU
/** 20 sheared steps on the CPU platform with 1 and 2 threads follow the Reference platform's to 1e-10. */
void expectCpuFollowsReference(System& system, const Scheme& scheme, const std::vector<Vec3>& positions,
                               const std::vector<Vec3>& velocities) {
    std::unique_ptr<DPDThermostatIntegrator> reference(scheme.make());
    std::unique_ptr<Context> expected = shearedContext(system, *reference, "Reference", positions, velocities);
    reference->step(20);
    const State want = expected->getState(State::Positions | State::Velocities);
    for (int threads : {1, 2}) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(scheme.make());
        std::unique_ptr<Context> context =
                shearedContext(system, *integrator, "CPU", positions, velocities, {{"Threads", std::to_string(threads)}});
        integrator->step(20);
        const State got = context->getState(State::Positions | State::Velocities);
        EXPECT_LT(relativeDifference(want.getPositions(), got.getPositions()), 1e-10) << scheme.name << ", " << threads;
        EXPECT_LT(relativeDifference(want.getVelocities(), got.getVelocities()), 1e-10) << scheme.name << ", " << threads;
    }
}

TEST_P(LeesEdwards, CpuOnOneAndTwoThreadsFollowsTheReferenceTrajectory) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearFluid(500, positions, velocities));
    expectCpuFollowsReference(*system, GetParam(), positions, velocities);
}
#endif

std::string schemeName(const testing::TestParamInfo<Scheme>& info) {
    std::string name = info.param.name;
    for (char& c : name)
        if (!std::isalnum((unsigned char) c))
            c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(EveryIntegrator, LeesEdwards, testing::ValuesIn(schemesAt(0.02)), schemeName);

// ---- The staggered integrator: the polymer is sub-cycled, and crosses the boundary there.

const int CHAINS = 4, BEADS = 5;

/** Bonds 25 (r - 0.5)^2 in force group 1 (the staggered integrator's fast group), not periodic: they see their molecule whole. */
CustomBondForce* fastBonds() {
    CustomBondForce* bonds = new CustomBondForce("25*(r-0.5)^2");
    bonds->setForceGroup(1);
    return bonds;
}

/**
 * makeShearFluid whose first CHAINS x BEADS particles are chains, tilted in y so that they
 * straddle y = 0 or Ly (raw bead heights beyond the box, molecule centres inside) and moving
 * across it at 2 nm/ps.
 */
System* makeShearChains(int n, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) {
    System* system = makeShearFluid(n, positions, velocities);
    CustomBondForce* bonds = fastBonds();
    for (int c = 0; c < CHAINS; c++) {
        const bool top = (c % 2 == 0);
        for (int k = 0; k < BEADS; k++) {
            const int i = BEADS * c + k;
            positions[i] = Vec3(0.5 + 0.45 * k + c, (top ? L - 0.05 : 0.05) + 0.25 * (k - 2), 0.5 + 1.2 * c);
            velocities[i][1] = (top ? 2.0 : -2.0);
            if (k > 0)
                bonds->addBond(i - 1, i, {});
        }
    }
    system->addForce(bonds);
    return system;
}

/** The largest raw (not minimum-image) bond length of the chains. */
double longestBond(const std::vector<Vec3>& r) {
    double longest = 0;
    for (int c = 0; c < CHAINS; c++)
        for (int k = 1; k < BEADS; k++) {
            const Vec3 d = r[BEADS * c + k] - r[BEADS * c + k - 1];
            longest = std::max(longest, std::sqrt(d.dot(d)));
        }
    return longest;
}

class StaggeredLeesEdwards : public testing::TestWithParam<Scheme> {};

/**
 * As PairAcrossTheBoundaryFeelsTheImageVelocity: a bonded pair (the polymer) moving up
 * across y = Ly, with (velocity-Verlet base) a solvent particle beside it that crosses
 * later, against the same particles moved down by Ly/2 into the box, where no boundary is
 * near.  Every pair has the same geometry and random numbers in both, so the crossing copy
 * must be the other one moved up again and wrapped by whole lattice vectors (n b, x velocity
 * - n U), whether the molecule crossed in the outer drift or within the sub-cycle.  (The
 * Lowe base sweeps its pairs in an order set by their cells: with one pair it cannot differ.)
 */
TEST_P(StaggeredLeesEdwards, CrossingMoleculesMoveAsInsideTheBox) {
    const double U = RATE * L;
    std::unique_ptr<DPDThermostatIntegrator> probe(GetParam().make());
    const bool sequential = (dynamic_cast<StaggeredDPDIntegrator&>(*probe).getBaseScheme() == StaggeredDPDIntegrator::LoweAndersen);
    const int n = (sequential ? 2 : 3);
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    for (int i = 0; i < n; i++)
        system.addParticle(1.0);
    system.addForce(new DPDSoftRepulsionForce(25.0, 1.0));
    CustomBondForce* bond = fastBonds();
    bond->addBond(0, 1, {});
    system.addForce(bond);
    const std::vector<Vec3> across = {Vec3(2.0, L - 0.35, 2.5), Vec3(2.4, L + 0.15, 2.6), Vec3(2.9, L - 0.1, 2.4)};
    const std::vector<Vec3> velocities = {Vec3(0.3, 1.5, 0.1), Vec3(-0.2, 1.5, 0.2), Vec3(0.1, 0.8, -0.1)};
    const Vec3 lift(0, 0.5 * L, 0);
    for (const std::string& platform : platforms()) {
        std::vector<State> states;
        for (bool isAcross : {true, false}) {
            std::vector<Vec3> r(across.begin(), across.begin() + n), v(velocities.begin(), velocities.begin() + n);
            for (Vec3& position : r)
                position -= (isAcross ? Vec3() : lift);
            std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
            integrator->setDefaultFriction(20.0);
            std::unique_ptr<Context> context = shearedContext(system, *integrator, platform, r, v);
            context->setPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(1.7, L, 0), Vec3(0, 0, L));
            integrator->step(10);
            states.push_back(context->getState(State::Positions | State::Velocities));
        }
        Vec3 a, b, c;
        states[0].getPeriodicBoxVectors(a, b, c);
        const std::string label = GetParam().name + " on " + platform;
        int crossed = 0;
        for (int i = 0; i < n; i++) {
            const Vec3 d = states[0].getPositions()[i] - (states[1].getPositions()[i] + lift);
            const double images = std::round(d[1] / L);
            crossed += (images != 0);
            Vec3 e = d - b * images;
            e[0] -= L * std::round(e[0] / L);
            EXPECT_LT(std::sqrt(e.dot(e)), 1e-10) << label << ", particle " << i;
            const Vec3 dv = states[0].getVelocities()[i] - states[1].getVelocities()[i] - Vec3(images * U, 0, 0);
            EXPECT_LT(std::sqrt(dv.dot(dv)), 1e-10) << label << ", particle " << i;
        }
        EXPECT_EQ(crossed, n) << label << ": not every particle crossed";
        EXPECT_GT(std::fabs(states[0].getVelocities()[0][0] - velocities[0][0]), 1e-3) << label << ": no interaction";
    }
}

/** x momentum changes only by the counted boundary jumps, polymer crossings included; the box slides at U. */
TEST_P(StaggeredLeesEdwards, MomentumChangesOnlyByTheBoundaryJumps) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearChains(500, positions, velocities));
    std::vector<std::vector<int>> crossings;
    ASSERT_NO_FATAL_FAILURE(expectMomentumChangesOnlyByTheJumps(*system, GetParam(), positions, velocities, 40, crossings));
    for (size_t p = 0; p < crossings.size(); p++)
        EXPECT_GE(std::accumulate(crossings[p].begin(), crossings[p].begin() + CHAINS * BEADS, 0), CHAINS * BEADS)
                << GetParam().name << " on " << platforms()[p];
}

/** Chains straddling the boundary cross it whole: no bond is ever stretched across the box. */
TEST_P(StaggeredLeesEdwards, ChainsCrossWholeWithShortBonds) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearChains(500, positions, velocities));
    for (const std::string& platform : platforms()) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
        std::unique_ptr<Context> context = shearedContext(*system, *integrator, platform, positions, velocities);
        std::vector<Vec3> before = positions;
        int wraps = 0;
        for (int step = 0; step < 30; step++) {
            integrator->step(1);
            const std::vector<Vec3> r = context->getState(State::Positions).getPositions();
            // Stretched by the flow to ~1.2 at most; one across the box would be ~L.
            ASSERT_LT(longestBond(r), 2.0) << GetParam().name << " on " << platform << ", step " << step;
            for (int c = 0; c < CHAINS; c++)
                wraps += (std::fabs(r[BEADS * c][1] - before[BEADS * c][1]) > 0.5 * L);
            before = r;
        }
        EXPECT_GE(wraps, CHAINS) << GetParam().name << " on " << platform << ": the chains did not cross";
    }
}

TEST_P(StaggeredLeesEdwards, CheckpointContinuesBitForBit) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearChains(300, positions, velocities));
    for (const std::string& platform : platforms()) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
        std::unique_ptr<Context> context = shearedContext(*system, *integrator, platform, positions, velocities);
        expectCheckpointContinuesBitForBit(*context, *integrator, GetParam().name + " on " + platform);
    }
}

#if OPENMMDPD_HAVE_CPU
TEST_P(StaggeredLeesEdwards, CpuOnOneAndTwoThreadsFollowsTheReferenceTrajectory) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearChains(500, positions, velocities));
    expectCpuFollowsReference(*system, GetParam(), positions, velocities);
}
#endif

INSTANTIATE_TEST_SUITE_P(BothBases, StaggeredLeesEdwards, testing::ValuesIn(staggeredSchemesAt(0.02)), schemeName);

/** A molecule held together by one bonded Force of each kind that does not mark a bond for OpenMM. */
struct HeldMolecule {
    std::string kind;
    int size;
    std::function<Force*()> make;  // the Force joining particles 0 .. size-1
};

const std::vector<HeldMolecule> HELD_MOLECULES = {
    {"CustomCompoundBondForce", 2, [] {
         CustomCompoundBondForce* bond = new CustomCompoundBondForce(2, "50*(distance(p1,p2)-0.5)^2");
         bond->addBond({0, 1}, {});
         return bond;
     }},
    {"HarmonicAngleForce", 3, [] {
         HarmonicAngleForce* angle = new HarmonicAngleForce();
         angle->addAngle(0, 1, 2, 2.0, 10.0);
         return angle;
     }},
    {"PeriodicTorsionForce", 4, [] {
         PeriodicTorsionForce* torsion = new PeriodicTorsionForce();
         torsion->addTorsion(0, 1, 2, 3, 1, 0.0, 1.0);
         return torsion;
     }},
    {"CustomCentroidBondForce", 2, [] {
         CustomCentroidBondForce* centroid = new CustomCentroidBondForce(2, "50*(distance(g1,g2)-0.5)^2");
         centroid->addGroup({0});
         centroid->addGroup({1});
         centroid->addBond({0, 1}, {});
         return centroid;
     }},
    {"CMAPTorsionForce", 5, [] {
         CMAPTorsionForce* cmap = new CMAPTorsionForce();
         cmap->addMap(2, std::vector<double>(4, 0.0));
         cmap->addTorsion(0, 0, 1, 2, 3, 1, 2, 3, 4);
         return cmap;
     }},
};

/**
 * A molecule whose only link is a term of a Force OpenMM does not count as a bond crosses the
 * top of the sheared box: it must be wrapped whole (its particles stay ~0.5 apart), not
 * particle by particle (a box height apart).
 */
TEST(LeesEdwardsMolecules, EveryBondedTermKeepsItsMoleculeWhole) {
    for (const HeldMolecule& held : HELD_MOLECULES)
        for (const Scheme& scheme : {schemesAt(0.02)[0], schemesAt(0.02)[4]})  // GW, S1
            for (const std::string& platform : platforms()) {
                System system;
                system.setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
                std::vector<Vec3> positions, velocities;
                for (int i = 0; i < held.size; i++) {
                    system.addParticle(1.0);
                    // A zigzag just below y = L, moving up: its centre crosses within a few steps.
                    positions.push_back(Vec3(1.0 + 0.4 * i, L - 0.15 + 0.1 * (i % 2), 2.0 + 0.1 * (i % 3)));
                    velocities.push_back(Vec3(0, 2.0, 0));
                }
                system.addForce(held.make());
                CustomBondForce* marker = new CustomBondForce("0");  // makes the System periodic
                marker->setUsesPeriodicBoundaryConditions(true);
                system.addForce(marker);
                std::unique_ptr<DPDThermostatIntegrator> integrator(scheme.make());
                std::unique_ptr<Context> context = shearedContext(system, *integrator, platform, positions, velocities);
                integrator->step(20);
                const std::vector<Vec3> r = context->getState(State::Positions).getPositions();
                const std::string where = held.kind + ", " + scheme.name + " on " + platform;
                double centre = 0;
                for (int i = 0; i < held.size; i++) {
                    centre += r[i][1] / held.size;
                    for (int j = 0; j < i; j++)
                        EXPECT_LT(std::sqrt((r[i] - r[j]).dot(r[i] - r[j])), 0.5 * L) << where << ", particles " << j << ", " << i;
                }
                EXPECT_LT(centre, 0.5 * L) << where << ": the molecule did not cross";
            }
}

/** Each combination that cannot be sheared is refused when the Context is made, naming shearRate. */
TEST(LeesEdwardsRefuses, WhatCannotBeSheared) {
    auto refused = [](const std::function<void(System&)>& change, DPDThermostatIntegrator* integrator) {
        std::vector<Vec3> positions, velocities;
        std::unique_ptr<System> system(makeShearFluid(100, positions, velocities));
        change(*system);
        std::unique_ptr<DPDThermostatIntegrator> owned(integrator);
        owned->setShearRate(RATE);
        expectErrorNaming([&] { Context context(*system, *owned, Platform::getPlatformByName("Reference")); }, "shearRate");
    };
    auto gw = [] { return schemesAt(0.02)[0].make(); };
    refused([](System& s) { s.setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0.5, 0, L)); }, gw());
    refused([](System& s) { s.addForce(new MonteCarloBarostat(1.0, 300.0)); }, gw());
    refused([](System& s) {
        CustomNonbondedForce* open = new CustomNonbondedForce("0");
        for (int i = 0; i < s.getNumParticles(); i++)
            open->addParticle({});
        s.addForce(open);
    }, gw());
    std::unique_ptr<DPDThermostatIntegrator> integrator(gw());
    expectErrorNaming([&] { integrator->setShearRate(NAN); }, "shearRate");
}

/** A box tilted on a live Context is refused at the next step, as it is in the System. */
TEST(LeesEdwardsRefuses, ATiltedBoxSetOnALiveContext) {
    for (const std::string& platform : platforms()) {
        std::vector<Vec3> positions, velocities;
        std::unique_ptr<System> system(makeShearFluid(100, positions, velocities));
        std::unique_ptr<DPDThermostatIntegrator> integrator(schemesAt(0.02)[0].make());
        std::unique_ptr<Context> context = shearedContext(*system, *integrator, platform, positions, velocities);
        integrator->step(1);
        context->setPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0.5, 0.6, L));
        expectErrorNaming([&] { integrator->step(1); }, "the third vector of the Context's box must be (0, 0, Lz)");
        EXPECT_EQ(context->getState(0).getStepCount(), 1) << platform;
    }
}

} // namespace
