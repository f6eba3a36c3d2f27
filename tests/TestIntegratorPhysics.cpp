// The physics every platform must reproduce, written once for every integrator (TestSchemes.h)
// and run on each platform: TestDPD runs it on Reference and CPU, TestDPDOpenCL on OpenCL and
// TestDPDCUDA on CUDA.  Five variants of one System (a soft fluid of two particle types with
// their own type pairs, mixed masses, springs between a few pairs in force group 1, the fast
// group of StaggeredDPDIntegrator): still, under Lees-Edwards shear at rate 0.5, with rigid
// dimers (constraints) each carrying a virtual site at its middle, in a triclinic box, and
// open (no periodic box: the fluid's cube in vacuum, beside ten frozen particles).
//
// - FollowsTheReference: positions and velocities after 1 and 3 steps equal the Reference
//   platform's (CPU: 1e-10 relative, only the summation order differs; a device: 2e-5 of the
//   box in position and of the largest speed in velocity, float pair terms, see
//   TestGpuPlatform.cpp).  Where the Reference samples the pressure tensor (not for every
//   integrator, nor with constraints), a second pair of runs samples it over one step: each
//   part's components agree to 1e-9 (CPU) or 1e-4 (a device) of the part's largest.
// - ConservesMomentumAndContinuesFromCheckpoints: still and with constraints, the total
//   momentum after 5 steps is the first's (a device: to the float rounding of m v, which the
//   sweeps' many pair updates take to ~1e-4, so 1e-3); still, sheared and with constraints, a
//   run continues from a checkpoint bit for bit (neither depends on the box: the triclinic
//   and open variants are left out).
//
// Where the Reference refuses a case the test is skipped.  Every platform runs every case the
// Reference runs: a refusal fails.

#include "TestHelpers.h"
#include "TestSchemes.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/VirtualSite.h"
#include <cctype>

using namespace DPDPlugin;

namespace {

enum class Variant { Still, Sheared, Constrained, Triclinic, Open };

struct PhysicsCase {
    std::string platform;
    Scheme scheme;
    Variant variant;
};

void PrintTo(const PhysicsCase& c, std::ostream* out) {
    *out << c.platform << " " << c.scheme.name << " " << (int) c.variant;
}

constexpr int NUM_PARTICLES = 600;  // a box of 5.31 nm at density 4: 3 cells or more on every axis, so the sweeps run by colour
constexpr int NUM_DIMERS = 30;      // particles 0-89 as (bead, bead, site) with the Constrained variant
constexpr int NUM_FROZEN = 10;      // the last particles, with the Open variant

std::vector<std::string> testedPlatforms() {
#if OPENMMDPD_TEST_CUDA
    return {"CUDA"};
#elif OPENMMDPD_HAVE_OPENCL
    return {"OpenCL"};
#else
    return platforms();
#endif
}

bool isDevice(const std::string& platform) { return platform == "OpenCL" || platform == "CUDA"; }



int typeOf(int i) { return i % 3 == 0 ? 1 : 0; }

System* makeSystem(const PhysicsCase& c, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) {
    System* system = makeFluid(NUM_PARTICLES, 0, positions);
    system->removeForce(0);
    DPDSoftRepulsionForce* soft = new DPDSoftRepulsionForce(25.0, 1.0);
    for (int i = 0; i < NUM_PARTICLES; i++) {
        soft->setParticleType(i, typeOf(i));
        if (i % 4 == 0 && !c.scheme.uniformMasses)
            system->setParticleMass(i, 2.0);
    }
    soft->addTypePair(0, 1, 30.0, 0.9);
    if (c.variant == Variant::Open) {
        soft->setNonbondedMethod(DPDSoftRepulsionForce::CutoffNonPeriodic);
        // Ten frozen particles (mass 0) beside the cube: in the soft force's bounding box,
        // not in the thermostat's, which holds only the particles that move.
        Vec3 a, b, cVector;
        system->getDefaultPeriodicBoxVectors(a, b, cVector);
        for (int i = NUM_PARTICLES - NUM_FROZEN; i < NUM_PARTICLES; i++) {
            system->setParticleMass(i, 0.0);
            positions[i][0] = a[0] + 0.4;
        }
    }
    system->addForce(soft);
    // Stiff springs (period ~20 steps), so that the staggered schemes' fast force matters.
    HarmonicBondForce* springs = new HarmonicBondForce();  // molecules are kept whole
    for (int i = 100; i + 1 < NUM_PARTICLES; i += 50) {
        springs->addBond(i, i + 1, 0.5, 100.0);
        positions[i + 1] = positions[i] + Vec3(0, 0.6, 0);
    }
    springs->setForceGroup(1);
    system->addForce(springs);
    if (c.variant == Variant::Triclinic) {  // the cube's volume and OpenMM's reduced form, b and c both tilted
        Vec3 a, b, cVector;
        system->getDefaultPeriodicBoxVectors(a, b, cVector);
        const double edge = a[0];
        system->setDefaultPeriodicBoxVectors(a, Vec3(0.2 * edge, edge, 0), Vec3(-0.15 * edge, 0.25 * edge, edge));
    }
    if (c.variant == Variant::Constrained)
        for (int k = 0; k < 3 * NUM_DIMERS; k += 3) {
            positions[k + 1] = positions[k] + Vec3(0.5, 0, 0);
            positions[k + 2] = positions[k] + Vec3(0.25, 0, 0);
            system->addConstraint(k, k + 1, 0.5);
            system->setParticleMass(k + 2, 0.0);
            system->setVirtualSite(k + 2, new TwoParticleAverageSite(k, k + 1, 0.5, 0.5));
        }
    std::mt19937 rng(17);
    std::normal_distribution<double> normal(0, 1);
    velocities.resize(NUM_PARTICLES);
    for (int i = 0; i < NUM_PARTICLES; i++) {
        const double mass = system->getParticleMass(i);
        velocities[i] = mass > 0 ? Vec3(normal(rng), normal(rng), normal(rng)) * std::sqrt(1 / mass) : Vec3();  // kT = 1 kJ/mol
    }
    return system;
}

DPDThermostatIntegrator* makeIntegrator(const PhysicsCase& c) {
    DPDThermostatIntegrator* integrator = c.scheme.make();
    for (int i = 0; i < NUM_PARTICLES; i++)
        integrator->setParticleType(i, typeOf(i));
    integrator->addTypePair(0, 1, 6.0, 0.9);
    integrator->setRandomNumberSeed(1234);
    // The Reference's constraints and OpenMM's on a device each stop within the tolerance; the
    // middle splittings' half drifts turn the default 1e-5 into velocity differences past the
    // float tolerance, so both are held to 1e-8.
    if (c.variant == Variant::Constrained)
        integrator->setConstraintTolerance(1e-8);
    if (c.variant == Variant::Sheared)
        integrator->setShearRate(0.5);
    return integrator;
}

struct Simulation {
    std::unique_ptr<System> system;
    std::unique_ptr<DPDThermostatIntegrator> integrator;
    std::unique_ptr<Context> context;
};

/** The case's System and integrator in a Context on `platform`; null context if the platform refused it. */
Simulation start(const PhysicsCase& c, const std::string& platform, bool pressure, std::string& refusal) {
    Simulation run;
    std::vector<Vec3> positions, velocities;
    run.system.reset(makeSystem(c, positions, velocities));
    run.integrator.reset(makeIntegrator(c));
    std::map<std::string, std::string> properties;
    if (platform == "CPU")
        properties["Threads"] = "2";
    try {
        run.integrator->setPressureTensorEnabled(pressure);
        run.context.reset(new Context(*run.system, *run.integrator, Platform::getPlatformByName(platform), properties));
    }
    catch (const OpenMMException& e) {
        refusal = e.what();
        return run;
    }
    run.context->setPositions(positions);
    run.context->setVelocities(velocities);
    return run;
}

class IntegratorPhysics : public testing::TestWithParam<PhysicsCase> {
protected:
    /**
     * A Context for the case on its platform; a null one, with `skip` saying why, where the
     * platform, or the Reference, has no run of it (a failure where the platform refuses it).
     */
    Simulation startTested(bool pressure, std::string& skip) {
        const PhysicsCase& c = GetParam();
        std::string refusal;
        Simulation run;
        if (!platformExists(c.platform))
            skip = "OpenMM has no " + c.platform + " platform here";
        else if (!start(c, "Reference", pressure, refusal).context)
            skip = "the Reference refuses it: " + refusal;
        if (!skip.empty())
            return run;
        run = start(c, c.platform, pressure, refusal);
        if (!run.context) {
            ADD_FAILURE() << c.platform << " refuses " << c.scheme.name << ": " << refusal;
            skip = "refused";
        }
        return run;
    }
};

void expectStatesAgree(const State& expected, const State& actual, const std::string& platform, double box, const std::string& label) {
    if (isDevice(platform)) {
        EXPECT_LT(maxImageDifference(expected.getPositions(), actual.getPositions(), box), 2e-5 * box) << label << ", positions";
        EXPECT_LT(maxDifference(expected.getVelocities(), actual.getVelocities()), 2e-5 * maxNorm(expected.getVelocities()))
                << label << ", velocities";
        return;
    }
    EXPECT_LT(relativeDifference(expected.getPositions(), actual.getPositions()), 1e-10) << label << ", positions";
    EXPECT_LT(relativeDifference(expected.getVelocities(), actual.getVelocities()), 1e-10) << label << ", velocities";
}

TEST_P(IntegratorPhysics, FollowsTheReference) {
    const PhysicsCase& c = GetParam();
    if (c.platform == "Reference")
        GTEST_SKIP() << "the Reference is the definition";
    std::string skip, refusal;
    Simulation tested = startTested(false, skip);
    if (!skip.empty())
        GTEST_SKIP() << skip;
    if (!tested.context)
        return;
    Simulation reference = start(c, "Reference", false, refusal);
    Vec3 a, b, cc;
    tested.system->getDefaultPeriodicBoxVectors(a, b, cc);
    const double box = a[0];
    int done = 0;
    for (int steps : {1, 3}) {
        reference.integrator->step(steps - done);
        tested.integrator->step(steps - done);
        const int parts = State::Positions | State::Velocities;
        expectStatesAgree(reference.context->getState(parts), tested.context->getState(parts), c.platform, box,
                          "after " + std::to_string(steps) + " steps");
        done = steps;
    }
    // The pressure tensor where the Reference samples it (it leaves out constraint forces).
    Simulation sampledReference = start(c, "Reference", true, refusal);
    if (c.variant == Variant::Constrained || !sampledReference.context)
        return;
    Simulation sampled = start(c, c.platform, true, refusal);
    ASSERT_TRUE(sampled.context) << c.platform << " refuses the pressure tensor: " << refusal;
    sampledReference.integrator->step(1);
    sampled.integrator->step(1);
    expectPressurePartsNear(pressureParts(*sampledReference.integrator), pressureParts(*sampled.integrator),
                            isDevice(c.platform) ? 1e-4 : 1e-9, "after 1 step");
}

/** IntegratorPhysics's cases but the triclinic and open ones. */
class IntegratorConservation : public IntegratorPhysics {};

TEST_P(IntegratorConservation, ConservesMomentumAndContinuesFromCheckpoints) {
    const PhysicsCase& c = GetParam();
    std::string skip;
    Simulation run = startTested(false, skip);
    if (!skip.empty())
        GTEST_SKIP() << skip;
    if (!run.context)
        return;
    if (c.variant != Variant::Sheared) {  // crossing a sheared boundary changes a velocity by the shear's U
        auto momentum = [&] {
            Vec3 p;
            const State state = run.context->getState(State::Velocities);
            for (int i = 0; i < NUM_PARTICLES; i++)
                p += state.getVelocities()[i] * run.system->getParticleMass(i);
            return p;
        };
        const Vec3 before = momentum();
        run.integrator->step(5);
        const Vec3 change = momentum() - before;
        EXPECT_LT(std::sqrt(change.dot(change)), isDevice(c.platform) ? 1e-3 : 1e-9);
    }
    expectCheckpointContinuesBitForBit(*run.context, *run.integrator, c.platform + " " + c.scheme.name);
}

std::vector<PhysicsCase> physicsCases(const std::vector<Variant>& variants) {
    std::vector<Scheme> schemes = schemesAt(0.02), staggered = staggeredSchemesAt(0.02);
    schemes.insert(schemes.end(), staggered.begin(), staggered.end());
    std::vector<PhysicsCase> cases;
    for (const std::string& platform : testedPlatforms())
        for (const Scheme& scheme : schemes)
            for (Variant variant : variants)
                cases.push_back({platform, scheme, variant});
    return cases;
}

std::string caseName(const testing::TestParamInfo<PhysicsCase>& info) {
    static const char* variants[] = {"Still", "Sheared", "Constrained", "Triclinic", "Open"};
    std::string name = info.param.platform + "_" + info.param.scheme.name + "_" + variants[(int) info.param.variant];
    for (char& ch : name)
        if (!std::isalnum((unsigned char) ch))
            ch = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(EveryPlatform, IntegratorPhysics,
                         testing::ValuesIn(physicsCases({Variant::Still, Variant::Sheared, Variant::Constrained, Variant::Triclinic,
                                                         Variant::Open})),
                         caseName);
INSTANTIATE_TEST_SUITE_P(EveryPlatform, IntegratorConservation,
                         testing::ValuesIn(physicsCases({Variant::Still, Variant::Sheared, Variant::Constrained})), caseName);

} // namespace
