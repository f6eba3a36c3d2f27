// What the checkpoint tests share (TestCheckpoints.cpp, and the device's in TestGpuPlatform.cpp):
// a System, every integrator class and variant, a run a few steps in, and the offsets and
// checksum of a checkpoint's integrator part, so that a test can damage one field behind a
// valid checksum.

#ifndef OPENMMDPD_CHECKPOINTTESTING_H_
#define OPENMMDPD_CHECKPOINTTESTING_H_

#include "TestHelpers.h"
#include "openmmdpd/DPDSoftRepulsionForce.h"
#include "openmmdpd/DPDVVIntegrator.h"
#include "openmmdpd/DenOtterClarkeIntegrator.h"
#include "openmmdpd/EDPDIntegrator.h"
#include "openmmdpd/LoweAndersenIntegrator.h"
#include "openmmdpd/ShardlowIntegrator.h"
#include "openmmdpd/StaggeredDPDIntegrator.h"
#include "openmm/HarmonicBondForce.h"
#include <cstdint>
#include <cstring>
#include <functional>
#include <sstream>
#include <stdexcept>
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace CheckpointTesting {

using namespace DPDPlugin;

constexpr int NUM_PARTICLES = 300;
constexpr int CHAIN_LENGTH = 5;
constexpr double DT = 0.02;
constexpr int STEPS_BEFORE = 5, STEPS_AFTER = 3;

/** A soft fluid at density ~4 with a harmonic 5-bead chain in force group 1 (for the staggered scheme). */
inline System* makeSystem(std::vector<Vec3>& positions) {
    const double box = std::cbrt(NUM_PARTICLES / 4.0);
    System* system = new System();
    system->setDefaultPeriodicBoxVectors(Vec3(box, 0, 0), Vec3(0, box, 0), Vec3(0, 0, box));
    DPDSoftRepulsionForce* soft = new DPDSoftRepulsionForce(25.0, 1.0);
    HarmonicBondForce* chain = new HarmonicBondForce();
    chain->setForceGroup(1);
    chain->setUsesPeriodicBoundaryConditions(true);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> uniform(0, box);
    for (int i = 0; i < NUM_PARTICLES; i++) {
        system->addParticle(1.0);
        if (i > 0 && i < CHAIN_LENGTH) {
            positions.push_back(positions.back() + Vec3(0.5, 0, 0));
            chain->addBond(i - 1, i, 0.5, 50.0);
        }
        else
            positions.push_back(Vec3(uniform(rng), uniform(rng), uniform(rng)));
    }
    system->addForce(soft);
    system->addForce(chain);
    return system;
}

struct Scheme {
    std::string name;
    std::function<Integrator*()> make;
};

template <class T>
T* seeded(T* integrator) {
    integrator->setRandomNumberSeed(77);
    return integrator;
}

inline Integrator* dpdvv(DPDVVIntegrator::Variant variant) {
    DPDVVIntegrator* integrator = seeded(new DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrator->setVariant(variant);
    return integrator;
}

inline Integrator* shardlow(int order) {
    ShardlowIntegrator* integrator = seeded(new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrator->setOrder(order);
    return integrator;
}

inline Integrator* lowe(LoweAndersenIntegrator::Method method, LoweAndersenIntegrator::Splitting splitting = LoweAndersenIntegrator::AfterVerlet) {
    LoweAndersenIntegrator* integrator = seeded(new LoweAndersenIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrator->setMethod(method);
    integrator->setSplitting(splitting);
    return integrator;
}

inline Integrator* edpd(EDPDIntegrator::Scheme scheme) {
    EDPDIntegrator* integrator = seeded(new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, DT));
    integrator->setScheme(scheme);
    return integrator;
}

inline Integrator* staggered(StaggeredDPDIntegrator::BaseScheme base) {
    StaggeredDPDIntegrator* integrator = seeded(new StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, DT, 1));
    integrator->setBaseScheme(base);
    return integrator;
}

inline Integrator* denOtterClarke() {
    DenOtterClarkeIntegrator* integrator = seeded(new DenOtterClarkeIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrator->setAverageFDDotV(-4.985245);  // model B (Nikunen et al. 2003, Table III)
    integrator->setAverageFDDotFD(14.507340);
    integrator->setAverageFRDotFR(9.976453);
    return integrator;
}

const std::vector<Scheme> SCHEMES = {
    {"GW", [] { return dpdvv(DPDVVIntegrator::GrootWarren); }},
    {"DPD-VV", [] { return dpdvv(DPDVVIntegrator::DPDVV); }},
    {"SC-VV", [] { return dpdvv(DPDVVIntegrator::SelfConsistent); }},
    {"S1", [] { return shardlow(1); }},
    {"S2", [] { return shardlow(2); }},
    {"Lowe", [] { return lowe(LoweAndersenIntegrator::Lowe); }},
    {"PairOU", [] { return lowe(LoweAndersenIntegrator::PairOrnsteinUhlenbeck); }},
    {"PairOU-mid", [] { return lowe(LoweAndersenIntegrator::PairOrnsteinUhlenbeck, LoweAndersenIntegrator::Middle); }},
    {"EDPD-OneSided", [] { return edpd(EDPDIntegrator::OneSided); }},
    {"EDPD-Symmetric", [] { return edpd(EDPDIntegrator::Symmetric); }},
    {"Staggered-VV", [] { return staggered(StaggeredDPDIntegrator::VelocityVerlet); }},
    {"Staggered-Lowe", [] { return staggered(StaggeredDPDIntegrator::LoweAndersen); }},
    {"OC", denOtterClarke},
};

inline const Scheme& schemeNamed(const std::string& name) {
    for (const Scheme& scheme : SCHEMES)
        if (scheme.name == name)
            return scheme;
    throw std::invalid_argument("no scheme " + name);
}

/** A System, one of our integrators and a Context on one platform, a few steps into a run. */
struct Simulation {
    Simulation(const Scheme& scheme, const std::string& platform, int steps = STEPS_BEFORE) {
        std::vector<Vec3> positions;
        system.reset(makeSystem(positions));
        integrator.reset(scheme.make());
        std::map<std::string, std::string> properties;
        if (platform == "CPU")
            properties["Threads"] = "1";
        context.reset(new Context(*system, *integrator, Platform::getPlatformByName(platform), properties));
        context->setPositions(positions);
        context->setVelocitiesToTemperature(KT_KELVIN, 11);
        integrator->step(steps);
    }
    std::string checkpoint() {
        std::ostringstream bytes;
        context->createCheckpoint(bytes);
        return bytes.str();
    }
    /** Loads `bytes`, which must be refused with an error that says so. */
    void expectRefused(const std::string& bytes, const std::string& why) {
        std::istringstream stream(bytes);
        try {
            context->loadCheckpoint(stream);
            ADD_FAILURE() << "a checkpoint was accepted: " << why;
        }
        catch (const OpenMMException& e) {
            EXPECT_NE(std::string(e.what()).find("cannot load this checkpoint"), std::string::npos) << why << ": " << e.what();
        }
    }
    std::unique_ptr<System> system;
    std::unique_ptr<Integrator> integrator;
    std::unique_ptr<Context> context;
};

/**
 * After a refused load, `run` holds the state OpenMM restored: its next steps must be those
 * of a new Context started from that state (the integrator re-derived what it carries).
 */
inline void expectStepsLikeANewContext(Simulation& run, const Scheme& scheme, const std::string& platform) {
    const State state = run.context->getState(State::Positions | State::Velocities);
    Simulation fresh(scheme, platform, 0);
    fresh.context->setPositions(state.getPositions());
    fresh.context->setVelocities(state.getVelocities());
    fresh.context->setStepCount(state.getStepCount());
    fresh.context->setTime(state.getTime());
    run.integrator->step(STEPS_AFTER);
    fresh.integrator->step(STEPS_AFTER);
    const std::vector<Vec3> a = run.context->getState(State::Positions).getPositions();
    const std::vector<Vec3> b = fresh.context->getState(State::Positions).getPositions();
    for (int i = 0; i < NUM_PARTICLES; i++)
        ASSERT_EQ(a[i], b[i]) << scheme.name << " on " << platform << ", particle " << i;
}

/**
 * Where the integrator's part of a checkpoint starts (its magic), where its payload does, and
 * where the integrator's state follows the pressure tensor's sums (count, 3 x 6 doubles).
 */
struct IntegratorPart {
    explicit IntegratorPart(const std::string& bytes) {
        begin = bytes.find("OMMDPDCK");
        EXPECT_NE(begin, std::string::npos);
        uint32_t tagLength;
        std::memcpy(&tagLength, bytes.data() + begin + 20, 4);
        payload = begin + 24 + tagLength + 4 + 8;
        std::memcpy(&payloadSize, bytes.data() + payload - 8, 8);
        state = payload + 8 + 18 * 8;
    }
    size_t begin, payload, state;
    uint64_t payloadSize;
};

/** The checkpoint with its checksum made anew, so that only the fields' own checks can refuse a change. */
inline std::string sealed(std::string bytes) {
    const uint64_t digest = XXH3_64bits(bytes.data(), bytes.size() - 8);
    std::memcpy(&bytes[bytes.size() - 8], &digest, 8);
    return bytes;
}

/** One field changed, the checksum made anew. */
template <class T>
std::string withField(std::string bytes, size_t offset, T value) {
    std::memcpy(&bytes[offset], &value, sizeof(T));
    return sealed(bytes);
}

} // namespace CheckpointTesting

#endif
