// MDPDForce (docs/theory/mdpd.md): its forces are minus the gradient of its energy on every
// host platform; the CPU follows the Reference through DPD steps; momentum is conserved; the
// pressure tensor's conservative part is the strain derivative of the energy; bad input is
// refused naming the parameter; XML round-trips.

#include "TestHelpers.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/MDPDForce.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/HarmonicBondForce.h"
#include "openmm/VerletIntegrator.h"
#include "openmm/serialization/XmlSerializer.h"
#include <sstream>

using namespace DPDPlugin;

namespace {

constexpr double L = 4.0;

/**
 * Warren's liquid (A -40, B 25, rd 0.75) at density 6 with a second particle type: its own
 * A and cutoff against type 0 and itself, its own B; every seventh pair of neighbours in
 * index excluded, as bonded beads might be.
 */
System* makeMDPDLiquid(std::vector<Vec3>& positions, unsigned seed = 3, int n = 384) {
    System* system = new System();
    system->setDefaultPeriodicBoxVectors(Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L));
    MDPDForce* force = new MDPDForce(-40, 25, 1.0, 0.75);
    force->addTypePair(0, 1, -30, 0.9);
    force->addTypePair(1, 1, -45, 1.1);
    force->setTypeB(1, 20);
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0, L);
    for (int i = 0; i < n; i++) {
        system->addParticle(1.0);
        force->setParticleType(i, i % 3 == 0 ? 1 : 0);
        positions.push_back(Vec3(uniform(rng), uniform(rng), uniform(rng)));
    }
    for (int i = 0; i + 1 < n; i += 7)
        force->addExclusion(i, i + 1);
    system->addForce(force);
    return system;
}

double energyAt(Context& context, const std::vector<Vec3>& positions) {
    context.setPositions(positions);
    return context.getState(State::Energy).getPotentialEnergy();
}

} // namespace

TEST(MDPDForce, ForcesAreMinusTheEnergyGradient) {
    for (const std::string& platform : platforms()) {
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeMDPDLiquid(positions));
        VerletIntegrator integrator(0.001);
        std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions);
        const std::vector<Vec3> forces = context->getState(State::Forces).getForces();
        const double h = 1e-5;
        double worst = 0;
        for (int i = 0; i < 30; i++)
            for (int k = 0; k < 3; k++) {
                std::vector<Vec3> plus = positions, minus = positions;
                plus[i][k] += h;
                minus[i][k] -= h;
                const double gradient = (energyAt(*context, plus) - energyAt(*context, minus)) / (2 * h);
                worst = std::max(worst, std::fabs(forces[i][k] + gradient) / std::max(1.0, std::fabs(forces[i][k])));
            }
        EXPECT_LT(worst, 1e-6) << platform;
    }
}

TEST(MDPDForce, DensityTermMatchesWarrensNormalisation) {
    // Two particles at r: rho = 15/(2 pi rd^3) (1 - r/rd)^2 each, E = 2 pi rd^4 B rho^2 / 30 + A rc (1 - r/rc)^2 / 2.
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(5, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 5));
    system.addParticle(1.0);
    system.addParticle(1.0);
    system.addForce(new MDPDForce(-40, 25, 1.0, 0.75));
    for (const std::string& platform : platforms()) {
        VerletIntegrator integrator(0.001);
        const double r = 0.4, rd = 0.75, pi = 3.14159265358979323846;
        std::unique_ptr<Context> context = makeContext(system, integrator, platform, {Vec3(1, 1, 1), Vec3(1 + r, 1, 1)});
        const double rho = 15 / (2 * pi * rd * rd * rd) * (1 - r / rd) * (1 - r / rd);
        const double expected = 2 * pi * std::pow(rd, 4) * 25 * rho * rho / 30 - 40 * 0.5 * (1 - r) * (1 - r);
        EXPECT_NEAR(context->getState(State::Energy).getPotentialEnergy(), expected, 1e-12 * std::fabs(expected)) << platform;
        const double force = -40 * (1 - r) + 25 * 2 * rho * (1 - r / rd);  // on particle 0 along -x
        EXPECT_NEAR(context->getState(State::Forces).getForces()[0][0], -force, 1e-12 * std::fabs(force)) << platform;
    }
}

#if OPENMMDPD_HAVE_CPU
/**
 * The thermostat cutoffs of the CPU's two ways of adding the force in a DPD step: 1.0, below
 * the force's largest cutoff (1.1), leaves it to its own pair pass; 1.1 lets the thermostat's
 * pair pass add it, from the densities of a pass over r_d alone.
 */
const double THERMOSTAT_CUTOFFS[] = {1.0, 1.1};

TEST(MDPDForce, CpuFollowsTheReferenceThroughDPDSteps) {
    for (double cutoff : THERMOSTAT_CUTOFFS) {
        std::vector<std::vector<Vec3>> final;
        for (std::string platform : {"Reference", "CPU"}) {
            std::vector<Vec3> positions;
            std::unique_ptr<System> system(makeMDPDLiquid(positions));
            DPDVVIntegrator integrator(KT_KELVIN, 4.5, cutoff, 0.01);
            integrator.setRandomNumberSeed(5);
            std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions, 2);
            integrator.step(20);
            final.push_back(context->getState(State::Positions).getPositions());
        }
        EXPECT_LT(relativeDifference(final[0], final[1]), 1e-10) << "thermostat cutoff " << cutoff;
    }
}

/** The staggered scheme's slow forces without the MDPDForce, which the thermostat pass adds. */
TEST(MDPDForce, StaggeredCpuFollowsTheReference) {
    std::vector<std::vector<Vec3>> final;
    for (std::string platform : {"Reference", "CPU"}) {
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeMDPDLiquid(positions));
        HarmonicBondForce* bonds = new HarmonicBondForce();
        for (int i = 0; i + 1 < 40; i += 2)
            bonds->addBond(i, i + 1, 0.5, 50.0);
        bonds->setUsesPeriodicBoundaryConditions(true);
        bonds->setForceGroup(1);
        system->addForce(bonds);
        StaggeredDPDIntegrator integrator(KT_KELVIN, 4.5, 1.1, 0.01, 2);
        integrator.setFastForceGroups(1 << 1);
        integrator.setRandomNumberSeed(5);
        std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions, 2);
        integrator.step(20);
        final.push_back(context->getState(State::Positions).getPositions());
    }
    EXPECT_LT(relativeDifference(final[0], final[1]), 1e-10);
}

/**
 * S1 with the pressure tensor, CPU against the Reference, still (the pairs found four at a
 * time) and under Lees-Edwards shear (the box tilted, the pairs found one by one).
 */
TEST(MDPDForce, ShardlowCpuFollowsTheReference) {
    for (double rate : {0.0, 0.5})
        for (double cutoff : THERMOSTAT_CUTOFFS) {
            std::vector<std::vector<Vec3>> final;
            std::vector<std::vector<double>> pressure;
            for (std::string platform : {"Reference", "CPU"}) {
                std::vector<Vec3> positions;
                std::unique_ptr<System> system(makeMDPDLiquid(positions));
                ShardlowIntegrator integrator(KT_KELVIN, 4.5, cutoff, 0.01);
                integrator.setRandomNumberSeed(5);
                integrator.setShearRate(rate);
                integrator.setPressureTensorEnabled(true);
                std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions, 2);
                integrator.step(20);
                final.push_back(context->getState(State::Positions).getPositions());
                pressure.push_back(integrator.getAveragePressureTensor(DPDThermostatIntegrator::PressureTotal));
            }
            const std::string where = "shear rate " + std::to_string(rate) + ", thermostat cutoff " + std::to_string(cutoff);
            EXPECT_LT(relativeDifference(final[0], final[1]), 1e-10) << where;
            for (int k = 0; k < 6; k++)
                EXPECT_NEAR(pressure[1][k], pressure[0][k], 1e-9 * std::max(1.0, std::fabs(pressure[0][k])))
                        << "component " << k << ", " << where;
        }
}
#endif

TEST(MDPDForce, MomentumIsConserved) {
    for (const std::string& platform : platforms()) {
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeMDPDLiquid(positions));
        DPDVVIntegrator integrator(KT_KELVIN, 4.5, 1.0, 0.01);
        std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions);
        Vec3 sum;
        double scale = 0;
        const State state = context->getState(State::Forces);
        for (const Vec3& f : state.getForces()) {
            sum += f;
            scale = std::max(scale, std::sqrt(f.dot(f)));
        }
        EXPECT_LT(std::sqrt(sum.dot(sum)), 1e-10 * scale * positions.size()) << platform;
        const Vec3 before = totalMomentum(*context);
        integrator.step(50);
        const Vec3 drift = totalMomentum(*context) - before;
        EXPECT_LT(std::sqrt(drift.dot(drift)), 1e-9 * positions.size()) << platform;
    }
}

/**
 * The conservative pressure tensor of one sampled step times the volume against minus the
 * central strain derivative of the energy at the same positions, computed here by straining
 * the positions and box (no thermostat: friction 0, so the step's positions are Verlet's).
 */
TEST(MDPDForce, ConservativePressureIsTheStrainDerivative) {
    const int axes[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};
    for (const std::string& platform : platforms()) {
        std::vector<Vec3> positions;
        std::unique_ptr<System> system(makeMDPDLiquid(positions));
        DPDVVIntegrator integrator(KT_KELVIN, 0.0, 1.0, 0.005);
        integrator.setPressureTensorEnabled(true);
        std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions);
        integrator.step(1);
        const std::vector<double> pressure = integrator.getAveragePressureTensor(DPDThermostatIntegrator::PressureConservative);
        const std::vector<Vec3> at = context->getState(State::Positions).getPositions();
        VerletIntegrator verlet(0.001);
        std::unique_ptr<Context> probe = makeContext(*system, verlet, platform, at);
        const double epsilon = 1e-6;
        for (int k = 0; k < 6; k++) {
            double energy[2];
            for (int side = 0; side < 2; side++) {
                const double e = (side == 0 ? epsilon : -epsilon);
                Vec3 box[3] = {Vec3(L, 0, 0), Vec3(0, L, 0), Vec3(0, 0, L)};
                for (Vec3& edge : box)
                    edge[axes[k][0]] += e * edge[axes[k][1]];
                std::vector<Vec3> strained = at;
                for (Vec3& r : strained)
                    r[axes[k][0]] += e * r[axes[k][1]];
                probe->setPeriodicBoxVectors(box[0], box[1], box[2]);
                energy[side] = energyAt(*probe, strained);
            }
            const double virial = -(energy[0] - energy[1]) / (2 * epsilon);
            EXPECT_NEAR(pressure[k] * L * L * L, virial, 1e-6 * std::max(1.0, std::fabs(virial))) << platform << " component " << k;
        }
    }
}

TEST(MDPDForce, InvalidParametersNameThemselves) {
    expectErrorNaming([] { MDPDForce(-40, -25, 1, 0.75); }, "defaultB");
    expectErrorNaming([] { MDPDForce(-40, 25, 1, 1.2); }, "densityCutoff");
    expectErrorNaming([] { MDPDForce(-40, 25, 1, 0); }, "densityCutoff");
    expectErrorNaming([] { MDPDForce(-40, 25, -1, 0.5); }, "defaultCutoff");
    MDPDForce force(-40, 25, 1.0, 0.75);
    expectErrorNaming([&] { force.addTypePair(0, 1, -30, 0.7); }, "cutoff");
    expectErrorNaming([&] { force.setTypeB(1, -1); }, "B");
    expectErrorNaming([&] { force.setDefaultCutoff(0.5); }, "defaultCutoff");
    expectErrorNaming([&] { force.setDefaultA(std::nan("")); }, "defaultA");
    expectErrorNaming([&] { force.addExclusion(3, 3); }, "exclusion");
    EXPECT_EQ(force.getNumTypePairs(), 0);
    System system;
    system.setDefaultPeriodicBoxVectors(Vec3(1.5, 0, 0), Vec3(0, 3, 0), Vec3(0, 0, 3));
    system.addParticle(1.0);
    system.addParticle(1.0);
    MDPDForce* wide = new MDPDForce(-40, 25, 1.0, 0.75);
    system.addForce(wide);
    VerletIntegrator integrator(0.001);
    expectErrorNaming([&] { Context c(system, integrator, Platform::getPlatformByName("Reference")); }, "half the periodic box");
    wide->setDefaultCutoff(0.75);
    wide->addTypePair(0, 5, -10, 0.75);
    expectErrorNaming([&] { Context c(system, integrator, Platform::getPlatformByName("Reference")); }, "unknown particle type");
}

TEST(MDPDForce, UpdateParametersInContext) {
    std::vector<Vec3> positions;
    std::unique_ptr<System> system(makeMDPDLiquid(positions));
    MDPDForce& force = dynamic_cast<MDPDForce&>(system->getForce(0));
    for (const std::string& platform : platforms()) {
        VerletIntegrator integrator(0.001);
        std::unique_ptr<Context> context = makeContext(*system, integrator, platform, positions);
        const double before = context->getState(State::Energy).getPotentialEnergy();
        force.setTypeB(1, 30);
        force.updateParametersInContext(*context);
        const double after = context->getState(State::Energy).getPotentialEnergy();
        force.setTypeB(1, 20);
        EXPECT_GT(after, before + 1.0) << platform;
    }
}

TEST(MDPDForce, XmlRoundTrip) {
    MDPDForce force(-40, 25, 1.0, 0.75);
    force.setParticleType(4, 2);
    force.addTypePair(0, 2, -30, 0.9);
    force.setTypeB(2, 18);
    force.addExclusion(1, 2);
    force.setForceGroup(3);
    force.setNonbondedMethod(MDPDForce::CutoffNonPeriodic);
    std::stringstream buffer, again;
    XmlSerializer::serialize<Force>(&force, "Force", buffer);
    std::unique_ptr<Force> copy(XmlSerializer::deserialize<Force>(buffer));
    XmlSerializer::serialize<Force>(copy.get(), "Force", again);
    EXPECT_EQ(buffer.str(), again.str());
    MDPDForce* c = dynamic_cast<MDPDForce*>(copy.get());
    ASSERT_NE(c, nullptr);
    EXPECT_EQ(c->getParticleType(4), 2);
    EXPECT_EQ(c->getTypeB(2), 18);
    EXPECT_EQ(c->getDensityCutoff(), 0.75);
    EXPECT_EQ(c->getNumExclusions(), 1);
    EXPECT_FALSE(c->usesPeriodicBoundaryConditions());
}
