#include "StaggeredTestSystems.h"
#include "TestHelpers.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/CMAPTorsionForce.h"
#include "openmm/CMMotionRemover.h"
#include "openmm/CustomAngleForce.h"
#include "openmm/CustomBondForce.h"
#include "openmm/CustomCentroidBondForce.h"
#include "openmm/CustomCompoundBondForce.h"
#include "openmm/CustomExternalForce.h"
#include "openmm/CustomHbondForce.h"
#include "openmm/CustomNonbondedForce.h"
#include "openmm/CustomTorsionForce.h"
#include "openmm/HarmonicAngleForce.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/PeriodicTorsionForce.h"
#include "openmm/RBTorsionForce.h"
#include "openmm/State.h"
#include "openmm/serialization/XmlSerializer.h"
#include <algorithm>
#include <iostream>
#include <sstream>

using namespace DPDPlugin;

namespace {

const int CHAINS = 4;

/**
 * The fene-chains scene in small: a soft DPD fluid (a = 18.75, or the ideal gas with a = 0)
 * of n particles, the first CHAINS * m of which are straight chains with FENE bonds
 * (k = 7, rmax = 3) and WCA between beads, both in force group 1.
 */
System* makeChains(int n, int m, double a, std::vector<Vec3>& positions) {
    System* system = makeFluid(n, 0, positions);
    // The plugin's soft force: double precision on both platforms, like the scenes use.
    if (a > 0) {
        DPDSoftRepulsionForce* soft = new DPDSoftRepulsionForce(a, 1.0);
        soft->setNonbondedMethod(DPDSoftRepulsionForce::CutoffPeriodic);
        system->addForce(soft);
    }
    const double box = std::cbrt(n / 4.0);
    CustomBondForce* fene = new CustomBondForce("-k*rmax^2*log(sqrt(1 - (r/rmax)^2)); k=7; rmax=3");
    fene->setUsesPeriodicBoundaryConditions(true);
    CustomNonbondedForce* wca = new CustomNonbondedForce("4*((l/r)^12 - (l/r)^6 + 0.25); l=0.8908987181403393");
    wca->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    wca->setCutoffDistance(1.0);
    for (int i = 0; i < n; i++)
        wca->addParticle({});
    for (int c = 0; c < CHAINS; c++)
        for (int k = 0; k < m; k++)
            positions[c * m + k] = Vec3(0.2 + 0.97 * k, 0.3 + 0.5 * box * (c % 2), 0.4 + 0.5 * box * (c / 2));
    addChainForces(*system, fene, wca, CHAINS, m);
    return system;
}

/**
 * makeChains with the WCA written as a CustomBondForce over every pair of beads that are not
 * bonded: the same forces, but every force in double precision on the CPU platform too
 * (OpenMM's CPU CustomNonbondedForce is single precision), so that CPU and Reference can be
 * compared to double rounding.
 */
System* makeDoubleChains(int n, int m, double a, std::vector<Vec3>& positions) {
    System* system = makeChains(n, m, a, positions);
    system->removeForce(system->getNumForces() - 1);
    CustomBondForce* wca = new CustomBondForce("step(1-r)*4*((l/r)^12 - (l/r)^6 + 0.25); l=0.8908987181403393");
    wca->setUsesPeriodicBoundaryConditions(true);
    for (int i = 0; i < CHAINS * m; i++)
        for (int j = i + 2; j < CHAINS * m; j++)
            wca->addBond(i, j, {});
    for (int i = 0; i + 1 < CHAINS * m; i++)
        if ((i + 1) % m == 0)
            wca->addBond(i, i + 1, {});  // last bead of a chain and first of the next: not bonded
    wca->setForceGroup(1);
    system->addForce(wca);
    return system;
}

std::unique_ptr<StaggeredDPDIntegrator> makeStaggered(StaggeredDPDIntegrator::BaseScheme base, double dt, int k, int seed = 42) {
    std::unique_ptr<StaggeredDPDIntegrator> integrator(new StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, dt, k));
    integrator->setBaseScheme(base);
    integrator->useRecommendedParameters();
    integrator->setRandomNumberSeed(seed);
    return integrator;
}

const StaggeredDPDIntegrator::BaseScheme BASES[] = {StaggeredDPDIntegrator::VelocityVerlet, StaggeredDPDIntegrator::LoweAndersen};

State runState(System& system, Integrator& integrator, const std::string& platform, const std::vector<Vec3>& positions, int steps) {
    auto context = makeContext(system, integrator, platform, positions);
    integrator.step(steps);
    return context->getState(State::Positions | State::Velocities);
}

double maxComponentDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double worst = 0;
    for (size_t i = 0; i < a.size(); i++)
        for (int d = 0; d < 3; d++)
            worst = std::max(worst, std::fabs(a[i][d] - b[i][d]));
    return worst;
}

} // namespace

TEST(StaggeredIntegrator, InvalidParametersNameThemselves) {
    expectErrorNaming([] { StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, 0.01, 0); }, "numSubSteps");
    StaggeredDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01, 5);
    expectErrorNaming([&] { integrator.setNumSubSteps(0); }, "numSubSteps");
    expectErrorNaming([&] { integrator.setMu(1.5); }, "mu");
    expectErrorNaming([&] { integrator.setA(-1.01); }, "a must be");
    expectErrorNaming([&] { integrator.setB(2); }, "b must be");
    expectErrorNaming([&] { integrator.setRelaxationParameters(0, 0, NAN); }, "b must be");
    expectErrorNaming([&] { integrator.setLambda(1.1); }, "lambda");
    expectErrorNaming([&] { integrator.setFastForceGroups(0); }, "fastForceGroups");
    expectErrorNaming([&] { integrator.setBaseScheme((StaggeredDPDIntegrator::BaseScheme) 4); }, "baseScheme");
    expectErrorNaming([&] { integrator.addPolymerParticle(-1); }, "polymer particle");
    // Nothing changed; the defaults are Symeonidis and Karniadakis' (2006)
    // recommendation for the vV base.
    EXPECT_EQ(integrator.getNumSubSteps(), 5);
    EXPECT_EQ(integrator.getMu(), 0.0);
    EXPECT_EQ(integrator.getA(), 0.6);
    EXPECT_EQ(integrator.getB(), 0.0);
    EXPECT_EQ(integrator.getLambda(), 0.65);
    EXPECT_TRUE(integrator.getWeighted());
    EXPECT_EQ(integrator.getFastForceGroups(), 2);
    EXPECT_DOUBLE_EQ(integrator.getSubStepSize(), 0.002);
    integrator.setBaseScheme(StaggeredDPDIntegrator::LoweAndersen);
    EXPECT_EQ(integrator.getA(), 0.6);  // setBaseScheme changes nothing else
    integrator.useRecommendedParameters();
    EXPECT_EQ(integrator.getA(), 0.0);
    EXPECT_EQ(integrator.getB(), 0.4);

    std::vector<Vec3> positions;
    std::unique_ptr<System> chains(makeChains(500, 5, 18.75, positions));
    Platform& reference = Platform::getPlatformByName("Reference");
    // No force in the fast groups.
    StaggeredDPDIntegrator none(KT_KELVIN, 4.5, 1.0, 0.01, 5);
    none.setFastForceGroups(1 << 4);
    expectErrorNaming([&] { Context c(*chains, none, reference); }, "no force of the System is in a fast force group");
    // Fast groups outside the integration groups.
    StaggeredDPDIntegrator outside(KT_KELVIN, 4.5, 1.0, 0.01, 5);
    outside.setIntegrationForceGroups(1);
    expectErrorNaming([&] { Context c(*chains, outside, reference); }, "subset of the integration force groups");
    // Gamma Dt is a probability with the Lowe base.
    StaggeredDPDIntegrator lowe(KT_KELVIN, 20, 1.0, 0.1, 5);
    lowe.setBaseScheme(StaggeredDPDIntegrator::LoweAndersen);
    expectErrorNaming([&] { Context c(*chains, lowe, reference); }, "Gamma Dt");
    // A polymer particle that is not in the System.
    StaggeredDPDIntegrator beyond(KT_KELVIN, 4.5, 1.0, 0.01, 5);
    beyond.addPolymerParticle(500);
    expectErrorNaming([&] { Context c(*chains, beyond, reference); }, "polymer particle 500");
    // A fast force that acts on every particle gives no polymer to derive.
    std::vector<Vec3> fluidPositions;
    std::unique_ptr<System> fluid(makeFluid(500, 18.75, fluidPositions));
    fluid->getForce(0).setForceGroup(1);
    StaggeredDPDIntegrator everything(KT_KELVIN, 4.5, 1.0, 0.01, 5);
    expectErrorNaming([&] { Context c(*fluid, everything, reference); }, "without interaction groups");
    // An explicit polymer list that leaves out a particle of a FENE bond (bond 3: beads 3-4).
    StaggeredDPDIntegrator partial(KT_KELVIN, 4.5, 1.0, 0.01, 5);
    partial.setPolymerParticles({0, 1, 2, 3});
    expectErrorNaming([&] { Context c(*chains, partial, reference); }, "particle 4 is in bond 3 of CustomBondForce (force 2, group 1)");
}

TEST(StaggeredIntegrator, PolymerParticlesDerivedFromFastForces) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeChains(500, 5, 18.75, positions));
    StaggeredDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01, 5);
    std::vector<int> expected(CHAINS * 5);
    for (int i = 0; i < CHAINS * 5; i++)
        expected[i] = i;
    EXPECT_EQ(integrator.findPolymerParticles(*system), expected);
    // Bonds of a HarmonicBondForce in a fast group count too.
    HarmonicBondForce* extra = new HarmonicBondForce();
    extra->addBond(100, 101, 0, 7);
    extra->setForceGroup(2);
    system->addForce(extra);
    integrator.setFastForceGroups(2 | 4);
    expected.push_back(100);
    expected.push_back(101);
    EXPECT_EQ(integrator.findPolymerParticles(*system), expected);
    // Every kind of bonded force counts its terms' particles.
    HarmonicAngleForce* angle = new HarmonicAngleForce();
    angle->addAngle(200, 201, 202, 2, 1);
    CustomAngleForce* customAngle = new CustomAngleForce("0");
    customAngle->addAngle(203, 204, 205, {});
    PeriodicTorsionForce* periodic = new PeriodicTorsionForce();
    periodic->addTorsion(210, 211, 212, 213, 1, 0, 1);
    RBTorsionForce* rb = new RBTorsionForce();
    rb->addTorsion(214, 215, 216, 217, 0, 0, 0, 0, 0, 0);
    CustomTorsionForce* customTorsion = new CustomTorsionForce("0");
    customTorsion->addTorsion(218, 219, 220, 221, {});
    CustomCompoundBondForce* compound = new CustomCompoundBondForce(2, "0");
    compound->addBond({230, 231}, {});
    CMAPTorsionForce* cmap = new CMAPTorsionForce();
    cmap->addMap(2, {0, 0, 0, 0});
    cmap->addTorsion(0, 240, 241, 242, 243, 244, 245, 246, 247);
    // A centroid bond acts on the particles of the groups it joins, not on those of group 2.
    CustomCentroidBondForce* centroid = new CustomCentroidBondForce(2, "distance(g1, g2)");
    centroid->addGroup({250, 251});
    centroid->addGroup({252});
    centroid->addGroup({253});
    centroid->addBond({0, 1}, {});
    CustomExternalForce* external = new CustomExternalForce("x");
    external->addParticle(260, {});
    CustomHbondForce* hbond = new CustomHbondForce("distance(d1, a1)");
    hbond->addDonor(270, 271, -1, {});
    hbond->addAcceptor(272, -1, -1, {});
    for (Force* force : std::vector<Force*>{angle, customAngle, periodic, rb, customTorsion, compound, cmap, centroid, external, hbond}) {
        force->setForceGroup(3);
        system->addForce(force);
    }
    integrator.setFastForceGroups(2 | 4 | 8);
    for (int i : {200, 201, 202, 203, 204, 205, 210, 211, 212, 213, 214, 215, 216, 217, 218, 219, 220, 221, 230, 231, 240, 241,
                  242, 243, 244, 245, 246, 247, 250, 251, 252, 260, 270, 271, 272})
        expected.push_back(i);
    EXPECT_EQ(integrator.findPolymerParticles(*system), expected);
    EXPECT_TRUE(integrator.fastForcesListTheirParticles(*system));
    // A force it cannot see into asks for the explicit list.
    CMMotionRemover* remover = new CMMotionRemover();
    remover->setForceGroup(3);
    system->addForce(remover);
    EXPECT_FALSE(integrator.fastForcesListTheirParticles(*system));
    expectErrorNaming([&] { integrator.findPolymerParticles(*system); }, "cannot tell which particles");
    // The explicit list wins: it may hold more than the fast forces' particles, in any order.
    std::vector<int> explicitList(expected.rbegin(), expected.rend());
    explicitList.push_back(7);
    explicitList.push_back(400);
    integrator.setPolymerParticles(explicitList);
    expected.push_back(400);
    std::sort(expected.begin(), expected.end());
    EXPECT_EQ(integrator.findPolymerParticles(*system), expected);
}

namespace {

/**
 * A chain at rest, where only a check of the bonds' particles finds beads left out of the
 * polymer list: beads 0-4 a chain of HarmonicBondForce (group 1, force 1) at its rest
 * length 0.7, so that the fast force on every bead is zero at the start, in a soft fluid of
 * n particles.
 */
System* makeRestingChain(int n, std::vector<Vec3>& positions) {
    System* system = makeFluid(n, 18.75, positions);
    HarmonicBondForce* bonds = new HarmonicBondForce();
    bonds->setUsesPeriodicBoundaryConditions(true);
    for (int i = 0; i < 5; i++) {
        positions[i] = Vec3(0.3 + 0.7 * i, 1.0, 1.0);
        if (i > 0)
            bonds->addBond(i - 1, i, 0.7, 500);
    }
    bonds->setForceGroup(1);
    system->addForce(bonds);
    return system;
}

/** A fast force (group 1) whose terms act on particles 10-13, and what an error about particle 13 says. */
struct FastForceCase {
    std::function<Force*(int n)> make;
    std::string named;  // the error when particle 13 is left out
};

std::vector<FastForceCase> fastForceCases() {
    return {
        {[](int) {
             HarmonicAngleForce* angle = new HarmonicAngleForce();
             angle->addAngle(10, 11, 12, 2, 10);
             angle->addAngle(11, 12, 13, 2, 10);
             return angle;
         }, "particle 13 is in angle 1 of HarmonicAngleForce (force 1, group 1)"},
        {[](int) {
             CustomCompoundBondForce* compound = new CustomCompoundBondForce(3, "distance(p1, p3) + angle(p1, p2, p3)");
             compound->addBond({10, 11, 12}, {});
             compound->addBond({11, 12, 13}, {});
             compound->setName("Stiffness");
             return compound;
         }, "particle 13 is in bond 1 of CustomCompoundBondForce \"Stiffness\" (force 1, group 1)"},
        {[](int n) {
             CustomNonbondedForce* wca = new CustomNonbondedForce("(0.8/r)^12");
             wca->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
             wca->setCutoffDistance(1.0);
             for (int i = 0; i < n; i++)
                 wca->addParticle({});
             wca->addInteractionGroup({10, 11}, {10, 11});
             wca->addInteractionGroup({10, 11}, {12, 13});
             return wca;
         }, "particle 13 is in interaction group 1 of CustomNonbondedForce (force 1, group 1)"},
        {[](int) {
             CustomCentroidBondForce* centroid = new CustomCentroidBondForce(2, "distance(g1, g2)^2");
             centroid->addGroup({10, 11});
             centroid->addGroup({12, 13});
             centroid->addBond({0, 1}, {});
             return centroid;
         }, "particle 13 is in bond 0 of CustomCentroidBondForce (force 1, group 1)"},
        {[](int) {
             CustomExternalForce* external = new CustomExternalForce("x^2");
             for (int i = 10; i <= 13; i++)
                 external->addParticle(i, {});
             return external;
         }, "particle 13 is in particle entry 3 of CustomExternalForce (force 1, group 1)"},
    };
}

} // namespace

TEST(StaggeredIntegrator, PolymerListMissingABondedBeadRaisesAtContextCreation) {
    // Bonds at rest give no fast force at the start: only a check of the bonds' particles
    // sees beads 3 and 4 left out (a run would drop the bond force on them).
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeRestingChain(200, positions));
    for (const std::string& platform : platforms()) {
        StaggeredDPDIntegrator partial(KT_KELVIN, 4.5, 1.0, 0.01, 3);
        partial.setPolymerParticles({0, 1, 2});
        expectErrorNaming([&] { Context c(*system, partial, Platform::getPlatformByName(platform)); },
                          "StaggeredDPDIntegrator: particle 3 is in bond 2 of HarmonicBondForce (force 1, group 1) but not "
                          "in the polymer particles");
        // The whole chain: builds and runs with the total momentum conserved (every force is a
        // pair force).  Measured drift over 100 steps: 2e-14 (Reference), 1e-6 to 3e-6 (CPU,
        // whose CustomNonbondedForce is single precision); with the bond force on beads 3 and 4
        // dropped (the check disabled, list {0, 1, 2}) it is 4 to 11.
        StaggeredDPDIntegrator whole(KT_KELVIN, 4.5, 1.0, 0.01, 3);
        whole.setPolymerParticles({4, 3, 2, 1, 0});
        auto context = makeContext(*system, whole, platform, positions);
        const Vec3 before = totalMomentum(*context);
        whole.step(100);
        const Vec3 drift = totalMomentum(*context) - before;
        EXPECT_LT(std::sqrt(drift.dot(drift)), platform == "Reference" ? 1e-9 : 1e-4) << platform;
    }
}

TEST(StaggeredIntegrator, PolymerListMissingAParticleOfAnyFastForceRaises) {
    std::vector<Vec3> positions;
    for (const FastForceCase& fast : fastForceCases()) {
        std::unique_ptr<System> system(makeFluid(200, 18.75, positions));
        Force* force = fast.make(200);
        force->setForceGroup(1);
        system->addForce(force);
        StaggeredDPDIntegrator partial(KT_KELVIN, 4.5, 1.0, 0.01, 3);
        partial.setPolymerParticles({10, 11, 12});
        expectErrorNaming([&] { Context c(*system, partial, Platform::getPlatformByName("Reference")); }, fast.named);
        StaggeredDPDIntegrator whole(KT_KELVIN, 4.5, 1.0, 0.01, 3);
        whole.setPolymerParticles({10, 11, 12, 13});
        EXPECT_NO_THROW(Context(*system, whole, Platform::getPlatformByName("Reference"))) << fast.named;
    }
}

TEST(StaggeredIntegrator, PolymerListCheckedAgainWhenItOrTheContextChanges) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeRestingChain(200, positions));
    const std::string missing = "particle 3 is in bond 2 of HarmonicBondForce";
    for (const std::string& platform : platforms()) {
        StaggeredDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01, 3);
        integrator.setPolymerParticles({0, 1, 2, 3, 4});
        auto context = makeContext(*system, integrator, platform, positions);
        integrator.step(2);
        // A new list on the live Context is checked at the next step, before anything moves.
        integrator.setPolymerParticles({0, 1, 2});
        expectErrorNaming([&] { integrator.step(1); }, missing);
        EXPECT_EQ(context->getState(0).getStepCount(), 2) << platform;
        integrator.setPolymerParticles({0, 1, 2, 3, 4});
        integrator.step(1);
        // And again when the Context is reinitialized.
        integrator.setPolymerParticles({0, 1, 2});
        expectErrorNaming([&] { context->reinitialize(true); }, missing);
    }
}

TEST(StaggeredIntegrator, FastForceWithoutParticleListIsCheckedAtEveryEvaluation) {
    // A CustomNonbondedForce without interaction groups lists no particles, so an explicit
    // list cannot be checked when the Context is made.  This one joins polymer bead 0 to
    // solvent particle 5 by a spring of stiffness k: zero through the first step (k = 0: at
    // its rest length it was not zero to rounding on every platform and processor), non-zero
    // in the second.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(200, 18.75, positions));
    CustomNonbondedForce* spring = new CustomNonbondedForce("k*f1*f2*(r-0.5)^2");
    spring->addGlobalParameter("k", 0);
    spring->addPerParticleParameter("f");
    spring->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    spring->setCutoffDistance(1.0);
    for (int i = 0; i < 200; i++)
        spring->addParticle({i == 0 || i == 5 ? 1.0 : 0.0});
    spring->setForceGroup(1);
    system->addForce(spring);
    positions[0] = Vec3(1, 1, 1);
    positions[5] = Vec3(1.5, 1, 1);
    for (const std::string& platform : platforms()) {
        StaggeredDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01, 3);
        integrator.setPolymerParticles({0, 1, 2, 3, 4});
        EXPECT_FALSE(integrator.fastForcesListTheirParticles(*system));
        auto context = makeContext(*system, integrator, platform, positions);
        integrator.step(1);
        context->setParameter("k", 100);
        expectErrorNaming([&] { integrator.step(1); }, "at step 1 the fast forces act on particle 5, which is not a polymer particle");
    }
}

TEST(StaggeredIntegrator, OneSubStepIsTheBaseIntegrator) {
    // K = 1 with (mu, a, b) = (0, 0, 1) is Groot-Warren velocity Verlet, or velocity Verlet
    // followed by Lowe-Andersen, step for step with the same random numbers.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeChains(500, 5, 18.75, positions));
    for (const std::string& platform : platforms()) {
        DPDVVIntegrator gw(KT_KELVIN, 4.5, 1.0, 0.01);
        gw.setLambda(0.65);
        gw.setRandomNumberSeed(42);
        LoweAndersenIntegrator lowe(KT_KELVIN, 4.5, 1.0, 0.01);
        lowe.setRandomNumberSeed(42);
        for (auto base : BASES) {
            auto staggered = makeStaggered(base, 0.01, 1);
            staggered->setRelaxationParameters(0, 0, 1);
            Integrator& reference = (base == StaggeredDPDIntegrator::VelocityVerlet ? (Integrator&) gw : (Integrator&) lowe);
            State expected = runState(*system, reference, platform, positions, 20);
            State actual = runState(*system, *staggered, platform, positions, 20);
            // positions ~ 5 nm, velocities ~ 1 nm/ps
            EXPECT_LE(maxComponentDifference(expected.getPositions(), actual.getPositions()), 5e-12) << platform << " base " << base;
            EXPECT_LE(maxComponentDifference(expected.getVelocities(), actual.getVelocities()), 1e-12) << platform << " base " << base;
            EXPECT_EQ(actual.getStepCount(), 20);
            EXPECT_NEAR(actual.getTime(), 0.2, 1e-12);
        }
    }
}

TEST(StaggeredIntegrator, MomentumConservedToRounding) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeChains(500, 5, 18.75, positions));
    // Reference: double-precision forces (the CPU platform's WCA is single precision, whose
    // pair forces do not cancel to double rounding).
    for (const std::string platform : {"Reference"})
        for (auto base : BASES)
            for (bool weighted : {true, false}) {
                auto integrator = makeStaggered(base, 0.01, 5);
                integrator->setWeighted(weighted);
                auto context = makeContext(*system, *integrator, platform, positions);
                auto momentum = [&] {
                    Vec3 p;
                    const State state = context->getState(State::Velocities);
                    for (const Vec3& v : state.getVelocities())
                        p += v;
                    return p;
                };
                const Vec3 before = momentum();
                integrator->step(50);
                const Vec3 change = momentum() - before;
                EXPECT_LT(std::sqrt(change.dot(change)), 1e-10) << platform << " base " << base << " weighted " << weighted;
            }
}

TEST(StaggeredIntegrator, SolventTakesOneStepPerOuterStep) {
    // The sub-steps move the polymer only: after one outer step the solvent's positions
    // (Dt u + Dt^2/(2m) F) and velocities (F^ is evaluated at the predicted polymer
    // positions, which do not depend on K) are the same whatever K is -- to rounding, since
    // K = 1 evaluates the soft force from the thermostat's pair list and K > 1 in a Context
    // without the fast forces, which sum it in another order.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeChains(500, 5, 18.75, positions));
    std::vector<State> states;
    for (int k : {1, 2, 5}) {
        auto integrator = makeStaggered(StaggeredDPDIntegrator::VelocityVerlet, 0.01, k);
        auto context = makeContext(*system, *integrator, "Reference", positions);
        integrator->step(1);
        states.push_back(context->getState(State::Positions | State::Velocities));
    }
    for (size_t s = 1; s < states.size(); s++)
        for (int i = CHAINS * 5; i < 500; i++) {
            const Vec3 dr = states[0].getPositions()[i] - states[s].getPositions()[i];
            const Vec3 dv = states[0].getVelocities()[i] - states[s].getVelocities()[i];
            ASSERT_LT(std::sqrt(dr.dot(dr)), 1e-12) << "solvent particle " << i;
            ASSERT_LT(std::sqrt(dv.dot(dv)), 1e-12) << "solvent particle " << i;
        }
    // ... while the polymer did take different paths.
    EXPECT_NE(states[0].getPositions()[0], states[2].getPositions()[0]);
}

TEST(StaggeredIntegrator, CheckpointContinuesBitForBit) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> soft(makeChains(500, 5, 18.75, positions)), ideal(makeChains(500, 5, 0, positions));
    for (const std::string& platform : platforms())
        for (auto base : BASES) {
            // As for DPDVVIntegrator: on CPU the soft force's summation order depends on when
            // its neighbour list was built, so there the solvent is the ideal gas.
            System* system = (platform == "CPU" ? ideal.get() : soft.get());
            auto integrator = makeStaggered(base, 0.01, 5, 0);
            std::map<std::string, std::string> properties;
            if (platform == "CPU")
                properties["DeterministicForces"] = "true";
            Context context(*system, *integrator, Platform::getPlatformByName(platform), properties);
            context.setPositions(positions);
            context.setVelocitiesToTemperature(KT_KELVIN, 11);
            expectCheckpointContinuesBitForBit(context, *integrator, platform + " base " + std::to_string(base));
        }
}

TEST(StaggeredIntegrator, XmlRoundTrip) {
    StaggeredDPDIntegrator integrator(250.0, 3.5, 1.0, 0.02, 7);
    integrator.setBaseScheme(StaggeredDPDIntegrator::LoweAndersen);
    integrator.setRelaxationParameters(-0.5, 0.25, 0.4);
    integrator.setLambda(0.55);
    integrator.setWeighted(false);
    integrator.setFastForceGroups(6);
    integrator.setPolymerParticles({4, 2, 9});
    integrator.setRandomNumberSeed(17);
    std::stringstream buffer;
    XmlSerializer::serialize<Integrator>(&integrator, "Integrator", buffer);
    std::unique_ptr<Integrator> copy(XmlSerializer::deserialize<Integrator>(buffer));
    StaggeredDPDIntegrator* c = dynamic_cast<StaggeredDPDIntegrator*>(copy.get());
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->getStepSize(), 0.02);
    EXPECT_EQ(c->getNumSubSteps(), 7);
    EXPECT_EQ(c->getBaseScheme(), StaggeredDPDIntegrator::LoweAndersen);
    EXPECT_EQ(c->getMu(), -0.5);
    EXPECT_EQ(c->getA(), 0.25);
    EXPECT_EQ(c->getB(), 0.4);
    EXPECT_EQ(c->getLambda(), 0.55);
    EXPECT_FALSE(c->getWeighted());
    EXPECT_EQ(c->getFastForceGroups(), 6);
    EXPECT_EQ(c->getPolymerParticles(), std::vector<int>({4, 2, 9}));
    EXPECT_EQ(c->getRandomNumberSeed(), 17);
}

TEST(StaggeredIntegrator, FeneBeyondRmaxStopsWithTheStep) {
    // Two bonded beads pulled apart faster than FENE can hold them: past rmax the force is
    // NaN, and the step must say so instead of carrying it on.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeChains(500, 5, 0, positions));
    for (const std::string& platform : platforms())
        for (auto base : BASES) {
            auto integrator = makeStaggered(base, 0.01, 5);
            auto context = makeContext(*system, *integrator, platform, positions);
            std::vector<Vec3> velocities = context->getState(State::Velocities).getVelocities();
            velocities[0] = Vec3(-150, 0, 0);
            velocities[1] = Vec3(150, 0, 0);
            context->setVelocities(velocities);
            try {
                integrator->step(100);
                FAIL() << "no error on " << platform;
            }
            catch (const OpenMMException& e) {
                const std::string message = e.what();
                EXPECT_NE(message.find("blew up at step"), std::string::npos) << message;
                EXPECT_LT(context->getState(0).getStepCount(), 100);
            }
        }
}

#if OPENMMDPD_HAVE_CPU
TEST(StaggeredIntegrator, SideContextsMatchTheFullContext) {
    // On the CPU platform, for K > 1 the fast forces come from a Context of the polymer alone
    // and the slow ones from a Context without the fast forces.  A fast force that cannot be
    // copied (here an empty HarmonicAngleForce) makes the integrator evaluate everything in
    // the Context itself: the two must follow the same trajectory, to rounding.  (Reference
    // always evaluates in the Context itself.)
    std::vector<Vec3> positions;
    std::unique_ptr<System> copyable(makeChains(500, 5, 18.75, positions));
    std::unique_ptr<System> fallback(makeChains(500, 5, 18.75, positions));
    HarmonicAngleForce* angles = new HarmonicAngleForce();
    angles->setForceGroup(1);
    fallback->addForce(angles);
    for (auto base : BASES) {
        auto a = makeStaggered(base, 0.01, 5), b = makeStaggered(base, 0.01, 5);
        State sa = runState(*copyable, *a, "CPU", positions, 10);
        State sb = runState(*fallback, *b, "CPU", positions, 10);
        EXPECT_LE(maxComponentDifference(sa.getPositions(), sb.getPositions()), 1e-11) << "base " << base;
        EXPECT_LE(maxComponentDifference(sa.getVelocities(), sb.getVelocities()), 1e-10) << "base " << base;
        EXPECT_GT(maxComponentDifference(sa.getPositions(), positions), 0.01);
    }
}
#endif

#if OPENMMDPD_HAVE_CPU
namespace {

/** max over particles of |a_i - b_i| / (1 + |b_i|): relative for large values, absolute near 0. */
double maxRelativeDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double worst = 0;
    for (size_t i = 0; i < a.size(); i++) {
        const Vec3 d = a[i] - b[i];
        worst = std::max(worst, std::sqrt(d.dot(d)) / (1 + std::sqrt(b[i].dot(b[i]))));
    }
    return worst;
}

/**
 * Folds makeChains' straight chains into zigzags (bonds 0.92, beads k and k + 2 0.9 apart),
 * so that the WCA acts from the first step.
 */
void foldChains(int m, std::vector<Vec3>& positions) {
    for (int c = 0; c < CHAINS; c++)
        for (int k = 0; k < m; k++)
            positions[c * m + k] += Vec3(-0.52 * k, 0.8 * (k % 2), 0);
}

/**
 * Runs the scheme on Reference and on CPU with 1 and 2 threads side by side (Dt = 0.02), and
 * returns the largest relative difference of CPU from Reference in positions and velocities
 * after 1, 3 and 20 outer steps.
 */

std::vector<double> cpuAgainstReference(System& system, const std::vector<Vec3>& positions, StaggeredDPDIntegrator::BaseScheme base,
                                        int k, bool weighted) {
    std::vector<std::unique_ptr<StaggeredDPDIntegrator>> integrators;
    std::vector<std::unique_ptr<Context>> contexts;
    for (int threads : {0, 1, 2}) {
        integrators.push_back(makeStaggered(base, 0.02, k));
        integrators.back()->setWeighted(weighted);
        contexts.push_back(makeContext(system, *integrators.back(), threads == 0 ? "Reference" : "CPU", positions, threads));
    }
    std::vector<double> differences;
    int done = 0;
    for (int steps : {1, 3, 20}) {
        for (auto& integrator : integrators)
            integrator->step(steps - done);
        done = steps;
        const State reference = contexts[0]->getState(State::Positions | State::Velocities);
        double worst = 0;
        for (size_t c = 1; c < contexts.size(); c++) {
            const State cpu = contexts[c]->getState(State::Positions | State::Velocities);
            EXPECT_EQ(cpu.getStepCount(), steps);
            worst = std::max(worst, maxRelativeDifference(cpu.getPositions(), reference.getPositions()));
            worst = std::max(worst, maxRelativeDifference(cpu.getVelocities(), reference.getVelocities()));
        }
        differences.push_back(worst);
    }
    return differences;
}

} // namespace

TEST(StaggeredIntegrator, CpuMatchesReference) {
    // The CPU platform evaluates the same scheme with side Contexts, the soft force from the
    // thermostat pairs, one-pass pair forces and the coloured parallel sweep; Reference with
    // plain loops over the Context's forces.  Same random numbers, same pairs, same order of
    // the Lowe sweep: with every force in double precision the trajectories agree to
    // rounding.  What is left is the order of the force sums (and libmvec's Box-Muller),
    // ~1e-16 relative per step, which the dynamics amplifies (chaos, and the stiff FENE/WCA
    // sub-steps) by far less than 1e6 over 20 steps of Dt = 0.02 (measured: 2e-15 after one
    // step, 4e-14 after 20): 1e-10 is ample, and a wrong weight, step key, pair or force term
    // anywhere gives 1e-4 or more (a sub-step weight s/K -> (s+1)/K: 3e-2; the Lowe
    // thermalisation over the pairs at the predicted instead of the end-of-step positions:
    // 6e-4 at K = 1, 3e-3 at K = 3, after one step).
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeDoubleChains(500, 5, 18.75, positions));
    foldChains(5, positions);
    for (auto base : BASES)
        for (int k : {1, 3})
            for (bool weighted : {true, false}) {
                if (k == 1 && !weighted)
                    continue;  // K = 1 interpolates nothing
                const std::vector<double> d = cpuAgainstReference(*system, positions, base, k, weighted);
                const int steps[] = {1, 3, 20};
                for (size_t s = 0; s < d.size(); s++)
                    EXPECT_LT(d[s], 1e-10) << "base " << base << " K " << k << " weighted " << weighted << " after "
                                           << steps[s] << " steps";
                std::cout << "base " << base << " K " << k << " weighted " << weighted << ": max relative difference CPU vs "
                          << "Reference after 1, 3, 20 steps: " << d[0] << ", " << d[1] << ", " << d[2] << std::endl;
            }
}

TEST(StaggeredIntegrator, PolymerFollowsTheIntegrator) {
    // A new explicit polymer list between steps makes both platforms derive the polymer again
    // (and start from fresh forces): two solvent particles join the sub-cycled set.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeDoubleChains(500, 5, 18.75, positions));
    foldChains(5, positions);
    std::vector<int> polymer(CHAINS * 5);
    for (int i = 0; i < CHAINS * 5; i++)
        polymer[i] = i;
    polymer.push_back(100);
    polymer.push_back(101);
    for (auto base : BASES) {
        std::vector<std::unique_ptr<StaggeredDPDIntegrator>> integrators;
        std::vector<std::unique_ptr<Context>> contexts;
        for (const std::string platform : {"Reference", "CPU", "CPU"}) {
            integrators.push_back(makeStaggered(base, 0.02, 3));
            contexts.push_back(makeContext(*system, *integrators.back(), platform, positions, 2));
            integrators.back()->step(2);
        }
        for (int c : {0, 1})
            integrators[c]->setPolymerParticles(polymer);  // the third keeps the derived polymer
        std::vector<State> states;
        for (size_t c = 0; c < integrators.size(); c++) {
            integrators[c]->step(3);
            states.push_back(contexts[c]->getState(State::Positions | State::Velocities));
        }
        EXPECT_LT(maxRelativeDifference(states[1].getPositions(), states[0].getPositions()), 1e-10) << "base " << base;
        EXPECT_LT(maxRelativeDifference(states[1].getVelocities(), states[0].getVelocities()), 1e-10) << "base " << base;
        EXPECT_GT(maxRelativeDifference(states[2].getVelocities(), states[1].getVelocities()), 1e-6) << "base " << base;
    }
}

TEST(StaggeredIntegrator, CpuMatchesReferenceWithNonbondedWca) {
    // The chains as the scenes build them: the WCA is a CustomNonbondedForce.  For K > 1 the
    // CPU platform evaluates the fast forces of a small polymer on the Reference platform,
    // the WCA as the listed pairs of a Verlet list (PolymerForceContext), in double
    // precision; Reference evaluates OpenMM's CustomNonbondedForce kernel in the full
    // Context.  What is left is the order of the force sums: the trajectories agree to
    // rounding as in CpuMatchesReference (measured 2e-15 after one step, 2e-14 after 20;
    // OpenMM's single-precision CPU kernel, evaluated before, gave 2.5e-7), while a pair
    // missed by the list or a wrong cutoff gives 1e-4 or more.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeChains(500, 5, 18.75, positions));
    foldChains(5, positions);
    for (auto base : BASES) {
        const std::vector<double> d = cpuAgainstReference(*system, positions, base, 3, true);
        for (double difference : d)
            EXPECT_LT(difference, 1e-10) << "base " << base;
        std::cout << "base " << base << " K 3, nonbonded WCA: max relative difference CPU vs Reference after 1, 3, "
                  << "20 steps: " << d[0] << ", " << d[1] << ", " << d[2] << std::endl;
    }
}
#endif
