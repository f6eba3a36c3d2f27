// The CPU platform (fast: threads, SIMD, fused passes, cell-sorted slots) against the
// Reference platform (plain loops that read like algorithms.md): the same trajectory to
// 1e-10 relative after 1, 3 and 20 steps, for every integrator and variant, with one and
// two threads.  The systems are made to reach the corners: mixed masses, two particle types
// with their own type-pair parameters, and a triclinic box.

#include "TestHelpers.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include <functional>

using namespace DPDPlugin;

#if OPENMMDPD_HAVE_CPU
namespace {

constexpr int NUM_PARTICLES = 500;
constexpr double DT = 0.02;
// Only float summation order differs between the platforms; chaos amplifies that by
// about 10^2 over 20 steps here, from ~1e-16.
constexpr double TOLERANCE = 1e-10;

/** Particle i: type i % 2, mass 2 for every third particle (so types and masses mix). */
int typeOf(int i) { return i % 2; }
double massOf(int i) { return i % 3 == 0 ? 2.0 : 1.0; }

/** A triclinic periodic box at density ~3.8; with soft repulsion (its own type pairs) or none. */
System* makeSystem(bool soft, std::vector<Vec3>& positions, std::vector<Vec3>& velocities) {
    const Vec3 a(5.2, 0, 0), b(1.1, 5.0, 0), c(-0.9, 1.3, 5.1);
    System* system = new System();
    system->setDefaultPeriodicBoxVectors(a, b, c);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uniform(0, 1);
    std::normal_distribution<double> normal(0, 1);
    for (int i = 0; i < NUM_PARTICLES; i++) {
        system->addParticle(massOf(i));
        positions.push_back(a * uniform(rng) + b * uniform(rng) + c * uniform(rng));
        const double scale = std::sqrt(1.0 / massOf(i));  // kT = 1 kJ/mol
        velocities.push_back(Vec3(normal(rng), normal(rng), normal(rng)) * scale);
    }
    if (soft) {
        DPDSoftRepulsionForce* force = new DPDSoftRepulsionForce(25.0, 1.0);
        for (int i = 0; i < NUM_PARTICLES; i++)
            force->setParticleType(i, typeOf(i));
        force->addTypePair(0, 1, 40.0, 0.9);
        system->addForce(force);
    }
    else {
        CustomBondForce* none = new CustomBondForce("0");  // marks the System periodic
        none->setUsesPeriodicBoundaryConditions(true);
        system->addForce(none);
    }
    return system;
}

/** The thermostat's types and type pairs, and a fixed seed, on any of our integrators. */
DPDThermostatIntegrator* withTypes(DPDThermostatIntegrator* integrator) {
    for (int i = 0; i < NUM_PARTICLES; i++)
        integrator->setParticleType(i, typeOf(i));
    integrator->addTypePair(0, 1, 3.0, 0.9);
    integrator->addTypePair(1, 1, 6.0, 1.0);
    integrator->setRandomNumberSeed(1234);
    return integrator;
}

DPDThermostatIntegrator* dpdvv(DPDVVIntegrator::Variant variant, double lambda) {
    DPDVVIntegrator* integrator = new DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, DT);
    integrator->setVariant(variant);
    integrator->setLambda(lambda);
    return integrator;
}

DPDThermostatIntegrator* shardlow(int order) {
    ShardlowIntegrator* integrator = new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, DT);
    integrator->setOrder(order);
    return integrator;
}

DPDThermostatIntegrator* lowe(LoweAndersenIntegrator::Method method) {
    LoweAndersenIntegrator* integrator = new LoweAndersenIntegrator(KT_KELVIN, 4.5, 1.0, DT);
    integrator->setMethod(method);
    return integrator;
}

DPDThermostatIntegrator* edpd(EDPDIntegrator::Scheme scheme) {
    EDPDIntegrator* integrator = new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, DT);
    integrator->setScheme(scheme);
    return integrator;
}

struct Scheme {
    std::string name;
    std::function<DPDThermostatIntegrator*()> make;
};

void PrintTo(const Scheme& scheme, std::ostream* out) {
    *out << scheme.name;
}

const std::vector<Scheme> SCHEMES = {
    {"GW-0.5", [] { return dpdvv(DPDVVIntegrator::GrootWarren, 0.5); }},
    {"GW-0.65", [] { return dpdvv(DPDVVIntegrator::GrootWarren, 0.65); }},
    {"DPD-VV", [] { return dpdvv(DPDVVIntegrator::DPDVV, 0.5); }},
    {"SC-VV", [] { return dpdvv(DPDVVIntegrator::SelfConsistent, 0.5); }},
    {"S1", [] { return shardlow(1); }},
    {"S2", [] { return shardlow(2); }},
    {"Lowe", [] { return lowe(LoweAndersenIntegrator::Lowe); }},
    {"PairOU", [] { return lowe(LoweAndersenIntegrator::PairOrnsteinUhlenbeck); }},
    {"EDPD-OneSided", [] { return edpd(EDPDIntegrator::OneSided); }},
    {"EDPD-Symmetric", [] { return edpd(EDPDIntegrator::Symmetric); }},
};

/** max |a - b| / max |a| over the particles (0 if a is all zero). */
double relativeDifference(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
    double difference = 0, scale = 0;
    for (size_t i = 0; i < a.size(); i++) {
        const Vec3 d = a[i] - b[i];
        difference = std::max(difference, std::sqrt(d.dot(d)));
        scale = std::max(scale, std::sqrt(a[i].dot(a[i])));
    }
    return scale > 0 ? difference / scale : difference;
}

struct Simulation {
    std::unique_ptr<DPDThermostatIntegrator> integrator;
    std::unique_ptr<Context> context;
};

Simulation start(System& system, const Scheme& scheme, const std::string& platform, int threads, const std::vector<Vec3>& positions,
          const std::vector<Vec3>& velocities) {
    Simulation run;
    run.integrator.reset(withTypes(scheme.make()));
    std::map<std::string, std::string> properties;
    if (platform == "CPU")
        properties["Threads"] = std::to_string(threads);
    run.context.reset(new Context(system, *run.integrator, Platform::getPlatformByName(platform), properties));
    run.context->setPositions(positions);
    run.context->setVelocities(velocities);
    return run;
}

class PlatformsAgree : public testing::TestWithParam<std::tuple<Scheme, bool>> {};

TEST_P(PlatformsAgree, CpuOnOneAndTwoThreadsFollowsTheReferenceTrajectory) {
    const Scheme& scheme = std::get<0>(GetParam());
    const bool soft = std::get<1>(GetParam());
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeSystem(soft, positions, velocities));
    Simulation reference = start(*system, scheme, "Reference", 1, positions, velocities);
    std::vector<Simulation> cpu;
    for (int threads : {1, 2})
        cpu.push_back(start(*system, scheme, "CPU", threads, positions, velocities));
    int done = 0;
    for (int checkpoint : {1, 3, 20}) {
        reference.integrator->step(checkpoint - done);
        const State expected = reference.context->getState(State::Positions | State::Velocities);
        for (size_t k = 0; k < cpu.size(); k++) {
            cpu[k].integrator->step(checkpoint - done);
            const State actual = cpu[k].context->getState(State::Positions | State::Velocities);
            const double dr = relativeDifference(expected.getPositions(), actual.getPositions());
            const double dv = relativeDifference(expected.getVelocities(), actual.getVelocities());
            EXPECT_LT(dr, TOLERANCE) << scheme.name << ", " << k + 1 << " thread(s), positions after " << checkpoint << " steps";
            EXPECT_LT(dv, TOLERANCE) << scheme.name << ", " << k + 1 << " thread(s), velocities after " << checkpoint << " steps";
        }
        done = checkpoint;
    }
}

TEST(PlatformsAgree, EDPDForgetsAndRecallsPairsAlike) {
    // alpha dt = 1: a pair variable is forgotten after 27 steps and the archive is cleaned
    // every 6, so in 60 steps pairs leave, come back, are caught up, redrawn and dropped.
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeSystem(true, positions, velocities));
    for (EDPDIntegrator::Scheme scheme : {EDPDIntegrator::OneSided, EDPDIntegrator::Symmetric}) {
        Scheme fast{"EDPD-alpha-50", [scheme] {
            EDPDIntegrator* integrator = new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 50.0, DT);
            integrator->setScheme(scheme);
            return integrator;
        }};
        Simulation reference = start(*system, fast, "Reference", 1, positions, velocities);
        Simulation cpu = start(*system, fast, "CPU", 2, positions, velocities);
        reference.integrator->step(60);
        cpu.integrator->step(60);
        const State a = reference.context->getState(State::Positions | State::Velocities);
        const State b = cpu.context->getState(State::Positions | State::Velocities);
        EXPECT_LT(relativeDifference(a.getPositions(), b.getPositions()), TOLERANCE) << "scheme " << scheme;
        EXPECT_LT(relativeDifference(a.getVelocities(), b.getVelocities()), TOLERANCE) << "scheme " << scheme;
        const EDPDIntegrator& r = static_cast<const EDPDIntegrator&>(*reference.integrator);
        const EDPDIntegrator& c = static_cast<const EDPDIntegrator&>(*cpu.integrator);
        EXPECT_EQ(r.getNumPairVariables(), c.getNumPairVariables()) << "scheme " << scheme;
    }
}

/** Every thermostat setter of a live Context, at once: hotter, more friction, other types and type pairs. */
void changeThermostat(DPDThermostatIntegrator& integrator) {
    integrator.setTemperature(2 * KT_KELVIN);
    integrator.setDefaultFriction(6.0);
    integrator.setDefaultCutoff(0.95);
    integrator.setParticleType(4, 1);
    integrator.setTypePairParameters(0, 0, 1, 2.0, 0.8);
    integrator.addTypePair(0, 0, 5.0, 1.0);
}

TEST_P(PlatformsAgree, LiveThermostatChangesTakeEffectAlike) {
    // The setters change the dynamics from the next step on (not only what the getters
    // return), the same way on both platforms.
    const Scheme& scheme = std::get<0>(GetParam());
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeSystem(std::get<1>(GetParam()), positions, velocities));
    Simulation reference = start(*system, scheme, "Reference", 1, positions, velocities);
    Simulation cpu = start(*system, scheme, "CPU", 2, positions, velocities);
    Simulation unchanged = start(*system, scheme, "CPU", 2, positions, velocities);
    for (Simulation* s : {&reference, &cpu, &unchanged})
        s->integrator->step(3);
    changeThermostat(*reference.integrator);
    changeThermostat(*cpu.integrator);
    for (Simulation* s : {&reference, &cpu, &unchanged})
        s->integrator->step(5);
    const State a = reference.context->getState(State::Velocities), b = cpu.context->getState(State::Velocities);
    const State c = unchanged.context->getState(State::Velocities);
    EXPECT_LT(relativeDifference(a.getVelocities(), b.getVelocities()), TOLERANCE) << scheme.name;
    EXPECT_GT(relativeDifference(c.getVelocities(), b.getVelocities()), 1e-3) << scheme.name << ": the change had no effect";
}

std::string caseName(const testing::TestParamInfo<PlatformsAgree::ParamType>& info) {
    std::string name = std::get<0>(info.param).name + (std::get<1>(info.param) ? "_soft" : "_ideal");
    for (char& c : name)
        if (!std::isalnum((unsigned char) c))
            c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(EveryIntegrator, PlatformsAgree, testing::Combine(testing::ValuesIn(SCHEMES), testing::Bool()), caseName);

} // namespace
#endif
