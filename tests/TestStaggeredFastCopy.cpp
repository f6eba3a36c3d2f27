// The copies of fast forces that the CPU platform's staggered integrator evaluates in a
// Context of the polymer alone (for K > 1).  A force it cannot copy costs speed silently
// (the main Context evaluates the fast groups instead), so what must copy is tested here,
// and that PolymerForceContext gives the polymer the forces the full System gives it.
#if OPENMMDPD_HAVE_CPU
#include "StaggeredTestSystems.h"
#include "openmmdpd/PolymerForceContext.h"
#include "openmm/Context.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/Platform.h"
#include "openmm/State.h"
#include "openmm/System.h"
#include "openmm/VerletIntegrator.h"
#include <gtest/gtest.h>
#include <cmath>
#include <memory>
#include <random>

using namespace DPDPlugin;
using namespace OpenMM;

#if OPENMMDPD_OPENMM_MAJOR >= 8
TEST(StaggeredFastCopy, CustomNonbondedWithComputedValuesIsCopied) {
    // Particles 1, 3, 4 are the polymer (one interaction group among them); 0, 2, 5 solvent.
    // A WCA-like force whose sigma is a computed value (OpenMM >= 8): the copy over the
    // polymer must give the polymer the forces the full System gives it.
    System full;
    std::vector<Vec3> positions;
    for (int i = 0; i < 6; i++) {
        full.addParticle(1.0);
        positions.push_back(Vec3(0.37 * i, 0.05 * (i % 2), 0.02 * i));
    }
    CustomNonbondedForce* wca = new CustomNonbondedForce("4*((s/r)^12-(s/r)^6)+1; s=0.5*(sig1+sig2)");
    wca->addPerParticleParameter("half");
    wca->addComputedValue("sig", "2*half");
    for (int i = 0; i < 6; i++)
        wca->addParticle({0.19 + 0.01 * i});
    wca->setCutoffDistance(1.5);
    wca->addInteractionGroup({1, 3, 4}, {1, 3, 4});
    full.addForce(wca);

    const std::vector<int> index = {-1, 0, -1, 1, 2, -1};
    std::unique_ptr<Force> copy(copyOverPolymer(*wca, index));
    ASSERT_NE(copy, nullptr);
    System polymer;
    for (int k = 0; k < 3; k++)
        polymer.addParticle(1.0);
    polymer.addForce(copy.release());

    Platform& reference = Platform::getPlatformByName("Reference");
    VerletIntegrator i1(0.001), i2(0.001);
    Context fullContext(full, i1, reference), polymerContext(polymer, i2, reference);
    fullContext.setPositions(positions);
    polymerContext.setPositions({positions[1], positions[3], positions[4]});
    const std::vector<Vec3> fullForce = fullContext.getState(State::Forces).getForces();
    const std::vector<Vec3> polymerForce = polymerContext.getState(State::Forces).getForces();
    for (int i = 0; i < 6; i++)
        if (index[i] >= 0) {
            EXPECT_GT(std::sqrt(fullForce[i].dot(fullForce[i])), 1.0) << "particle " << i << " feels the force";
            for (int d = 0; d < 3; d++)
                EXPECT_NEAR(polymerForce[index[i]][d], fullForce[i][d], 1e-10) << "particle " << i;
        }
}
#endif

namespace {

/**
 * 300 particles in a periodic box of 5, the first 60 a "polymer" of three 20-bead chains:
 * FENE bonds (group 1), a WCA-like force with a per-particle size and a global strength,
 * switched off from 1.0 to its cutoff 1.2, between the beads (one interaction group, bonded
 * pairs excluded; group 1), and a soft repulsion between all particles (group 0).
 */
System* makePolymerSystem(std::vector<Vec3>& positions) {
    const double box = 5;
    System* system = new System();
    system->setDefaultPeriodicBoxVectors(Vec3(box, 0, 0), Vec3(0, box, 0), Vec3(0, 0, box));
    std::mt19937 random(7);
    std::uniform_real_distribution<double> uniform(0, 1);
    CustomBondForce* fene = new CustomBondForce("-0.5*k*3^2*log(1 - (r/3)^2); k=7");
    fene->setUsesPeriodicBoundaryConditions(true);
    CustomNonbondedForce* wca = new CustomNonbondedForce("eps*4*((s/r)^12 - (s/r)^6 + 0.25); s=0.5*(sig1+sig2)");
    wca->addPerParticleParameter("sig");
    wca->addGlobalParameter("eps", 1.3);
    wca->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    wca->setCutoffDistance(1.2);
    wca->setUseSwitchingFunction(true);
    wca->setSwitchingDistance(1.0);
    CustomNonbondedForce* soft = new CustomNonbondedForce("10*(1-r)^2");
    soft->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    soft->setCutoffDistance(1.0);
    for (int i = 0; i < 300; i++) {
        system->addParticle(1.0);
        positions.push_back(Vec3(box * uniform(random), box * uniform(random), box * uniform(random)));
        wca->addParticle({0.8 + 0.2 * uniform(random)});
        soft->addParticle({});
        if (i < 60 && i % 20 != 0) {
            // chains cross the periodic boundary: positions wrapped into the box
            const Vec3 step(0.5 + 0.4 * uniform(random), 0.5 * uniform(random) - 0.25, 0.5 * uniform(random) - 0.25);
            positions[i] = positions[i - 1] + step;
            for (int d = 0; d < 3; d++)
                positions[i][d] -= box * std::floor(positions[i][d] / box);
        }
    }
    addChainForces(*system, fene, wca, 3, 20);
    system->addForce(soft);
    return system;
}

PolymerSelection firstParticles(int numPolymer, int numParticles) {
    PolymerSelection polymer;
    polymer.index.assign(numParticles, -1);
    for (int k = 0; k < numPolymer; k++) {
        polymer.particles.push_back(k);
        polymer.index[k] = k;
    }
    return polymer;
}

/** A Reference Context of `system` and the copy of its fast group (1) over the first 60 particles, the polymer. */
struct FastGroupContexts {
    explicit FastGroupContexts(System& system)
            : full(system, integrator, Platform::getPlatformByName("Reference")),
              side(PolymerForceContext::create(system, 1 << 1, firstParticles(60, 300),
                                               Platform::getPlatformByName("Reference"), {})) {}
    VerletIntegrator integrator{0.001};
    Context full;
    std::unique_ptr<PolymerForceContext> side;
};

/** Largest |fast[k] - force on particle k of the fast group in `full`| over the polymer, and the largest force. */
std::pair<double, double> differenceFromFull(Context& full, PolymerForceContext& side, const std::vector<Vec3>& positions) {
    full.setPositions(positions);
    const std::vector<Vec3> truth = full.getState(State::Forces, false, 1 << 1).getForces();
    Vec3 box[3];
    full.getState(0).getPeriodicBoxVectors(box[0], box[1], box[2]);
    std::vector<Vec3> fast;
    side.compute(positions, box, full.getParameters(), fast);
    double worst = 0, largest = 0;
    for (size_t k = 0; k < fast.size(); k++) {
        const Vec3 d = fast[k] - truth[k];
        worst = std::max(worst, std::sqrt(d.dot(d)));
        largest = std::max(largest, std::sqrt(truth[k].dot(truth[k])));
    }
    return {worst, largest};
}

} // namespace

TEST(StaggeredFastCopy, ListedPairsGiveTheFullSystemsForceOnThePolymer) {
    // Truth: the fast force group of the whole System on the Reference platform, in double
    // precision, with OpenMM's own CustomNonbondedForce kernel.  The polymer alone, with the
    // WCA as listed pairs, must give the same forces to rounding, as the beads move
    // (within the Verlet skin, and beyond it), a global parameter changes, and the box is
    // sheared and resized.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makePolymerSystem(positions));
    FastGroupContexts contexts(*system);
    ASSERT_NE(contexts.side, nullptr);
    EXPECT_TRUE(contexts.side->evaluatesListedPairs());
    std::mt19937 random(11);
    std::normal_distribution<double> gauss(0, 1);
    std::vector<Vec3> velocity(60);
    for (Vec3& v : velocity)
        v = Vec3(gauss(random), gauss(random), gauss(random));
    for (int round = 0; round < 40; round++) {
        if (round == 20)
            contexts.full.setParameter("eps", 0.7);
        if (round == 25)
            contexts.full.setPeriodicBoxVectors(Vec3(5, 0, 0), Vec3(0.4, 5, 0), Vec3(0, 0, 5));
        if (round == 30)
            contexts.full.setPeriodicBoxVectors(Vec3(5.2, 0, 0), Vec3(-0.3, 5.1, 0), Vec3(0, 0, 4.9));
        const std::pair<double, double> d = differenceFromFull(contexts.full, *contexts.side, positions);
        EXPECT_GT(d.second, 1.0) << "round " << round << ": the forces act";
        EXPECT_LT(d.first, 1e-12 * (1 + d.second)) << "round " << round;
        // Straight moves of ~0.02 per round: pairs come within the cutoff from beyond the skin
        // (0.3) over the rounds, the list is kept for a few rounds at a time and rebuilt.
        for (int i = 0; i < 60; i++)
            positions[i] += velocity[i] * 0.012;
    }
}

TEST(StaggeredFastCopy, PairInTwoInteractionGroupsIsCopiedInstead) {
    // How often a pair in two interaction groups counts is OpenMM's to say: such a force is
    // copied as it is (on the main Context's platform), not listed, and still gives the truth.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makePolymerSystem(positions));
    auto& wca = dynamic_cast<CustomNonbondedForce&>(system->getForce(1));
    wca.addInteractionGroup({0, 1, 2, 3}, {2, 3, 4, 5});
    FastGroupContexts contexts(*system);
    ASSERT_NE(contexts.side, nullptr);
    EXPECT_FALSE(contexts.side->evaluatesListedPairs());
    const std::pair<double, double> d = differenceFromFull(contexts.full, *contexts.side, positions);
    EXPECT_LT(d.first, 1e-12 * (1 + d.second));
}

#endif
