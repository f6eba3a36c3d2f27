#include "TestHelpers.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/PairMemory.h"
#include "openmm/State.h"
#include "openmm/serialization/XmlSerializer.h"
#include <sstream>

using namespace DPDPlugin;

namespace {

const EDPDIntegrator::Scheme SCHEMES[] = {EDPDIntegrator::OneSided, EDPDIntegrator::Symmetric};

EDPDIntegrator makeIntegrator(EDPDIntegrator::Scheme scheme, double alpha, double dt, int seed = 42) {
    EDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, alpha, dt);
    integrator.setScheme(scheme);
    integrator.setRandomNumberSeed(seed);
    return integrator;
}

// Two unit-mass particles in a 4 nm periodic box, no conservative force.
System* makeTwoParticles() {
    std::vector<Vec3> unused;
    System* system = makeFluid(2, 0, unused);
    system->setDefaultPeriodicBoxVectors(Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(0, 0, 4));
    return system;
}

} // namespace

TEST(EDPDIntegrator, InvalidParametersNameThemselves) {
    expectErrorNaming([] { EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 0.0, 0.01); }, "alpha");
    expectErrorNaming([] { EDPDIntegrator(KT_KELVIN, 4.5, 1.0, -2.0, 0.01); }, "alpha");
    EDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, 5.0, 0.01);
    expectErrorNaming([&] { integrator.setAlpha(std::nan("")); }, "alpha");
    expectErrorNaming([&] { integrator.setScheme((EDPDIntegrator::Scheme) 2); }, "scheme");
    expectErrorNaming([&] { integrator.setDefaultFriction(-1); }, "defaultFriction");
    EXPECT_EQ(integrator.getAlpha(), 5.0);
    EXPECT_EQ(integrator.getScheme(), EDPDIntegrator::OneSided);
    expectErrorNaming([&] { integrator.getPairVariable(0, 1); }, "Context");
}

TEST(EDPDIntegrator, MomentumConservedToRounding) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(500, 25, positions));
    for (const std::string& platform : platforms())
        for (auto scheme : SCHEMES) {
            EDPDIntegrator integrator = makeIntegrator(scheme, 5.0, 0.02);
            auto context = makeContext(*system, integrator, platform, positions);
            const Vec3 start = totalMomentum(*context);
            for (int k = 0; k < 5; k++) {
                integrator.step(10);
                const Vec3 drift = totalMomentum(*context) - start;
                // The random and auxiliary pair forces cancel exactly; the CPU platform's
                // own float forces leave ~1e-5 per particle.
                EXPECT_LT(std::sqrt(drift.dot(drift)), platform == "CPU" ? 1e-3 : 1e-10) << platform << " scheme " << scheme;
            }
        }
}

TEST(EDPDIntegrator, CpuMatchesReferenceAndThreadCountDoesNotMatter) {
#if OPENMMDPD_HAVE_CPU
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(1000, 0, positions));
    for (auto scheme : SCHEMES) {
        EDPDIntegrator ref = makeIntegrator(scheme, 2.0, 0.02), one = makeIntegrator(scheme, 2.0, 0.02),
                       two = makeIntegrator(scheme, 2.0, 0.02);
        auto cRef = makeContext(*system, ref, "Reference", positions);
        auto c1 = makeContext(*system, one, "CPU", positions, 1);
        auto c2 = makeContext(*system, two, "CPU", positions, 2);
        for (Integrator* integrator : {(Integrator*) &ref, (Integrator*) &one, (Integrator*) &two})
            integrator->step(20);
        const State sRef = cRef->getState(State::Velocities), s1 = c1->getState(State::Velocities),
                    s2 = c2->getState(State::Velocities);
        for (int i = 0; i < 1000; i++) {
            const Vec3 d1 = s1.getVelocities()[i] - sRef.getVelocities()[i], d2 = s2.getVelocities()[i] - sRef.getVelocities()[i];
            // Same pairs, same random numbers, same pair variables: only the order of the
            // per-particle sums differs between worker counts.
            ASSERT_LT(std::sqrt(d1.dot(d1)), 1e-10) << "particle " << i;
            ASSERT_LT(std::sqrt(d2.dot(d2)), 1e-10) << "particle " << i;
        }
        EXPECT_EQ(ref.getNumPairVariables(), two.getNumPairVariables());
        EXPECT_EQ(ref.getPairVariableStep(0, 1), two.getPairVariableStep(0, 1));
    }
#endif
}

TEST(EDPDIntegrator, CheckpointContinuesBitForBitWithThePairVariables) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(500, 0, positions));
    for (const std::string& platform : platforms())
        for (auto scheme : SCHEMES) {
            EDPDIntegrator integrator = makeIntegrator(scheme, 3.0, 0.03, 0);
            auto context = makeContext(*system, integrator, platform, positions);
            integrator.step(30);
            std::stringstream checkpoint;
            context->createCheckpoint(checkpoint);
            const long long stored = integrator.getNumPairVariables();
            integrator.step(30);
            const State first = context->getState(State::Positions | State::Velocities);
            std::vector<double> firstS;
            for (int j = 1; j < 500; j++)
                firstS.push_back(integrator.getPairVariable(0, j));
            // Disturb everything, pair variables included, then restore.
            context->setVelocitiesToTemperature(KT_KELVIN, 99);
            integrator.step(7);
            context->loadCheckpoint(checkpoint);
            EXPECT_EQ(integrator.getNumPairVariables(), stored);
            integrator.step(30);
            const State second = context->getState(State::Positions | State::Velocities);
            for (size_t i = 0; i < positions.size(); i++) {
                ASSERT_EQ(first.getPositions()[i], second.getPositions()[i]) << platform << " scheme " << scheme;
                ASSERT_EQ(first.getVelocities()[i], second.getVelocities()[i]) << platform << " scheme " << scheme;
            }
            for (int j = 1; j < 500; j++) {
                const double s = integrator.getPairVariable(0, j);
                if (std::isnan(firstS[j - 1]))
                    ASSERT_TRUE(std::isnan(s));
                else
                    ASSERT_EQ(firstS[j - 1], s) << "pair (0, " << j << ")";
            }
        }
}

TEST(EDPDIntegrator, XmlRoundTrip) {
    EDPDIntegrator integrator(250.0, 3.5, 1.1, 7.5, 0.02);
    integrator.setScheme(EDPDIntegrator::Symmetric);
    integrator.setRandomNumberSeed(17);
    integrator.addTypePair(1, 2, 2.5, 0.9);
    std::stringstream buffer;
    XmlSerializer::serialize<Integrator>(&integrator, "Integrator", buffer);
    std::unique_ptr<Integrator> copy(XmlSerializer::deserialize<Integrator>(buffer));
    EDPDIntegrator* c = dynamic_cast<EDPDIntegrator*>(copy.get());
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->getTemperature(), 250.0);
    EXPECT_EQ(c->getDefaultFriction(), 3.5);
    EXPECT_EQ(c->getDefaultCutoff(), 1.1);
    EXPECT_EQ(c->getAlpha(), 7.5);
    EXPECT_EQ(c->getStepSize(), 0.02);
    EXPECT_EQ(c->getScheme(), EDPDIntegrator::Symmetric);
    EXPECT_EQ(c->getRandomNumberSeed(), 17);
    EXPECT_EQ(c->getNumTypePairs(), 1);
}

// The recurrence with h constant, stepped explicitly (pairs at their cutoff, wR = 0) and
// caught up in closed form after absences, keeps the stationary variance
// docs/theory/edpd.md gives: kT lambda (symmetric) and kT lambda / (1 + alpha dt/2) (one-sided).
TEST(EDPDIntegrator, PairVariablesHeldOutOfRangeKeepTheirStationaryVariance) {
    const int numPairs = 1000;
    const double alpha = 20, dt = 0.01, friction = 4.5;
    System system;
    for (int i = 0; i < 2 * numPairs; i++)
        system.addParticle(1.0);
    std::vector<PairGeometry> held(numPairs), none;
    for (int k = 0; k < numPairs; k++)
        held[k] = PairGeometry{2 * k, 2 * k + 1, Vec3(1, 0, 0), 0.0, 0.0, 0.0, friction};
    const double lambda = alpha * friction;  // gamma = 2 mu friction = friction for unit masses
    for (auto scheme : SCHEMES) {
        EDPDIntegrator integrator(KT_KELVIN, friction, 1.0, alpha, dt);
        const bool symmetric = (scheme == EDPDIntegrator::Symmetric);
        DPDPairParameters parameters(system, integrator);
        const double kT = parameters.getKT();
        const double expected = kT * lambda / (symmetric ? 1.0 : 1 + 0.5 * alpha * dt);
        PairRandom random(1234);
        SerialExecutor executor;
        const AuxiliaryRecurrence recurrence(alpha, dt, parameters.getKT(), symmetric);
        ASSERT_NEAR(recurrence.variancePerLambda * lambda, expected, 1e-9 * expected);
        const double rho = recurrence.rho;
        // Independent samples per pair: the sum of squares of a series with correlation rho^k.
        auto relativeError = [&](double samples, int spacing) {
            const double r2 = std::pow(rho, 2.0 * spacing);
            return std::sqrt(2 / samples * (1 + r2) / (1 - r2));
        };

        // Stepped explicitly, from their first (stationary) draw on.
        PairMemory stepped(parameters, random, executor);
        std::vector<double> s;
        stepped.bind(held, 0, recurrence, s);
        double sum2 = 0;
        const int steps = 500;
        for (int step = 0; step < steps; step++) {
            stepped.advance(held, step, recurrence, s);
            for (double x : s)
                sum2 += x * x;
        }
        const double variance = sum2 / (steps * numPairs);
        EXPECT_NEAR(variance / expected, 1, 4 * relativeError((double) steps * numPairs, 1)) << "stepped, scheme " << scheme;

        // Out of range for 1..9 steps at a time, caught up in closed form on return; each
        // return must also keep the correlation rho^gap with the value at departure.
        PairMemory away(parameters, random, executor);
        away.bind(held, 0, recurrence, s);
        double returned2 = 0, cross = 0, before2 = 0;
        long long step = 0, samples = 0;
        for (int cycle = 0; cycle < 100; cycle++) {
            const int gap = 1 + cycle % 9;
            const std::vector<double> before = s;
            away.bind(none, step, recurrence, s);
            step += gap;
            away.bind(held, step, recurrence, s);
            for (int k = 0; k < numPairs; k++) {
                returned2 += s[k] * s[k];
                cross += s[k] * before[k] / std::pow(rho, gap);
                before2 += before[k] * before[k];
            }
            samples += numPairs;
        }
        EXPECT_NEAR(returned2 / samples / expected, 1, 4 * relativeError((double) samples, 1)) << "caught up, scheme " << scheme;
        // E[s_after s_before] = rho^gap E[s_before^2]: memory is kept, not redrawn.
        EXPECT_NEAR(cross / before2, 1, 0.1) << "scheme " << scheme;
    }
}

// A pair that leaves its cutoff and comes back keeps its s, decayed by rho per step away,
// plus the closed-form noise of those steps; after its memory is gone it is forgotten.
TEST(EDPDIntegrator, PairLeavingAndReenteringKeepsItsVariable) {
    std::unique_ptr<System> system(makeTwoParticles());
    const std::vector<Vec3> near = {Vec3(1, 1, 1), Vec3(1.5, 1, 1)}, far = {Vec3(1, 1, 1), Vec3(2.8, 1, 1)};
    for (const std::string& platform : platforms())
        for (int seed = 1; seed <= 5; seed++) {
            // alpha dt = 1e-6: a memory of ~10^6 steps.
            const double alpha = 1e-4, dt = 0.01, lambda = alpha * 4.5;
            EDPDIntegrator integrator = makeIntegrator(EDPDIntegrator::OneSided, alpha, dt, seed);
            auto context = makeContext(*system, integrator, platform, near);
            integrator.step(5);
            const double before = integrator.getPairVariable(0, 1);
            const long long left = integrator.getPairVariableStep(0, 1);
            EXPECT_EQ(left, 5);
            context->setPositions(far);
            integrator.step(3);
            // Archived while away: still the value of the step it left.
            EXPECT_EQ(integrator.getPairVariableStep(0, 1), left);
            EXPECT_EQ(integrator.getPairVariable(0, 1), before);
            context->setPositions(near);
            integrator.step(1);
            const double after = integrator.getPairVariable(0, 1);
            EXPECT_EQ(integrator.getPairVariableStep(0, 1), 9);
            // 4 steps of the recurrence: decay rho^4 = (1 + alpha dt)^-4, noise of variance
            // V (1 - rho^8) with V = kT lambda / (1 + alpha dt/2); plus one step's lambda dh.
            const double x = alpha * dt, rho = 1 / (1 + x);
            const double V = lambda / (1 + 0.5 * x), spread = std::sqrt(V * (1 - std::pow(rho, 8)));
            const double dh = 0.5 * 1.0 * 0.25;  // from r = rc/2 (h = -rc wR^2/2 = -1/8) at most
            EXPECT_LT(std::fabs(after - std::pow(rho, 4) * before), 5 * spread + lambda * dh) << platform << " seed " << seed;
            // A fresh draw would be N(0, V): far from `before` almost surely at this memory.
            EXPECT_GT(std::fabs(before), 3 * (5 * spread + lambda * dh)) << "seed " << seed << " tests nothing";
        }
    // With alpha dt = 1 (rho = 1/2) the memory is gone after 27 steps: the pair is dropped.
    EDPDIntegrator fast = makeIntegrator(EDPDIntegrator::OneSided, 100.0, 0.01);
    auto context = makeContext(*system, fast, "Reference", near);
    fast.step(2);
    EXPECT_EQ(fast.getNumPairVariables(), 1);
    context->setPositions(far);
    fast.step(40);
    EXPECT_EQ(fast.getNumPairVariables(), 0);
    EXPECT_TRUE(std::isnan(fast.getPairVariable(0, 1)));
}

// A pair separating by its own motion is archived at the step it leaves and brought back
// up to date at the step it returns.
TEST(EDPDIntegrator, PairMovingOutAndBackIsArchivedMeanwhile) {
    std::unique_ptr<System> system(makeTwoParticles());
    EDPDIntegrator integrator = makeIntegrator(EDPDIntegrator::OneSided, 1.0, 0.01);
    auto context = makeContext(*system, integrator, "Reference", {Vec3(1, 1, 1), Vec3(1.5, 1, 1)});
    // Apart at 2 nm/ps relative: out of range after ~25 steps, back (through the periodic
    // image, 4 nm box) after ~250.
    context->setVelocities({Vec3(-1, 0, 0), Vec3(1, 0, 0)});
    long long left = -1, returned = -1;
    for (int step = 1; step <= 300 && returned < 0; step++) {
        integrator.step(1);
        const long long at = integrator.getPairVariableStep(0, 1);
        ASSERT_GE(at, 0) << "forgotten at step " << step;
        if (at != step) {
            // Away: the value stays that of the step it left (its last update).
            if (left < 0)
                left = at;
            ASSERT_EQ(at, left) << "step " << step;
        }
        else if (left >= 0)
            returned = step;
    }
    EXPECT_GT(left, 10);
    EXPECT_GT(returned, left + 100);
}

// Context.setStepCount() renumbers the steps; the pair variables, in range or archived, keep
// their values (a redraw would be far from them at this memory of ~10^6 steps).
TEST(EDPDIntegrator, SetStepCountKeepsThePairVariables) {
    std::unique_ptr<System> system(makeTwoParticles());
    const std::vector<Vec3> near = {Vec3(1, 1, 1), Vec3(1.5, 1, 1)}, far = {Vec3(1, 1, 1), Vec3(2.8, 1, 1)};
    for (const std::string& platform : platforms()) {
        EDPDIntegrator integrator = makeIntegrator(EDPDIntegrator::OneSided, 1e-4, 0.01, 3);
        auto context = makeContext(*system, integrator, platform, near);
        integrator.step(5);
        const double inRange = integrator.getPairVariable(0, 1);
        context->setStepCount(1000);
        integrator.step(1);
        EXPECT_EQ(integrator.getPairVariableStep(0, 1), 1001) << platform;
        EXPECT_LT(std::fabs(integrator.getPairVariable(0, 1) - inRange), 0.1 * std::fabs(inRange)) << platform;
        context->setPositions(far);
        integrator.step(1);
        const double archived = integrator.getPairVariable(0, 1);
        const long long archivedStep = integrator.getPairVariableStep(0, 1);
        context->setStepCount(50);
        EXPECT_NO_THROW(integrator.step(2)) << platform;
        EXPECT_EQ(integrator.getPairVariableStep(0, 1), archivedStep + 50 - 1002) << platform;
        EXPECT_EQ(integrator.getPairVariable(0, 1), archived) << platform;
    }
}
