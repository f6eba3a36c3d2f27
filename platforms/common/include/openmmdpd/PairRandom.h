#ifndef OPENMMDPD_PAIRRANDOM_H_
#define OPENMMDPD_PAIRRANDOM_H_

#include <Random123/philox.h>
#include <cmath>
#include <cstdint>

#ifdef OPENMMDPD_HAVE_LIBMVEC
#include <emmintrin.h>
// glibc's vector math library (libmvec): log and cos of two doubles at once.
extern "C" __m128d _ZGVbN2v_log(__m128d);
extern "C" __m128d _ZGVbN2v_cos(__m128d);
#endif

namespace DPDPlugin {

/**
 * Per-pair random numbers from a counter-based generator (Philox4x32-10, Random123).
 *
 * A draw is a pure function of (seed, stream, step, min(i,j), max(i,j)): it is symmetric
 * in i and j, does not depend on the order in which pairs are visited or on the number of
 * threads, and is the same on every platform that includes this header.  `stream`
 * separates independent uses within one step (e.g. the random force and a Lowe-Andersen
 * acceptance test).
 */
class PairRandom {
public:
    enum Stream : uint32_t {
        RandomForce = 0, PairThermalisation = 1, SecondSweep = 2,
        AuxiliaryNoise = 3,    // EDPD: the noise of a pair variable's step
        AuxiliaryRecall = 4    // EDPD: a pair variable drawn or caught up when a pair (re)appears
    };

    explicit PairRandom(uint32_t seed = 0) : seed(seed) {}
    uint32_t getSeed() const { return seed; }

    /** Four independent 32-bit words for the pair (i, j) at a step. */
    r123::Philox4x32::ctr_type bits(Stream stream, long long step, int i, int j) const {
        if (i > j) {
            int t = i; i = j; j = t;
        }
        const uint64_t s = (uint64_t) step;
        r123::Philox4x32::ctr_type counter = {{(uint32_t) s, (uint32_t) (s >> 32), (uint32_t) i, (uint32_t) j}};
        r123::Philox4x32::key_type key = {{seed, (uint32_t) stream}};
        return r123::Philox4x32()(counter, key);
    }

    /**
     * bits(stream, step, i[k], j[k]) into out[k] for k < n: the same words, four pairs at a
     * time where the processor has AVX2.
     */
    void bits(Stream stream, long long step, const int* i, const int* j, int n, r123::Philox4x32::ctr_type* out) const;

    /** A standard normal number for the pair (Box-Muller on the first two words). */
    double gaussian(Stream stream, long long step, int i, int j) const {
        return boxMuller(bits(stream, step, i, j));
    }

    /** A uniform number in [0, 1) from one word of a draw. */
    static double toUniform(uint32_t x) {
        return (double) x * (1.0 / 4294967296.0);
    }

    /** A standard normal number from the first two words of a draw (Box-Muller). */
    static double boxMuller(const r123::Philox4x32::ctr_type& r) {
        double x;
        boxMuller(&r[0], &r[1], 1, 4, &x);
        return x;
    }

    /**
     * out[k] = the Box-Muller normal number of the words first[k * stride] and
     * second[k * stride], for k < n: what boxMuller() gives for each draw, computed two at a
     * time where glibc's vector math library is available (log and cos are most of a
     * normal number's cost).  Every number takes the same path whatever its position.
     */
    static void boxMuller(const uint32_t* first, const uint32_t* second, int n, int stride, double* out) {
        // (x + 1) / 2^32 lies in (0, 1], so the logarithm is finite.
        auto u1 = [&](int k) { return ((double) first[k * stride] + 1.0) * (1.0 / 4294967296.0); };
        auto u2 = [&](int k) { return toUniform(second[k * stride]); };
#ifdef OPENMMDPD_HAVE_LIBMVEC
        for (int k = 0; k < n; k += 2) {
            const int other = (k + 1 < n ? k + 1 : k);
            const __m128d radius = _mm_sqrt_pd(_mm_mul_pd(_mm_set1_pd(-2.0), _ZGVbN2v_log(_mm_set_pd(u1(other), u1(k)))));
            const __m128d angle = _mm_mul_pd(_mm_set1_pd(2.0 * M_PI), _mm_set_pd(u2(other), u2(k)));
            double x[2];
            _mm_storeu_pd(x, _mm_mul_pd(radius, _ZGVbN2v_cos(angle)));
            out[k] = x[0];
            if (k + 1 < n)
                out[k + 1] = x[1];
        }
#else
        for (int k = 0; k < n; k++)
            out[k] = std::sqrt(-2.0 * std::log(u1(k))) * std::cos(2.0 * M_PI * u2(k));
#endif
    }

private:
    uint32_t seed;
};

} // namespace DPDPlugin

#endif
