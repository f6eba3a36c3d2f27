// The pressure tensor (docs/theory/pressure-tensor.md): sampling it leaves every trajectory alone;
// the CPU's equals the Reference's; the exact pair virial of DPDSoftRepulsionForce equals the
// strain derivative of the same energy written as a CustomNonbondedForce; a sweep's part is
// the impulse its pair received over dt; a checkpoint carries the running average, so loading
// one rewinds it with the run; what cannot be sampled is refused.

#include "TestHelpers.h"
#include "TestSchemes.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include <sstream>

using namespace DPDPlugin;

namespace {

constexpr double L = 5.0;

/** Model B (rho 4, a 25) of 500 particles in an L^3 box, the soft force as DPDSoftRepulsionForce or as a CustomNonbondedForce. */
System* makeModelB(bool native, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) {
    System* system = new System();
    system->setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uniform(0, L);
    std::normal_distribution<double> normal(0, 1);
    for (int i = 0; i < 500; i++) {
        system->addParticle(1.0);
        positions.push_back(Vec3(uniform(rng), uniform(rng), uniform(rng)));
        velocities.push_back(Vec3(normal(rng), normal(rng), normal(rng)));
    }
    if (native) {
        system->addForce(new DPDSoftRepulsionForce(25.0, 1.0));
        return system;
    }
    CustomNonbondedForce* soft = new CustomNonbondedForce("25*(1-r)^2/2");
    soft->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    soft->setCutoffDistance(1.0);
    for (int i = 0; i < 500; i++)
        soft->addParticle({});
    system->addForce(soft);
    return system;
}

std::unique_ptr<Context> sampledContext(System& system, DPDThermostatIntegrator& integrator, const std::string& platform,
                                        const std::vector<Vec3>& positions, const std::vector<Vec3>& velocities, bool sample) {
    integrator.setRandomNumberSeed(17);
    integrator.setPressureTensorEnabled(sample);
    std::unique_ptr<Context> context(new Context(system, integrator, Platform::getPlatformByName(platform)));
    context->setPositions(positions);
    context->setVelocities(velocities);
    return context;
}

/** The schemes whose steps sample the pressure tensor. */
std::vector<Scheme> sampledSchemes() {
    std::vector<Scheme> schemes;
    for (const Scheme& scheme : schemesAt(0.02))
        if (scheme.name != "OC")
            schemes.push_back(scheme);
    return schemes;
}

/** max over the components of |a - b|, over max |a|. */
double tensorDifference(const std::vector<double>& a, const std::vector<double>& b) {
    double difference = 0, scale = 0;
    for (int k = 0; k < 6; k++) {
        difference = std::max(difference, std::fabs(a[k] - b[k]));
        scale = std::max(scale, std::fabs(a[k]));
    }
    return difference / scale;
}

class PressureTensorSchemes : public testing::TestWithParam<Scheme> {};

TEST_P(PressureTensorSchemes, SamplingLeavesTheTrajectoryAlone) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeModelB(true, positions, velocities));
    for (const std::string& platform : platforms()) {
        std::vector<State> states;
        for (bool sample : {false, true}) {
            std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
            integrator->setShearRate(0.5);
            std::unique_ptr<Context> context = sampledContext(*system, *integrator, platform, positions, velocities, sample);
            integrator->step(5);
            EXPECT_EQ(integrator->getPressureTensorSampleCount(), sample ? 5 : 0);
            states.push_back(context->getState(State::Positions | State::Velocities));
        }
        for (size_t i = 0; i < positions.size(); i++) {
            ASSERT_EQ(states[0].getPositions()[i], states[1].getPositions()[i]) << platform << " particle " << i;
            ASSERT_EQ(states[0].getVelocities()[i], states[1].getVelocities()[i]) << platform << " particle " << i;
        }
    }
}

TEST_P(PressureTensorSchemes, CpuFollowsReference) {
    if (platforms().size() < 2)
        GTEST_SKIP() << "no CPU platform";
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeModelB(true, positions, velocities));
    std::vector<std::vector<double>> parts[2];
    for (int p = 0; p < 2; p++) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(GetParam().make());
        integrator->setShearRate(0.5);
        std::unique_ptr<Context> context = sampledContext(*system, *integrator, platforms()[p], positions, velocities, true);
        integrator->step(5);
        for (int part = 0; part <= DPDThermostatIntegrator::PressureThermostat; part++)
            parts[p].push_back(integrator->getAveragePressureTensor(part));
    }
    for (int part = 0; part <= DPDThermostatIntegrator::PressureThermostat; part++)
        EXPECT_LT(tensorDifference(parts[0][part], parts[1][part]), 1e-9) << "part " << part;
    // The parts add up to the whole.
    for (int k = 0; k < 6; k++)
        EXPECT_NEAR(parts[0][0][k], parts[0][1][k] + parts[0][2][k] + parts[0][3][k], 1e-12 * std::fabs(parts[0][0][0]));
}

INSTANTIATE_TEST_SUITE_P(Schemes, PressureTensorSchemes, testing::ValuesIn(sampledSchemes()),
                         [](const testing::TestParamInfo<Scheme>& info) {
                             std::string name = info.param.name;
                             std::replace(name.begin(), name.end(), '-', '_');
                             std::replace(name.begin(), name.end(), '.', '_');
                             return name;
                         });

/**
 * One step of S1 from the same state with the soft force as DPDSoftRepulsionForce (its
 * kernel's pair virial) and as a CustomNonbondedForce (the strain derivative of its energy).
 */
TEST(PressureTensor, StrainDerivativeMatchesThePairVirial) {
    for (const std::string& platform : platforms()) {
        std::vector<std::vector<double>> conservative;
        for (bool native : {true, false}) {
            std::vector<Vec3> positions, velocities;
            std::unique_ptr<System> system(makeModelB(native, positions, velocities));
            ShardlowIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.02);
            integrator.setShearRate(0.5);  // a sheared box, so the xy strain meets b = (offset, Ly, 0)
            std::unique_ptr<Context> context = sampledContext(*system, integrator, platform, positions, velocities, true);
            integrator.step(1);
            conservative.push_back(integrator.getAveragePressureTensor(DPDThermostatIntegrator::PressureConservative));
        }
        // The CPU platform evaluates a CustomNonbondedForce in single precision.
        EXPECT_LT(tensorDifference(conservative[0], conservative[1]), platform == "Reference" ? 1e-5 : 2e-4) << platform;
        EXPECT_GT(conservative[0][0], 10.0) << platform;  // model B's virial pressure is ~40
    }
}

/**
 * Two particles, no conservative force, a thermostat pair update that always acts: the
 * thermostat part is r J e e^T / (dt V), J the impulse the pair received (m times particle
 * 0's velocity change), r and e the pair's at the positions the sweep saw.
 */
TEST(PressureTensor, SweepPartIsTheImpulseOverTheStep) {
    const double dt = 0.02, V = L * L * L;
    const std::vector<Vec3> positions = {Vec3(1.0, 1.0, 1.0), Vec3(1.5, 1.3, 0.8)}, velocities = {Vec3(0.3, -0.2, 0.1), Vec3(-0.5, 0.4, 0.2)};
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    system.addParticle(1.0);
    system.addParticle(1.0);
    CustomBondForce* none = new CustomBondForce("0");
    none->setUsesPeriodicBoundaryConditions(true);
    system.addForce(none);
    for (const std::string& platform : platforms())
        for (bool lowe : {true, false}) {
            std::unique_ptr<DPDThermostatIntegrator> integrator;
            if (lowe)
                integrator.reset(new LoweAndersenIntegrator(KT_KELVIN, 1 / dt, 1.0, dt));  // Gamma dt = 1: the pair always collides
            else
                integrator.reset(new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, dt));
            std::unique_ptr<Context> context = sampledContext(system, *integrator, platform, positions, velocities, true);
            integrator->step(1);
            const State state = context->getState(State::Positions | State::Velocities);
            // Lowe acts after the drift, S1 before it.
            const Vec3 d = lowe ? state.getPositions()[0] - state.getPositions()[1] : positions[0] - positions[1];
            const double r = std::sqrt(d.dot(d));
            const Vec3 e = d / r, impulse = state.getVelocities()[0] - velocities[0];
            const double J = impulse.dot(e);
            EXPECT_NEAR((impulse - e * J).dot(impulse - e * J), 0.0, 1e-24);
            const double expected[6] = {e[0] * e[0], e[1] * e[1], e[2] * e[2], e[0] * e[1], e[0] * e[2], e[1] * e[2]};
            const std::vector<double> part = integrator->getAveragePressureTensor(DPDThermostatIntegrator::PressureThermostat);
            for (int k = 0; k < 6; k++)
                EXPECT_NEAR(part[k], r * J * expected[k] / (dt * V), 1e-12) << platform << (lowe ? " Lowe" : " S1") << " component " << k;
            const std::vector<double> kinetic = integrator->getAveragePressureTensor(DPDThermostatIntegrator::PressureKinetic);
            // the velocities less their mean (u0 = -u1)
            const Vec3 u = (state.getVelocities()[0] - state.getVelocities()[1]) * 0.5;
            EXPECT_NEAR(kinetic[3], 2 * u[0] * u[1] / V, 1e-14);
            EXPECT_EQ(integrator->getAveragePressureTensor(DPDThermostatIntegrator::PressureConservative)[0], 0.0);
        }
}

TEST(PressureTensor, LoadingACheckpointRewindsTheAverage) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeModelB(true, positions, velocities));
    for (const std::string& platform : platforms()) {
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.02);
        std::unique_ptr<Context> context = sampledContext(*system, integrator, platform, positions, velocities, false);
        std::stringstream unsampled;
        context->createCheckpoint(unsampled);
        integrator.setPressureTensorEnabled(true);
        integrator.step(10);
        std::stringstream atTen;
        context->createCheckpoint(atTen);
        const std::vector<double> averageAtTen = integrator.getAveragePressureTensor();
        integrator.step(10);
        ASSERT_EQ(integrator.getPressureTensorSampleCount(), 20);
        context->loadCheckpoint(atTen);
        EXPECT_EQ(integrator.getPressureTensorSampleCount(), 10) << platform;
        EXPECT_EQ(integrator.getAveragePressureTensor(), averageAtTen) << platform;
        context->loadCheckpoint(unsampled);
        EXPECT_EQ(integrator.getPressureTensorSampleCount(), 0) << platform;
    }
}

TEST(PressureTensor, Refuses) {
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeModelB(true, positions, velocities));
    DenOtterClarkeIntegrator denOtterClarke(KT_KELVIN, 4.5, 1.0, 0.02);
    expectErrorNaming([&] { denOtterClarke.setPressureTensorEnabled(true); }, "pressure tensor");
    StaggeredDPDIntegrator staggered(KT_KELVIN, 4.5, 1.0, 0.02);
    expectErrorNaming([&] { staggered.setPressureTensorEnabled(true); }, "pressure tensor");
    DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.02);
    std::unique_ptr<Context> context = sampledContext(*system, integrator, "Reference", positions, velocities, true);
    expectErrorNaming([&] { integrator.getAveragePressureTensor(); }, "no step has sampled");
    integrator.step(1);
    expectErrorNaming([&] { integrator.getAveragePressureTensor(4); }, "pressure tensor part");
    integrator.resetPressureTensor();
    EXPECT_EQ(integrator.getPressureTensorSampleCount(), 0);
    system->addConstraint(0, 1, 0.5);
    DPDVVIntegrator constrained(KT_KELVIN, 4.5, 1.0, 0.02);
    std::unique_ptr<Context> withConstraint = sampledContext(*system, constrained, "Reference", positions, velocities, true);
    expectErrorNaming([&] { constrained.step(1); }, "constraints");
}

} // namespace
