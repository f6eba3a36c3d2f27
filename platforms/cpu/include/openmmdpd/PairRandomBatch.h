#ifndef OPENMMDPD_PAIRRANDOMBATCH_H_
#define OPENMMDPD_PAIRRANDOMBATCH_H_

#include "openmmdpd/PairRandom.h"

#ifdef OPENMMDPD_HAVE_LIBMVEC
#include <emmintrin.h>
// glibc's vector math library (libmvec): log and cos of two doubles at once.
extern "C" __m128d _ZGVbN2v_log(__m128d);
extern "C" __m128d _ZGVbN2v_cos(__m128d);
#endif

namespace DPDPlugin {

/**
 * PairRandom's numbers drawn many at a time, for the CPU platform's pair loops: the same
 * words (bit for bit), and normal numbers equal to PairRandom::boxMuller's to rounding.
 */
struct PairRandomBatch {
    /**
     * out[k] = random.bits(stream, step, i[k], j[k]) for k < n, four pairs at a time where
     * the processor has AVX2.
     */
    static void bits(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j, int n,
                     r123::Philox4x32::ctr_type* out);

    /**
     * out[k] = the Box-Muller normal number of the words first[k * stride] and
     * second[k * stride], for k < n, two at a time where glibc's vector math library is
     * available (log and cos are most of a normal number's cost).  Every number takes the
     * same path whatever its position in the batch.
     */
    static void boxMuller(const uint32_t* first, const uint32_t* second, int n, int stride, double* out) {
        auto u1 = [&](int k) { return PairRandom::toOpenUniform(first[k * stride]); };
        auto u2 = [&](int k) { return PairRandom::toUniform(second[k * stride]); };
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
};

} // namespace DPDPlugin

#endif
