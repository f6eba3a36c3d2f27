#include "TestHelpers.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmm/State.h"
#include "openmm/TabulatedFunction.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/serialization/XmlSerializer.h"
#include <sstream>

using namespace DPDPlugin;

namespace {

// Three particle types with their a_ij; type-pair cutoffs differ too.
const double A[3][3] = {{25, 40, 30}, {40, 15, 50}, {30, 50, 20}};
const double RC[3][3] = {{1.0, 0.9, 1.1}, {0.9, 1.0, 0.8}, {1.1, 0.8, 1.2}};

struct TwoForces {
    System system;
    std::vector<Vec3> positions;
    DPDSoftRepulsionForce* native;
};

// The same interaction twice: our force (group 0) and a CustomNonbondedForce (group 1).
void makeSystems(TwoForces& setup, const Vec3* box, int n, unsigned seed) {
    System& system = setup.system;
    system.setDefaultPeriodicBoxVectors(box[0], box[1], box[2]);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    std::vector<int> types(n);
    for (int i = 0; i < n; i++) {
        system.addParticle(1.0);
        types[i] = i % 3;
        setup.positions.push_back(box[0] * uniform(rng) + box[1] * uniform(rng) + box[2] * uniform(rng));
    }
    DPDSoftRepulsionForce* native = new DPDSoftRepulsionForce(A[0][0], RC[0][0]);
    CustomNonbondedForce* custom = new CustomNonbondedForce("0.5*a*rc*(1-r/rc)^2*step(rc-r); a=atab(t1, t2); rc=rctab(t1, t2)");
    std::vector<double> aTable, rcTable;
    for (int j = 0; j < 3; j++)
        for (int i = 0; i < 3; i++) {
            aTable.push_back(A[i][j]);
            rcTable.push_back(RC[i][j]);
        }
    custom->addTabulatedFunction("atab", new Discrete2DFunction(3, 3, aTable));
    custom->addTabulatedFunction("rctab", new Discrete2DFunction(3, 3, rcTable));
    custom->addPerParticleParameter("t");
    custom->setNonbondedMethod(CustomNonbondedForce::CutoffPeriodic);
    custom->setCutoffDistance(1.2);
    custom->setForceGroup(1);
    for (int i = 0; i < n; i++) {
        native->setParticleType(i, types[i]);
        custom->addParticle({(double) types[i]});
    }
    for (int t1 = 0; t1 < 3; t1++)
        for (int t2 = t1; t2 < 3; t2++)
            if (t1 + t2 > 0)
                native->addTypePair(t1, t2, A[t1][t2], RC[t1][t2]);
    // Exclusions, as for bonded neighbours.
    for (int i = 0; i + 1 < n; i += 7) {
        native->addExclusion(i, i + 1);
        custom->addExclusion(i, i + 1);
    }
    system.addForce(native);
    system.addForce(custom);
    setup.native = native;
}

void compareWithCustom(const Vec3* box, const std::string& platform) {
    TwoForces setup;
    makeSystems(setup, box, 600, 3);
    VerletIntegrator integrator(0.001);
    Context context(setup.system, integrator, Platform::getPlatformByName("Reference"));
    context.setPositions(setup.positions);
    const State expected = context.getState(State::Energy | State::Forces, false, 1 << 1);
    VerletIntegrator integrator2(0.001);
    auto ours = makeContext(setup.system, integrator2, platform, setup.positions, 2);
    const State actual = ours->getState(State::Energy | State::Forces, false, 1 << 0);
    ASSERT_GT(expected.getPotentialEnergy(), 100.0);
    EXPECT_NEAR(actual.getPotentialEnergy(), expected.getPotentialEnergy(), 1e-5 * expected.getPotentialEnergy());
    for (size_t i = 0; i < setup.positions.size(); i++) {
        const Vec3 d = actual.getForces()[i] - expected.getForces()[i];
        const double scale = std::max(1.0, std::sqrt(expected.getForces()[i].dot(expected.getForces()[i])));
        ASSERT_LT(std::sqrt(d.dot(d)), 1e-5 * scale) << platform << " particle " << i;
    }
}

} // namespace

TEST(DPDSoftRepulsionForce, MatchesCustomNonbondedForceRectangular) {
    const Vec3 box[3] = {Vec3(5, 0, 0), Vec3(0, 4.5, 0), Vec3(0, 0, 4)};
    for (const std::string& platform : platforms())
        compareWithCustom(box, platform);
}

TEST(DPDSoftRepulsionForce, MatchesCustomNonbondedForceTriclinic) {
    const Vec3 box[3] = {Vec3(5, 0, 0), Vec3(1.5, 4.5, 0), Vec3(-2.0, 1.2, 4)};
    for (const std::string& platform : platforms())
        compareWithCustom(box, platform);
}

TEST(DPDSoftRepulsionForce, ForcesAreMinusTheEnergyGradient) {
    const Vec3 box[3] = {Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(0, 0, 4)};
    TwoForces setup;
    makeSystems(setup, box, 200, 9);
    VerletIntegrator integrator(0.001);
    Context context(setup.system, integrator, Platform::getPlatformByName("Reference"));
    context.setPositions(setup.positions);
    const std::vector<Vec3> forces = context.getState(State::Forces, false, 1).getForces();
    const double h = 1e-6;
    for (int i = 0; i < 20; i++)
        for (int k = 0; k < 3; k++) {
            std::vector<Vec3> plus = setup.positions, minus = setup.positions;
            plus[i][k] += h;
            minus[i][k] -= h;
            context.setPositions(plus);
            const double ePlus = context.getState(State::Energy, false, 1).getPotentialEnergy();
            context.setPositions(minus);
            const double eMinus = context.getState(State::Energy, false, 1).getPotentialEnergy();
            EXPECT_NEAR(forces[i][k], -(ePlus - eMinus) / (2 * h), 1e-4 * std::max(1.0, std::fabs(forces[i][k])));
        }
}

TEST(DPDSoftRepulsionForce, UpdateParametersInContext) {
    const Vec3 box[3] = {Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(0, 0, 4)};
    TwoForces setup;
    makeSystems(setup, box, 200, 4);
    VerletIntegrator integrator(0.001);
    Context context(setup.system, integrator, Platform::getPlatformByName("Reference"));
    context.setPositions(setup.positions);
    const double before = context.getState(State::Energy, false, 1).getPotentialEnergy();
    setup.native->setDefaultA(2 * A[0][0]);
    for (int k = 0; k < setup.native->getNumTypePairs(); k++) {
        int t1, t2;
        double a, rc;
        setup.native->getTypePairParameters(k, t1, t2, a, rc);
        setup.native->setTypePairParameters(k, t1, t2, 2 * a, rc);
    }
    setup.native->updateParametersInContext(context);
    EXPECT_NEAR(context.getState(State::Energy, false, 1).getPotentialEnergy(), 2 * before, 1e-9 * before);
}

TEST(DPDSoftRepulsionForce, InvalidParametersNameThemselves) {
    expectErrorNaming([] { DPDSoftRepulsionForce(25, -1); }, "defaultCutoff");
    expectErrorNaming([] { DPDSoftRepulsionForce(-25, 1); }, "defaultA");
    DPDSoftRepulsionForce force(25, 1);
    expectErrorNaming([&] { force.addTypePair(0, 1, 25, 0); }, "cutoff");
    expectErrorNaming([&] { force.setParticleType(0, -1); }, "type");
    expectErrorNaming([&] { force.addExclusion(3, 3); }, "exclusion");
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(1.5, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3));
    system.addParticle(1.0);
    system.addParticle(1.0);
    DPDSoftRepulsionForce* wide = new DPDSoftRepulsionForce(25, 1.0);
    system.addForce(wide);
    VerletIntegrator integrator(0.001);
    expectErrorNaming([&] { Context c(system, integrator, Platform::getPlatformByName("Reference")); }, "half the periodic box");
    wide->setDefaultCutoff(0.7);
    wide->addTypePair(0, 5, 10, 0.5);
    expectErrorNaming([&] { Context c(system, integrator, Platform::getPlatformByName("Reference")); }, "unknown particle type");
}

TEST(DPDSoftRepulsionForce, XmlRoundTrip) {
    DPDSoftRepulsionForce force(25, 1.0);
    force.setParticleType(4, 2);
    force.addTypePair(0, 2, 40, 0.9);
    force.addExclusion(1, 2);
    force.setForceGroup(3);
    force.setNonbondedMethod(DPDSoftRepulsionForce::CutoffNonPeriodic);
    std::stringstream buffer, again;
    XmlSerializer::serialize<Force>(&force, "Force", buffer);
    std::unique_ptr<Force> copy(XmlSerializer::deserialize<Force>(buffer));
    XmlSerializer::serialize<Force>(copy.get(), "Force", again);
    EXPECT_EQ(buffer.str(), again.str());
    DPDSoftRepulsionForce* c = dynamic_cast<DPDSoftRepulsionForce*>(copy.get());
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->getParticleType(4), 2);
    EXPECT_EQ(c->getNumExclusions(), 1);
    EXPECT_EQ(c->getForceGroup(), 3);
    EXPECT_FALSE(c->usesPeriodicBoundaryConditions());
}

TEST(DPDSoftRepulsionForce, CheckpointWithDPDIsBitExactOnEveryPlatform) {
    // Unlike OpenMM's CPU nonbonded forces, this force sums in a fixed order, so a DPD run
    // with it continues bit for bit across a checkpoint on CPU too.
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeFluid(1000, 0, positions));
    system->addForce(new DPDSoftRepulsionForce(25, 1.0));
    for (const std::string& platform : platforms()) {
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.04);
        integrator.setRandomNumberSeed(3);
        auto context = makeContext(*system, integrator, platform, positions, 2);
        integrator.step(10);
        std::stringstream checkpoint;
        context->createCheckpoint(checkpoint);
        integrator.step(10);
        const State first = context->getState(State::Positions | State::Velocities);
        context->loadCheckpoint(checkpoint);
        integrator.step(10);
        const State second = context->getState(State::Positions | State::Velocities);
        for (size_t i = 0; i < positions.size(); i++) {
            ASSERT_EQ(first.getPositions()[i], second.getPositions()[i]) << platform;
            ASSERT_EQ(first.getVelocities()[i], second.getVelocities()[i]) << platform;
        }
    }
}

// Within a DPD step the force is evaluated from the thermostat's pair list when that list
// holds all its pairs (thermostat cutoff 1.2 >= every force cutoff), and by its own kernel
// otherwise (thermostat cutoff 1.0 < 1.2): either way the trajectory is that of the same
// interaction written as a CustomNonbondedForce.
TEST(DPDSoftRepulsionForce, DPDStepsGetTheSameForceWithOrWithoutTheThermostatPairList) {
    const Vec3 box[3] = {Vec3(5, 0, 0), Vec3(1.5, 4.5, 0), Vec3(-2.0, 1.2, 4)};
    TwoForces setup;
    makeSystems(setup, box, 600, 3);
    for (double thermostatCutoff : {1.2, 1.0})
        for (const std::string& platform : platforms()) {
            std::vector<std::vector<Vec3>> velocities;
            for (int group : {0, 1}) {
                DPDVVIntegrator integrator(KT_KELVIN, 4.5, thermostatCutoff, 0.01);
                integrator.setRandomNumberSeed(5);
                integrator.setIntegrationForceGroups(1 << group);
                auto context = makeContext(setup.system, integrator, platform, setup.positions, 2);
                integrator.step(5);
                velocities.push_back(context->getState(State::Velocities).getVelocities());
            }
            for (size_t i = 0; i < setup.positions.size(); i++) {
                const Vec3 d = velocities[0][i] - velocities[1][i];
                // CPU: the CustomNonbondedForce is single precision.
                ASSERT_LT(std::sqrt(d.dot(d)), platform == "CPU" ? 1e-4 : 1e-9)
                        << platform << " thermostat cutoff " << thermostatCutoff << " particle " << i;
            }
        }
}
