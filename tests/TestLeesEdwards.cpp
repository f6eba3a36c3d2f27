// Lees-Edwards shear (algorithms.md section 8) in every single-rate integrator: a pair across
// the sliding boundary is the same pair as inside the box with its partner's image velocity;
// x momentum changes only by the counted boundary jumps; the box slides at U = rate Ly;
// checkpoints continue bit for bit; the CPU follows the Reference trajectory; combinations
// that cannot work are refused, naming shearRate.

#include "TestHelpers.h"
#include "TestSchemes.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/MonteCarloBarostat.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"

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

/** Total x momentum changes only by m U per boundary crossing (counted from the y jumps); y and z stay. */
TEST_P(LeesEdwards, MomentumChangesOnlyByTheBoundaryJumps) {
    const double U = RATE * L;
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearFluid(500, positions, velocities));
    for (const std::string& platform : platforms()) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
        std::unique_ptr<Context> context = shearedContext(*system, *integrator, platform, positions, velocities);
        const double tolerance = (platform == "Reference" ? 1e-10 : 1e-4);  // the CPU sums forces in float
        State before = context->getState(State::Positions | State::Velocities);
        int crossings = 0;
        for (int step = 0; step < 100; step++) {
            integrator->step(1);
            const State after = context->getState(State::Positions | State::Velocities);
            double jump = 0;
            for (int i = 0; i < system->getNumParticles(); i++) {
                const double n = std::round((after.getPositions()[i][1] - before.getPositions()[i][1]) / L);
                jump += n * U;
                crossings += (n != 0);
            }
            Vec3 p0, p1;
            for (int i = 0; i < system->getNumParticles(); i++) {
                p0 += before.getVelocities()[i];
                p1 += after.getVelocities()[i];
            }
            ASSERT_NEAR(p1[0] - p0[0], jump, tolerance) << GetParam().name << " on " << platform << ", step " << step;
            ASSERT_NEAR(p1[1], p0[1], tolerance) << GetParam().name << " on " << platform;
            ASSERT_NEAR(p1[2], p0[2], tolerance) << GetParam().name << " on " << platform;
            before = after;
        }
        EXPECT_GT(crossings, 10) << GetParam().name << " on " << platform;
        // The box slid by U t, reduced to |offset| <= L/2.
        Vec3 a, b, c;
        context->getState(0).getPeriodicBoxVectors(a, b, c);
        const double slid = U * 100 * integrator->getStepSize();
        EXPECT_NEAR(b[0], slid - L * std::round(slid / L), 1e-9) << GetParam().name;
    }
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
TEST_P(LeesEdwards, CpuOnOneAndTwoThreadsFollowsTheReferenceTrajectory) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeShearFluid(500, positions, velocities));
    std::unique_ptr<DPDThermostatIntegrator> reference(GetParam().make());
    std::unique_ptr<Context> expected = shearedContext(*system, *reference, "Reference", positions, velocities);
    reference->step(20);
    const State want = expected->getState(State::Positions | State::Velocities);
    for (int threads : {1, 2}) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
        std::unique_ptr<Context> context =
                shearedContext(*system, *integrator, "CPU", positions, velocities, {{"Threads", std::to_string(threads)}});
        integrator->step(20);
        const State got = context->getState(State::Positions | State::Velocities);
        EXPECT_LT(relativeDifference(want.getPositions(), got.getPositions()), 1e-10) << GetParam().name << ", " << threads;
        EXPECT_LT(relativeDifference(want.getVelocities(), got.getVelocities()), 1e-10) << GetParam().name << ", " << threads;
    }
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
    refused([](System&) {}, new StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, 0.02, 2));
    std::unique_ptr<DPDThermostatIntegrator> integrator(gw());
    expectErrorNaming([&] { integrator->setShearRate(NAN); }, "shearRate");
}

} // namespace
