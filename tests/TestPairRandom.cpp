#include "openmmdpd/PairRandomBatch.h"
#include <gtest/gtest.h>
#include <cmath>
#include <vector>

using namespace DPDPlugin;

TEST(PairRandom, SymmetricInThePair) {
    PairRandom random(1234);
    for (int i = 0; i < 50; i++)
        for (int j = 0; j < 50; j++)
            EXPECT_EQ(random.gaussian(PairRandom::RandomForce, 17, i, j), random.gaussian(PairRandom::RandomForce, 17, j, i));
}

TEST(PairRandom, DependsOnEveryKey) {
    PairRandom a(1), b(2);
    const double x = a.gaussian(PairRandom::RandomForce, 5, 3, 9);
    EXPECT_NE(x, b.gaussian(PairRandom::RandomForce, 5, 3, 9));
    EXPECT_NE(x, a.gaussian(PairRandom::RandomForce, 6, 3, 9));
    EXPECT_NE(x, a.gaussian(PairRandom::RandomForce, 5, 4, 9));
    EXPECT_NE(x, a.gaussian(PairRandom::PairThermalisation, 5, 3, 9));
    EXPECT_NE(x, a.gaussian(PairRandom::RandomForce, 5LL + (1LL << 32), 3, 9));
}

TEST(PairRandom, GaussianMeanAndVariance) {
    PairRandom random(99);
    const int n = 400000;
    double sum = 0, sum2 = 0, sum4 = 0;
    for (int k = 0; k < n; k++) {
        double x = random.gaussian(PairRandom::RandomForce, k / 1000, k % 1000, 1000 + k % 7);
        sum += x;
        sum2 += x * x;
        sum4 += x * x * x * x;
    }
    const double mean = sum / n, var = sum2 / n - mean * mean;
    // Standard errors: 1/sqrt(n) for the mean, sqrt(2/n) for the variance; 4 of them.
    EXPECT_NEAR(mean, 0.0, 4 / std::sqrt(n));
    EXPECT_NEAR(var, 1.0, 4 * std::sqrt(2.0 / n));
    EXPECT_NEAR(sum4 / n, 3.0, 4 * std::sqrt(96.0 / n));
}

TEST(PairRandom, PartnerIsAnIndependentStandardNormal) {
    // S2's second sweep takes partnerGaussian of the key the next step's first sweep takes
    // gaussian of: it must be a standard normal number, uncorrelated with its partner.
    PairRandom random(99);
    const int n = 400000;
    double sum = 0, sum2 = 0, product = 0;
    for (int k = 0; k < n; k++) {
        const int i = k % 1000, j = 1000 + k % 7;
        const double x = random.partnerGaussian(PairRandom::RandomForce, k / 1000, i, j);
        const double y = random.gaussian(PairRandom::RandomForce, k / 1000, i, j);
        sum += x;
        sum2 += x * x;
        product += x * y;
    }
    const double mean = sum / n, var = sum2 / n - mean * mean;
    // Standard errors 1/sqrt(n) (0.0016) for the mean and the correlation, sqrt(2/n) (0.0022)
    // for the variance: 3 of them see a 1 % error.
    EXPECT_NEAR(mean, 0.0, 3 / std::sqrt(n));
    EXPECT_NEAR(var, 1.0, 3 * std::sqrt(2.0 / n));
    EXPECT_NEAR(product / n, 0.0, 3 / std::sqrt(n));
    // The two are one Box-Muller pair: their squares add up to -2 log u of the first word.
    for (int k = 0; k < 100; k++) {
        const r123::Philox4x32::ctr_type draw = random.bits(PairRandom::RandomForce, k, 3, 5);
        const double x = PairRandom::boxMuller(draw), y = PairRandom::boxMullerPartner(draw);
        EXPECT_NEAR(x * x + y * y, -2 * std::log(PairRandom::toOpenUniform(draw[0])), 1e-12);
    }
}

TEST(PairRandom, UniformInUnitInterval) {
    PairRandom random(7);
    const int n = 200000;
    double sum = 0;
    for (int k = 0; k < n; k++) {
        // The uniform Lowe-Andersen's collision test uses: the third word of the draw.
        double u = PairRandom::toUniform(random.bits(PairRandom::PairThermalisation, k, 1, 2)[2]);
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        sum += u;
    }
    EXPECT_NEAR(sum / n, 0.5, 4 * std::sqrt(1.0 / 12 / n));
}

TEST(PairRandom, BatchedNormalsEqualOneAtATime) {
    // Each number is the same whatever its position in a batch (eights, fours, the tail) or
    // the batch's size, and equals random.gaussian() to rounding (vector log and cos).
    PairRandom random(31);
    const int pairs = 19;
    std::vector<int> first, second;
    for (int k = 0; k < pairs; k++) {
        first.push_back(k % 3 == 0 ? 100 + k : 7 * k);
        second.push_back(k % 3 == 0 ? k : 1000000 + k);
    }
    std::vector<double> alone(pairs);
    for (int k = 0; k < pairs; k++)
        PairRandomBatch::normals(random, PairRandom::RandomForce, 3, &first[k], &second[k], 1, &alone[k]);
    for (int n = 1; n <= pairs; n++) {
        std::vector<double> batch(n);
        PairRandomBatch::normals(random, PairRandom::RandomForce, 3, first.data(), second.data(), n, batch.data());
        for (int k = 0; k < n; k++) {
            EXPECT_EQ(batch[k], alone[k]) << "batch of " << n << ", number " << k;
            EXPECT_NEAR(batch[k], random.gaussian(PairRandom::RandomForce, 3, first[k], second[k]), 1e-14)
                    << "batch of " << n << ", number " << k;
        }
    }
    // The partners drawn with them: the same numbers as alone, and partnerGaussian() to rounding.
    for (int n = 1; n <= pairs; n++) {
        std::vector<double> batch(n), partners(n);
        PairRandomBatch::normalsAndPartners(random, PairRandom::RandomForce, 3, first.data(), second.data(), n, batch.data(),
                                            partners.data());
        for (int k = 0; k < n; k++) {
            EXPECT_EQ(batch[k], alone[k]) << "batch of " << n << ", number " << k;
            EXPECT_NEAR(partners[k], random.partnerGaussian(PairRandom::RandomForce, 3, first[k], second[k]), 1e-14)
                    << "batch of " << n << ", partner " << k;
        }
    }
    // The noise vectors of transverse friction: normalVector() to rounding in every batch, the
    // pairs named either way round (first[k] > second[k] for every third) giving the negative.
    for (int n = 1; n <= pairs; n++) {
        std::vector<double> vectors(3 * n);
        PairRandomBatch::normalVectors(random, PairRandom::TransverseNoise, 3, first.data(), second.data(), n, vectors.data());
        for (int k = 0; k < n; k++) {
            double expected[3], reversed[3];
            random.normalVector(PairRandom::TransverseNoise, 3, first[k], second[k], expected);
            random.normalVector(PairRandom::TransverseNoise, 3, second[k], first[k], reversed);
            for (int c = 0; c < 3; c++) {
                EXPECT_NEAR(vectors[3 * k + c], expected[c], 1e-14) << "batch of " << n << ", vector " << k << ", component " << c;
                EXPECT_EQ(reversed[c], -expected[c]) << "vector " << k;
            }
        }
    }
    // ...and the scalar one agrees with the textbook formula to rounding.
    for (int k = 0; k < pairs; k++) {
        const r123::Philox4x32::ctr_type draw = random.bits(PairRandom::RandomForce, 3, first[k], second[k]);
        const double u1 = ((double) draw[0] + 1.0) / 4294967296.0, u2 = (double) draw[1] / 4294967296.0;
        EXPECT_NEAR(PairRandom::boxMuller(draw), std::sqrt(-2 * std::log(u1)) * std::cos(2 * M_PI * u2), 1e-13);
    }
}

TEST(PairRandom, BatchedDrawsEqualOneAtATime) {
    // Eight or four at a time (AVX-512, AVX2 where available) or one at a time: the same
    // words, for either order of the pair, large indices and steps past 2^32, and every
    // length of the tails after the eights.
    PairRandom random(0xDEADBEEF);
    std::vector<int> first, second;
    for (int k = 0; k < 19; k++) {
        first.push_back(k % 2 == 0 ? 1000003 * k : k);
        second.push_back(k % 2 == 0 ? k + 1 : 2000000000 - k);
    }
    for (long long step : {0LL, 12345LL, (1LL << 32) + 77}) {
        for (int n = 0; n <= 19; n++) {
            std::vector<r123::Philox4x32::ctr_type> batch(n);
            PairRandomBatch::bits(random, PairRandom::AuxiliaryNoise, step, first.data(), second.data(), n, batch.data());
            for (int k = 0; k < n; k++) {
                const auto one = random.bits(PairRandom::AuxiliaryNoise, step, first[k], second[k]);
                for (int w = 0; w < 4; w++)
                    ASSERT_EQ(batch[k][w], one[w]) << "step " << step << ", batch of " << n << ", draw " << k << ", word " << w;
            }
        }
    }
}
