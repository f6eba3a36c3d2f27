// The integrator part of a checkpoint (platforms/core CheckpointIO.h) as a hostile file
// would test it: every other integrator class and variant refuses it, truncations, damaged
// bytes anywhere in the file and damaged fields (behind a valid checksum) are refused with an
// OpenMMException (never a crash), and after a refused load the integrator steps exactly as a
// new Context would from the Context's state; loadCheckpoint (Checkpoints.h) leaves the Context
// as it was, bit for bit.

#include "TestHelpers.h"
#include "openmmdpd/Checkpoints.h"
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
#include <limits>
#include <sstream>
#include <stdexcept>
#define XXH_INLINE_ALL
#include <xxhash.h>

using namespace DPDPlugin;

namespace {

constexpr int NUM_PARTICLES = 300;
constexpr int CHAIN_LENGTH = 5;
constexpr double DT = 0.02;
constexpr int STEPS_BEFORE = 5, STEPS_AFTER = 3;

/** A soft fluid at density ~4 with a harmonic 5-bead chain in force group 1 (for the staggered scheme). */
System* makeSystem(std::vector<Vec3>& positions) {
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

Integrator* dpdvv(DPDVVIntegrator::Variant variant) {
    DPDVVIntegrator* integrator = seeded(new DPDVVIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrator->setVariant(variant);
    return integrator;
}

Integrator* shardlow(int order) {
    ShardlowIntegrator* integrator = seeded(new ShardlowIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrator->setOrder(order);
    return integrator;
}

Integrator* lowe(LoweAndersenIntegrator::Method method, LoweAndersenIntegrator::Splitting splitting = LoweAndersenIntegrator::AfterVerlet) {
    LoweAndersenIntegrator* integrator = seeded(new LoweAndersenIntegrator(KT_KELVIN, 4.5, 1.0, DT));
    integrator->setMethod(method);
    integrator->setSplitting(splitting);
    return integrator;
}

Integrator* edpd(EDPDIntegrator::Scheme scheme) {
    EDPDIntegrator* integrator = seeded(new EDPDIntegrator(KT_KELVIN, 4.5, 1.0, 10.0, DT));
    integrator->setScheme(scheme);
    return integrator;
}

Integrator* staggered(StaggeredDPDIntegrator::BaseScheme base) {
    StaggeredDPDIntegrator* integrator = seeded(new StaggeredDPDIntegrator(KT_KELVIN, 4.5, 1.0, DT, 1));
    integrator->setBaseScheme(base);
    return integrator;
}

Integrator* denOtterClarke() {
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

const Scheme& schemeNamed(const std::string& name) {
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
void expectStepsLikeANewContext(Simulation& run, const Scheme& scheme, const std::string& platform) {
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
std::string sealed(std::string bytes) {
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

class Checkpoints : public testing::TestWithParam<std::string> {};

TEST_P(Checkpoints, EveryOtherIntegratorClassAndVariantRefusesIt) {
    const std::string platform = GetParam();
    std::vector<std::string> checkpoints;
    for (const Scheme& scheme : SCHEMES)
        checkpoints.push_back(Simulation(scheme, platform).checkpoint());
    for (size_t b = 0; b < SCHEMES.size(); b++) {
        Simulation run(SCHEMES[b], platform);
        for (size_t a = 0; a < SCHEMES.size(); a++)
            if (a != b)
                run.expectRefused(checkpoints[a], SCHEMES[a].name + " into " + SCHEMES[b].name);
        expectStepsLikeANewContext(run, SCHEMES[b], platform);
    }
}

TEST_P(Checkpoints, TruncationsAreRefused) {
    const std::string platform = GetParam();
    for (const Scheme& scheme : SCHEMES) {
        Simulation run(scheme, platform);
        const std::string bytes = run.checkpoint();
        const IntegratorPart part(bytes);
        const size_t end = part.payload + part.payloadSize;
        for (size_t cut : {part.begin + 3, part.begin + 10, part.payload - 4, part.payload, part.payload + 3,
                           part.payload + 20, (part.payload + end) / 2, end - 1})
            run.expectRefused(bytes.substr(0, cut), scheme.name + " cut at " + std::to_string(cut));
        expectStepsLikeANewContext(run, scheme, platform);
    }
}

TEST_P(Checkpoints, HeadersOfOtherFormatsAreRefusedAndSaySo) {
    const std::string platform = GetParam();
    Simulation run(schemeNamed("GW"), platform);
    const std::string bytes = run.checkpoint();
    const IntegratorPart part(bytes);
    // Format 1 had the payload alone where the header now starts.
    const std::string old = bytes.substr(0, part.begin) + bytes.substr(part.payload);
    expectErrorNaming([&] { std::istringstream s(old); run.context->loadCheckpoint(s); }, "before checkpoint format 2");
    const std::string second = withField<uint32_t>(bytes, part.begin + 8, 2);
    expectErrorNaming([&] { std::istringstream s(second); run.context->loadCheckpoint(s); }, "format 2 and this build reads format 3");
    const std::string future = withField<uint32_t>(bytes, part.begin + 8, 4);
    expectErrorNaming([&] { std::istringstream s(future); run.context->loadCheckpoint(s); }, "format 4");
    const std::string otherSize = withField<int32_t>(bytes, part.payload - 12, NUM_PARTICLES + 1);
    expectErrorNaming([&] { std::istringstream s(otherSize); run.context->loadCheckpoint(s); }, "this System has 300");
    run.expectRefused(withField<uint64_t>(bytes, part.payload - 8, part.payloadSize + 1), "payload size + 1");
    run.expectRefused(withField<uint64_t>(bytes, part.payload - 8, 1ULL << 60), "payload size 2^60");
    run.expectRefused(withField<uint32_t>(bytes, part.begin + 20, 1u << 30), "tag length 2^30");
    run.expectRefused(withField<uint64_t>(bytes, part.begin + 12, bytes.size()), "OpenMM's part longer than the file");
    expectStepsLikeANewContext(run, schemeNamed("GW"), platform);
}

// Fields every integrator's payload starts with: seed (4), flag (1), count (8), force (N x 24).
TEST_P(Checkpoints, DamagedCarriedForceIsRefused) {
    const std::string platform = GetParam();
    Simulation run(schemeNamed("S1"), platform);
    const std::string bytes = run.checkpoint();
    const size_t state = IntegratorPart(bytes).state;
    run.expectRefused(withField<char>(bytes, state + 4, 7), "flag 7");
    run.expectRefused(withField<uint64_t>(bytes, state + 5, NUM_PARTICLES + 1), "force count N + 1");
    run.expectRefused(withField<double>(bytes, state + 13 + 24 * 7 + 8, std::numeric_limits<double>::quiet_NaN()),
                      "NaN force");
    run.expectRefused(withField<double>(bytes, state + 13, std::numeric_limits<double>::infinity()), "infinite force");
    const size_t sums = IntegratorPart(bytes).payload;
    run.expectRefused(withField<int64_t>(bytes, sums, -1), "pressure sample count -1");
    run.expectRefused(withField<double>(bytes, sums + 8, std::numeric_limits<double>::quiet_NaN()), "NaN pressure sum");
    expectStepsLikeANewContext(run, schemeNamed("S1"), platform);
}

/** Everything loadCheckpoint promises to keep, bit for bit. */
struct Snapshot {
    explicit Snapshot(Context& context) {
        const State state = context.getState(State::Positions | State::Velocities);
        positions = state.getPositions();
        velocities = state.getVelocities();
        time = state.getTime();
        step = state.getStepCount();
    }
    bool operator==(const Snapshot& other) const {
        return positions == other.positions && velocities == other.velocities && time == other.time && step == other.step;
    }
    std::vector<Vec3> positions, velocities;
    double time;
    long long step;
};

bool isPrintable(const std::string& text) {
    return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) { return c >= 0x20 && c < 0x7f; });
}

TEST_P(Checkpoints, DamagedBytesAnywhereAreRefusedAndLoadCheckpointKeepsTheState) {
    const std::string platform = GetParam();
    std::mt19937 rng(5);
    for (const Scheme& scheme : SCHEMES) {
        Simulation run(scheme, platform);
        const std::string bytes = run.checkpoint();
        run.integrator->step(2);
        const Snapshot before(*run.context);
        std::uniform_int_distribution<size_t> offset(0, bytes.size() - 1);
        std::vector<std::string> damaged = {bytes + "x"};
        for (int k = 0; k < 10; k++) {
            std::string flipped = bytes;
            flipped[offset(rng)] ^= (char) (1 << (k % 8));
            damaged.push_back(flipped);
        }
        for (const std::string& file : damaged) {
            std::istringstream stream(file);
            try {
                loadCheckpoint(*run.context, stream);
                ADD_FAILURE() << scheme.name << " on " << platform << ": a damaged checkpoint was accepted";
            }
            catch (const OpenMMException& e) {
                EXPECT_TRUE(isPrintable(e.what())) << scheme.name << ": \"" << e.what() << "\"";
            }
            ASSERT_TRUE(Snapshot(*run.context) == before) << scheme.name << " on " << platform << ": the state changed";
        }
        std::istringstream intact(bytes);
        loadCheckpoint(*run.context, intact);
        EXPECT_EQ(run.context->getState(0).getStepCount(), STEPS_BEFORE) << scheme.name;
    }
}

TEST_P(Checkpoints, ACheckpointOfAnotherIntegratorLeavesTheContextAsItWas) {
    const std::string platform = GetParam();
    const std::string gw = Simulation(schemeNamed("GW"), platform, 3).checkpoint();
    Simulation run(schemeNamed("S1"), platform, 7);
    const Snapshot before(*run.context);
    std::istringstream stream(gw);
    expectErrorNaming([&] { loadCheckpoint(*run.context, stream); }, "written by a DPDVVIntegrator (GrootWarren)");
    EXPECT_TRUE(Snapshot(*run.context) == before);
    // The raw load restores OpenMM's part before ours is refused.
    std::istringstream raw(gw);
    EXPECT_THROW(run.context->loadCheckpoint(raw), OpenMMException);
    EXPECT_EQ(run.context->getState(0).getStepCount(), 3);
}

TEST_P(Checkpoints, DamagedTagReadsAsPrintableText) {
    const std::string platform = GetParam();
    Simulation run(schemeNamed("GW"), platform);
    const std::string bytes = run.checkpoint();
    const size_t tag = IntegratorPart(bytes).begin + 24;
    expectErrorNaming([&] { std::istringstream s(withField<unsigned char>(bytes, tag + 2, 0xff)); run.context->loadCheckpoint(s); },
                      "written by a DP\\xffVVIntegrator (GrootWarren)");
}

INSTANTIATE_TEST_SUITE_P(Platforms, Checkpoints, testing::ValuesIn(platforms()),
                         [](const testing::TestParamInfo<std::string>& info) { return info.param; });

/** Checkpoints with damaged EDPD pair variables, in each platform's layout of PairMemory: all refused. */
class DamagedPairVariables : public testing::Test {
protected:
    // Pair variables forget slowly at alpha = 10, dt = 0.02: after 20 steps some pairs have left.
    DamagedPairVariables() : scheme(schemeNamed("EDPD-OneSided")) {}
    void expectAllRefused(Simulation& run, const std::string& platform, const std::vector<std::pair<std::string, std::string>>& cases) {
        for (const auto& c : cases)
            run.expectRefused(c.second, c.first);
        expectStepsLikeANewContext(run, scheme, platform);
    }
    const Scheme& scheme;
    static constexpr size_t MEMORY = 13 + 24 * NUM_PARTICLES;  // after seed, flag and force
};

TEST_F(DamagedPairVariables, RefusedOnTheReferencePlatform) {
    // particles (int32), step (int64), count, (i, j, s, wR^2) each; count, (i, j, s, step) each
    Simulation run(scheme, "Reference", 20);
    const std::string bytes = run.checkpoint();
    const size_t memory = IntegratorPart(bytes).state + MEMORY;
    const size_t inRange = memory + 12, first = inRange + 8;
    uint64_t numInRange;
    std::memcpy(&numInRange, &bytes[inRange], 8);
    ASSERT_GT(numInRange, 2u);
    const size_t archivedCount = first + 24 * numInRange;
    uint64_t numArchived;
    std::memcpy(&numArchived, &bytes[archivedCount], 8);
    ASSERT_GT(numArchived, 0u) << "no pair has left its cutoff yet";
    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::string duplicate = bytes;
    duplicate.replace(first + 24, 8, bytes.substr(first, 8));
    duplicate = sealed(duplicate);
    expectAllRefused(run, "Reference", {
        {"partner 10^6", withField<int32_t>(bytes, first + 4, 1000000)},
        {"partner -1", withField<int32_t>(bytes, first + 4, -1)},
        {"first index -5", withField<int32_t>(bytes, first, -5)},
        {"i > j", withField<int32_t>(bytes, first, NUM_PARTICLES - 1)},
        {"a pair twice", duplicate},
        {"s NaN", withField<double>(bytes, first + 8, nan)},
        {"wR^2 = 2", withField<double>(bytes, first + 16, 2.0)},
        {"count 10^18", withField<uint64_t>(bytes, inRange, 1000000000000000000ULL)},
        {"particles N + 1", withField<int32_t>(bytes, memory, NUM_PARTICLES + 1)},
        {"archived partner 10^6", withField<int32_t>(bytes, archivedCount + 12, 1000000)},
        {"archived step in the future", withField<int64_t>(bytes, archivedCount + 24, 1000)},
        {"step 2^63 - 1", withField<int64_t>(bytes, memory + 4, std::numeric_limits<int64_t>::max())},
    });
}

#if OPENMMDPD_HAVE_CPU
TEST_F(DamagedPairVariables, RefusedOnTheCpuPlatform) {
    // step (int64), particles, count, offsets (N + 1 int32), (j, s, wR^2) each, then per
    // particle: count, (j, s, step) each
    Simulation run(scheme, "CPU", 20);
    const std::string bytes = run.checkpoint();
    const size_t memory = IntegratorPart(bytes).state + MEMORY;
    const size_t offsets = memory + 24, pairs = offsets + 4 * (NUM_PARTICLES + 1);
    uint64_t numInRange;
    std::memcpy(&numInRange, &bytes[memory + 16], 8);
    ASSERT_GT(numInRange, 2u);
    int32_t second;
    std::memcpy(&second, &bytes[offsets + 4], 4);
    // The first particle with archived pairs (i): its count, then its first entry.
    size_t archive = pairs + 20 * numInRange;
    int32_t i = 0;
    for (uint64_t count; std::memcpy(&count, &bytes[archive], 8), count == 0; archive += 8, i++)
        ASSERT_LT(i, NUM_PARTICLES - 1) << "no pair has left its cutoff yet";
    const double nan = std::numeric_limits<double>::quiet_NaN();
    expectAllRefused(run, "CPU", {
        {"partner 10^6", withField<int32_t>(bytes, pairs, 1000000)},
        {"partner -1", withField<int32_t>(bytes, pairs, -1)},
        {"offset 10^8", withField<int32_t>(bytes, offsets + 4, 100000000)},
        {"offset -5", withField<int32_t>(bytes, offsets + 4, -5)},
        {"offsets out of order", withField<int32_t>(bytes, offsets + 8, second - 1)},
        {"first offset 1", withField<int32_t>(bytes, offsets, 1)},
        {"s NaN", withField<double>(bytes, pairs + 4, nan)},
        {"wR^2 = 2", withField<double>(bytes, pairs + 12, 2.0)},
        {"count 10^18", withField<uint64_t>(bytes, memory + 16, 1000000000000000000ULL)},
        {"particles N + 1", withField<uint64_t>(bytes, memory + 8, NUM_PARTICLES + 1)},
        {"archived partner 10^6", withField<int32_t>(bytes, archive + 8, 1000000)},
        {"archived partner = its particle", withField<int32_t>(bytes, archive + 8, i)},
        {"archived count 10^18", withField<uint64_t>(bytes, archive, 1000000000000000000ULL)},
        {"archived step in the future", withField<int64_t>(bytes, archive + 20, 1000)},
        {"step 2^63 - 1", withField<int64_t>(bytes, memory, std::numeric_limits<int64_t>::max())},
    });
}
#endif

} // namespace
