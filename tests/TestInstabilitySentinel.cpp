// The instability sentinel (DPDThermostatIntegrator::setInstabilityThreshold): a step after
// which a particle's kinetic energy exceeds the threshold times kT stops the run, on both
// platforms and for every integrator, at the step the exact trajectory predicts, and leaves
// the Context at that step: its state, time and step count.

#include "TestHelpers.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/serialization/XmlSerializer.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include <functional>
#include <regex>
#include <sstream>

using namespace DPDPlugin;

namespace {

constexpr double DT = 0.01, PUSH = 10.0;  // ps; kJ/mol/nm on particle 0 (unit mass)

/**
 * Particle 0 alone, pushed along x by a constant force: no thermostat pair ever forms, so
 * its speed after n steps is exactly PUSH n DT (every scheme is exact for a constant force)
 * and its kinetic energy 50 (0.1 n)^2 kJ/mol.  With kT = 1 kJ/mol and threshold 40 that is
 * 39.605 after step 89 and 40.5 after step 90.  Particles 1 and 2, out of each other's
 * cutoff and at rest, carry a null bond in force group 1 (the staggered integrator's fast group).
 */
System* makePushedParticle(std::vector<Vec3>& positions) {
    System* system = new System();
    for (int i = 0; i < 3; i++)
        system->addParticle(1.0);
    CustomExternalForce* push = new CustomExternalForce("-f*x");
    push->addGlobalParameter("f", PUSH);
    push->addParticle(0, {});
    system->addForce(push);
    CustomBondForce* fast = new CustomBondForce("0");
    fast->addBond(1, 2, {});
    fast->setForceGroup(1);
    system->addForce(fast);
    positions = {Vec3(0, 0, 0), Vec3(0, 50, 0), Vec3(0, 52, 0)};
    return system;
}

struct Scheme {
    std::string name;
    std::function<DPDThermostatIntegrator*(double temperature)> make;
};

template <class Integrator, class Setting>
std::function<DPDThermostatIntegrator*(double)> withSetting(Setting setting) {
    return [setting](double temperature) {
        Integrator* integrator = new Integrator(temperature, 4.5, 1.0, DT);
        setting(*integrator);
        return integrator;
    };
}

const std::vector<Scheme> SCHEMES = {
    {"GW", withSetting<DPDVVIntegrator>([](DPDVVIntegrator& i) { i.setLambda(0.5); })},
    {"S1", withSetting<ShardlowIntegrator>([](ShardlowIntegrator& i) { i.setOrder(1); })},
    {"Lowe", withSetting<LoweAndersenIntegrator>([](LoweAndersenIntegrator& i) { i.setMethod(LoweAndersenIntegrator::Lowe); })},
    {"PairOU", withSetting<LoweAndersenIntegrator>(
            [](LoweAndersenIntegrator& i) { i.setMethod(LoweAndersenIntegrator::PairOrnsteinUhlenbeck); })},
    {"EDPD", [](double temperature) { return new EDPDIntegrator(temperature, 4.5, 1.0, 10.0, DT); }},
    {"Staggered-VV", withSetting<StaggeredDPDIntegrator>(
            [](StaggeredDPDIntegrator& i) { i.setBaseScheme(StaggeredDPDIntegrator::VelocityVerlet); })},
    {"Staggered-Lowe", withSetting<StaggeredDPDIntegrator>(
            [](StaggeredDPDIntegrator& i) { i.setBaseScheme(StaggeredDPDIntegrator::LoweAndersen); })},
};

/** Steps until the run stops (at most maxSteps); the message, or "" if it did not stop. */
std::string runUntilStopped(DPDThermostatIntegrator& integrator, const std::string& platform, int maxSteps) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makePushedParticle(positions));
    Context context(*system, integrator, Platform::getPlatformByName(platform));
    context.setPositions(positions);
    context.setVelocities(std::vector<Vec3>(3));
    try {
        integrator.step(maxSteps);
    }
    catch (const OpenMMException& e) {
        return e.what();
    }
    return "";
}

} // namespace

TEST(InstabilitySentinel, StopsEveryIntegratorAtTheExactStepOnBothPlatforms) {
    for (const Scheme& scheme : SCHEMES)
        for (const std::string& platform : platforms())
            for (double kT : {1.0, 2.0}) {
                // Threshold 40 at kT = 1 and 20 at kT = 2: the same 40 kJ/mol, crossed at step 90.
                std::unique_ptr<DPDThermostatIntegrator> integrator(scheme.make(kT * KT_KELVIN));
                integrator->setInstabilityThreshold(40 / kT);
                const std::string message = runUntilStopped(*integrator, platform, 200);
                const std::string where = scheme.name + " on " + platform + ", kT = " + std::to_string(kT);
                const std::string expected = integrator->className() + std::string(": the simulation is unstable at step 90: particle 0 ");
                EXPECT_EQ(message.find(expected), 0u) << where << ": " << message;
                EXPECT_NE(message.find("above the instability threshold " + std::string(kT == 1 ? "40" : "20") + " kT"),
                          std::string::npos) << where << ": " << message;
            }
}

TEST(InstabilitySentinel, LeavesTheContextAtTheStoppedStep) {
    for (const Scheme& scheme : SCHEMES)
        for (const std::string& platform : platforms()) {
            std::unique_ptr<DPDThermostatIntegrator> integrator(scheme.make(KT_KELVIN));
            integrator->setInstabilityThreshold(40);
            std::vector<Vec3> positions;
            std::unique_ptr<System> system(makePushedParticle(positions));
            Context context(*system, *integrator, Platform::getPlatformByName(platform));
            context.setPositions(positions);
            context.setVelocities(std::vector<Vec3>(3));
            EXPECT_THROW(integrator->step(200), OpenMMException);
            const std::string where = scheme.name + " on " + platform;
            State state = context.getState(State::Velocities);
            EXPECT_EQ(state.getStepCount(), 90) << where;
            EXPECT_NEAR(state.getTime(), 90 * DT, 1e-12) << where;
            EXPECT_NEAR(state.getVelocities()[0][0], PUSH * 90 * DT, 1e-9) << where;
            // Stepping on continues from that state: the next step is step 91.
            integrator->setInstabilityThreshold(0);
            integrator->step(1);
            state = context.getState(State::Velocities);
            EXPECT_EQ(state.getStepCount(), 91) << where;
            EXPECT_NEAR(state.getVelocities()[0][0], PUSH * 91 * DT, 1e-9) << where;
        }
}

TEST(InstabilitySentinel, OffByDefaultAndAtZeroTemperature) {
    for (const Scheme& scheme : SCHEMES)
        for (const std::string& platform : platforms()) {
            // After 200 steps particle 0 has 200 kJ/mol: far above 40 kT, and nothing stops.
            std::unique_ptr<DPDThermostatIntegrator> off(scheme.make(KT_KELVIN));
            EXPECT_EQ(off->getInstabilityThreshold(), 0.0);
            EXPECT_EQ(runUntilStopped(*off, platform, 200), "") << scheme.name << " on " << platform;
            // At 0 K there is no kT to measure against: the check is off.
            std::unique_ptr<DPDThermostatIntegrator> cold(scheme.make(0.0));
            cold->setInstabilityThreshold(40);
            EXPECT_EQ(runUntilStopped(*cold, platform, 200), "") << scheme.name << " at 0 K on " << platform;
        }
}

TEST(InstabilitySentinel, TakesEffectOnALiveContext) {
    for (const std::string& platform : platforms()) {
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, DT);
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makePushedParticle(positions));
        Context context(*system, integrator, Platform::getPlatformByName(platform));
        context.setPositions(positions);
        context.setVelocities(std::vector<Vec3>(3));
        integrator.step(95);  // off: past the crossing at step 90
        integrator.setInstabilityThreshold(40);
        expectErrorNaming([&] { integrator.step(1); }, "unstable at step 96: particle 0");
    }
}

TEST(InstabilitySentinel, HugeVelocityStopsAtTheFirstStep) {
    // A fluid with one particle 100 times too fast: its kinetic energy ~1e4 kT.
    for (const std::string& platform : platforms()) {
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeFluid(500, 25.0, positions));
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01);
        integrator.setInstabilityThreshold(40);
        std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions);
        std::vector<Vec3> v = context->getState(State::Velocities).getVelocities();
        v[123] = Vec3(100, 50, -80);
        context->setVelocities(v);
        expectErrorNaming([&] { integrator.step(10); }, "DPDVVIntegrator: the simulation is unstable at step 1: particle 123 has kinetic energy");
    }
}

#if OPENMMDPD_HAVE_CPU
TEST(InstabilitySentinel, TwoThreadsNameTheFirstParticleAsOneDoes) {
    // Enough particles for the CPU platform to share the end-of-step check out over its
    // threads (ParallelExecutor::SERIAL_LOOP_LIMIT): a fast particle in either thread's half
    // stops the run, and with one in each the lower index is named, as with one thread.
    const int n = 20000;
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(n, 0.0, positions));
    for (const std::vector<int>& fast : {std::vector<int>{15000}, std::vector<int>{3000, 15000}})
        for (int threads : {1, 2}) {
            ShardlowIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01);
            integrator.setInstabilityThreshold(40);
            std::unique_ptr<Context> context = makeContext(*system, integrator, "CPU", positions, threads);
            std::vector<Vec3> v = context->getState(State::Velocities).getVelocities();
            for (int i : fast)
                v[i] = Vec3(100, 50, -80);
            context->setVelocities(v);
            expectErrorNaming([&] { integrator.step(2); },
                              "unstable at step 1: particle " + std::to_string(fast[0]) + " has kinetic energy");
        }
}
#endif

TEST(InstabilitySentinel, RejectsBadThresholds) {
    DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01);
    for (double bad : {-1.0, (double) NAN, (double) INFINITY})
        expectErrorNaming([&] { integrator.setInstabilityThreshold(bad); }, "instabilityThreshold must be >= 0");
    EXPECT_EQ(integrator.getInstabilityThreshold(), 0.0);
    integrator.setInstabilityThreshold(40);
    EXPECT_EQ(integrator.getInstabilityThreshold(), 40.0);
}

TEST(InstabilitySentinel, SerializedWithEveryIntegratorAndAbsentFromOldXmlMeansOff) {
    for (const Scheme& scheme : SCHEMES) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(scheme.make(KT_KELVIN));
        integrator->setInstabilityThreshold(37.5);
        std::stringstream buffer;
        XmlSerializer::serialize<Integrator>(integrator.get(), "Integrator", buffer);
        const std::string xml = buffer.str();
        std::stringstream current(xml);
        std::unique_ptr<Integrator> copy(XmlSerializer::deserialize<Integrator>(current));
        EXPECT_EQ(dynamic_cast<DPDThermostatIntegrator&>(*copy).getInstabilityThreshold(), 37.5) << scheme.name;
        // XML written before the sentinel existed: the attribute is missing.
        std::stringstream old(std::regex_replace(xml, std::regex(" instabilityThreshold=\"[^\"]*\""), ""));
        ASSERT_EQ(old.str().find("instabilityThreshold"), std::string::npos) << scheme.name;
        std::unique_ptr<Integrator> oldCopy(XmlSerializer::deserialize<Integrator>(old));
        EXPECT_EQ(dynamic_cast<DPDThermostatIntegrator&>(*oldCopy).getInstabilityThreshold(), 0.0) << scheme.name;
    }
}
