#include "TestHelpers.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DPDThermostatForces.h"
#include "openmm/Context.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/OpenMMException.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/serialization/XmlSerializer.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include <gtest/gtest.h>
#include <cmath>
#include <memory>
#include <random>
#include <sstream>

using namespace DPDPlugin;
using namespace OpenMM;

namespace {

DPDVVIntegrator makeIntegrator(DPDVVIntegrator::Variant variant, double dt, int seed = 42) {
    DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, dt);
    integrator.setVariant(variant);
    integrator.setRandomNumberSeed(seed);
    return integrator;
}

const DPDVVIntegrator::Variant VARIANTS[] = {DPDVVIntegrator::GrootWarren, DPDVVIntegrator::DPDVV, DPDVVIntegrator::SelfConsistent};

} // namespace

TEST(DPDVVIntegrator, InvalidParametersNameThemselves) {
    expectErrorNaming([] { DPDVVIntegrator(-1, 4.5, 1, 0.01); }, "temperature");
    expectErrorNaming([] { DPDVVIntegrator(300, -1, 1, 0.01); }, "defaultFriction");
    expectErrorNaming([] { DPDVVIntegrator(300, 4.5, 0, 0.01); }, "defaultCutoff");
    expectErrorNaming([] { DPDVVIntegrator(300, 4.5, 1, -0.01); }, "stepSize");
    DPDVVIntegrator integrator(300, 4.5, 1, 0.01);
    expectErrorNaming([&] { integrator.setLambda(1.2); }, "lambda");
    expectErrorNaming([&] { integrator.setLambda(-0.1); }, "lambda");
    expectErrorNaming([&] { integrator.setMaxIterations(0); }, "maxIterations");
    expectErrorNaming([&] { integrator.setStepSize(0); }, "stepSize");
    expectErrorNaming([&] { integrator.setParticleType(0, -2); }, "type");
    expectErrorNaming([&] { integrator.addTypePair(0, 1, 4.5, -1); }, "cutoff");
    expectErrorNaming([&] { integrator.addTypePair(0, 1, -4.5, 1); }, "friction");
    expectErrorNaming([&] { integrator.setTypePairParameters(0, 0, 1, 1, 1); }, "pairIndex");
    // Nothing was changed by the failed calls.
    EXPECT_EQ(integrator.getLambda(), 0.5);
    EXPECT_EQ(integrator.getNumTypePairs(), 0);
    EXPECT_EQ(integrator.getStepSize(), 0.01);

    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(64, 25, positions));  // box 2.52 nm
    DPDVVIntegrator wide(KT_KELVIN, 4.5, 1.5, 0.01);
    expectErrorNaming([&] { Context c(*system, wide, Platform::getPlatformByName("Reference")); }, "half the periodic box");
    DPDVVIntegrator unknown(KT_KELVIN, 4.5, 1.0, 0.01);
    unknown.addTypePair(0, 3, 1.0, 1.0);
    expectErrorNaming([&] { Context c(*system, unknown, Platform::getPlatformByName("Reference")); }, "unknown particle type");
    DPDVVIntegrator outside(KT_KELVIN, 4.5, 1.0, 0.01);
    outside.setParticleType(1000, 1);
    expectErrorNaming([&] { Context c(*system, outside, Platform::getPlatformByName("Reference")); }, "particle index 1000");
}

TEST(DPDVVIntegrator, MomentumConservedToRounding) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(500, 25, positions));
    for (auto variant : VARIANTS) {
        DPDVVIntegrator integrator = makeIntegrator(variant, 0.04);
        // Reference: double-precision forces, so the total momentum only sees rounding.
        auto context = makeContext(*system, integrator, "Reference", positions);
        std::vector<Vec3> v = context->getState(State::Velocities).getVelocities();
        Vec3 p0;
        for (const Vec3& vi : v)
            p0 += vi;

        for (int step = 0; step < 50; step++) {
            integrator.step(1);
            Vec3 p;
            const State state = context->getState(State::Velocities);
            for (const Vec3& vi : state.getVelocities())
                p += vi;
            // One particle's thermal momentum is ~1; rounding of 500 of them is ~1e-13.
            ASSERT_LT(std::sqrt((p - p0).dot(p - p0)), 1e-11) << "variant " << variant << " step " << step;
        }
    }
}

#if OPENMMDPD_HAVE_CPU
// CPU against Reference: TestPlatformsAgree.cpp.

TEST(DPDVVIntegrator, OneAndTwoThreadsAgree) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(2000, 25, positions));
    DPDVVIntegrator one = makeIntegrator(DPDVVIntegrator::GrootWarren, 0.04), two = makeIntegrator(DPDVVIntegrator::GrootWarren, 0.04);
    auto c1 = makeContext(*system, one, "CPU", positions, 1);
    auto c2 = makeContext(*system, two, "CPU", positions, 2);
    one.step(5);
    two.step(5);
    std::vector<Vec3> v1 = c1->getState(State::Velocities).getVelocities(), v2 = c2->getState(State::Velocities).getVelocities();
    for (size_t i = 0; i < v1.size(); i++) {
        Vec3 d = v1[i] - v2[i];
        // Float rounding of the CPU platform's conservative force sums, nothing more.
        ASSERT_LT(std::sqrt(d.dot(d)), 1e-4) << "particle " << i;
    }
}
#endif

TEST(DPDVVIntegrator, CheckpointContinuesBitForBit) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> soft(makeFluid(500, 25, positions)), ideal(makeFluid(500, 0, positions));
    for (const std::string& platform : platforms())
        for (auto variant : VARIANTS) {
            // The CPU platform's own nonbonded forces are summed in an order that depends on
            // when its neighbour list was built, which a checkpoint does not record; so there
            // our half of the step is checked bit for bit on the ideal gas.
            System* system = (platform == "CPU" ? ideal.get() : soft.get());
            DPDVVIntegrator integrator = makeIntegrator(variant, 0.04);
            integrator.setRandomNumberSeed(0);  // a seed drawn at context creation must be checkpointed too
            // The CPU platform sums its own forces in an order that varies between calls
            // unless asked not to: bit-exact continuation needs DeterministicForces there.
            std::map<std::string, std::string> properties;
            if (platform == "CPU")
                properties["DeterministicForces"] = "true";
            auto context = std::unique_ptr<Context>(new Context(*system, integrator, Platform::getPlatformByName(platform), properties));
            context->setPositions(positions);
            context->setVelocitiesToTemperature(KT_KELVIN, 11);
            expectCheckpointContinuesBitForBit(*context, integrator, platform + " variant " + std::to_string(variant));
        }
}

TEST(DPDVVIntegrator, XmlRoundTrip) {
    DPDVVIntegrator integrator(250.0, 3.5, 1.1, 0.02);
    integrator.setVariant(DPDVVIntegrator::SelfConsistent);
    integrator.setLambda(0.65);
    integrator.setMaxIterations(9);
    integrator.setTolerance(1e-4);
    integrator.setRandomNumberSeed(17);
    integrator.setIntegrationForceGroups(5);
    integrator.setConstraintTolerance(3e-7);
    integrator.setParticleType(3, 2);
    integrator.setParticleType(7, 1);
    integrator.addTypePair(1, 2, 2.5, 0.9);
    integrator.addTypePair(2, 2, 1.5, 1.2);
    std::stringstream buffer;
    XmlSerializer::serialize<Integrator>(&integrator, "Integrator", buffer);
    std::unique_ptr<Integrator> copy(XmlSerializer::deserialize<Integrator>(buffer));
    DPDVVIntegrator* c = dynamic_cast<DPDVVIntegrator*>(copy.get());
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->getTemperature(), 250.0);
    EXPECT_EQ(c->getDefaultFriction(), 3.5);
    EXPECT_EQ(c->getDefaultCutoff(), 1.1);
    EXPECT_EQ(c->getStepSize(), 0.02);
    EXPECT_EQ(c->getVariant(), DPDVVIntegrator::SelfConsistent);
    EXPECT_EQ(c->getLambda(), 0.65);
    EXPECT_EQ(c->getMaxIterations(), 9);
    EXPECT_EQ(c->getTolerance(), 1e-4);
    EXPECT_EQ(c->getRandomNumberSeed(), 17);
    EXPECT_EQ(c->getIntegrationForceGroups(), 5);
    EXPECT_EQ(c->getConstraintTolerance(), 3e-7);
    EXPECT_EQ(c->getParticleTypes(), integrator.getParticleTypes());
    ASSERT_EQ(c->getNumTypePairs(), 2);
    for (int k = 0; k < 2; k++) {
        int a1, a2, b1, b2;
        double fa, ca, fb, cb;
        integrator.getTypePairParameters(k, a1, a2, fa, ca);
        c->getTypePairParameters(k, b1, b2, fb, cb);
        EXPECT_EQ(a1, b1);
        EXPECT_EQ(a2, b2);
        EXPECT_EQ(fa, fb);
        EXPECT_EQ(ca, cb);
    }
}

/** The XML of `integrator` with attribute `name` set to `value` (or removed if value is null). */
std::string withAttribute(const Integrator& integrator, const std::string& name, const char* value) {
    std::stringstream buffer;
    XmlSerializer::serialize<Integrator>(&integrator, "Integrator", buffer);
    std::string text = buffer.str();
    const size_t at = text.find(" " + name + "=\"");
    const size_t end = text.find('"', at + name.size() + 3) + 1;
    text.replace(at, end - at, value == nullptr ? "" : " " + name + "=\"" + value + "\"");
    return text;
}

TEST(DPDVVIntegrator, XmlWithAMissingOrGarbledAttributeIsRefusedNamingIt) {
    DPDVVIntegrator integrator(250.0, 3.5, 1.1, 0.02);
    const std::vector<const char*> notNumbers = {"abc", "", "1.5x"}, notIntegers = {"abc", "", "1.5", "2147483648"};
    for (const char* name : {"temperature", "lambda", "maxIterations", "randomSeed", "variant"}) {
        const bool isInteger = std::string(name) == "maxIterations" || std::string(name) == "randomSeed" ||
                               std::string(name) == "variant";
        for (const char* garbled : isInteger ? notIntegers : notNumbers) {
            std::istringstream xml(withAttribute(integrator, name, garbled));
            expectErrorNaming([&] { delete XmlSerializer::deserialize<Integrator>(xml); },
                              std::string("attribute ") + name + " is \"" + garbled + "\", not a");
        }
        std::istringstream missing(withAttribute(integrator, name, nullptr));
        expectErrorNaming([&] { delete XmlSerializer::deserialize<Integrator>(missing); },
                          std::string("attribute ") + name + " is missing");
    }
    // A damaged byte is shown escaped, so the message stays text.
    std::istringstream damaged(withAttribute(integrator, "lambda", "0.\xff"));
    expectErrorNaming([&] { delete XmlSerializer::deserialize<Integrator>(damaged); }, "is \"0.\\xff\", not a number");
}

TEST(DPDVVIntegrator, CountsThatCouldHangAreLimited) {
    DPDVVIntegrator integrator(250.0, 3.5, 1.1, 0.02);
    expectErrorNaming([&] { integrator.setMaxIterations(DPDVVIntegrator::MAX_ITERATIONS + 1); }, "maxIterations must be from 1 to 1000");
    StaggeredDPDIntegrator staggered(250.0, 3.5, 1.1, 0.02);
    expectErrorNaming([&] { staggered.setNumSubSteps(2147483647); }, "numSubSteps (K) must be from 1 to 10000");
    std::istringstream xml(withAttribute(staggered, "numSubSteps", "2147483648"));
    expectErrorNaming([&] { delete XmlSerializer::deserialize<Integrator>(xml); }, "attribute numSubSteps is \"2147483648\"");
}

TEST(DPDVVIntegrator, BlowUpStopsWithTheStep) {
    // A stiff bond and a huge step: the run diverges within a few steps.  (Bonds through
    // the minimum image would cap the force at k L/2, so these are not periodic.)
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(5, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 5));
    for (int i = 0; i < 4; i++)
        system.addParticle(1.0);
    HarmonicBondForce* bonds = new HarmonicBondForce();
    for (int i = 0; i < 3; i++)
        bonds->addBond(i, i + 1, 0.0, 1e4);
    system.addForce(bonds);
    for (const std::string& platform : platforms()) {
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 1.0);
        Context context(system, integrator, Platform::getPlatformByName(platform));
        context.setPositions({Vec3(1, 1, 1), Vec3(1.5, 1, 1), Vec3(1.5, 1.5, 1), Vec3(2, 1.5, 1.2)});
        try {
            integrator.step(1000);
            FAIL() << "no error on " << platform;
        }
        catch (const OpenMMException& e) {
            const std::string message = e.what();
            EXPECT_NE(message.find("blew up at step"), std::string::npos) << message;
            // Nothing non-finite was handed to the caller as a valid state.
            EXPECT_LT(context.getState(0).getStepCount(), 1000);
        }
    }
}

TEST(DPDVVIntegrator, ParticleTypesSelectPairParameters) {
    // Two particles of type 1 with zero friction between them: no thermostat force, so
    // their relative velocity is conserved exactly (no conservative force either).
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(0, 0, 4));
    system.addParticle(1.0);
    system.addParticle(1.0);
    CustomBondForce* none = new CustomBondForce("0");
    none->setUsesPeriodicBoundaryConditions(true);
    system.addForce(none);
    for (double friction : {0.0, 4.5}) {
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01);
        integrator.setParticleType(0, 1);
        integrator.setParticleType(1, 1);
        integrator.addTypePair(1, 1, friction, 1.5);
        Context context(system, integrator, Platform::getPlatformByName("Reference"));
        context.setPositions({Vec3(1, 1, 1), Vec3(2.2, 1, 1)});  // 1.2 apart: beyond the default cutoff, within the pair's
        context.setVelocities({Vec3(0.1, 0, 0), Vec3(-0.1, 0, 0)});
        integrator.step(1);
        Vec3 v0 = context.getState(State::Velocities).getVelocities()[0];
        if (friction == 0)
            EXPECT_EQ(v0, Vec3(0.1, 0, 0));
        else
            EXPECT_NE(v0, Vec3(0.1, 0, 0));
    }
}

// The one-pass evaluation that GW steps use gives the pair-list result: same pairs, same
// random numbers, only the order of the sums differs.  With one mass (gamma and sigma looked
// up per type pair) and with mixed masses (computed per pair), and two types.
TEST(DPDVVIntegrator, OnePassForcesEqualThePairListOnes) {
    for (bool mixedMasses : {false, true}) {
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeFluid(1500, 0, positions));
        std::mt19937 rng(3);
        std::uniform_real_distribution<double> uniform(-1, 1);
        std::vector<Vec3> velocities(positions.size());
        for (size_t i = 0; i < positions.size(); i++) {
            velocities[i] = Vec3(uniform(rng), uniform(rng), uniform(rng));
            if (mixedMasses)
                system->setParticleMass(i, 1.5 + uniform(rng));
        }
        DPDVVIntegrator integrator = makeIntegrator(DPDVVIntegrator::GrootWarren, 0.04);
        for (int i = 0; i < (int) positions.size(); i += 3)
            integrator.setParticleType(i, 1);
        integrator.addTypePair(0, 1, 9.0, 0.8);
        Vec3 box[3];
        system->getDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
        SerialExecutor executor;
        DPDThermostatForces thermostat(*system, integrator, executor);
        std::vector<Vec3> fromList(positions.size()), onePass(positions.size());
        thermostat.updatePairs(positions, box);
        ASSERT_GT(thermostat.getPairs().size(), 5000u);
        thermostat.compute(DissipativeTerm | RandomTerm, velocities, 7, 0.04, fromList, fromList);
        thermostat.computeInOnePass(positions, box, velocities, 7, 0.04, nullptr, nullptr, onePass);
        for (size_t i = 0; i < positions.size(); i++) {
            const Vec3 d = onePass[i] - fromList[i];
            ASSERT_LT(std::sqrt(d.dot(d)), 1e-11 * (1 + std::sqrt(fromList[i].dot(fromList[i]))))
                    << "particle " << i << (mixedMasses ? " (mixed masses)" : "");
        }
    }
}
