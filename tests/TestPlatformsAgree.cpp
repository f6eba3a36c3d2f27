// The CPU platform (fast: threads, SIMD, fused passes, cell-sorted slots) against the
// Reference platform (plain loops that read like docs/theory/): the same trajectory to
// 1e-10 relative after 1, 3 and 20 steps, for every integrator and variant, with one and
// two threads.  The systems are made to reach the corners: mixed masses, two particle types
// with their own type-pair parameters, and a triclinic box.

#include "TestHelpers.h"
#include "TestSchemes.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include <functional>

using namespace DPDPlugin;

#if OPENMMDPD_HAVE_CPU
namespace {

constexpr int NUM_PARTICLES = 500;
constexpr double DT = 0.02;
// Only float summation order differs between the platforms; chaos amplifies that by
// about 10^2 over 20 steps here, from ~1e-16.
constexpr double TOLERANCE = 1e-10;

/**
 * Particle i: type i % 2, mass 2 for every third particle (so types and masses mix), or 1
 * for integrators that take one mass only.
 */
int typeOf(int i) { return i % 2; }
double massOf(int i, bool uniformMasses) { return i % 3 == 0 && !uniformMasses ? 2.0 : 1.0; }

/** A triclinic periodic box at density ~3.8; with soft repulsion (its own type pairs) or none. */
System* makeSystem(bool soft, std::vector<Vec3>& positions, std::vector<Vec3>& velocities, bool uniformMasses = false) {
    const Vec3 a(5.2, 0, 0), b(1.1, 5.0, 0), c(-0.9, 1.3, 5.1);
    System* system = new System();
    system->setDefaultPeriodicBoxVectors(a, b, c);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> uniform(0, 1);
    std::normal_distribution<double> normal(0, 1);
    for (int i = 0; i < NUM_PARTICLES; i++) {
        system->addParticle(massOf(i, uniformMasses));
        positions.push_back(a * uniform(rng) + b * uniform(rng) + c * uniform(rng));
        const double scale = std::sqrt(1.0 / massOf(i, uniformMasses));  // kT = 1 kJ/mol
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

const std::vector<Scheme> SCHEMES = schemesAt(DT);


struct Simulation {
    std::unique_ptr<DPDThermostatIntegrator> integrator;
    std::unique_ptr<Context> context;
};

/** Changes made to a fresh integrator after withTypes (or instead of it). */
typedef std::function<void(DPDThermostatIntegrator&)> Configure;

Simulation start(System& system, const Scheme& scheme, const std::string& platform, int threads, const std::vector<Vec3>& positions,
          const std::vector<Vec3>& velocities, const Configure& configure = nullptr, bool typed = true) {
    Simulation run;
    run.integrator.reset(scheme.make());
    if (typed)
        withTypes(run.integrator.get());
    else
        run.integrator->setRandomNumberSeed(1234);
    if (configure)
        configure(*run.integrator);
    std::map<std::string, std::string> properties;
    if (platform == "CPU")
        properties["Threads"] = std::to_string(threads);
    run.context.reset(new Context(system, *run.integrator, Platform::getPlatformByName(platform), properties));
    run.context->setPositions(positions);
    run.context->setVelocities(velocities);
    return run;
}

/** The CPU on 1 and 2 threads follows the Reference to TOLERANCE after 1, 3 and 20 steps. */
void expectCpuFollowsReference(System& system, const Scheme& scheme, const std::vector<Vec3>& positions,
                               const std::vector<Vec3>& velocities, const Configure& configure = nullptr, bool typed = true) {
    Simulation reference = start(system, scheme, "Reference", 1, positions, velocities, configure, typed);
    std::vector<Simulation> cpu;
    for (int threads : {1, 2})
        cpu.push_back(start(system, scheme, "CPU", threads, positions, velocities, configure, typed));
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

class PlatformsAgree : public testing::TestWithParam<std::tuple<Scheme, bool>> {};

TEST_P(PlatformsAgree, CpuOnOneAndTwoThreadsFollowsTheReferenceTrajectory) {
    const Scheme& scheme = std::get<0>(GetParam());
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeSystem(std::get<1>(GetParam()), positions, velocities, scheme.uniformMasses));
    expectCpuFollowsReference(*system, scheme, positions, velocities);
}

bool isEDPD(const DPDThermostatIntegrator& integrator) {
    return dynamic_cast<const EDPDIntegrator*>(&integrator) != nullptr;
}

/** Whether the scheme's thermostat has a weight function (Lowe's collisions have none; EDPD refuses exponents other than 2). */
bool hasWeights(const DPDThermostatIntegrator& integrator) {
    const LoweAndersenIntegrator* lowe = dynamic_cast<const LoweAndersenIntegrator*>(&integrator);
    const StaggeredDPDIntegrator* staggered = dynamic_cast<const StaggeredDPDIntegrator*>(&integrator);
    return !isEDPD(integrator) && !(lowe && lowe->getMethod() == LoweAndersenIntegrator::Lowe) &&
           !(staggered && staggered->getBaseScheme() == StaggeredDPDIntegrator::LoweAndersen);
}

TEST_P(PlatformsAgree, WeightExponentsFollowTheReference) {
    // s = 1 by default and 0.5 for type pair (1, 1), with the type pairs of withTypes; and a
    // fluid of one type and one mass with s = 0.5, which the CPU must not take for the
    // standard fluid its vector paths serve.  (EDPD refuses exponents other than 2.)
    const Scheme& scheme = std::get<0>(GetParam());
    std::unique_ptr<DPDThermostatIntegrator> probe(scheme.make());
    if (isEDPD(*probe))
        return;
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeSystem(std::get<1>(GetParam()), positions, velocities, scheme.uniformMasses));
    expectCpuFollowsReference(*system, scheme, positions, velocities, [](DPDThermostatIntegrator& i) {
        i.setDefaultWeightExponent(1.0);
        i.setTypePairWeightExponent(1, 0.5);
    });
    positions.clear();
    velocities.clear();
    std::unique_ptr<System> uniform(makeSystem(false, positions, velocities, true));
    expectCpuFollowsReference(*uniform, scheme, positions, velocities,
                              [](DPDThermostatIntegrator& i) { i.setDefaultWeightExponent(0.5); }, false);
}

/** Exceptions for every pair of particles 1, 2 and 3 apart in index (factors 0, 0.25, 0.5): about a fifth of the pairs in range. */
void addExceptions(DPDThermostatIntegrator& integrator) {
    const double factors[3] = {0.0, 0.25, 0.5};
    for (int i = 0; i < NUM_PARTICLES; i++)
        for (int gap = 1; gap <= 3; gap++)
            if (i + gap < NUM_PARTICLES)
                integrator.addThermostatException(i, i + gap, factors[gap - 1]);
}

TEST_P(PlatformsAgree, ThermostatExceptionsFollowTheReference) {
    // With the type pairs of withTypes, and in a fluid of one type and one mass (which the
    // CPU must not take for the standard fluid its vector paths serve).
    const Scheme& scheme = std::get<0>(GetParam());
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeSystem(std::get<1>(GetParam()), positions, velocities, scheme.uniformMasses));
    expectCpuFollowsReference(*system, scheme, positions, velocities, addExceptions);
    positions.clear();
    velocities.clear();
    std::unique_ptr<System> uniform(makeSystem(false, positions, velocities, true));
    expectCpuFollowsReference(*uniform, scheme, positions, velocities, addExceptions, false);
}

/** Whether the scheme has transverse friction: the velocity-Verlet family, Shardlow, and the pair OU method. */
bool hasTransverse(const DPDThermostatIntegrator& integrator) {
    const LoweAndersenIntegrator* lowe = dynamic_cast<const LoweAndersenIntegrator*>(&integrator);
    return dynamic_cast<const DPDVVIntegrator*>(&integrator) != nullptr || dynamic_cast<const ShardlowIntegrator*>(&integrator) != nullptr ||
           (lowe != nullptr && lowe->getMethod() == LoweAndersenIntegrator::PairOrnsteinUhlenbeck);
}

TEST_P(PlatformsAgree, TransverseFrictionFollowsTheReference) {
    // gamma_perp 3 with s_perp 1 by default and 6 with 0.5 for type pair (1, 1), with the
    // exceptions of addExceptions (which scale it too); and a fluid of one type and one mass
    // with gamma_perp = gamma, which the CPU must not take for the standard fluid its vector
    // paths serve.
    const Scheme& scheme = std::get<0>(GetParam());
    std::unique_ptr<DPDThermostatIntegrator> probe(scheme.make());
    if (!hasTransverse(*probe))
        return;
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeSystem(std::get<1>(GetParam()), positions, velocities, scheme.uniformMasses));
    expectCpuFollowsReference(*system, scheme, positions, velocities, [](DPDThermostatIntegrator& i) {
        i.setDefaultTransverseFriction(3.0);
        i.setDefaultTransverseWeightExponent(1.0);
        i.setTypePairTransverseFriction(1, 6.0, 0.5);
        addExceptions(i);
    });
    positions.clear();
    velocities.clear();
    std::unique_ptr<System> uniform(makeSystem(false, positions, velocities, true));
    expectCpuFollowsReference(*uniform, scheme, positions, velocities,
                              [](DPDThermostatIntegrator& i) { i.setDefaultTransverseFriction(4.5); }, false);
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

/**
 * One setter of a live Context: what it changes, on the integrators where it means
 * something (e.g. lambda on the GrootWarren variant only).
 */
struct LiveSetter {
    std::string name;
    std::function<void(DPDThermostatIntegrator&)> change;
    std::function<bool(const DPDThermostatIntegrator&)> appliesTo;
};

template <class T>
LiveSetter setterOf(const std::string& name, std::function<void(T&)> change,
                    std::function<bool(const T&)> appliesTo = [](const T&) { return true; }) {
    return {name, [change](DPDThermostatIntegrator& i) { change(dynamic_cast<T&>(i)); },
            [appliesTo](const DPDThermostatIntegrator& i) {
                const T* t = dynamic_cast<const T*>(&i);
                return t != nullptr && appliesTo(*t);
            }};
}

using Staggered = StaggeredDPDIntegrator;
bool vvBase(const Staggered& i) { return i.getBaseScheme() == Staggered::VelocityVerlet; }

/** Every setter of every integrator class but setBaseScheme (which raises, below). */
const std::vector<LiveSetter> LIVE_SETTERS = {
    setterOf<DPDThermostatIntegrator>("setTemperature", [](auto& i) { i.setTemperature(2 * KT_KELVIN); }),
    setterOf<DPDThermostatIntegrator>("setDefaultFriction", [](auto& i) { i.setDefaultFriction(6.0); }),
    setterOf<DPDThermostatIntegrator>("setDefaultCutoff", [](auto& i) { i.setDefaultCutoff(0.95); }),
    setterOf<DPDThermostatIntegrator>("setParticleType", [](auto& i) { i.setParticleType(4, 1); }),
    setterOf<DPDThermostatIntegrator>("addTypePair", [](auto& i) { i.addTypePair(0, 0, 5.0, 1.0); }),
    setterOf<DPDThermostatIntegrator>("setTypePairParameters", [](auto& i) { i.setTypePairParameters(0, 0, 1, 2.0, 0.8); }),
    setterOf<DPDThermostatIntegrator>("setRandomNumberSeed", [](auto& i) { i.setRandomNumberSeed(99); }),
    setterOf<DPDThermostatIntegrator>("setDefaultWeightExponent", [](auto& i) { i.setDefaultWeightExponent(1.0); }, hasWeights),
    setterOf<DPDThermostatIntegrator>("setTypePairWeightExponent", [](auto& i) { i.setTypePairWeightExponent(0, 0.5); }, hasWeights),
    setterOf<DPDThermostatIntegrator>("setDefaultTransverseFriction", [](auto& i) { i.setDefaultTransverseFriction(4.5); },
                                      hasTransverse),
    setterOf<DPDThermostatIntegrator>("setTypePairTransverseFriction", [](auto& i) { i.setTypePairTransverseFriction(0, 6.0, 1.0); },
                                      hasTransverse),
    setterOf<DPDThermostatIntegrator>("addThermostatException", [](auto& i) {
        for (int j = 1; j < NUM_PARTICLES; j++)
            i.addThermostatException(0, j, 0.0);
    }),
    setterOf<DPDThermostatIntegrator>("setStepSize", [](auto& i) { i.setStepSize(0.015); }),
    // Group 1 only: the soft force (group 0) is left out, the bonds kept.
    setterOf<DPDThermostatIntegrator>("setIntegrationForceGroups", [](auto& i) { i.setIntegrationForceGroups(1 << 1); }),
    setterOf<DPDVVIntegrator>("setVariant", [](auto& i) { i.setVariant(DPDVVIntegrator::Variant((i.getVariant() + 1) % 3)); }),
    setterOf<DPDVVIntegrator>("setLambda", [](auto& i) { i.setLambda(0.8); },
                              [](auto& i) { return i.getVariant() == DPDVVIntegrator::GrootWarren; }),
    setterOf<DPDVVIntegrator>("setMaxIterations", [](auto& i) { i.setMaxIterations(1); },
                              [](auto& i) { return i.getVariant() == DPDVVIntegrator::SelfConsistent; }),
    setterOf<DPDVVIntegrator>("setTolerance", [](auto& i) { i.setTolerance(0.5); },
                              [](auto& i) { return i.getVariant() == DPDVVIntegrator::SelfConsistent; }),
    setterOf<ShardlowIntegrator>("setOrder", [](auto& i) { i.setOrder(3 - i.getOrder()); }),
    setterOf<LoweAndersenIntegrator>("setMethod", [](auto& i) { i.setMethod(LoweAndersenIntegrator::Method(1 - i.getMethod())); }),
    setterOf<LoweAndersenIntegrator>("setSplitting",
                                     [](auto& i) { i.setSplitting(LoweAndersenIntegrator::Splitting(1 - i.getSplitting())); }),
    setterOf<EDPDIntegrator>("setAlpha", [](auto& i) { i.setAlpha(3.0); }),
    setterOf<EDPDIntegrator>("setScheme", [](auto& i) { i.setScheme(EDPDIntegrator::Scheme(1 - i.getScheme())); }),
    setterOf<DenOtterClarkeIntegrator>("setAverageFDDotV", [](auto& i) { i.setAverageFDDotV(-6.0); }),
    setterOf<DenOtterClarkeIntegrator>("setAverageFDDotFD", [](auto& i) { i.setAverageFDDotFD(20.0); }),
    setterOf<DenOtterClarkeIntegrator>("setAverageFRDotFR", [](auto& i) { i.setAverageFRDotFR(12.0); }),
    setterOf<Staggered>("setNumSubSteps", [](auto& i) { i.setNumSubSteps(3); }),
    setterOf<Staggered>("setLambda", [](auto& i) { i.setLambda(0.3); }, vvBase),
    setterOf<Staggered>("setMu", [](auto& i) { i.setMu(0.5); }),
    setterOf<Staggered>("setA", [](auto& i) { i.setA(-0.5); }, vvBase),
    setterOf<Staggered>("setB", [](auto& i) { i.setB(0.9); }),
    setterOf<Staggered>("setRelaxationParameters", [](auto& i) { i.setRelaxationParameters(0.2, 0.1, 0.8); }),
    setterOf<Staggered>("setWeighted", [](auto& i) { i.setWeighted(!i.getWeighted()); }),
    setterOf<Staggered>("setFastForceGroups", [](auto& i) { i.setFastForceGroups(1 << 2); }),
    setterOf<Staggered>("setPolymerParticles", [](auto& i) { i.setPolymerParticles({0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11}); }),
    setterOf<Staggered>("addPolymerParticle", [](auto& i) { i.addPolymerParticle(30); },
                        [](auto& i) { return !i.getPolymerParticles().empty(); }),
    setterOf<Staggered>("useRecommendedParameters", [](auto& i) { i.useRecommendedParameters(); },
                        [](auto& i) { return i.getMu() != 0; }),
};

DPDThermostatIntegrator* staggered(Staggered::BaseScheme base) {
    // K = 2: the polymer is sub-cycled (on the CPU in its side Contexts); relaxation
    // parameters away from the recommendation, so that useRecommendedParameters changes them.
    Staggered* integrator = new Staggered(KT_KELVIN, 4.5, 1.0, DT, 2);
    integrator->setBaseScheme(base);
    integrator->setRelaxationParameters(0.3, 0.3, 0.3);
    return integrator;
}

/** Every integrator, the staggered one with either base; both with an explicit polymer list. */
std::vector<Scheme> liveSchemes() {
    std::vector<Scheme> schemes = SCHEMES;
    for (Staggered::BaseScheme base : {Staggered::VelocityVerlet, Staggered::LoweAndersen}) {
        const std::string name = base == Staggered::VelocityVerlet ? "Staggered-VV" : "Staggered-Lowe";
        schemes.push_back({name, [base] { return staggered(base); }});
        schemes.push_back({name + "-explicit", [base] {
            DPDThermostatIntegrator* integrator = staggered(base);
            static_cast<Staggered*>(integrator)->setPolymerParticles({0, 1, 2, 3, 4, 5, 6, 7, 20, 21, 22, 23});
            return integrator;
        }});
    }
    return schemes;
}

/** makeSystem(soft) with harmonic bonds in force groups 1 (0-1, 2-3, ...; 6-7) and 2 (20-21, 22-23). */
System* makeBondedSystem(std::vector<Vec3>& positions, std::vector<Vec3>& velocities, bool uniformMasses) {
    System* system = makeSystem(true, positions, velocities, uniformMasses);
    for (int group : {1, 2}) {
        CustomBondForce* bonds = new CustomBondForce("2*(r-0.5)^2");
        bonds->setUsesPeriodicBoundaryConditions(true);
        bonds->setForceGroup(group);
        for (int i = (group == 1 ? 0 : 20); i < (group == 1 ? 8 : 24); i += 2)
            bonds->addBond(i, i + 1, {});
        system->addForce(bonds);
    }
    return system;
}

struct LiveCase {
    Scheme scheme;
    LiveSetter setter;
};

std::vector<LiveCase> liveCases() {
    std::vector<LiveCase> cases;
    for (const Scheme& scheme : liveSchemes()) {
        std::unique_ptr<DPDThermostatIntegrator> integrator(withTypes(scheme.make()));
        for (const LiveSetter& setter : LIVE_SETTERS)
            if (setter.appliesTo(*integrator))
                cases.push_back({scheme, setter});
    }
    return cases;
}

void PrintTo(const LiveCase& c, std::ostream* out) {
    *out << c.scheme.name << " " << c.setter.name;
}

class LiveSetters : public testing::TestWithParam<LiveCase> {};

TEST_P(LiveSetters, TakeEffectAtTheNextStepAlike) {
    // A setter called on a live Context changes the dynamics from the next step on (not only
    // what the getter returns), the same way on both platforms.
    const LiveCase& c = GetParam();
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeBondedSystem(positions, velocities, c.scheme.uniformMasses));
    Simulation reference = start(*system, c.scheme, "Reference", 1, positions, velocities);
    Simulation cpu = start(*system, c.scheme, "CPU", 2, positions, velocities);
    Simulation unchanged = start(*system, c.scheme, "CPU", 2, positions, velocities);
    for (Simulation* s : {&reference, &cpu, &unchanged})
        s->integrator->step(3);
    c.setter.change(*reference.integrator);
    c.setter.change(*cpu.integrator);
    for (Simulation* s : {&reference, &cpu, &unchanged})
        s->integrator->step(5);
    const State a = reference.context->getState(State::Velocities), b = cpu.context->getState(State::Velocities);
    const State d = unchanged.context->getState(State::Velocities);
    EXPECT_LT(relativeDifference(a.getVelocities(), b.getVelocities()), TOLERANCE);
    // Ignored, the run would be bit for bit the unchanged one; some changes (the polymer's
    // sub-steps) move only a few particles a little.
    EXPECT_GT(relativeDifference(d.getVelocities(), b.getVelocities()), 1e4 * TOLERANCE) << "the change had no effect";
}

std::string liveCaseName(const testing::TestParamInfo<LiveCase>& info) {
    std::string name = info.param.scheme.name + "_" + info.param.setter.name;
    for (char& c : name)
        if (!std::isalnum((unsigned char) c))
            c = '_';
    return name;
}

INSTANTIATE_TEST_SUITE_P(EverySetter, LiveSetters, testing::ValuesIn(liveCases()), liveCaseName);

TEST(LiveSetters, StaggeredBaseSchemeRaisesUntilReinitialize) {
    // The base scheme decides what the Context's dynamics holds (the pair order, what the
    // slow force is): it cannot change under a live Context, and the next step says so.
    std::vector<Vec3> positions, velocities;
    std::unique_ptr<System> system(makeBondedSystem(positions, velocities, false));
    const Scheme scheme{"Staggered-VV", [] { return staggered(Staggered::VelocityVerlet); }};
    for (const std::string platform : {"Reference", "CPU"}) {
        Simulation s = start(*system, scheme, platform, 1, positions, velocities);
        s.integrator->step(1);
        static_cast<Staggered&>(*s.integrator).setBaseScheme(Staggered::LoweAndersen);
        expectErrorNaming([&] { s.integrator->step(1); }, "reinitialize");
        expectErrorNaming([&] { s.integrator->step(1); }, "setBaseScheme");
        s.context->reinitialize(true);
        s.integrator->step(2);
        EXPECT_EQ(s.context->getState(0).getStepCount(), 3) << platform;
    }
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
