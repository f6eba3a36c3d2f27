#include "openmmdpd/PairSearch.h"
#include <gtest/gtest.h>
#include <algorithm>
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

std::set<std::pair<int, int>> searchPairs(PairSearch& search, const std::vector<Vec3>& pos, const Vec3* box, double cutoff) {
    search.update(pos, box);
    std::set<std::pair<int, int>> result;
    for (const PairSearch::Pair& p : search.getPairs()) {
        Vec3 d = minimumImage(pos[p.i] - pos[p.j], box, search.isPeriodic());
        if (d.dot(d) < cutoff * cutoff) {
            auto key = std::make_pair(std::min(p.i, p.j), std::max(p.i, p.j));
            EXPECT_EQ(result.count(key), 0u) << "pair listed twice";
            result.insert(key);
        }
    }
    return result;
}

void checkBox(const Vec3* box, bool periodic, double cutoff, double skin, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> uniform(0, 1);
    const int n = 600;
    std::vector<Vec3> pos(n);
    for (Vec3& r : pos) {
        // Spread over more than one box so that wrapping is exercised.
        r = box[0] * (3 * uniform(rng) - 1) + box[1] * (3 * uniform(rng) - 1) + box[2] * (3 * uniform(rng) - 1);
    }
    PairSearch search(std::vector<bool>(n, true), cutoff, skin, periodic);
    auto expected = bruteForcePairs(pos, box, periodic, cutoff);
    ASSERT_GT(expected.size(), 100u);
    EXPECT_EQ(searchPairs(search, pos, box, cutoff), expected);
    // Move every particle by less than skin/2: the list must be reused and stay complete.
    std::normal_distribution<double> step(0, skin > 0 ? 0.1 * skin : 0.1);
    for (Vec3& r : pos)
        r += Vec3(step(rng), step(rng), step(rng)) * (skin > 0 ? 0.5 : 1);
    const int buildsBefore = search.getNumBuilds();
    auto moved = bruteForcePairs(pos, box, periodic, cutoff);
    EXPECT_EQ(searchPairs(search, pos, box, cutoff), moved);
    if (skin == 0) {
        EXPECT_EQ(search.getNumBuilds(), buildsBefore + 1);
    }
    else {
        EXPECT_EQ(search.getNumBuilds(), buildsBefore);
    }
}

} // namespace

TEST(PairSearch, RectangularBoxMatchesBruteForce) {
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(0, 4.2, 0), Vec3(0, 0, 3.7)};
    checkBox(box, true, 1.0, 0.0, 1);
    checkBox(box, true, 1.0, 0.3, 2);
}

TEST(PairSearch, TriclinicBoxMatchesBruteForce) {
    // OpenMM's reduced form: a along x, |b_x| <= a_x/2, |c_x| <= a_x/2, |c_y| <= b_y/2.
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(2.4, 4.2, 0), Vec3(-2.3, 2.0, 3.7)};
    checkBox(box, true, 1.0, 0.0, 3);
    checkBox(box, true, 1.0, 0.3, 4);
    checkBox(box, true, 1.8, 0.0, 5);
}

TEST(PairSearch, NonPeriodicMatchesBruteForce) {
    Vec3 box[3] = {Vec3(6, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 4)};
    checkBox(box, false, 1.0, 0.0, 6);
    checkBox(box, false, 1.0, 0.3, 7);
}

TEST(PairSearch, SkipsInactiveParticles) {
    std::vector<Vec3> pos = {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(0, 0.5, 0)};
    Vec3 box[3] = {Vec3(5, 0, 0), Vec3(0, 5, 0), Vec3(0, 0, 5)};
    PairSearch search({true, false, true}, 1.0, 0.0, true);
    search.update(pos, box);
    ASSERT_EQ(search.getPairs().size(), 1u);
    EXPECT_EQ(std::min(search.getPairs()[0].i, search.getPairs()[0].j), 0);
    EXPECT_EQ(std::max(search.getPairs()[0].i, search.getPairs()[0].j), 2);
}
