// DenOtterClarkeIntegrator: two steps of a bonded pair against Table II written out by hand,
// the prefactors against eqs. 6-7, bad input, checkpoints.  The physics (calibration against
// the ideal gas's closed forms and Nikunen et al. 2003, Table III, <kT>) is in the Python tests.

#include "TestHelpers.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/PairRandom.h"
#include "openmm/HarmonicBondForce.h"
#include <sstream>

using namespace DPDPlugin;

namespace {

// Model B (Nikunen et al. 2003, Table III), reduced units = OpenMM units with kT = 1 kJ/mol.
constexpr double FD_DOT_V = -4.985245, FD_DOT_FD = 14.507340, FR_DOT_FR = 9.976453;
// KT_KELVIN's kT, 1 kJ/mol to 4e-8.
const double KT = BOLTZMANN_KJ_PER_MOL_K * KT_KELVIN;

DenOtterClarkeIntegrator* modelB(double dt, int seed = 1234) {
    DenOtterClarkeIntegrator* integrator = new DenOtterClarkeIntegrator(KT_KELVIN, 4.5, 1.0, dt);
    integrator->setAverageFDDotV(FD_DOT_V);
    integrator->setAverageFDDotFD(FD_DOT_FD);
    integrator->setAverageFRDotFR(FR_DOT_FR);
    integrator->setRandomNumberSeed(seed);
    return integrator;
}

/** Eqs. 6-7 with m = 1, as the paper writes them. */
void paperPrefactors(double dt, double& alpha, double& beta) {
    const double G = -FD_DOT_V / (3 * KT);  // <v.v> = 3 kT/m
    alpha = (1 - std::exp(-G * dt)) / (G * dt);
    beta = std::sqrt((-2 * alpha * FD_DOT_V - alpha * alpha * dt * FD_DOT_FD) / FR_DOT_FR);
}

TEST(DenOtterClarke, PrefactorsAreEquations6And7) {
    for (double dt : {0.001, 0.04, 0.3}) {
        std::unique_ptr<DenOtterClarkeIntegrator> integrator(modelB(dt));
        double alpha, beta, expectedAlpha, expectedBeta;
        integrator->getPrefactors(1.0, alpha, beta);
        paperPrefactors(dt, expectedAlpha, expectedBeta);
        // 1 - exp(-G dt) as the paper writes it loses ~1e-14 to cancellation at small dt.
        EXPECT_NEAR(alpha, expectedAlpha, 1e-12) << dt;
        EXPECT_NEAR(beta, expectedBeta, 1e-12) << dt;
    }
}

TEST(DenOtterClarke, TwoStepsOfABondedPairAreTableII) {
    // Particles 0 and 1 within the cutoff, a harmonic bond between them, no box; Table II by
    // hand: v += alpha dt (FC + FD) + beta sqrt(dt) FR (FR without 1/sqrt(dt)), r += dt v.
    const double dt = 0.04, k = 50, length = 0.3, gamma = 4.5, sigma = std::sqrt(2 * gamma * KT);
    System system;
    system.addParticle(1.0);
    system.addParticle(1.0);
    HarmonicBondForce* bond = new HarmonicBondForce();
    bond->addBond(0, 1, length, k);
    system.addForce(bond);
    const std::vector<Vec3> r0 = {Vec3(0, 0, 0), Vec3(0.6, 0.2, -0.1)}, v0 = {Vec3(0.3, -0.2, 0.5), Vec3(-0.4, 0.1, 0.2)};
    std::vector<Vec3> r = r0, v = v0;
    const PairRandom random(1234);
    double alpha, beta;
    paperPrefactors(dt, alpha, beta);
    for (int step = 0; step < 2; step++) {
        const Vec3 d = r[0] - r[1];
        const double distance = std::sqrt(d.dot(d)), wR = 1 - distance;
        const Vec3 e = d / distance;
        const Vec3 FC = e * (-k * (distance - length));
        const Vec3 FD = e * (-gamma * wR * wR * e.dot(v[0] - v[1]));
        const Vec3 FR = e * (sigma * wR * random.gaussian(PairRandom::RandomForce, step, 0, 1));
        const Vec3 kick = (FC + FD) * (alpha * dt) + FR * (beta * std::sqrt(dt));
        v[0] += kick;
        v[1] -= kick;
        for (int i : {0, 1})
            r[i] += v[i] * dt;
    }
    for (const std::string& platform : platforms()) {
        std::unique_ptr<DenOtterClarkeIntegrator> integrator(modelB(dt));
        Context context(system, *integrator, Platform::getPlatformByName(platform));
        context.setPositions(r0);
        context.setVelocities(v0);
        integrator->step(2);
        const State state = context.getState(State::Positions | State::Velocities);
        for (int i : {0, 1})
            for (int c = 0; c < 3; c++) {
                // The CPU platform's conservative forces are single precision.
                const double tolerance = (platform == "CPU" ? 1e-6 : 1e-13);
                EXPECT_NEAR(state.getPositions()[i][c], r[i][c], tolerance) << platform << " particle " << i;
                EXPECT_NEAR(state.getVelocities()[i][c], v[i][c], tolerance) << platform << " particle " << i;
            }
    }
}

TEST(DenOtterClarke, BadInputIsRefusedNamingTheParameter) {
    DenOtterClarkeIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.04);
    for (double bad : {0.0, 1.0, std::nan("")})
        expectErrorNaming([&] { integrator.setAverageFDDotV(bad); }, "averageFDDotV must be < 0");
    for (double bad : {0.0, -1.0, (double) INFINITY})
        expectErrorNaming([&] { integrator.setAverageFDDotFD(bad); }, "averageFDDotFD must be > 0");
    for (double bad : {0.0, -1.0})
        expectErrorNaming([&] { integrator.setAverageFRDotFR(bad); }, "averageFRDotFR must be > 0");
    EXPECT_EQ(integrator.getAverageFDDotV(), 0);  // nothing changed
    expectErrorNaming([] { DenOtterClarkeIntegrator(KT_KELVIN, 4.5, -1.0, 0.04); }, "defaultCutoff");
    expectErrorNaming([&] {
        double sumV, sumD, sumR;
        long long count;
        integrator.getMeasuredSums(sumV, sumD, sumR, count);
    }, "not bound to a Context");
}

TEST(DenOtterClarke, ContextCreationRefusesWhatTheSchemeCannotTake) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(100, 0, positions));
    auto refused = [&](DenOtterClarkeIntegrator* integrator, const std::string& why) {
        std::unique_ptr<DenOtterClarkeIntegrator> owned(integrator);
        expectErrorNaming([&] { Context context(*system, *owned, Platform::getPlatformByName("Reference")); }, why);
    };
    refused(new DenOtterClarkeIntegrator(KT_KELVIN, 4.5, 1.0, 0.04), "the averages are not set");
    DenOtterClarkeIntegrator* cold = modelB(0.04);
    cold->setTemperature(0);
    refused(cold, "temperature must be > 0 K");
    DenOtterClarkeIntegrator* tooLong = modelB(0.04);
    tooLong->setAverageFDDotFD(1000);  // alpha dt <FD.FD> > -2 m <FD.v>
    refused(tooLong, "the step size (0.04 ps) is too long");
    system->setParticleMass(7, 2.0);
    refused(modelB(0.04), "the same mass");
}

TEST(DenOtterClarke, CheckpointContinuesBitForBit) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> soft(makeFluid(500, 25, positions)), ideal(makeFluid(500, 0, positions));
    for (const std::string& platform : platforms()) {
        // On CPU, OpenMM's own nonbonded force is not bit-reproducible across a checkpoint.
        System& system = (platform == "CPU" ? *ideal : *soft);
        std::unique_ptr<DenOtterClarkeIntegrator> integrator(modelB(0.04, 0));
        auto context = makeContext(system, *integrator, platform, positions);
        expectCheckpointContinuesBitForBit(*context, *integrator, platform);
    }
}

#if OPENMMDPD_HAVE_CPU
TEST(DenOtterClarke, CpuMeasuresWhatTheReferenceMeasures) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(500, 0, positions));
    std::unique_ptr<DenOtterClarkeIntegrator> a(modelB(0.02)), b(modelB(0.02));
    auto reference = makeContext(*system, *a, "Reference", positions);
    auto cpu = makeContext(*system, *b, "CPU", positions, 2);
    a->step(20);
    b->step(20);
    double x[3], y[3];
    long long n, m;
    a->getMeasuredSums(x[0], x[1], x[2], n);
    b->getMeasuredSums(y[0], y[1], y[2], m);
    EXPECT_EQ(n, 20 * 500);
    EXPECT_EQ(m, n);
    for (int k = 0; k < 3; k++)
        EXPECT_NEAR(y[k], x[k], 1e-10 * std::fabs(x[k])) << "sum " << k;
}
#endif

} // namespace
