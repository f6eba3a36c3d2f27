// The integrator part of a checkpoint (platforms/core CheckpointIO.h) as a hostile file
// would test it: every other integrator class and variant refuses it, truncations, damaged
// bytes anywhere in the file and damaged fields (behind a valid checksum) are refused with an
// OpenMMException (never a crash), and after a refused load the integrator steps exactly as a
// new Context would from the Context's state; loadCheckpoint (Checkpoints.h) leaves the Context
// as it was, bit for bit.

#include "CheckpointTesting.h"
#include "openmmdpd/Checkpoints.h"
#include <limits>

using namespace DPDPlugin;
using namespace CheckpointTesting;

namespace {

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
