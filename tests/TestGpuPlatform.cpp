// The OpenCL platform's kernels (platforms/common) against the Reference platform and the host's
// PairRandom.  OpenCL runs on the CPU here (POCL), in single precision unless a test asks for
// mixed; each Context compiles OpenMM's programs and ours (seconds), so the tests share few.
//
// Tolerance: a position or velocity on the device is a float (6e-8 relative); a step adds the
// rounding of ~20 pair terms in float before the fixed-point sum, so after 3 steps the device
// differs from the Reference (double) by ~1e-6 relative.  We ask for 2e-5 relative (to the box
// for positions, to the largest speed for velocities): any error in the rule or the random
// numbers (a wrong Philox word moves a particle by sigma dt^1.5 ~ 1e-2 nm) is 1000x that.
#include "TestHelpers.h"
#include "openmmdpd/CommonPairRandomCheck.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/internal/ContextImpl.h"
#include "openmmdpd/OpenCLDPDKernelFactory.h"

using namespace DPDPlugin;

namespace {

bool haveOpenCL() {
    try {
        Platform::getPlatformByName("OpenCL");
        return true;
    }
    catch (const OpenMMException&) {
        return false;
    }
}

#define REQUIRE_OPENCL() \
    if (!haveOpenCL()) \
        GTEST_SKIP() << "OpenMM has no OpenCL platform here"

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
    return getOpenCLComputeContext(access.of(context));
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

void configure(DPDVVIntegrator& integrator, DPDVVIntegrator::Variant variant) {
    integrator.setVariant(variant);
    integrator.setLambda(0.65);
    integrator.setRandomNumberSeed(1234);
    for (int i = 0; i < 600; i += 3)
        integrator.setParticleType(i, 1);
    integrator.addTypePair(0, 1, 6.0, 0.9);
}

double maxNorm(const std::vector<Vec3>& a) {
    double m = 0;
    for (const Vec3& x : a)
        m = std::max(m, std::sqrt(x.dot(x)));
    return m;
}

double maxDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double m = 0;
    for (size_t i = 0; i < a.size(); i++)
        m = std::max(m, std::sqrt((a[i] - b[i]).dot(a[i] - b[i])));
    return m;
}

Vec3 momentum(System& system, const State& state) {
    Vec3 p;
    for (int i = 0; i < system.getNumParticles(); i++)
        p += state.getVelocities()[i] * system.getParticleMass(i);
    return p;
}

} // namespace

TEST(GpuPlatform, PhiloxWordsEqualTheHostsBitForBit) {
    REQUIRE_OPENCL();
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(8, 0, positions));
    VerletIntegrator integrator(0.001);
    Context context(*system, integrator, Platform::getPlatformByName("OpenCL"));
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
