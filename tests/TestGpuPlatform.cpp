// The GPU platforms' kernels (platforms/common) against the Reference platform and the host's
// PairRandom, on OpenCL (TestDPDOpenCL; POCL runs it on the CPU here) or CUDA (TestDPDCUDA,
// built with OPENMMDPD_BUILD_CUDA_TESTS for scripts/gpu-check.sh), in single precision unless a
// test asks for mixed; each Context compiles OpenMM's programs and ours (seconds), so the tests
// share few.
//
// Tolerance: a position or velocity on the device is a float (6e-8 relative); a step adds the
// rounding of ~20 pair terms in float before the fixed-point sum, so after 3 steps the device
// differs from the Reference (double) by ~1e-6 relative.  We ask for 2e-5 relative (to the box
// for positions, to the largest speed for velocities): any error in the rule or the random
// numbers (a wrong Philox word moves a particle by sigma dt^1.5 ~ 1e-2 nm) is 1000x that.
#include "CheckpointTesting.h"
#include "TestHelpers.h"
#include "openmmdpd/Checkpoints.h"
#include "openmmdpd/CommonPairRandomCheck.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/CustomBondForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/VirtualSite.h"
#include "openmm/internal/ContextImpl.h"
#include <array>
#include <limits>
#if OPENMMDPD_TEST_CUDA
#include "openmmdpd/CudaDPDKernelFactory.h"
#else
#include "openmmdpd/OpenCLDPDKernelFactory.h"
#endif

using namespace DPDPlugin;

namespace {

#if OPENMMDPD_TEST_CUDA
const std::string GPU = "CUDA";
#else
const std::string GPU = "OpenCL";
#endif

bool haveDevice() { return platformExists(GPU); }

#define REQUIRE_DEVICE() \
    if (!haveDevice()) \
        GTEST_SKIP() << "OpenMM has no " << GPU << " platform here"

// Reaches the ContextImpl of a Context (Force's protected accessor), for the device's ComputeContext.
class ContextAccess : public Force {
public:
    ContextImpl& of(Context& context) { return getContextImpl(context); }
    bool usesPeriodicBoundaryConditions() const override { return false; }

protected:
    ForceImpl* createImpl() const override { return nullptr; }
};

ComputeContext& computeContext(Context& context) {
    ContextAccess access;
#if OPENMMDPD_TEST_CUDA
    return getCudaComputeContext(access.of(context));
#else
    return getOpenCLComputeContext(access.of(context));
#endif
}

// A soft DPD fluid of two particle types with their own type pairs, mixed masses and a few exclusions.
System* makeSoftSystem(int n, std::vector<Vec3>& positions) {
    System* system = makeFluid(n, 0, positions);
    system->removeForce(0);
    DPDSoftRepulsionForce* force = new DPDSoftRepulsionForce(25.0, 1.0);
    for (int i = 0; i < n; i += 3)
        force->setParticleType(i, 1);
    force->addTypePair(0, 1, 30.0, 0.9);
    for (int i = 0; i + 1 < n; i += 50)
        force->addExclusion(i, i + 1);
    system->addForce(force);
    for (int i = 0; i < n; i += 4)
        system->setParticleMass(i, 2.0);
    return system;
}

// A spring that uses OpenMM's periodic device kernels, which take the box as the Context was
// made: allowed without shear or the pressure tensor, refused with either.
void addPeriodicSprings(System& system) {
    HarmonicBondForce* bonds = new HarmonicBondForce();
    bonds->addBond(0, 1, 0.0, 4.0);
    bonds->setUsesPeriodicBoundaryConditions(true);
    bonds->setName("PeriodicSprings");
    system.addForce(bonds);
}

void configure(DPDVVIntegrator& integrator, DPDVVIntegrator::Variant variant, int numParticles = 600) {
    integrator.setVariant(variant);
    integrator.setLambda(0.65);
    integrator.setRandomNumberSeed(1234);
    for (int i = 0; i < numParticles; i += 3)
        integrator.setParticleType(i, 1);
    integrator.addTypePair(0, 1, 6.0, 0.9);
}

Vec3 momentum(System& system, const State& state) {
    Vec3 p;
    for (int i = 0; i < system.getNumParticles(); i++)
        p += state.getVelocities()[i] * system.getParticleMass(i);
    return p;
}

} // namespace

TEST(GpuPlatform, PhiloxWordsEqualTheHostsBitForBit) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(8, 0, positions));
    VerletIntegrator integrator(0.001);
    Context context(*system, integrator, Platform::getPlatformByName(GPU));
    std::vector<PairRandomKey> keys;
    std::mt19937 rng(3);
    for (int k = 0; k < 500; k++)
        keys.push_back({(PairRandom::Stream) (k % 5), (long long) rng() * (k % 3 == 0 ? 4099 : 1), (int) (rng() % 100000),
                        (int) (rng() % 100000)});
    const uint32_t seed = 987654321u;
    std::vector<uint32_t> words;
    std::vector<float> normals;
    drawDevicePairRandom(computeContext(context), seed, keys, words, normals);
    const PairRandom host(seed);
    for (size_t k = 0; k < keys.size(); k++) {
        const r123::Philox4x32::ctr_type expected = host.bits(keys[k].stream, keys[k].step, keys[k].i, keys[k].j);
        for (int m = 0; m < 4; m++)
            ASSERT_EQ(words[4 * k + m], expected[m]) << "key " << k << " word " << m;
        // Box-Muller in float: 1e-4 absolute covers float log and cos of these arguments.
        EXPECT_NEAR(normals[k], PairRandom::boxMuller(expected), 1e-4) << "key " << k;
    }
}

TEST(GpuPlatform, SoftRepulsionForceEqualsReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(600, positions));
    VerletIntegrator a(0.001), b(0.001);
    Context reference(*system, a, Platform::getPlatformByName("Reference"));
    Context device(*system, b, Platform::getPlatformByName(GPU));
    reference.setPositions(positions);
    device.setPositions(positions);
    const State expected = reference.getState(State::Forces | State::Energy);
    const State actual = device.getState(State::Forces | State::Energy);
    // Float pair terms: 1e-5 of the largest force, 1e-5 relative energy (see the tolerance note above).
    EXPECT_LT(maxDifference(expected.getForces(), actual.getForces()), 1e-5 * maxNorm(expected.getForces()));
    EXPECT_NEAR(actual.getPotentialEnergy(), expected.getPotentialEnergy(), 1e-5 * std::fabs(expected.getPotentialEnergy()));
}

namespace {

// Warren's MDPD liquid (A -40, B 25, rd 0.75) with a second type: its own A, cutoff and B; a few exclusions.
System* makeMDPDSystem(int n, std::vector<Vec3>& positions) {
    System* system = makeFluid(n, 0, positions);
    system->removeForce(0);
    MDPDForce* force = new MDPDForce(-40.0, 25.0, 1.0, 0.75);
    for (int i = 0; i < n; i += 3)
        force->setParticleType(i, 1);
    force->addTypePair(0, 1, -30.0, 0.9);
    force->setTypeB(1, 20.0);
    for (int i = 0; i + 1 < n; i += 50)
        force->addExclusion(i, i + 1);
    system->addForce(force);
    return system;
}

} // namespace

// Forces, energy and (one sampled DPD-VV step) the conservative pressure tensor against the Reference's.
TEST(GpuPlatform, MDPDForceEqualsReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeMDPDSystem(600, positions));
    std::vector<State> states;
    std::vector<std::vector<double>> pressure;
    for (const std::string& platform : {std::string("Reference"), GPU}) {
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.005);
        integrator.setPressureTensorEnabled(true);
        integrator.setRandomNumberSeed(1234);
        Context context(*system, integrator, Platform::getPlatformByName(platform));
        context.setPositions(positions);
        states.push_back(context.getState(State::Forces | State::Energy));
        integrator.step(1);
        pressure.push_back(integrator.getAveragePressureTensor(DPDThermostatIntegrator::PressureConservative));
    }
    // Float pair terms, as SoftRepulsionForceEqualsReference.
    EXPECT_LT(maxDifference(states[0].getForces(), states[1].getForces()), 1e-5 * maxNorm(states[0].getForces()));
    EXPECT_NEAR(states[1].getPotentialEnergy(), states[0].getPotentialEnergy(), 1e-5 * std::fabs(states[0].getPotentialEnergy()));
    double scale = 0;
    for (double x : pressure[0])
        scale = std::max(scale, std::fabs(x));
    for (int c = 0; c < 6; c++)
        EXPECT_NEAR(pressure[1][c], pressure[0][c], 1e-4 * scale) << "component " << c;
}

namespace {

// The forces and energy of a System on the device against the Reference's (float pair terms, as above).
void expectForcesEqualReference(const System& system, const std::vector<Vec3>& positions, const std::string& label) {
    VerletIntegrator first(0.001), second(0.001);
    Context reference(system, first, Platform::getPlatformByName("Reference"));
    Context device(system, second, Platform::getPlatformByName(GPU));
    for (Context* context : {&reference, &device})
        context->setPositions(positions);
    const State expected = reference.getState(State::Forces | State::Energy);
    const State actual = device.getState(State::Forces | State::Energy);
    EXPECT_LT(maxDifference(expected.getForces(), actual.getForces()), 1e-5 * maxNorm(expected.getForces())) << label;
    EXPECT_NEAR(actual.getPotentialEnergy(), expected.getPotentialEnergy(), 1e-5 * std::fabs(expected.getPotentialEnergy())) << label;
}

} // namespace

// Tilted boxes: the one Lees-Edwards shear makes, b = (tilt, Ly, 0), at tilts up to OpenMM's
// Lx/2, and triclinic ones with c tilted too.  The device bins them on their fractional axes
// (kernels/cellList.cc) and takes images along c, b, a (kernels/utilities.cc).
TEST(GpuPlatform, PairForcesEqualReferenceInTiltedBoxes) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> soft(makeSoftSystem(600, positions)), mdpd(makeMDPDSystem(600, positions));
    Vec3 a, b, c;
    soft->getDefaultPeriodicBoxVectors(a, b, c);
    // (b_x, c_x, c_y): Lees-Edwards offsets, then triclinic boxes
    const std::vector<std::array<double, 3>> tilts = {{0.3, 0, 0}, {1.7, 0, 0}, {-2.6, 0, 0}, {2.65, 0, 0},
                                                      {1.1, -1.9, 1.3}, {-0.4, 2.2, -2.4}};
    for (System* system : {soft.get(), mdpd.get()})
        for (const std::array<double, 3>& tilt : tilts) {
            // The System's own box: OpenMM 8 refuses to tilt a Context made with a rectangular one.
            system->setDefaultPeriodicBoxVectors(a, Vec3(tilt[0], b[1], 0), Vec3(tilt[1], tilt[2], c[2]));
            const std::string label = std::string(system == soft.get() ? "soft repulsion" : "MDPD") + ", tilts " +
                                      std::to_string(tilt[0]) + " " + std::to_string(tilt[1]) + " " + std::to_string(tilt[2]);
            expectForcesEqualReference(*system, positions, label);
        }
}

// Open Systems (CutoffNonPeriodic): the grid spans the particles' bounding box, no images.
TEST(GpuPlatform, PairForcesEqualReferenceInAnOpenSystem) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> soft(makeSoftSystem(600, positions)), mdpd(makeMDPDSystem(600, positions));
    dynamic_cast<DPDSoftRepulsionForce&>(soft->getForce(0)).setNonbondedMethod(DPDSoftRepulsionForce::CutoffNonPeriodic);
    dynamic_cast<MDPDForce&>(mdpd->getForce(0)).setNonbondedMethod(MDPDForce::CutoffNonPeriodic);
    expectForcesEqualReference(*soft, positions, "soft repulsion, open");
    expectForcesEqualReference(*mdpd, positions, "MDPD, open");
}

namespace {

struct Run {
    std::vector<Vec3> positions, velocities;
};

using MakeIntegrator = std::function<std::unique_ptr<DPDThermostatIntegrator>(int numParticles)>;

MakeIntegrator dpdvv(DPDVVIntegrator::Variant variant) {
    return [variant](int numParticles) {
        std::unique_ptr<DPDVVIntegrator> integrator(new DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, 0.02));
        configure(*integrator, variant, numParticles);
        return std::unique_ptr<DPDThermostatIntegrator>(std::move(integrator));
    };
}

// Steps 1 and 3 on a platform, from the positions and velocities of kT = 1 drawn with a fixed seed.
std::vector<Run> runSteps(System& system, const std::vector<Vec3>& positions, const MakeIntegrator& make, const std::string& platform,
                          const std::map<std::string, std::string>& properties) {
    std::vector<Vec3> velocities(positions.size());
    std::mt19937 rng(17);
    std::normal_distribution<double> normal(0, 1);
    for (size_t i = 0; i < velocities.size(); i++)
        velocities[i] = Vec3(normal(rng), normal(rng), normal(rng)) * (system.isVirtualSite(i) ? 0.0 : std::sqrt(1 / system.getParticleMass(i)));
    std::unique_ptr<DPDThermostatIntegrator> integrator = make(system.getNumParticles());
    Context context(system, *integrator, Platform::getPlatformByName(platform), properties);
    context.setPositions(positions);
    context.setVelocities(velocities);
    std::vector<Run> runs;
    for (int steps : {1, 2}) {
        integrator->step(steps);
        const State s = context.getState(State::Positions | State::Velocities);
        runs.push_back({s.getPositions(), s.getVelocities()});
    }
    return runs;
}

// Steps 1 and 3 on the device equal the Reference's within 2e-5 relative (see the tolerance note above).
void expectFollowsReference(System& system, const std::vector<Vec3>& positions, const MakeIntegrator& make, const std::string& label,
                            const std::map<std::string, std::string>& properties = {}) {
    const std::vector<Run> expected = runSteps(system, positions, make, "Reference", {});
    const std::vector<Run> actual = runSteps(system, positions, make, GPU, properties);
    Vec3 a, b, c;
    system.getDefaultPeriodicBoxVectors(a, b, c);
    for (int k = 0; k < 2; k++) {
        const std::string after = label + ": after " + (k == 0 ? "1 step" : "3 steps");
        EXPECT_LT(maxImageDifference(actual[k].positions, expected[k].positions, a[0]), 2e-5 * a[0]) << after << ", positions";
        EXPECT_LT(maxDifference(expected[k].velocities, actual[k].velocities), 2e-5 * maxNorm(expected[k].velocities))
                << after << ", velocities";
    }
}

// The soft fluid of n particles.  n = 600: a box of 5.31 nm (5 cells per axis for the pair
// forces); n = 900: 6.08 nm, 6 sweep cells per axis (8 cells of each colour swept at once);
// n = 100: 2.92 nm, 2 cells per axis (no colours: one work item sweeps every cell in order).
void expectFollowsReference(const MakeIntegrator& make, int n, const std::string& label,
                            const std::map<std::string, std::string>& properties = {}) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(n, positions));
    expectFollowsReference(*system, positions, make, label, properties);
}

} // namespace

// Single precision, still and sheared for every integrator, constrained for those that take
// constraints here: TestIntegratorPhysics.cpp.
TEST(GpuPlatform, DPDVVFollowsReferenceInMixedPrecision) {
    REQUIRE_DEVICE();
    expectFollowsReference(dpdvv(DPDVVIntegrator::DPDVV), 600, "DPD-VV mixed precision", {{"Precision", "mixed"}});
}

// SC-VV iterates until the kinetic energy changes by less than 1e-6 (relative): the float
// sum may stop an iteration earlier or later than the Reference's, which moves the velocities
// by about that much, well inside the 2e-5.
TEST(GpuPlatform, SelfConsistentFollowsReference) {
    REQUIRE_DEVICE();
    expectFollowsReference(dpdvv(DPDVVIntegrator::SelfConsistent), 600, "SC-VV mixed precision", {{"Precision", "mixed"}});
}

TEST(GpuPlatform, MomentumSeedsAndCheckpoints) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(600, positions));
    for (DPDVVIntegrator::Variant variant : {DPDVVIntegrator::GrootWarren, DPDVVIntegrator::DPDVV, DPDVVIntegrator::SelfConsistent}) {
        DPDVVIntegrator first(KT_KELVIN, 4.5, 1.0, 0.02), second(KT_KELVIN, 4.5, 1.0, 0.02);
        configure(first, variant);
        configure(second, variant);
        std::unique_ptr<Context> a = makeContext(*system, first, GPU, positions);
        std::unique_ptr<Context> b = makeContext(*system, second, GPU, positions);
        const Vec3 p0 = momentum(*system, a->getState(State::Velocities));
        first.step(5);
        second.step(5);
        const State sa = a->getState(State::Positions | State::Velocities), sb = b->getState(State::Positions | State::Velocities);
        // Forces cancel exactly in fixed point; what remains is the float rounding of each m v (~1e-7 of ~1 per particle).
        const Vec3 dp = momentum(*system, sa) - p0;
        EXPECT_LT(std::sqrt(dp.dot(dp)), 1e-4) << "variant " << variant;
        for (size_t i = 0; i < positions.size(); i++) {
            ASSERT_EQ(sa.getPositions()[i], sb.getPositions()[i]) << "one seed, two runs: particle " << i;
            ASSERT_EQ(sa.getVelocities()[i], sb.getVelocities()[i]) << "one seed, two runs: particle " << i;
        }
        expectCheckpointContinuesBitForBit(*a, first, GPU + " variant " + std::to_string(variant));
        // A byte flipped anywhere is refused, and loadCheckpoint leaves the Context as it was.
        std::stringstream checkpoint;
        a->createCheckpoint(checkpoint);
        first.step(2);
        const State before = a->getState(State::Positions | State::Velocities);
        for (size_t offset : {(size_t) 100, checkpoint.str().size() / 2, checkpoint.str().size() - 20}) {
            std::string damaged = checkpoint.str();
            damaged[offset] ^= 4;
            std::istringstream stream(damaged);
            expectErrorNaming([&] { DPDPlugin::loadCheckpoint(*a, stream); }, "cannot load this checkpoint");
            const State after = a->getState(State::Positions | State::Velocities);
            EXPECT_EQ(after.getStepCount(), before.getStepCount());
            EXPECT_EQ(after.getPositions(), before.getPositions()) << "byte " << offset;
            EXPECT_EQ(after.getVelocities(), before.getVelocities()) << "byte " << offset;
        }
    }
}

namespace {

// den Otter and Clarke's prefactors need one mass: the soft fluid with every mass 1, two
// thermostat types as the DPD-VV tests' integrators have them, sheared or still.
MakeIntegrator denOtterClarke(double shearRate) {
    return [shearRate](int numParticles) {
        std::unique_ptr<DenOtterClarkeIntegrator> integrator(new DenOtterClarkeIntegrator(KT_KELVIN, 4.5, 1.0, 0.02));
        integrator->setRandomNumberSeed(1234);
        integrator->setAverageFDDotV(-4.985245);  // model B (Nikunen et al. 2003, Table III)
        integrator->setAverageFDDotFD(14.507340);
        integrator->setAverageFRDotFR(9.976453);
        for (int i = 0; i < numParticles; i += 3)
            integrator->setParticleType(i, 1);
        integrator->addTypePair(0, 1, 6.0, 0.9);
        integrator->setShearRate(shearRate);
        return std::unique_ptr<DPDThermostatIntegrator>(std::move(integrator));
    };
}

System* makeOneMassSoftSystem(int n, std::vector<Vec3>& positions) {
    System* system = makeSoftSystem(n, positions);
    for (int i = 0; i < n; i++)
        system->setParticleMass(i, 1.0);
    return system;
}

} // namespace

// The measured sums (FD.v, FD.FD, FR.FR dt over particles and steps) agree with the
// Reference's to float rounding; a checkpoint continues bit for bit; momentum is kept to the
// float rounding of m v.
TEST(GpuPlatform, DenOtterClarkeSumsMomentumAndCheckpoints) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeOneMassSoftSystem(600, positions));
    std::vector<std::array<double, 3>> sums;
    for (const std::string& platform : {std::string("Reference"), GPU}) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = denOtterClarke(0)(600);
        std::unique_ptr<Context> context = makeContext(*system, *integrator, platform, positions);
        const Vec3 p0 = momentum(*system, context->getState(State::Velocities));
        integrator->step(5);
        const Vec3 dp = momentum(*system, context->getState(State::Velocities)) - p0;
        EXPECT_LT(std::sqrt(dp.dot(dp)), 1e-4) << platform;
        double fdDotV, fdDotFD, frDotFR;
        long long count;
        static_cast<DenOtterClarkeIntegrator&>(*integrator).getMeasuredSums(fdDotV, fdDotFD, frDotFR, count);
        EXPECT_EQ(count, 5 * 600) << platform;
        sums.push_back({fdDotV, fdDotFD, frDotFR});
        if (platform == GPU)
            expectCheckpointContinuesBitForBit(*context, *integrator, GPU + " den Otter-Clarke");
    }
    for (int c = 0; c < 3; c++)
        EXPECT_NEAR(sums[1][c], sums[0][c], 1e-4 * std::fabs(sums[0][c])) << "sum " << c;
}

TEST(GpuPlatform, RefusesWhatItDoesNotDo) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(100, positions));
    addPeriodicSprings(*system);
    DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.02);
    std::unique_ptr<Context> context = makeContext(*system, integrator, GPU, positions);
    integrator.step(1);
    const State before = context->getState(State::Positions);
    integrator.setShearRate(0.1);
    expectErrorNaming([&] { integrator.step(1); }, "OpenMM's periodic PeriodicSprings (force 1");
    integrator.setShearRate(0);
    EXPECT_EQ(context->getState(State::Positions).getPositions(), before.getPositions()) << "nothing changed";
    EXPECT_EQ(context->getState(0).getStepCount(), 1);
}

// A checkpoint of extended DPD on the device with one field of its pair variables damaged
// (behind a valid checksum): each is refused, and the next steps are a new Context's.
TEST(GpuPlatform, DamagedPairVariablesAreRefused) {
    REQUIRE_DEVICE();
    namespace ct = CheckpointTesting;
    const ct::Scheme& scheme = ct::schemeNamed("EDPD-OneSided");
    ct::Simulation run(scheme, GPU, 20);
    const std::string bytes = run.checkpoint();
    // After the seed, flag and force: particles (int32), step (int64), then per particle its
    // count and (partner int32, state int32, s, w^2, archived s, its step int64) each.
    const size_t memory = ct::IntegratorPart(bytes).state + 13 + 24 * ct::NUM_PARTICLES;
    const size_t count = memory + 12, first = count + 8, second = first + 40;
    uint64_t entries;
    std::memcpy(&entries, &bytes[count], 8);
    ASSERT_GE(entries, 2u);
    int32_t partner;
    std::memcpy(&partner, &bytes[first], 4);
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"partner 10^6", ct::withField<int32_t>(bytes, first, 1000000)},
        {"partner = its particle", ct::withField<int32_t>(bytes, first, 0)},
        {"a pair twice", ct::withField<int32_t>(bytes, second, partner)},
        {"state 0", ct::withField<int32_t>(bytes, first + 4, 0)},
        {"state 4", ct::withField<int32_t>(bytes, first + 4, 4)},
        {"s NaN", ct::withField<double>(bytes, first + 8, nan)},
        {"w^2 = 2", ct::withField<double>(bytes, first + 16, 2.0)},
        {"archived s NaN", ct::withField<double>(bytes, first + 24, nan)},
        {"archived step in the future", ct::withField<int64_t>(ct::withField<int32_t>(bytes, first + 4, 3), first + 32, 1000)},
        {"count 10^18", ct::withField<uint64_t>(bytes, count, 1000000000000000000ULL)},
        {"particles N + 1", ct::withField<int32_t>(bytes, memory, ct::NUM_PARTICLES + 1)},
        {"step 2^63 - 1", ct::withField<int64_t>(bytes, memory + 4, std::numeric_limits<int64_t>::max())},
    };
    for (const auto& c : cases)
        run.expectRefused(c.second, c.first);
    ct::expectStepsLikeANewContext(run, scheme, GPU);
}

namespace {

/** Whether two EDPD integrators hold the same pair variables for the pairs (i < 30, j): present alike, of one step, values within `tolerance`. */
void expectSamePairVariables(const EDPDIntegrator& expected, const EDPDIntegrator& actual, int n, double tolerance,
                             const std::string& label) {
    int present = 0;
    for (int i = 0; i < 30; i++)
        for (int j = i + 1; j < n; j++) {
            const double s = expected.getPairVariable(i, j);
            ASSERT_EQ(std::isnan(s), std::isnan(actual.getPairVariable(i, j))) << label << ": pair (" << i << ", " << j << ")";
            if (std::isnan(s))
                continue;
            present++;
            ASSERT_EQ(expected.getPairVariableStep(i, j), actual.getPairVariableStep(i, j)) << label << ": pair (" << i << ", " << j << ")";
            ASSERT_NEAR(actual.getPairVariable(i, j), s, tolerance) << label << ": pair (" << i << ", " << j << ")";
        }
    EXPECT_GT(present, 300) << label;
}

} // namespace

// Extended DPD's pair memory over 60 steps, in double precision, against the Reference's: pairs
// leave their cutoff, come back (caught up) and are forgotten (alpha 50: after 28 steps), the
// table outgrows its first capacity (alpha 1: nothing forgotten for 900 steps, so every
// partner met is kept), and the step count is set from outside halfway.  The number of
// variables is the Reference's, and so is each variable of 30 particles, with its step.  A
// checkpoint continues bit for bit, also in a new Context (whose table must grow to take it).
TEST(GpuPlatform, EDPDPairMemoryFollowsReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    const int n = 300;
    std::unique_ptr<System> system(makeSoftSystem(n, positions));
    Vec3 a, b, c;
    system->getDefaultPeriodicBoxVectors(a, b, c);
    const double box = a[0];
    auto start = [&](Integrator& integrator, const std::string& platform) {
        std::map<std::string, std::string> properties;
        if (platform == GPU)
            properties["Precision"] = "double";
        std::unique_ptr<Context> context(new Context(*system, integrator, Platform::getPlatformByName(platform), properties));
        context->setPositions(positions);
        context->setVelocitiesToTemperature(KT_KELVIN, 11);
        return context;
    };
    for (auto run : {std::make_pair(50.0, EDPDIntegrator::OneSided), std::make_pair(1.0, EDPDIntegrator::Symmetric)}) {
        const std::string label = "alpha " + std::to_string(run.first);
        auto make = [&]() {
            EDPDIntegrator* integrator = new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, run.first, 0.02);
            integrator->setScheme(run.second);
            integrator->setRandomNumberSeed(77);
            return integrator;
        };
        std::unique_ptr<EDPDIntegrator> reference(make()), device(make()), restored(make());
        std::unique_ptr<Context> onReference = start(*reference, "Reference"), onDevice = start(*device, GPU);
        for (int half = 0; half < 2; half++) {
            reference->step(30);
            device->step(30);
            if (half == 0) {
                onReference->setStepCount(5000);
                onDevice->setStepCount(5000);
            }
        }
        EXPECT_EQ(device->getNumPairVariables(), reference->getNumPairVariables()) << label;
        const State expected = onReference->getState(State::Positions);
        EXPECT_LT(maxImageDifference(onDevice->getState(State::Positions).getPositions(), expected.getPositions(), box), 1e-6 * box) << label;
        expectSamePairVariables(*reference, *device, n, 1e-6, label);
        std::stringstream checkpoint;
        onDevice->createCheckpoint(checkpoint);
        device->step(20);
        const State first = onDevice->getState(State::Positions | State::Velocities);
        std::unique_ptr<Context> fresh = start(*restored, GPU);
        fresh->loadCheckpoint(checkpoint);
        EXPECT_EQ(restored->getNumPairVariables(), reference->getNumPairVariables()) << label << ", restored";
        restored->step(20);
        const State second = fresh->getState(State::Positions | State::Velocities);
        EXPECT_EQ(first.getPositions(), second.getPositions()) << label << ", continued from a checkpoint";
        EXPECT_EQ(first.getVelocities(), second.getVelocities()) << label << ", continued from a checkpoint";
        expectSamePairVariables(*device, *restored, n, 0, label + ", continued from a checkpoint");
    }
}

namespace {

// The sweep integrators (S1, S2, Lowe, pair OU), configured as the DPD-VV tests' integrators:
// two particle types with their own type pair (friction or collision rate 6, cutoff 0.9).
void configureSweep(DPDThermostatIntegrator& integrator, int numParticles) {
    integrator.setRandomNumberSeed(1234);
    for (int i = 0; i < numParticles; i += 3)
        integrator.setParticleType(i, 1);
    integrator.addTypePair(0, 1, 6.0, 0.9);
}

MakeIntegrator edpd(EDPDIntegrator::Scheme scheme) {
    return [scheme](int numParticles) {
        std::unique_ptr<EDPDIntegrator> integrator(new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, 0.02));
        integrator->setScheme(scheme);
        configureSweep(*integrator, numParticles);
        return std::unique_ptr<DPDThermostatIntegrator>(std::move(integrator));
    };
}

MakeIntegrator shardlow(int order) {
    return [order](int numParticles) {
        std::unique_ptr<ShardlowIntegrator> integrator(new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, 0.02));
        integrator->setOrder(order);
        configureSweep(*integrator, numParticles);
        return std::unique_ptr<DPDThermostatIntegrator>(std::move(integrator));
    };
}

MakeIntegrator loweAndersen(LoweAndersenIntegrator::Method method, LoweAndersenIntegrator::Splitting splitting) {
    return [method, splitting](int numParticles) {
        std::unique_ptr<LoweAndersenIntegrator> integrator(new LoweAndersenIntegrator(KT_KELVIN, 4.5, 1.0, 0.02));
        integrator->setMethod(method);
        integrator->setSplitting(splitting);
        configureSweep(*integrator, numParticles);
        return std::unique_ptr<DPDThermostatIntegrator>(std::move(integrator));
    };
}

// Momentum, one seed twice, and a checkpoint that continues bit for bit (900 particles).
void expectSweepMomentumSeedsAndCheckpoints(const MakeIntegrator& make, const std::string& label) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(900, positions));
    std::unique_ptr<DPDThermostatIntegrator> first = make(900), second = make(900);
    std::unique_ptr<Context> a = makeContext(*system, *first, GPU, positions);
    std::unique_ptr<Context> b = makeContext(*system, *second, GPU, positions);
    const Vec3 p0 = momentum(*system, a->getState(State::Velocities));
    first->step(5);
    second->step(5);
    const State sa = a->getState(State::Positions | State::Velocities), sb = b->getState(State::Positions | State::Velocities);
    // Each pair update moves equal and opposite momenta (J e); what remains is the float
    // rounding of the two velocities it writes (~6e-8 of m v ~ 2), a random walk over 5 steps
    // of ~7500 pairs and up to 4 updates each: ~5e-5 (measured 4e-6 to 6e-5).  1e-3 allows
    // 20 times that; a wrong impulse (v_j -= J/m_i e) gives > 5.
    const Vec3 dp = momentum(*system, sa) - p0;
    EXPECT_LT(std::sqrt(dp.dot(dp)), 1e-3) << label;
    for (size_t i = 0; i < positions.size(); i++) {
        ASSERT_EQ(sa.getPositions()[i], sb.getPositions()[i]) << label << ": one seed, two runs: particle " << i;
        ASSERT_EQ(sa.getVelocities()[i], sb.getVelocities()[i]) << label << ": one seed, two runs: particle " << i;
    }
    expectCheckpointContinuesBitForBit(*a, *first, GPU + " " + label);
}

} // namespace

TEST(GpuPlatform, ShardlowFollowsReference) {
    REQUIRE_DEVICE();
    expectFollowsReference(shardlow(2), 900, "S2 mixed precision", {{"Precision", "mixed"}});
    expectFollowsReference(shardlow(2), 100, "S2, 2 cells per axis");
}

TEST(GpuPlatform, LoweAndersenFollowsReference) {
    REQUIRE_DEVICE();
    expectFollowsReference(loweAndersen(LoweAndersenIntegrator::Lowe, LoweAndersenIntegrator::Middle), 900, "Lowe, Middle, 6 cells per axis");
    expectFollowsReference(loweAndersen(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, LoweAndersenIntegrator::Middle), 100,
                                "pair OU, Middle, 2 cells per axis");
}

namespace {

/** An integrator of `make` with weight exponent s = 1 by default and 1.5 for its first type pair. */
MakeIntegrator withWeightExponents(const MakeIntegrator& make) {
    return [make](int numParticles) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = make(numParticles);
        integrator->setDefaultWeightExponent(1.0);
        if (integrator->getNumTypePairs() > 0)
            integrator->setTypePairWeightExponent(0, 1.5);
        return integrator;
    };
}

/** An integrator of `make` with thermostat exceptions for every pair 1 (factor 0) and 2 (factor 0.5) apart in index. */
MakeIntegrator withExceptions(const MakeIntegrator& make) {
    return [make](int numParticles) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = make(numParticles);
        for (int i = 0; i + 2 < numParticles; i++) {
            integrator->addThermostatException(i, i + 1, 0.0);
            integrator->addThermostatException(i, i + 2, 0.5);
        }
        return integrator;
    };
}

} // namespace

TEST(GpuPlatform, ThermostatExceptionsFollowReference) {
    REQUIRE_DEVICE();
    expectFollowsReference(withExceptions(dpdvv(DPDVVIntegrator::GrootWarren)), 600, "GW, exceptions");
    expectFollowsReference(withExceptions(shardlow(2)), 900, "S2, exceptions");
    expectFollowsReference(withExceptions(loweAndersen(LoweAndersenIntegrator::Lowe, LoweAndersenIntegrator::AfterVerlet)), 900,
                           "Lowe, exceptions");
    expectFollowsReference(withExceptions(loweAndersen(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, LoweAndersenIntegrator::Middle)),
                           900, "pair OU, exceptions");
    expectFollowsReference(withExceptions(edpd(EDPDIntegrator::OneSided)), 600, "EDPD, exceptions");
}

TEST(GpuPlatform, WeightExponentsFollowReference) {
    // In mixed precision: single precision's pow (under OpenMM's fast math) leaves the
    // Reference's trajectory faster than the tolerance allows over 3 steps.
    REQUIRE_DEVICE();
    const std::map<std::string, std::string> mixed = {{"Precision", "mixed"}};
    expectFollowsReference(withWeightExponents(dpdvv(DPDVVIntegrator::GrootWarren)), 600, "GW, s = 1", mixed);
    expectFollowsReference(withWeightExponents(shardlow(2)), 900, "S2, s = 1 and 1.5", mixed);
    expectFollowsReference(withWeightExponents(loweAndersen(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, LoweAndersenIntegrator::Middle)),
                           900, "pair OU, s = 1 and 1.5", mixed);
}

namespace {

/** An integrator of `make` with transverse friction 3 (exponent 1) by default and 6 (exponent 0.5) for its first type pair. */
MakeIntegrator withTransverseFriction(const MakeIntegrator& make) {
    return [make](int numParticles) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = make(numParticles);
        integrator->setDefaultTransverseFriction(3.0);
        integrator->setDefaultTransverseWeightExponent(1.0);
        if (integrator->getNumTypePairs() > 0)
            integrator->setTypePairTransverseFriction(0, 6.0, 0.5);
        return integrator;
    };
}

} // namespace

// Cell lists of 26^3 cells (the pair forces, the soft force) and 27^3 (the sweep grid), 138
// and 154 blocks of the scan (more than one work group's worth), nearly all empty: the 1000
// particles sit in 40 clumps of 25, 0 to ~10 to a cell.  A wrong cell start loses or repeats
// pairs, and the trajectory leaves the Reference's.
TEST(GpuPlatform, SparseClumpedCellsFollowReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(1000, positions));
    const double box = 27.0;
    system->setDefaultPeriodicBoxVectors(Vec3(box, 0, 0), Vec3(0, box, 0), Vec3(0, 0, box));
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> uniform(0, 1);
    Vec3 centre;
    for (int i = 0; i < 1000; i++) {
        if (i % 25 == 0)
            centre = Vec3(uniform(rng), uniform(rng), uniform(rng)) * box;
        positions[i] = centre + Vec3(uniform(rng), uniform(rng), uniform(rng)) * 1.6;
    }
    expectFollowsReference(*system, positions, dpdvv(DPDVVIntegrator::GrootWarren), "GW, clumps");
    expectFollowsReference(*system, positions, shardlow(1), "S1, clumps");
}

namespace {

// What a step that blows up says, from "the simulation" on (the platforms name the integrator
// differently), cut before a value measured in floating point.
std::string blowUpReport(Integrator& integrator) {
    try {
        integrator.step(1);
    }
    catch (const OpenMMException& e) {
        std::string m = e.what();
        m = m.substr(std::min(m.find("the simulation"), m.size()));
        for (const char* cut : {" moved ", " kinetic energy "})
            m = m.substr(0, m.find(cut));
        return m;
    }
    return "no error";
}

} // namespace

// The device reads its blow-up flags once, at the end of a step: a particle given a non-finite
// velocity, one that moves 1e28 nm (finite; beyond the device's 1e15 nm bound), one that moves
// 10-20 nm and one at 1800 kT (threshold 40 kT) stop step 3 with the Reference's report, and the
// step count stays 2.
TEST(GpuPlatform, BlowUpsStopTheStepTheyHappenInAsOnReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(600, positions));
    for (const MakeIntegrator& make : {dpdvv(DPDVVIntegrator::GrootWarren),
                                       loweAndersen(LoweAndersenIntegrator::Lowe, LoweAndersenIntegrator::Middle)}) {
        std::unique_ptr<DPDThermostatIntegrator> reference = make(600), device = make(600);
        std::unique_ptr<Context> onReference = makeContext(*system, *reference, "Reference", positions);
        std::unique_ptr<Context> onDevice = makeContext(*system, *device, GPU, positions);
        const State start = onReference->getState(State::Positions | State::Velocities);
        for (double speed : {std::nan(""), 1e30, 1000.0, 60.0}) {
            std::vector<std::string> reports;
            for (auto run : {std::make_pair(reference.get(), onReference.get()), std::make_pair(device.get(), onDevice.get())}) {
                run.first->setInstabilityThreshold(40);
                run.second->setState(start);
                run.first->step(2);
                std::vector<Vec3> v = run.second->getState(State::Velocities).getVelocities();
                v[7] = Vec3(speed, 0, 0);
                run.second->setVelocities(v);
                reports.push_back(blowUpReport(*run.first));
                // The Context is left at the stopped step.
                EXPECT_EQ(run.second->getState(0).getStepCount(), 3) << reports.back();
            }
            EXPECT_NE(reports[0].find("at step 3: "), std::string::npos) << reports[0];
            if (std::isnan(speed)) {
                // Fixed point cannot carry the NaN forces on 7's partners: the platforms may name different particles.
                EXPECT_NE(reports[1].find("blew up at step 3: particle "), std::string::npos) << reports[1];
                EXPECT_NE(reports[1].find(" has a non-finite position"), std::string::npos) << reports[1];
            }
            else
                EXPECT_EQ(reports[1], reports[0]) << "speed " << speed;
        }
    }
}

namespace {

// The pressure tensor's parts (kinetic, conservative, thermostat, total) sampled by one step on a platform.
std::vector<std::vector<double>> sampledPressureParts(System& system, const std::vector<Vec3>& positions, const MakeIntegrator& make,
                                                      const std::string& platform) {
    std::unique_ptr<DPDThermostatIntegrator> integrator = make(system.getNumParticles());
    integrator->setPressureTensorEnabled(true);
    std::unique_ptr<Context> context = makeContext(system, *integrator, platform, positions);
    integrator->step(1);
    return pressureParts(*integrator);
}

// The soft fluid with a DPD spring (k = 4, r0 = 0) between every 50th particle and the next.
System* makeBondedSoftSystem(int n, std::vector<Vec3>& positions) {
    System* system = makeSoftSystem(n, positions);
    HarmonicBondForce* bonds = new HarmonicBondForce();
    for (int i = 0; i + 1 < n; i += 50)
        bonds->addBond(i, i + 1, 0.0, 4.0);
    system->addForce(bonds);
    return system;
}

/*
 * One integrator's pressure tensor parts on the device against the Reference's, on the bonded soft
 * fluid of n particles: the conservative part takes both the soft force's exact pair virial
 * and the strain derivative of the springs' energy.  Each part's components agree within 1e-4
 * of the part's largest component: one step of a float trajectory (whose divergence, 2e-5
 * after three steps as above, moves the soft virial by ~2e-4 of its size), float pair terms,
 * and the strain derivative's float energies differenced over a strain of 1e-3 (an error of
 * ~1e-7 |U| / (2e-3 V): 6e-5 here; stiffer, longer bonds would need a wider tolerance).
 */
void expectPressureFollowsReference(int n, const std::string& label, const MakeIntegrator& make) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeBondedSoftSystem(n, positions));
    const std::vector<std::vector<double>> expected = sampledPressureParts(*system, positions, make, "Reference");
    const std::vector<std::vector<double>> actual = sampledPressureParts(*system, positions, make, GPU);
    expectPressurePartsNear(expected, actual, 1e-4, label + ", " + std::to_string(n) + " particles");
}

} // namespace

// The sweeps on one work item (100 particles: fewer than 3 cells on an axis); on a coloured
// grid, and every other integrator, in TestIntegratorPhysics.cpp.
TEST(GpuPlatform, PressureTensorFollowsReference) {
    REQUIRE_DEVICE();
    const std::vector<std::pair<std::string, MakeIntegrator>> sweeps = {
            {"S1", shardlow(1)}, {"S2", shardlow(2)},
            {"Lowe", loweAndersen(LoweAndersenIntegrator::Lowe, LoweAndersenIntegrator::AfterVerlet)},
            {"pair OU, Middle", loweAndersen(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, LoweAndersenIntegrator::Middle)}};
    for (const auto& sweep : sweeps)
        expectPressureFollowsReference(100, sweep.first, sweep.second);
}

namespace {

MakeIntegrator sheared(const MakeIntegrator& make, double rate) {
    return [make, rate](int n) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = make(n);
        integrator->setShearRate(rate);
        return integrator;
    };
}

} // namespace

// Lees-Edwards shear backwards (rate -0.5, U = -2.7 nm/ps) in mixed precision: the box slides
// 0.16 nm in 3 steps, particles and two-particle molecules cross the y boundaries with their
// velocity jumps, and pairs across them see their partner's image move.  Forwards, every
// integrator (with the pressure tensor where it is sampled): TestIntegratorPhysics.cpp.
TEST(GpuPlatform, ShearFollowsReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeBondedSoftSystem(600, positions));
    expectFollowsReference(*system, positions, sheared(dpdvv(DPDVVIntegrator::GrootWarren), -0.5), "GW sheared, mixed precision",
                           {{"Precision", "mixed"}});
}

// A sweep under shear backwards, in the Reference's pair order on the grid of the sheared
// lattice (forwards, every sweep: TestIntegratorPhysics.cpp).  And a box less than 3 cutoffs
// high (2.92 nm), whose rows across the sliding boundary are each other's neighbours twice over.
TEST(GpuPlatform, ShearedSweepsFollowReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeBondedSoftSystem(600, positions));
    expectFollowsReference(*system, positions, sheared(shardlow(2), -0.5), "S2 sheared backwards");
    expectFollowsReference(sheared(shardlow(2), 0.5), 100, "S2 sheared, 2 cutoffs high");
    expectFollowsReference(sheared(dpdvv(DPDVVIntegrator::GrootWarren), 0.5), 100, "GW sheared, 2 cutoffs high");
}

// Open grids with fewer than 3 cells on an axis, which the Reference still colours and sweeps
// over each cell's full shell: 100 particles in a cube of 2.9 nm (2 cells a side), and 600 in
// a slab 0.8 nm thick (5 x 5 x 1 cells, whose colour order is not the cells' index order).
TEST(GpuPlatform, SweepsOnSmallOpenGridsFollowReference) {
    REQUIRE_DEVICE();
    const MakeIntegrator lowe = loweAndersen(LoweAndersenIntegrator::Lowe, LoweAndersenIntegrator::AfterVerlet);
    for (int n : {100, 600}) {
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeSoftSystem(n, positions));
        dynamic_cast<DPDSoftRepulsionForce&>(system->getForce(0)).setNonbondedMethod(DPDSoftRepulsionForce::CutoffNonPeriodic);
        if (n == 600)
            for (Vec3& r : positions)
                r[2] *= 0.15;
        const std::string grid = (n == 100 ? ", open cube" : ", open slab");
        expectFollowsReference(*system, positions, shardlow(2), "S2" + grid);
        expectFollowsReference(*system, positions, lowe, "Lowe" + grid);
    }
}

// Transverse friction in mixed precision (single precision's pow, as for the weight exponents),
// sheared too, and the pressure tensor's parts, whose thermostat part is then not symmetric.
TEST(GpuPlatform, TransverseFrictionFollowsReference) {
    REQUIRE_DEVICE();
    const std::map<std::string, std::string> mixed = {{"Precision", "mixed"}};
    expectFollowsReference(withTransverseFriction(dpdvv(DPDVVIntegrator::GrootWarren)), 600, "GW, transverse", mixed);
    expectFollowsReference(withTransverseFriction(dpdvv(DPDVVIntegrator::SelfConsistent)), 600, "SC-VV, transverse", mixed);
    expectFollowsReference(withTransverseFriction(shardlow(2)), 900, "S2, transverse", mixed);
    const MakeIntegrator pairOU = loweAndersen(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, LoweAndersenIntegrator::Middle);
    expectFollowsReference(withTransverseFriction(pairOU), 900, "pair OU, transverse", mixed);
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeBondedSoftSystem(600, positions));
    expectFollowsReference(*system, positions, sheared(withTransverseFriction(dpdvv(DPDVVIntegrator::DPDVV)), 0.5),
                           "DPD-VV sheared, transverse", mixed);
    expectFollowsReference(*system, positions, sheared(withTransverseFriction(shardlow(1)), 0.5), "S1 sheared, transverse", mixed);
    expectPressureFollowsReference(600, "GW, transverse", withTransverseFriction(dpdvv(DPDVVIntegrator::GrootWarren)));
    expectPressureFollowsReference(600, "S1, transverse", withTransverseFriction(shardlow(1)));
    expectPressureFollowsReference(100, "pair OU, transverse", withTransverseFriction(pairOU));
}

// OpenMM's own device kernels take the box as the Context was made (rectangular): a periodic
// force of its own is refused under shear and with the pressure tensor, naming it; an empty
// CustomBondForce that only makes the System periodic is not.
TEST(GpuPlatform, RefusesOpenMMPeriodicForcesUnderShearOrStrain) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(600, positions));
    CustomBondForce* marker = new CustomBondForce("0");
    marker->setUsesPeriodicBoundaryConditions(true);
    system->addForce(marker);
    std::unique_ptr<DPDThermostatIntegrator> allowed = sheared(dpdvv(DPDVVIntegrator::GrootWarren), 0.5)(600);
    allowed->setPressureTensorEnabled(true);
    makeContext(*system, *allowed, GPU, positions);
    addPeriodicSprings(*system);
    for (bool shear : {true, false}) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = dpdvv(DPDVVIntegrator::GrootWarren)(600);
        integrator->setShearRate(shear ? 0.5 : 0.0);
        integrator->setPressureTensorEnabled(!shear);
        expectErrorNaming([&] { makeContext(*system, *integrator, GPU, positions); }, "OpenMM's periodic PeriodicSprings (force 2");
    }
}

// Made with a tilted box, OpenMM compiles its device kernels for any box: its own periodic
// pair force (here the soft repulsion as a CustomNonbondedForce) then takes the sliding box
// and the pressure tensor's strains, and follows the Reference (its energy's strain
// derivative is the whole conservative virial).
TEST(GpuPlatform, OpenMMPeriodicForcesTakeTheSlidingBoxOfATiltedSystem) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(600, 0, positions));
    system->removeForce(0);
    CustomNonbondedForce* soft = new CustomNonbondedForce("12.5*(1-r)^2");
    soft->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    soft->setCutoffDistance(1.0);
    for (int i = 0; i < 600; i++)
        soft->addParticle();
    system->addForce(soft);
    Vec3 a, b, c;
    system->getDefaultPeriodicBoxVectors(a, b, c);
    system->setDefaultPeriodicBoxVectors(a, Vec3(0.1, b[1], 0), c);
    const MakeIntegrator gw = sheared(dpdvv(DPDVVIntegrator::GrootWarren), 0.5);
    expectFollowsReference(*system, positions, gw, "GW sheared, OpenMM's periodic force");
    // In mixed precision: all of this force's virial comes from strained energies, which single
    // precision sums to ~1e-4 of the virial here.
    std::vector<std::vector<std::vector<double>>> parts;
    for (const std::string& platform : {std::string("Reference"), GPU}) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = gw(600);
        integrator->setPressureTensorEnabled(true);
        std::map<std::string, std::string> properties;
        if (platform == GPU)
            properties["Precision"] = "mixed";
        Context context(*system, *integrator, Platform::getPlatformByName(platform), properties);
        context.setPositions(positions);
        integrator->step(1);
        parts.push_back(pressureParts(*integrator));
    }
    expectPressurePartsNear(parts[0], parts[1], 1e-4, "GW sheared, OpenMM's periodic force");
}

// The strain puts the positions back to the bit and the virials change nothing: the same
// trajectory with the pressure tensor sampled or not.
TEST(GpuPlatform, SamplingThePressureTensorLeavesTheTrajectoryAlone) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeBondedSoftSystem(600, positions));
    for (DPDVVIntegrator::Variant variant : {DPDVVIntegrator::GrootWarren, DPDVVIntegrator::DPDVV}) {
        std::vector<State> states;
        for (bool sample : {false, true}) {
            std::unique_ptr<DPDThermostatIntegrator> integrator = dpdvv(variant)(600);
            integrator->setPressureTensorEnabled(sample);
            std::unique_ptr<Context> context = makeContext(*system, *integrator, GPU, positions);
            integrator->step(4);
            states.push_back(context->getState(State::Positions | State::Velocities));
        }
        EXPECT_EQ(states[0].getPositions(), states[1].getPositions()) << "variant " << variant;
        EXPECT_EQ(states[0].getVelocities(), states[1].getVelocities()) << "variant " << variant;
    }
}

TEST(GpuPlatform, SweepMomentumSeedsAndCheckpoints) {
    REQUIRE_DEVICE();
    expectSweepMomentumSeedsAndCheckpoints(shardlow(1), "S1");
    expectSweepMomentumSeedsAndCheckpoints(shardlow(2), "S2");
    expectSweepMomentumSeedsAndCheckpoints(loweAndersen(LoweAndersenIntegrator::Lowe, LoweAndersenIntegrator::AfterVerlet), "Lowe");
    expectSweepMomentumSeedsAndCheckpoints(loweAndersen(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, LoweAndersenIntegrator::Middle),
                                           "pair OU, Middle");
}

TEST(GpuPlatform, SweepIntegratorsRefuseWhatTheyDoNotDo) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeSoftSystem(100, positions));
    addPeriodicSprings(*system);
    std::unique_ptr<DPDThermostatIntegrator> s2 = shardlow(2)(100);
    std::unique_ptr<Context> context = makeContext(*system, *s2, GPU, positions);
    s2->step(1);
    const State before = context->getState(State::Positions | State::Velocities);
    s2->setShearRate(0.1);
    expectErrorNaming([&] { s2->step(1); }, "ShardlowIntegrator: Lees-Edwards shear or the pressure tensor with OpenMM's periodic");
    s2->setShearRate(0);
    const State after = context->getState(State::Positions | State::Velocities);
    EXPECT_EQ(after.getPositions(), before.getPositions()) << "nothing changed";
    EXPECT_EQ(after.getVelocities(), before.getVelocities()) << "nothing changed";
    EXPECT_EQ(after.getStepCount(), 1);
}

namespace {

// Dimers of two beads held by a harmonic bond (or a constraint), with a massless virtual site
// at each one's middle that the soft force acts on as on any bead (OpenMM passes its force on
// to the two): the first 90 particles of the one-mass soft fluid.
System* makeFluidWithSites(int n, std::vector<Vec3>& positions, bool constrained = false) {
    System* system = makeOneMassSoftSystem(n, positions);
    HarmonicBondForce* bonds = new HarmonicBondForce();  // not periodic: molecules are kept whole
    for (int k = 0; k + 2 < 90; k += 3) {
        positions[k + 1] = positions[k] + Vec3(0.5, 0, 0);
        positions[k + 2] = positions[k] + Vec3(0.25, 0, 0);
        if (constrained)
            system->addConstraint(k, k + 1, 0.5);
        else
            bonds->addBond(k, k + 1, 0.5, 50.0);
        system->setParticleMass(k + 2, 0.0);
        system->setVirtualSite(k + 2, new TwoParticleAverageSite(k, k + 1, 0.5, 0.5));
    }
    system->addForce(bonds);
    return system;
}

} // namespace

TEST(GpuPlatform, VirtualSitesFollowReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluidWithSites(600, positions));
    expectFollowsReference(*system, positions, dpdvv(DPDVVIntegrator::GrootWarren), "GW with virtual sites");
    expectFollowsReference(*system, positions, dpdvv(DPDVVIntegrator::DPDVV), "DPD-VV with virtual sites");
    expectFollowsReference(*system, positions, shardlow(1), "S1 with virtual sites");
    expectFollowsReference(*system, positions, denOtterClarke(0.5), "sheared den Otter-Clarke with virtual sites");
    // The pressure tensor: the strains move the sites with their beads, as on the Reference.
    for (const auto& scheme : {std::make_pair(std::string("GW"), dpdvv(DPDVVIntegrator::GrootWarren)), std::make_pair(std::string("S1"), shardlow(1)),
                               std::make_pair(std::string("sheared GW"), sheared(dpdvv(DPDVVIntegrator::GrootWarren), 0.5))})
        expectPressurePartsNear(sampledPressureParts(*system, positions, scheme.second, "Reference"),
                                sampledPressureParts(*system, positions, scheme.second, GPU), 1e-4,
                                scheme.first + " with virtual sites");
}

// Rigid dimers (OpenMM's constraints on the device, tolerance 1e-5) with their sites under
// shear: GW follows the Reference (still, every integrator: TestIntegratorPhysics.cpp).
TEST(GpuPlatform, ConstraintsFollowReference) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluidWithSites(600, positions, true));
    MakeIntegrator sheared = [](int n) {
        std::unique_ptr<DPDThermostatIntegrator> integrator = dpdvv(DPDVVIntegrator::GrootWarren)(n);
        integrator->setShearRate(0.5);
        return integrator;
    };
    expectFollowsReference(*system, positions, sheared, "sheared GW with constraints");
}

// The staggered schemes under shear with their polymer (spring dimers in the fast group)
// straddling the sliding boundary: molecules cross in the prediction and in the sub-steps,
// which start again from the box at the start of the step; with the recommended parameters
// and with others (mu, a, b all in play, the slow force not weighted).  (Away from the
// boundary, every base and K: TestIntegratorPhysics.cpp.)
TEST(GpuPlatform, StaggeredPolymerCrossesTheShearedBoundary) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeBondedSoftSystem(600, positions));
    system->getForce(system->getNumForces() - 1).setForceGroup(1);  // the springs: the fast forces
    Vec3 a, b, c;
    system->getDefaultPeriodicBoxVectors(a, b, c);
    for (int i = 0; i + 1 < 600; i += 50) {
        positions[i][1] = ((i / 50) % 2 == 0 ? b[1] - 0.005 : 0.005);
        positions[i + 1] = positions[i] + Vec3(0.3, 0, 0);
    }
    for (StaggeredDPDIntegrator::BaseScheme base : {StaggeredDPDIntegrator::VelocityVerlet, StaggeredDPDIntegrator::LoweAndersen})
        for (int K : {1, 3})
            for (bool recommended : {true, false}) {
                MakeIntegrator make = [base, K, recommended](int) {
                    std::unique_ptr<StaggeredDPDIntegrator> integrator(new StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, 0.02, K));
                    integrator->setBaseScheme(base);
                    integrator->useRecommendedParameters();
                    if (!recommended) {
                        integrator->setRelaxationParameters(0.2, 0.3, 0.4);
                        integrator->setWeighted(false);
                    }
                    integrator->setShearRate(0.5);
                    integrator->setRandomNumberSeed(1234);
                    return std::unique_ptr<DPDThermostatIntegrator>(std::move(integrator));
                };
                expectFollowsReference(*system, positions, make, "staggered base " + std::to_string(base) + ", K " +
                                       std::to_string(K) + (recommended ? "" : ", mu a b 0.2 0.3 0.4, not weighted"));
            }
}

// Live changes: new fast groups select a new polymer at the next step, as on the Reference;
// a new base scheme is refused until the Context is reinitialised.
TEST(GpuPlatform, StaggeredTakesNewFastGroupsAndRefusesANewBase) {
    REQUIRE_DEVICE();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeBondedSoftSystem(600, positions));
    system->getForce(system->getNumForces() - 1).setForceGroup(1);
    HarmonicBondForce* other = new HarmonicBondForce();
    for (int i = 25; i + 1 < 600; i += 50)
        other->addBond(i, i + 1, 0.0, 4.0);
    other->setForceGroup(2);
    system->addForce(other);
    std::vector<std::vector<Vec3>> after;
    for (const std::string& platform : {std::string("Reference"), GPU}) {
        StaggeredDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.02, 3);
        integrator.setRandomNumberSeed(1234);
        std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions);
        integrator.step(2);
        integrator.setFastForceGroups(1 << 2);
        integrator.step(2);
        after.push_back(context->getState(State::Positions).getPositions());
        integrator.setBaseScheme(StaggeredDPDIntegrator::LoweAndersen);
        expectErrorNaming([&] { integrator.step(1); }, "the base scheme changed after the Context was created");
    }
    Vec3 a, b, c;
    system->getDefaultPeriodicBoxVectors(a, b, c);
    EXPECT_LT(maxImageDifference(after[1], after[0], a[0]), 2e-5 * a[0]) << "positions after the new fast groups";
}
