#include "TestHelpers.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/PairEvaluators.h"
#include "openmm/State.h"
#include "openmm/serialization/XmlSerializer.h"
#include <map>
#include <random>
#include <sstream>
#include <utility>

using namespace DPDPlugin;

namespace {

// The pairwise-sequential schemes: Shardlow S1, S2, Lowe-Andersen, pair OU (after the
// velocity-Verlet step, and in its middle).
const char* SCHEMES[] = {"S1", "S2", "Lowe", "PairOU", "Lowe-mid", "PairOU-mid"};

std::unique_ptr<DPDThermostatIntegrator> makeScheme(const std::string& scheme, double dt, int seed = 42) {
    std::unique_ptr<DPDThermostatIntegrator> integrator;
    if (scheme == "S1" || scheme == "S2") {
        ShardlowIntegrator* shardlow = new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, dt);
        shardlow->setOrder(scheme == "S1" ? 1 : 2);
        integrator.reset(shardlow);
    }
    else {
        LoweAndersenIntegrator* lowe = new LoweAndersenIntegrator(KT_KELVIN, 4.5, 1.0, dt);
        lowe->setMethod(scheme.compare(0, 4, "Lowe") == 0 ? LoweAndersenIntegrator::Lowe : LoweAndersenIntegrator::PairOrnsteinUhlenbeck);
        if (scheme.size() > 4 && scheme.compare(scheme.size() - 4, 4, "-mid") == 0)
            lowe->setSplitting(LoweAndersenIntegrator::Middle);
        integrator.reset(lowe);
    }
    integrator->setRandomNumberSeed(seed);
    return integrator;
}

void expectSameState(Context& a, Context& b, const std::string& what) {
    const State sa = a.getState(State::Positions | State::Velocities), sb = b.getState(State::Positions | State::Velocities);
    for (size_t i = 0; i < sa.getPositions().size(); i++) {
        ASSERT_EQ(sa.getPositions()[i], sb.getPositions()[i]) << what << " particle " << i;
        ASSERT_EQ(sa.getVelocities()[i], sb.getVelocities()[i]) << what << " particle " << i;
    }
}

} // namespace

// The CPU platform applies Shardlow's halves as the one kick they add up to
// (ShardlowForm::OneKick): for unequal masses, strong and weak friction and both signs of
// the noise it must give the two halves' velocities to rounding.
TEST(SweepIntegrators, ShardlowOneKickIsTheTwoHalvesToRounding) {
    std::mt19937 engine(11);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0), weight(0.0, 1.0), mass(0.5, 3.0);
    std::normal_distribution<double> normal;
    const double gamma = 4.5, sigma = std::sqrt(2 * gamma * 1.0);
    for (double h : {0.01, 0.05, 0.2}) {
        for (int trial = 0; trial < 200; trial++) {
            const std::vector<double> invMass = {1 / mass(engine), 1 / mass(engine)};
            const FreePairImpulse impulse{invMass};
            PairGeometry p{};
            p.imageVx = uniform(engine);  // as under shear: j moves with its image
            p.i = 0;
            p.j = 1;
            p.e = Vec3(uniform(engine), uniform(engine), uniform(engine));
            p.e /= std::sqrt(p.e.dot(p.e));
            const double wR = weight(engine);
            p.sigmaWR = sigma * wR;
            p.gammaWD = gamma * wR * wR;
            const double xi = normal(engine);
            const std::vector<Vec3> v0 = {Vec3(uniform(engine), uniform(engine), uniform(engine)),
                                          Vec3(uniform(engine), uniform(engine), uniform(engine))};
            std::vector<Vec3> halves = v0, oneKick = v0;
            ShardlowPairUpdate<const FreePairImpulse&, ShardlowForm::TwoHalves>(h, impulse)(p, xi, halves);
            ShardlowPairUpdate<const FreePairImpulse&, ShardlowForm::OneKick>(h, impulse)(p, xi, oneKick);
            for (int k = 0; k < 2; k++) {
                const Vec3 d = halves[k] - oneKick[k];
                ASSERT_LT(std::sqrt(d.dot(d)), 1e-14) << "h " << h << " trial " << trial << " particle " << k;
            }
        }
    }
}

TEST(SweepIntegrators, InvalidParametersNameThemselves) {
    ShardlowIntegrator shardlow(KT_KELVIN, 4.5, 1.0, 0.01);
    expectErrorNaming([&] { shardlow.setOrder(3); }, "order");
    EXPECT_EQ(shardlow.getOrder(), 1);
    LoweAndersenIntegrator lowe(KT_KELVIN, 4.5, 1.0, 0.01);
    expectErrorNaming([&] { lowe.setMethod((LoweAndersenIntegrator::Method) 7); }, "method");
    expectErrorNaming([&] { lowe.setSplitting((LoweAndersenIntegrator::Splitting) 2); }, "splitting");
    EXPECT_EQ(lowe.getSplitting(), LoweAndersenIntegrator::AfterVerlet);
    expectErrorNaming([] { LoweAndersenIntegrator(KT_KELVIN, -1, 1.0, 0.01); }, "defaultFriction");

    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(500, 0, positions));
    // Gamma dt is a probability: refused when the Context is made ...
    LoweAndersenIntegrator fast(KT_KELVIN, 20.0, 1.0, 0.1);
    expectErrorNaming([&] { Context c(*system, fast, Platform::getPlatformByName("Reference")); }, "Gamma dt");
    // ... and before a step, if the step size grew afterwards; nothing moves then.
    LoweAndersenIntegrator later(KT_KELVIN, 4.5, 1.0, 0.1);
    auto context = makeContext(*system, later, "Reference", positions);
    later.setStepSize(0.3);
    expectErrorNaming([&] { later.step(1); }, "Gamma dt");
    EXPECT_EQ(context->getState(0).getStepCount(), 0);
    // A type pair's Gamma counts too; the pair OU update has no such limit.
    LoweAndersenIntegrator typed(KT_KELVIN, 4.5, 1.0, 0.1);
    typed.addTypePair(0, 0, 11.0, 1.0);
    expectErrorNaming([&] { Context c(*system, typed, Platform::getPlatformByName("Reference")); }, "Gamma dt");
    typed.setMethod(LoweAndersenIntegrator::PairOrnsteinUhlenbeck);
    Context accepted(*system, typed, Platform::getPlatformByName("Reference"));
}

TEST(SweepIntegrators, MomentumConservedToRounding) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(500, 25, positions));
    for (const char* scheme : SCHEMES) {
        auto integrator = makeScheme(scheme, 0.04);
        auto context = makeContext(*system, *integrator, "Reference", positions);
        const Vec3 p0 = totalMomentum(*context);
        for (int step = 0; step < 50; step++) {
            integrator->step(1);
            const Vec3 d = totalMomentum(*context) - p0;
            ASSERT_LT(std::sqrt(d.dot(d)), 1e-11) << scheme << " step " << step;
        }
    }
}

TEST(SweepIntegrators, SmallBoxConservesMomentumOnTwoThreads) {
    // 2.5 nm box, cutoff 1: fewer than 3 cells per axis, too few to colour, so the sweep runs
    // in one thread even with two; this checks only that such a box steps on two threads with
    // the total momentum conserved.  (Ideal gas: the CPU platform's float forces would blur
    // the momentum check.)
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(62, 0, positions));
    for (const char* scheme : SCHEMES) {
        auto integrator = makeScheme(scheme, 0.02);
        auto context = makeContext(*system, *integrator, platforms().back(), positions, 2);
        const Vec3 p0 = totalMomentum(*context);
        integrator->step(20);
        const Vec3 d = totalMomentum(*context) - p0;
        EXPECT_LT(std::sqrt(d.dot(d)), 1e-12) << scheme;
    }
}

#if OPENMMDPD_HAVE_CPU
TEST(SweepIntegrators, SameTrajectoryOnOneOrTwoCpuThreads) {
    // No conservative force: everything is our code, so runs agree bit for bit whatever the
    // thread count (the sweep order is fixed by the geometry).  With 2000 particles (6 cells
    // a side, 2 planes per group of colours) two threads share out each colour's cells; with
    // 6912 (12 a side) each group's planes; with 20000 (over ParallelExecutor::SERIAL_LOOP_LIMIT)
    // the element-wise passes, the search's among them, run on both threads too.  CPU against
    // Reference: TestPlatformsAgree.cpp.
    for (const std::pair<int, int>& size : {std::make_pair(2000, 100), std::make_pair(6912, 20), std::make_pair(20000, 3)}) {
        const int n = size.first, steps = size.second;
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeFluid(n, 0, positions));
        for (const char* scheme : SCHEMES) {
            auto one = makeScheme(scheme, 0.05), two = makeScheme(scheme, 0.05);
            auto cOne = makeContext(*system, *one, "CPU", positions, 1);
            auto cTwo = makeContext(*system, *two, "CPU", positions, 2);
            one->step(steps);
            two->step(steps);
            expectSameState(*cOne, *cTwo, std::string(scheme) + " CPU 1 vs 2 threads, N = " + std::to_string(n));
        }
    }
}

TEST(SweepIntegrators, CpuMatchesReferenceWithForces) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(1000, 25, positions));
    for (const char* scheme : SCHEMES) {
        auto ref = makeScheme(scheme, 0.04), cpu = makeScheme(scheme, 0.04);
        auto cRef = makeContext(*system, *ref, "Reference", positions);
        auto cCpu = makeContext(*system, *cpu, "CPU", positions, 2);
        ref->step(1);
        cpu->step(1);
        const State a = cRef->getState(State::Velocities), b = cCpu->getState(State::Velocities);
        double worst = 0;
        for (size_t i = 0; i < positions.size(); i++) {
            const Vec3 d = a.getVelocities()[i] - b.getVelocities()[i];
            worst = std::max(worst, std::sqrt(d.dot(d) / a.getVelocities()[i].dot(a.getVelocities()[i])));
        }
        // The CPU platform's conservative forces are single precision.
        EXPECT_LT(worst, 1e-5) << scheme;
    }
}
#endif

// Where every pair shares its parameters (one type, one mass, no shear), the CPU pair passes
// take them as constants, four hits at a time (UniformPairBlock); give a third of the
// particles a second type with the same parameters and they go pair by pair.  Both ways must
// give the same trajectory bit for bit: the sweeps' list pass (with the native soft force
// summed in it), GW's one-pass forces and DPD-VV's and SC-VV's first pass (the soft force's
// pair forces made in the rows too) and kept-pairs passes.
TEST(SweepIntegrators, SharedParametersGiveThePerTypeTrajectoryBitForBit) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(3000, 0, positions));
    DPDSoftRepulsionForce* soft = new DPDSoftRepulsionForce(25, 1.0);
    soft->setNonbondedMethod(DPDSoftRepulsionForce::CutoffPeriodic);
    for (int i = 0; i < system->getNumParticles(); i++)
        soft->setParticleType(i, 0);
    system->addForce(soft);
    const std::map<std::string, DPDVVIntegrator::Variant> variants = {
            {"GW", DPDVVIntegrator::GrootWarren}, {"DPD-VV", DPDVVIntegrator::DPDVV}, {"SC-VV", DPDVVIntegrator::SelfConsistent}};
    for (const std::string scheme : {"S1", "S2", "Lowe", "PairOU", "GW", "DPD-VV", "SC-VV"}) {
        std::unique_ptr<DPDThermostatIntegrator> shared, typed;
        for (auto* integrator : {&shared, &typed}) {
            if (variants.count(scheme)) {
                DPDVVIntegrator* vv = new DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, 0.04);
                vv->setVariant(variants.at(scheme));
                integrator->reset(vv);
            }
            else
                *integrator = makeScheme(scheme, 0.04);
            (*integrator)->setRandomNumberSeed(42);
        }
        for (int i = 0; i < system->getNumParticles(); i += 3)
            typed->setParticleType(i, 1);
        typed->addTypePair(0, 1, 4.5, 1.0);
        typed->addTypePair(1, 1, 4.5, 1.0);
        auto a = makeContext(*system, *shared, "CPU", positions, 1);
        auto b = makeContext(*system, *typed, "CPU", positions, 1);
        shared->step(10);
        typed->step(10);
        expectSameState(*a, *b, scheme);
    }
}

TEST(SweepIntegrators, CheckpointContinuesBitForBit) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> soft(makeFluid(500, 25, positions)), ideal(makeFluid(500, 0, positions));
    for (const std::string& platform : platforms())
        for (const char* scheme : SCHEMES) {
            // On CPU, OpenMM's own nonbonded force is not bit-reproducible across a
            // checkpoint (see TestDPDVVIntegrator); our half is checked on the ideal gas.
            System* system = (platform == "CPU" ? ideal.get() : soft.get());
            auto integrator = makeScheme(scheme, 0.04, 0);
            auto context = makeContext(*system, *integrator, platform, positions);
            expectCheckpointContinuesBitForBit(*context, *integrator, platform + " " + scheme);
        }
}

TEST(SweepIntegrators, XmlRoundTrip) {
    ShardlowIntegrator shardlow(250.0, 3.5, 1.1, 0.02);
    shardlow.setOrder(2);
    shardlow.setRandomNumberSeed(5);
    shardlow.setParticleType(2, 1);
    shardlow.addTypePair(0, 1, 2.0, 0.8);
    LoweAndersenIntegrator lowe(300.0, 4.5, 0.9, 0.03);
    lowe.setMethod(LoweAndersenIntegrator::PairOrnsteinUhlenbeck);
    lowe.setIntegrationForceGroups(3);
    for (Integrator* original : std::vector<Integrator*>{&shardlow, &lowe}) {
        std::stringstream buffer;
        XmlSerializer::serialize<Integrator>(original, "Integrator", buffer);
        std::unique_ptr<Integrator> copy(XmlSerializer::deserialize<Integrator>(buffer));
        std::stringstream again;
        XmlSerializer::serialize<Integrator>(copy.get(), "Integrator", again);
        EXPECT_EQ(buffer.str(), again.str());
    }
    std::stringstream buffer;
    XmlSerializer::serialize<Integrator>(&shardlow, "Integrator", buffer);
    std::unique_ptr<Integrator> copy(XmlSerializer::deserialize<Integrator>(buffer));
    ShardlowIntegrator* c = dynamic_cast<ShardlowIntegrator*>(copy.get());
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->getOrder(), 2);
    EXPECT_EQ(c->getTemperature(), 250.0);
    EXPECT_EQ(c->getParticleType(2), 1);
    EXPECT_EQ(c->getNumTypePairs(), 1);
}

TEST(SweepIntegrators, LoweSplittingSurvivesXmlAndOldFilesReadAfterVerlet) {
    LoweAndersenIntegrator lowe(KT_KELVIN, 4.5, 1.0, 0.01);
    lowe.setSplitting(LoweAndersenIntegrator::Middle);
    std::stringstream buffer;
    XmlSerializer::serialize<Integrator>(&lowe, "Integrator", buffer);
    std::unique_ptr<Integrator> copy(XmlSerializer::deserialize<Integrator>(buffer));
    EXPECT_EQ(dynamic_cast<LoweAndersenIntegrator&>(*copy).getSplitting(), LoweAndersenIntegrator::Middle);
    // A file written before the splitting existed has no such attribute.
    std::string xml = buffer.str();
    const size_t at = xml.find(" splitting=\"1\"");
    ASSERT_NE(at, std::string::npos);
    xml.erase(at, std::string(" splitting=\"1\"").size());
    std::stringstream old(xml);
    std::unique_ptr<Integrator> read(XmlSerializer::deserialize<Integrator>(old));
    EXPECT_EQ(dynamic_cast<LoweAndersenIntegrator&>(*read).getSplitting(), LoweAndersenIntegrator::AfterVerlet);
}

TEST(SweepIntegrators, BlowUpStopsWithTheStep) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(500, 25, positions));
    for (const char* scheme : SCHEMES) {
        auto integrator = makeScheme(scheme, 2.0);
        if (std::string(scheme).compare(0, 4, "Lowe") == 0)
            integrator->setDefaultFriction(0.4);  // keep Gamma dt <= 1
        auto context = makeContext(*system, *integrator, "Reference", positions);
        try {
            integrator->step(200);
            ADD_FAILURE() << "no error for " << scheme;
        }
        catch (const OpenMMException& e) {
            EXPECT_NE(std::string(e.what()).find("blew up at step"), std::string::npos) << e.what();
        }
    }
}
