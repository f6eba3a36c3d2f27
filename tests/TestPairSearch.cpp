#include "openmmdpd/PairSearch.h"
#include <gtest/gtest.h>
#include <algorithm>
#include <iostream>
#include <cmath>
#include <random>
#include <set>
#include <utility>

using namespace DPDPlugin;
using OpenMM::Vec3;

namespace {

// Brute force over explicit images: the true minimum distance, independent of the
// reduced-form rounding the search uses.
std::set<std::pair<int, int>> bruteForcePairs(const std::vector<Vec3>& pos, const Vec3* box, bool periodic, double cutoff) {
    std::set<std::pair<int, int>> result;
    const int range = periodic ? 1 : 0;
    for (int i = 0; i < (int) pos.size(); i++)
        for (int j = i + 1; j < (int) pos.size(); j++) {
            double best = 1e300;
            // Every image next to the rounded one.
            const Vec3 near = minimumImage(pos[i] - pos[j], box, periodic);
            for (int a = -range; a <= range; a++)
                for (int b = -range; b <= range; b++)
                    for (int c = -range; c <= range; c++) {
                        Vec3 d = near + box[0] * a + box[1] * b + box[2] * c;
                        best = std::min(best, d.dot(d));
                    }
            if (best < cutoff * cutoff)
                result.insert({i, j});
        }
    return result;
}

std::set<std::pair<int, int>> searchPairs(const std::vector<Vec3>& pos, const Vec3* box, bool periodic, double cutoff,
                                          int ranges) {
    PairSearch search(std::vector<bool>(pos.size(), true), cutoff, periodic);
    search.build(pos, box);
    std::set<std::pair<int, int>> result;
    const int cells = search.getNumCells();
    for (int r = 0; r < ranges; r++)
        search.forEachPair(cells * r / ranges, cells * (r + 1) / ranges, [&](int i, int j, const Vec3& d) {
            // The displacement handed over is the nearest image.
            Vec3 expected = minimumImage(pos[i] - pos[j], box, periodic);
            EXPECT_NEAR(d[0], expected[0], 1e-12);
            EXPECT_NEAR(d[1], expected[1], 1e-12);
            EXPECT_NEAR(d[2], expected[2], 1e-12);
            auto key = std::make_pair(std::min(i, j), std::max(i, j));
            EXPECT_EQ(result.count(key), 0u) << "pair listed twice";
            result.insert(key);
        });
    return result;
}

// The pairs in visiting order, searched in `ranges` consecutive cell ranges.
std::vector<std::pair<int, int>> pairOrder(const std::vector<Vec3>& pos, const Vec3* box, double cutoff, int ranges) {
    PairSearch search(std::vector<bool>(pos.size(), true), cutoff, true);
    search.build(pos, box);
    std::vector<std::pair<int, int>> order;
    const int cells = search.getNumCells();
    for (int r = 0; r < ranges; r++)
        search.forEachPair(cells * r / ranges, cells * (r + 1) / ranges,
                           [&](int i, int j, const Vec3&) { order.push_back({i, j}); });
    return order;
}

std::vector<Vec3> randomPositions(const Vec3* box, int n, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    std::vector<Vec3> pos(n);
    // Spread over more than one box so that wrapping is exercised.
    for (Vec3& r : pos)
        r = box[0] * (3 * uniform(rng) - 1) + box[1] * (3 * uniform(rng) - 1) + box[2] * (3 * uniform(rng) - 1);
    return pos;
}

void checkBox(const Vec3* box, bool periodic, double cutoff, unsigned seed) {
    std::vector<Vec3> pos = randomPositions(box, 600, seed);
    auto expected = bruteForcePairs(pos, box, periodic, cutoff);
    ASSERT_GT(expected.size(), 100u);
    EXPECT_EQ(searchPairs(pos, box, periodic, cutoff, 1), expected);
    EXPECT_EQ(searchPairs(pos, box, periodic, cutoff, 3), expected);
}

/** Workers run one after another in this thread: a worker count without threads. */
class SequentialWorkers : public ParallelExecutor {
public:
    explicit SequentialWorkers(int workers) : workers(workers) {}
    int getNumWorkers() const override { return workers; }
    void execute(const std::function<void(int worker)>& task) override {
        for (int w = 0; w < workers; w++)
            task(w);
    }

private:
    int workers;
};

} // namespace

TEST(PairSearch, RectangularBoxMatchesBruteForce) {
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(0, 4.2, 0), Vec3(0, 0, 3.7)};
    checkBox(box, true, 1.0, 1);
    checkBox(box, true, 1.3, 2);
}

TEST(PairSearch, TriclinicBoxMatchesBruteForce) {
    // OpenMM's reduced form: a along x, |b_x| <= a_x/2, |c_x| <= a_x/2, |c_y| <= b_y/2.
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(2.4, 4.2, 0), Vec3(-2.3, 2.0, 3.7)};
    checkBox(box, true, 1.0, 3);
    checkBox(box, true, 1.3, 4);
    checkBox(box, true, 1.8, 5);  // fewer than 3 cells along some axis
}

TEST(PairSearch, NonPeriodicMatchesBruteForce) {
    Vec3 box[3] = {Vec3(6, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 4)};
    checkBox(box, false, 1.0, 6);
    checkBox(box, false, 1.3, 7);
}

TEST(PairSearch, OrderIndependentOfHowCellsAreSplit) {
    Vec3 box[3] = {Vec3(6, 0, 0), Vec3(0, 6, 0), Vec3(0, 0, 6)};
    std::vector<Vec3> pos = randomPositions(box, 800, 8);
    auto one = pairOrder(pos, box, 1.0, 1);
    EXPECT_EQ(pairOrder(pos, box, 1.0, 2), one);
    EXPECT_EQ(pairOrder(pos, box, 1.0, 7), one);
}

TEST(PairSearch, SkipsInactiveParticles) {
    std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0.5, 0)};
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 5)};
    PairSearch search({true, false, true}, 1.0, true);
    search.build(pos, box);
    std::vector<std::pair<int, int>> found;
    search.forEachPair(0, search.getNumCells(), [&](int i, int j, const Vec3&) { found.push_back({std::min(i, j), std::max(i, j)}); });
    ASSERT_EQ(found.size(), 1u);
    EXPECT_EQ(found[0], std::make_pair(0, 2));
}

TEST(PairSearch, CrowdedCellsMatchBruteForce) {
    // Over 256 candidates per particle: the search goes through its chunked path.
    Vec3 box[3] = {Vec3(4, 0, 0), Vec3(0, 4, 0), Vec3(0, 0, 4)};
    std::vector<Vec3> pos = randomPositions(box, 2000, 9);
    EXPECT_EQ(searchPairs(pos, box, true, 1.0, 1), bruteForcePairs(pos, box, true, 1.0));
}

TEST(PairSearch, VectorScanFindsTheSamePairsInTheSameOrder) {
    Vec3 box[3] = {Vec3(6, 0, 0), Vec3(1.5, 5.5, 0), Vec3(-2.0, 1.2, 5.2)};
    for (int n : {900, 5000}) {  // sparse cells, and cells too full for one block
        std::vector<Vec3> pos = randomPositions(box, n, 10 + n);
        auto visit = [&](bool vector, bool& vectorUsed) {
            PairSearch search(std::vector<bool>(pos.size(), true), 1.0, true);
            vectorUsed = search.setVectorScan(vector);
            search.build(pos, box);
            std::vector<std::pair<std::pair<int, int>, Vec3>> pairs;
            search.forEachPair(0, search.getNumCells(), [&](int i, int j, const Vec3& d) { pairs.push_back({{i, j}, d}); });
            return pairs;
        };
        bool usedScalar, usedVector;
        auto scalar = visit(false, usedScalar), vector = visit(true, usedVector);
        EXPECT_FALSE(usedScalar);
        if (!usedVector)
            std::cout << "no AVX2 here: only the scalar scan was tested\n";
        ASSERT_EQ(scalar.size(), vector.size());
        for (size_t k = 0; k < scalar.size(); k++) {
            ASSERT_EQ(scalar[k].first, vector[k].first);
            // Bit for bit: the same arithmetic either way.
            ASSERT_EQ(scalar[k].second, vector[k].second);
        }
    }
}

TEST(PairSearch, CellOrderIndependentOfTheNumberOfWorkers) {
    // Enough particles for the counting sort to be shared out (ParallelExecutor::SERIAL_LOOP_LIMIT),
    // some of them inactive.
    Vec3 box[3] = {Vec3(17, 0, 0), Vec3(0, 17, 0), Vec3(0, 0, 17)};
    const int n = 20000;
    ASSERT_GT(n, (int) ParallelExecutor::SERIAL_LOOP_LIMIT);
    std::vector<Vec3> pos = randomPositions(box, n, 11);
    std::vector<bool> active(n, true);
    for (int i = 0; i < n; i += 7)
        active[i] = false;
    auto sorted = [&](ParallelExecutor* executor) {
        PairSearch search(active, 1.0, true);
        search.build(pos, box, executor);
        std::vector<std::pair<int, int>> order;
        search.forEachPair(0, search.getNumCells(), [&](int i, int j, const Vec3&) { order.push_back({i, j}); });
        return std::make_pair(search.getSortedIndex(), order);
    };
    SequentialWorkers two(2), three(3);
    const auto serial = sorted(nullptr);
    ASSERT_EQ((int) serial.first.size(), n - (n + 6) / 7);
    ASSERT_GT(serial.second.size(), 100000u);
    EXPECT_EQ(sorted(&two), serial);
    EXPECT_EQ(sorted(&three), serial);
}

TEST(PairSearch, EveryWorkersPairsLieWithinItsSlotReach) {
    // Workers' buffers by slot are zeroed and read only in their reach: a pair outside it
    // would lose its force.  Periodic grids of at least 3 cells a side (the half shell,
    // which wraps behind along x and y), thinner ones, a triclinic box and an open one.
    const Vec3 cube[3] = {Vec3(7, 0, 0), Vec3(0, 6, 0), Vec3(0, 0, 8)};
    const Vec3 thin[3] = {Vec3(7, 0, 0), Vec3(0, 2.5, 0), Vec3(0, 0, 8)};
    const Vec3 triclinic[3] = {Vec3(6, 0, 0), Vec3(1.5, 5.5, 0), Vec3(-2.0, 1.2, 5.2)};
    for (const Vec3* box : {cube, thin, triclinic})
        for (bool periodic : {true, false}) {
            const std::vector<Vec3> pos = randomPositions(box, 1500, 12);
            PairSearch search(std::vector<bool>(pos.size(), true), 1.0, periodic);
            search.build(pos, box);
            const size_t slots = search.getSortedIndex().size();
            for (int workers : {1, 2, 3, 5}) {
                size_t reached = 0;
                for (int w = 0; w < workers; w++) {
                    const PairSearch::SlotReach reach = search.workerSlotReach(w, workers);
                    reached += reach.count;
                    EXPECT_LE(reach.count, slots);
                    size_t begin, end, pairs = 0;
                    search.workerCells(w, workers, begin, end);
                    search.forEachSortedPair((int) begin, (int) end, [&](int p, int q, const Vec3&) {
                        pairs++;
                        EXPECT_TRUE(reach.contains(p) && reach.contains(q))
                            << "worker " << w << " of " << workers << ": pair of slots " << p << ", " << q << " outside ["
                            << reach.first << ", +" << reach.count << ") of " << slots;
                    });
                    EXPECT_GT(pairs, 0u);
                }
                // Each reach is the worker's own share and a few planes, not every slot.
                if (periodic && box == cube && workers == 5) {
                    EXPECT_LT(reached, 4 * slots);
                }
            }
        }
}
