// Constraints and virtual sites, on every integrator that supports them, on both platforms:
// a fluid of rigid dimers (constrained bonds) with virtual sites on some of them.  The
// constraints hold within the tolerance and the relative velocity along each bond vanishes
// (RATTLE), momentum is conserved, every virtual site sits where its definition puts it
// (computed here from its parents), the CPU platform follows the Reference trajectory, and
// the staggered scheme refuses both at Context creation.  A new integrator's constraint
// tolerance is 1e-5, as OpenMM's, with or without a round trip through XML.

#include "TestHelpers.h"
#include "openmm/VirtualSite.h"
#include "openmm/serialization/XmlSerializer.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include <algorithm>
#include <sstream>

using namespace DPDPlugin;

namespace {

// The Reference platform's loops are slow: it checks 1000 steps on fewer dimers
// (CpuFollowsTheReferenceTrajectory ties the two platforms on the same System).
constexpr int NUM_DIMERS_CPU = 300, NUM_DIMERS_REFERENCE = 60, STEPS = 1000;
constexpr double BOND = 0.5, DT = 0.02, TOLERANCE = 1e-6;

struct Dimers {
    std::unique_ptr<System> system;
    std::vector<Vec3> positions, velocities;
    int numSites = 0;
};

/** Dimer k is particles 2k, 2k+1 (unit mass, bond BOND constrained); kT = 1 velocities, not yet constrained. */
Dimers makeDimers(int numDimers, unsigned seed = 3) {
    Dimers d;
    d.system.reset(new System());
    const double box = std::cbrt(2 * numDimers / 3.0);
    d.system->setDefaultPeriodicBoxVectors(Vec3(box, 0, 0), Vec3(0, box, 0), Vec3(0, 0, box));
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0, box);
    std::normal_distribution<double> normal(0, 1);
    for (int k = 0; k < numDimers; k++) {
        Vec3 axis(normal(rng), normal(rng), normal(rng));
        axis *= BOND / std::sqrt(axis.dot(axis));
        const Vec3 centre(uniform(rng), uniform(rng), uniform(rng));
        for (const Vec3& r : {centre - axis * 0.5, centre + axis * 0.5}) {
            d.system->addParticle(1.0);
            d.positions.push_back(r);
            d.velocities.push_back(Vec3(normal(rng), normal(rng), normal(rng)));
        }
        d.system->addConstraint(2 * k, 2 * k + 1, BOND);
    }
    DPDSoftRepulsionForce* soft = new DPDSoftRepulsionForce(25.0, 1.0);
    d.system->addForce(soft);
    return d;
}

/**
 * Adds massless sites: a TwoParticleAverageSite on each of the first four dimers, a
 * ThreeParticleAverageSite and an OutOfPlaneSite on dimers 4 and 5 with a third parent from
 * dimer 6.  The soft repulsion acts on them too (their force goes to their parents).
 */
void addSites(Dimers& d) {
    auto add = [&](VirtualSite* site) {
        const int index = d.system->addParticle(0.0);
        d.system->setVirtualSite(index, site);
        d.positions.push_back(Vec3());
        d.velocities.push_back(Vec3());
        d.numSites++;
    };
    for (int k = 0; k < 4; k++)
        add(new TwoParticleAverageSite(2 * k, 2 * k + 1, 0.3, 0.7));
    d.positions[12] = d.positions[8] + Vec3(0.3, 0.2, 0.1);  // the third parent near dimers 4 and 5
    d.positions[13] = d.positions[12] + Vec3(0, BOND, 0);
    d.positions[10] = d.positions[8] + Vec3(-0.2, 0.3, 0.1);
    d.positions[11] = d.positions[10] + Vec3(0, 0, BOND);
    add(new ThreeParticleAverageSite(8, 9, 12, 0.2, 0.3, 0.5));
    add(new OutOfPlaneSite(10, 11, 12, 0.4, 0.3, 0.6));
}

/** Where the definition of each virtual site puts it, from its parents' positions. */
Vec3 expectedSite(const VirtualSite& site, const std::vector<Vec3>& r) {
    if (const auto* two = dynamic_cast<const TwoParticleAverageSite*>(&site))
        return r[two->getParticle(0)] * two->getWeight(0) + r[two->getParticle(1)] * two->getWeight(1);
    if (const auto* three = dynamic_cast<const ThreeParticleAverageSite*>(&site))
        return r[three->getParticle(0)] * three->getWeight(0) + r[three->getParticle(1)] * three->getWeight(1) +
               r[three->getParticle(2)] * three->getWeight(2);
    const auto& plane = dynamic_cast<const OutOfPlaneSite&>(site);
    const Vec3 r0 = r[plane.getParticle(0)];
    const Vec3 r01 = r[plane.getParticle(1)] - r0, r02 = r[plane.getParticle(2)] - r0;
    return r0 + r01 * plane.getWeight12() + r02 * plane.getWeight13() + r01.cross(r02) * plane.getWeightCross();
}

struct Scheme {
    std::string name;
    std::function<Integrator*()> make;
};

void PrintTo(const Scheme& scheme, std::ostream* out) {
    *out << scheme.name;
}

template <class T, class Setting>
std::function<Integrator*()> maker(Setting setting) {
    return [setting] {
        T* integrator = new T(KT_KELVIN, 4.5, 1.0, DT);
        setting(*integrator);
        integrator->setRandomNumberSeed(17);
        integrator->setConstraintTolerance(TOLERANCE);
        return integrator;
    };
}

const std::vector<Scheme> SCHEMES = {
    {"GW", maker<DPDVVIntegrator>([](DPDVVIntegrator& i) { i.setVariant(DPDVVIntegrator::GrootWarren); })},
    {"DPD-VV", maker<DPDVVIntegrator>([](DPDVVIntegrator& i) { i.setVariant(DPDVVIntegrator::DPDVV); })},
    {"SC-VV", maker<DPDVVIntegrator>([](DPDVVIntegrator& i) { i.setVariant(DPDVVIntegrator::SelfConsistent); })},
    {"S1", maker<ShardlowIntegrator>([](ShardlowIntegrator& i) { i.setOrder(1); })},
    {"S2", maker<ShardlowIntegrator>([](ShardlowIntegrator& i) { i.setOrder(2); })},
    {"Lowe", maker<LoweAndersenIntegrator>([](LoweAndersenIntegrator& i) { i.setMethod(LoweAndersenIntegrator::Lowe); })},
    {"PairOU", maker<LoweAndersenIntegrator>(
                   [](LoweAndersenIntegrator& i) { i.setMethod(LoweAndersenIntegrator::PairOrnsteinUhlenbeck); })},
    {"OC", maker<DenOtterClarkeIntegrator>([](DenOtterClarkeIntegrator& i) {
         i.setAverageFDDotV(-4.985245);  // model B (Nikunen et al. 2003, Table III)
         i.setAverageFDDotFD(14.507340);
         i.setAverageFRDotFR(9.976453);
     })},
    {"EDPD", [] {
         EDPDIntegrator* integrator = new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, DT);
         integrator->setRandomNumberSeed(17);
         integrator->setConstraintTolerance(TOLERANCE);
         return integrator;
     }},
};

struct Simulation {
    std::unique_ptr<Integrator> integrator;
    std::unique_ptr<Context> context;
};

Simulation start(Dimers& d, const Scheme& scheme, const std::string& platform) {
    Simulation run;
    run.integrator.reset(scheme.make());
    run.context.reset(new Context(*d.system, *run.integrator, Platform::getPlatformByName(platform)));
    run.context->setPositions(d.positions);
    run.context->setVelocities(d.velocities);
    run.context->computeVirtualSites();
    run.context->applyVelocityConstraints(1e-10);
    return run;
}

/** Over the constraints: max ||r_ij| - d| / d, and max |v_ij . e_ij| / |v_ij| (the bond-direction velocity). */
void constraintErrors(const System& system, const State& state, double& lengthError, double& velocityError) {
    lengthError = velocityError = 0;
    for (int c = 0; c < system.getNumConstraints(); c++) {
        int i, j;
        double d;
        system.getConstraintParameters(c, i, j, d);
        const Vec3 rij = state.getPositions()[i] - state.getPositions()[j];
        const Vec3 vij = state.getVelocities()[i] - state.getVelocities()[j];
        const double length = std::sqrt(rij.dot(rij));
        lengthError = std::max(lengthError, std::fabs(length - d) / d);
        velocityError = std::max(velocityError, std::fabs(vij.dot(rij)) / (length * std::sqrt(vij.dot(vij))));
    }
}

double maxSiteError(const System& system, const std::vector<Vec3>& r) {
    double error = 0;
    for (int i = 0; i < system.getNumParticles(); i++)
        if (system.isVirtualSite(i)) {
            const Vec3 d = r[i] - expectedSite(system.getVirtualSite(i), r);
            error = std::max(error, std::sqrt(d.dot(d)));
        }
    return error;
}

/** The momentum of the particles with mass (the sites have none). */
Vec3 momentum(const System& system, const State& state) {
    Vec3 p;
    for (int i = 0; i < system.getNumParticles(); i++)
        p += state.getVelocities()[i] * system.getParticleMass(i);
    return p;
}

class ConstraintsAndSites : public testing::TestWithParam<Scheme> {};

TEST_P(ConstraintsAndSites, ConstraintsHoldMomentumIsConservedSitesArePlaced) {
    const Scheme& scheme = GetParam();
    for (const std::string& platform : platforms()) {
        Dimers d = makeDimers(platform == "CPU" ? NUM_DIMERS_CPU : NUM_DIMERS_REFERENCE);
        addSites(d);
        Simulation run = start(d, scheme, platform);
        const Vec3 p0 = momentum(*d.system, run.context->getState(State::Velocities));
        double worstLength = 0, worstVelocity = 0, worstSite = 0, worstMomentum = 0;
        for (int step = 1; step <= STEPS; step++) {
            run.integrator->step(1);
            const int types = State::Positions | (step % 100 == 0 ? State::Velocities : 0);
            const State state = run.context->getState(types);
            worstSite = std::max(worstSite, maxSiteError(*d.system, state.getPositions()));
            if (step % 100 != 0)
                continue;
            double length, velocity;
            constraintErrors(*d.system, state, length, velocity);
            worstLength = std::max(worstLength, length);
            worstVelocity = std::max(worstVelocity, velocity);
            const Vec3 dp = momentum(*d.system, state) - p0;
            worstMomentum = std::max(worstMomentum, std::sqrt(dp.dot(dp)));
        }
        std::ostringstream measured;
        measured << std::scientific << "length " << worstLength << " velocity " << worstVelocity << " site " << worstSite
                 << " momentum " << worstMomentum;
        RecordProperty(scheme.name + "-" + platform, measured.str());
        // CCMA iterates until every constraint holds to the tolerance (relative).
        EXPECT_LT(worstLength, TOLERANCE) << scheme.name << " on " << platform;
        // Unconstrained velocities leave |v_ij . e| ~ |v_ij| / sqrt(3).
        EXPECT_LT(worstVelocity, 1e-4) << scheme.name << " on " << platform;
        EXPECT_LT(worstSite, 1e-10) << scheme.name << " on " << platform;
        // Constraint forces are pairwise; the CPU platform's float forces leave ~1e-5 per particle.
        EXPECT_LT(worstMomentum, platform == "CPU" ? 1e-3 : 1e-10) << scheme.name << " on " << platform;
    }
}

/** One integrator of each class that takes constraints, as constructed: no tolerance set. */
std::vector<std::unique_ptr<DPDThermostatIntegrator>> constructedIntegrators() {
    std::vector<std::unique_ptr<DPDThermostatIntegrator>> integrators;
    integrators.emplace_back(new DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrators.emplace_back(new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrators.emplace_back(new LoweAndersenIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrators.emplace_back(new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, DT));
    DenOtterClarkeIntegrator* denOtterClarke = new DenOtterClarkeIntegrator(KT_KELVIN, 4.5, 1.0, DT);
    denOtterClarke->setAverageFDDotV(-4.985245);  // model B (Nikunen et al. 2003, Table III)
    denOtterClarke->setAverageFDDotFD(14.507340);
    denOtterClarke->setAverageFRDotFR(9.976453);
    integrators.emplace_back(denOtterClarke);
    return integrators;
}

TEST(ConstraintTolerance, TheDefaultHoldsTheConstraints) {
    for (const std::string& platform : platforms())
        for (auto& integrator : constructedIntegrators()) {
            Dimers d = makeDimers(NUM_DIMERS_REFERENCE);
            Context context(*d.system, *integrator, Platform::getPlatformByName(platform));
            context.setPositions(d.positions);
            context.setVelocities(d.velocities);
            integrator->step(100);
            double length, velocity;
            constraintErrors(*d.system, context.getState(State::Positions | State::Velocities), length, velocity);
            EXPECT_LT(length, 2 * DEFAULT_CONSTRAINT_TOLERANCE) << integrator->className() << " on " << platform;
        }
}

TEST(ConstraintTolerance, XmlWithoutOneReadsTheDefault) {
    for (auto& integrator : constructedIntegrators()) {
        integrator->setConstraintTolerance(1e-7);
        std::stringstream xml;
        XmlSerializer::serialize<Integrator>(integrator.get(), "Integrator", xml);
        std::string text = xml.str();
        const std::string attribute = " constraintTolerance=\"1e-07\"";
        const size_t at = text.find(attribute);
        ASSERT_NE(at, std::string::npos) << integrator->className();
        std::istringstream written(text), stripped(text.erase(at, attribute.size()));
        EXPECT_EQ(std::unique_ptr<Integrator>(XmlSerializer::deserialize<Integrator>(written))->getConstraintTolerance(), 1e-7);
        EXPECT_EQ(std::unique_ptr<Integrator>(XmlSerializer::deserialize<Integrator>(stripped))->getConstraintTolerance(), 1e-5)
                << integrator->className();
    }
}

TEST(ConstraintTolerance, EveryClassStartsAtOpenMMsDefaultAndRefusesNonsense) {
    std::vector<std::unique_ptr<DPDThermostatIntegrator>> integrators = constructedIntegrators();
    integrators.emplace_back(new StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    for (auto& integrator : integrators) {
        EXPECT_EQ(integrator->getConstraintTolerance(), 1e-5) << integrator->className();
        for (double bad : {0.0, -1e-5, 1.0, (double) NAN})
            expectErrorNaming([&] { integrator->setConstraintTolerance(bad); }, "constraintTolerance");
        EXPECT_EQ(integrator->getConstraintTolerance(), 1e-5) << integrator->className();
    }
}

#if OPENMMDPD_HAVE_CPU

TEST_P(ConstraintsAndSites, CpuFollowsTheReferenceTrajectory) {
    // Without sites too: then every particle is in the thermostat, which the CPU platform's
    // loops take as leave to run in the pair search's order, and the constraints must still act.
    const Scheme& scheme = GetParam();
    for (bool sites : {true, false}) {
        Dimers d = makeDimers(100);
        if (sites)
            addSites(d);
        Simulation reference = start(d, scheme, "Reference"), cpu = start(d, scheme, "CPU");
        reference.integrator->step(5);
        cpu.integrator->step(5);
        const State a = reference.context->getState(State::Positions | State::Velocities);
        const State b = cpu.context->getState(State::Positions | State::Velocities);
        EXPECT_LT(relativeDifference(a.getPositions(), b.getPositions()), 1e-10) << scheme.name << (sites ? " with sites" : "");
        EXPECT_LT(relativeDifference(a.getVelocities(), b.getVelocities()), 1e-10) << scheme.name << (sites ? " with sites" : "");
    }
}
#endif

INSTANTIATE_TEST_SUITE_P(EveryScheme, ConstraintsAndSites, testing::ValuesIn(SCHEMES),
                         [](const testing::TestParamInfo<Scheme>& info) {
                             std::string name = info.param.name;
                             name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
                             return name;
                         });

TEST(ConstraintsAndSites, StaggeredRefusesConstraintsAndVirtualSites) {
    for (bool sites : {false, true}) {
        Dimers d = makeDimers(40);
        if (sites) {
            for (int c = d.system->getNumConstraints() - 1; c >= 0; c--)
                d.system->removeConstraint(c);
            addSites(d);
        }
        CustomBondForce* fast = new CustomBondForce("0");
        fast->addBond(0, 1);
        fast->setForceGroup(1);
        d.system->addForce(fast);
        StaggeredDPDIntegrator integrator(KT_KELVIN, 4.5, 1.0, DT, 2);
        integrator.setFastForceGroups(1 << 1);
        for (const std::string& platform : platforms())
            expectErrorNaming([&] { Context context(*d.system, integrator, Platform::getPlatformByName(platform)); },
                              sites ? "virtual sites" : "constraints");
    }
}

} // namespace
