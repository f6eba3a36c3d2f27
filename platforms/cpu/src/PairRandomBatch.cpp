#include "openmmdpd/PairRandomBatch.h"
#include "openmmdpd/CpuFeatures.h"
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>

#ifdef OPENMMDPD_X86_VECTORS
#include <immintrin.h>
#define OPENMMDPD_PHILOX_AVX2
#endif

using namespace DPDPlugin;
using Counter = r123::Philox4x32::ctr_type;

namespace {

#ifdef OPENMMDPD_PHILOX_AVX2
// Philox4x32-10 as Random123 defines it, for four counters at once: each 32-bit word of
// the four counters sits in the low half of a 64-bit lane, where _mm256_mul_epu32 forms
// the full 64-bit product that the round splits into its high and low words.
__attribute__((target("avx2"))) void philoxFour(uint32_t seed, uint32_t stream, long long step, const int* i, const int* j,
                                                Counter* out) {
    const __m256i multiplier0 = _mm256_set1_epi64x(PHILOX_M4x32_0), multiplier1 = _mm256_set1_epi64x(PHILOX_M4x32_1);
    const __m256i low = _mm256_set1_epi64x(0xffffffffu);
    const __m128i a = _mm_loadu_si128((const __m128i*) i), b = _mm_loadu_si128((const __m128i*) j);
    const uint64_t s = (uint64_t) step;
    __m256i c0 = _mm256_set1_epi64x((uint32_t) s), c1 = _mm256_set1_epi64x((uint32_t) (s >> 32));
    __m256i c2 = _mm256_cvtepu32_epi64(_mm_min_epi32(a, b)), c3 = _mm256_cvtepu32_epi64(_mm_max_epi32(a, b));
    uint32_t key0 = seed, key1 = stream;
    for (int round = 0; round < 10; round++) {
        if (round > 0) {
            key0 += PHILOX_W32_0;
            key1 += PHILOX_W32_1;
        }
        const __m256i product0 = _mm256_mul_epu32(c0, multiplier0), product1 = _mm256_mul_epu32(c2, multiplier1);
        const __m256i next0 = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(product1, 32), c1), _mm256_set1_epi64x(key0));
        const __m256i next2 = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(product0, 32), c3), _mm256_set1_epi64x(key1));
        c1 = _mm256_and_si256(product1, low);
        c3 = _mm256_and_si256(product0, low);
        c0 = next0;
        c2 = next2;
    }
    // Words (0, 1) and (2, 3) of each counter as one 64-bit value each.
    alignas(32) uint64_t words01[4], words23[4];
    _mm256_store_si256((__m256i*) words01, _mm256_or_si256(c0, _mm256_slli_epi64(c1, 32)));
    _mm256_store_si256((__m256i*) words23, _mm256_or_si256(c2, _mm256_slli_epi64(c3, 32)));
    for (int lane = 0; lane < 4; lane++) {
        std::memcpy(&out[lane].v[0], &words01[lane], 8);
        std::memcpy(&out[lane].v[2], &words23[lane], 8);
    }
}

// The same, eight counters at once in 512-bit registers.  (A template over the width,
// written with GCC's vector types, measured slower: the compiler did not see that the
// lanes' high halves are zero and made each product of three multiplies.)
__attribute__((target("avx512f"))) void philoxEight(uint32_t seed, uint32_t stream, long long step, const int* i, const int* j,
                                                   Counter* out) {
    const __m512i multiplier0 = _mm512_set1_epi64(PHILOX_M4x32_0), multiplier1 = _mm512_set1_epi64(PHILOX_M4x32_1);
    const __m512i low = _mm512_set1_epi64(0xffffffffu);
    const __m256i a = _mm256_loadu_si256((const __m256i*) i), b = _mm256_loadu_si256((const __m256i*) j);
    const uint64_t s = (uint64_t) step;
    __m512i c0 = _mm512_set1_epi64((uint32_t) s), c1 = _mm512_set1_epi64((uint32_t) (s >> 32));
    __m512i c2 = _mm512_cvtepu32_epi64(_mm256_min_epi32(a, b)), c3 = _mm512_cvtepu32_epi64(_mm256_max_epi32(a, b));
    uint32_t key0 = seed, key1 = stream;
    for (int round = 0; round < 10; round++) {
        if (round > 0) {
            key0 += PHILOX_W32_0;
            key1 += PHILOX_W32_1;
        }
        const __m512i product0 = _mm512_mul_epu32(c0, multiplier0), product1 = _mm512_mul_epu32(c2, multiplier1);
        const __m512i next0 = _mm512_xor_si512(_mm512_xor_si512(_mm512_srli_epi64(product1, 32), c1), _mm512_set1_epi64(key0));
        const __m512i next2 = _mm512_xor_si512(_mm512_xor_si512(_mm512_srli_epi64(product0, 32), c3), _mm512_set1_epi64(key1));
        c1 = _mm512_and_si512(product1, low);
        c3 = _mm512_and_si512(product0, low);
        c0 = next0;
        c2 = next2;
    }
    alignas(64) uint64_t words01[8], words23[8];
    _mm512_store_si512((__m512i*) words01, _mm512_or_si512(c0, _mm512_slli_epi64(c1, 32)));
    _mm512_store_si512((__m512i*) words23, _mm512_or_si512(c2, _mm512_slli_epi64(c3, 32)));
    for (int lane = 0; lane < 8; lane++) {
        std::memcpy(&out[lane].v[0], &words01[lane], 8);
        std::memcpy(&out[lane].v[2], &words23[lane], 8);
    }
}

#endif

#if defined(OPENMMDPD_PHILOX_AVX2) && defined(OPENMMDPD_HAVE_LIBMVEC)
// glibc's vector math library (libmvec): log and cos of four doubles at once, AVX2 variants.
extern "C" __m256d _ZGVdN4v_log(__m256d);
extern "C" __m256d _ZGVdN4v_cos(__m256d);

/** Words k .. k+3 (the last repeating words[n-1] past n) as exact doubles. */
__attribute__((target("avx2"), always_inline)) inline __m256d fourWords(const uint32_t* words, int k, int n, int stride) {
    const auto word = [&](int l) { return (int) words[std::min(k + l, n - 1) * stride]; };
    const __m128i w = _mm_set_epi32(word(3), word(2), word(1), word(0));
    // Unsigned to double: flip the sign bit, convert as signed, add 2^31 back (all exact).
    return _mm256_add_pd(_mm256_cvtepi32_pd(_mm_xor_si128(w, _mm_set1_epi32(INT32_MIN))), _mm256_set1_pd(2147483648.0));
}

__attribute__((target("avx2"))) void boxMullerFour(const uint32_t* first, const uint32_t* second, int n, int stride,
                                                   double* out) {
    // PairRandom::toOpenUniform and toUniform, the same operations four at a time.
    const __m256d scale = _mm256_set1_pd(1.0 / 4294967296.0);
    for (int k = 0; k < n; k += 4) {
        // A batch's last lanes repeat its last number, so that it too goes through libmvec.
        const __m256d u1 = _mm256_mul_pd(_mm256_add_pd(fourWords(first, k, n, stride), _mm256_set1_pd(1.0)), scale);
        const __m256d u2 = _mm256_mul_pd(fourWords(second, k, n, stride), scale);
        const __m256d radius = _mm256_sqrt_pd(_mm256_mul_pd(_mm256_set1_pd(-2.0), _ZGVdN4v_log(u1)));
        const __m256d angle = _mm256_mul_pd(_mm256_set1_pd(2.0 * M_PI), u2);
        alignas(32) double x[4];
        _mm256_store_pd(x, _mm256_mul_pd(radius, _ZGVdN4v_cos(angle)));
        for (int l = 0; l < 4 && k + l < n; l++)
            out[k + l] = x[l];
    }
}
#define OPENMMDPD_BOX_MULLER_AVX2
#endif

} // namespace

void PairRandomBatch::bits(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j, int n,
                           Counter* out) {
    int k = 0;
#ifdef OPENMMDPD_PHILOX_AVX2
    if (haveAVX512())
        for (; k + 8 <= n; k += 8)
            philoxEight(random.getSeed(), (uint32_t) stream, step, i + k, j + k, out + k);
    if (haveAVX2())
        for (; k + 4 <= n; k += 4)
            philoxFour(random.getSeed(), (uint32_t) stream, step, i + k, j + k, out + k);
#endif
    for (; k < n; k++)
        out[k] = random.bits(stream, step, i[k], j[k]);
}

void PairRandomBatch::boxMuller(const uint32_t* first, const uint32_t* second, int n, int stride, double* out) {
#ifdef OPENMMDPD_BOX_MULLER_AVX2
    if (haveAVX2()) {
        boxMullerFour(first, second, n, stride, out);
        return;
    }
#endif
    for (int k = 0; k < n; k++)
        out[k] = PairRandom::boxMuller(first[k * stride], second[k * stride]);
}
