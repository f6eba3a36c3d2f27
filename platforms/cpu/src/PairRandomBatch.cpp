#include "openmmdpd/PairRandomBatch.h"
#include "openmmdpd/CpuFeatures.h"
#include <algorithm>
#include <cmath>
#include <cstring>

#ifdef OPENMMDPD_X86_VECTORS
#include <immintrin.h>
#define OPENMMDPD_PHILOX_AVX2
#endif

using namespace DPDPlugin;
using Counter = r123::Philox4x32::ctr_type;

namespace {

/** The pairs PairRandomBatch::normals draws at a time (their words kept on the stack). */
constexpr int NORMALS_BLOCK = 64;

#ifdef OPENMMDPD_PHILOX_AVX2
// Philox4x32-10 as Random123 defines it, for four counters at once: each 32-bit word of
// the four counters sits in the low half of a 64-bit lane, where _mm256_mul_epu32 forms
// the full 64-bit product that the round splits into its high and low words.  c[w] holds
// word w of the four results.
__attribute__((target("avx2"), always_inline)) inline void philoxRoundsFour(uint32_t seed, uint32_t stream, long long step,
                                                                           const int* i, const int* j, __m256i* c) {
    const __m256i multiplier0 = _mm256_set1_epi64x(PHILOX_M4x32_0), multiplier1 = _mm256_set1_epi64x(PHILOX_M4x32_1);
    const __m256i low = _mm256_set1_epi64x(0xffffffffu);
    const __m128i a = _mm_loadu_si128((const __m128i*) i), b = _mm_loadu_si128((const __m128i*) j);
    const uint64_t s = (uint64_t) step;
    c[0] = _mm256_set1_epi64x((uint32_t) s);
    c[1] = _mm256_set1_epi64x((uint32_t) (s >> 32));
    c[2] = _mm256_cvtepu32_epi64(_mm_min_epi32(a, b));
    c[3] = _mm256_cvtepu32_epi64(_mm_max_epi32(a, b));
    uint32_t key0 = seed, key1 = stream;
    for (int round = 0; round < 10; round++) {
        if (round > 0) {
            key0 += PHILOX_W32_0;
            key1 += PHILOX_W32_1;
        }
        const __m256i product0 = _mm256_mul_epu32(c[0], multiplier0), product1 = _mm256_mul_epu32(c[2], multiplier1);
        const __m256i next0 = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(product1, 32), c[1]), _mm256_set1_epi64x(key0));
        const __m256i next2 = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(product0, 32), c[3]), _mm256_set1_epi64x(key1));
        c[1] = _mm256_and_si256(product1, low);
        c[3] = _mm256_and_si256(product0, low);
        c[0] = next0;
        c[2] = next2;
    }
}

__attribute__((target("avx2"))) void philoxFour(uint32_t seed, uint32_t stream, long long step, const int* i, const int* j,
                                                Counter* out) {
    __m256i c[4];
    philoxRoundsFour(seed, stream, step, i, j, c);
    // Words (0, 1) and (2, 3) of each counter as one 64-bit value each.
    alignas(32) uint64_t words01[4], words23[4];
    _mm256_store_si256((__m256i*) words01, _mm256_or_si256(c[0], _mm256_slli_epi64(c[1], 32)));
    _mm256_store_si256((__m256i*) words23, _mm256_or_si256(c[2], _mm256_slli_epi64(c[3], 32)));
    for (int lane = 0; lane < 4; lane++) {
        std::memcpy(&out[lane].v[0], &words01[lane], 8);
        std::memcpy(&out[lane].v[2], &words23[lane], 8);
    }
}

// GCC 12's avx512fintrin.h makes _mm512_undefined_epi32 by initialising a variable with itself,
// and -Wuninitialized then warns wherever an intrinsic that uses it (_mm512_mul_epu32,
// _mm512_srli_epi64, _mm512_cvtepu32_epi64) is inlined: a false alarm, silenced for the
// 512-bit code below only.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"

// The same, eight counters at once in 512-bit registers.  (A template over the width,
// written with GCC's vector types, measured slower: the compiler did not see that the
// lanes' high halves are zero and made each product of three multiplies.)
__attribute__((target("avx512f"), always_inline)) inline void philoxRoundsEight(uint32_t seed, uint32_t stream, long long step,
                                                                               const int* i, const int* j, __m512i* c) {
    const __m512i multiplier0 = _mm512_set1_epi64(PHILOX_M4x32_0), multiplier1 = _mm512_set1_epi64(PHILOX_M4x32_1);
    const __m512i low = _mm512_set1_epi64(0xffffffffu);
    const __m256i a = _mm256_loadu_si256((const __m256i*) i), b = _mm256_loadu_si256((const __m256i*) j);
    const uint64_t s = (uint64_t) step;
    c[0] = _mm512_set1_epi64((uint32_t) s);
    c[1] = _mm512_set1_epi64((uint32_t) (s >> 32));
    c[2] = _mm512_cvtepu32_epi64(_mm256_min_epi32(a, b));
    c[3] = _mm512_cvtepu32_epi64(_mm256_max_epi32(a, b));
    uint32_t key0 = seed, key1 = stream;
    for (int round = 0; round < 10; round++) {
        if (round > 0) {
            key0 += PHILOX_W32_0;
            key1 += PHILOX_W32_1;
        }
        const __m512i product0 = _mm512_mul_epu32(c[0], multiplier0), product1 = _mm512_mul_epu32(c[2], multiplier1);
        const __m512i next0 = _mm512_xor_si512(_mm512_xor_si512(_mm512_srli_epi64(product1, 32), c[1]), _mm512_set1_epi64(key0));
        const __m512i next2 = _mm512_xor_si512(_mm512_xor_si512(_mm512_srli_epi64(product0, 32), c[3]), _mm512_set1_epi64(key1));
        c[1] = _mm512_and_si512(product1, low);
        c[3] = _mm512_and_si512(product0, low);
        c[0] = next0;
        c[2] = next2;
    }
}

__attribute__((target("avx512f"))) void philoxEight(uint32_t seed, uint32_t stream, long long step, const int* i, const int* j,
                                                   Counter* out) {
    __m512i c[4];
    philoxRoundsEight(seed, stream, step, i, j, c);
    alignas(64) uint64_t words01[8], words23[8];
    _mm512_store_si512((__m512i*) words01, _mm512_or_si512(c[0], _mm512_slli_epi64(c[1], 32)));
    _mm512_store_si512((__m512i*) words23, _mm512_or_si512(c[2], _mm512_slli_epi64(c[3], 32)));
    for (int lane = 0; lane < 8; lane++) {
        std::memcpy(&out[lane].v[0], &words01[lane], 8);
        std::memcpy(&out[lane].v[2], &words23[lane], 8);
    }
}

#pragma GCC diagnostic pop
#endif

#if defined(OPENMMDPD_PHILOX_AVX2) && defined(OPENMMDPD_HAVE_LIBMVEC)
// glibc's vector math library (libmvec): log and cos of four doubles at once, AVX2 variants.
extern "C" __m256d _ZGVdN4v_log(__m256d);
extern "C" __m256d _ZGVdN4v_cos(__m256d);
extern "C" __m256d _ZGVdN4v_sin(__m256d);

/**
 * PairRandom::boxMuller of four pairs of words (given as exact doubles), with its operations:
 * the same numbers to rounding; and their partners (boxMullerPartner) where asked for.
 */
__attribute__((target("avx2"), always_inline)) inline __m256d boxMullerOf(__m256d first, __m256d second, __m256d* partner) {
    // PairRandom::toOpenUniform and toUniform, four at a time.
    const __m256d scale = _mm256_set1_pd(1.0 / 4294967296.0);
    const __m256d u1 = _mm256_mul_pd(_mm256_add_pd(first, _mm256_set1_pd(1.0)), scale);
    const __m256d u2 = _mm256_mul_pd(second, scale);
    const __m256d radius = _mm256_sqrt_pd(_mm256_mul_pd(_mm256_set1_pd(-2.0), _ZGVdN4v_log(u1)));
    const __m256d angle = _mm256_mul_pd(_mm256_set1_pd(2.0 * M_PI), u2);
    if (partner != nullptr)
        *partner = _mm256_mul_pd(radius, _ZGVdN4v_sin(angle));
    return _mm256_mul_pd(radius, _ZGVdN4v_cos(angle));
}

/** Philox words below 2^32 in 64-bit lanes as exact doubles: 2^52 + w as a double's bits, less 2^52. */
__attribute__((target("avx2"), always_inline)) inline __m256d wordsAsDoubles(__m256i words) {
    const __m256d twoTo52 = _mm256_set1_pd(4503599627370496.0);
    return _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(words, _mm256_castpd_si256(twoTo52))), twoTo52);
}

__attribute__((target("avx512f"), always_inline)) inline __m512d wordsAsDoubles(__m512i words) {
    const __m512d twoTo52 = _mm512_set1_pd(4503599627370496.0);
    return _mm512_sub_pd(_mm512_castsi512_pd(_mm512_or_si512(words, _mm512_castpd_si512(twoTo52))), twoTo52);
}

// Words 0 and 1 of four or eight pairs' draws, as doubles, where Box-Muller reads them four
// at a time (not as the words of each draw, to be gathered one by one).
__attribute__((target("avx2"))) void firstWordsFour(uint32_t seed, uint32_t stream, long long step, const int* i, const int* j,
                                                    double* first, double* second) {
    __m256i c[4];
    philoxRoundsFour(seed, stream, step, i, j, c);
    _mm256_storeu_pd(first, wordsAsDoubles(c[0]));
    _mm256_storeu_pd(second, wordsAsDoubles(c[1]));
}

__attribute__((target("avx512f"))) void firstWordsEight(uint32_t seed, uint32_t stream, long long step, const int* i, const int* j,
                                                       double* first, double* second) {
    __m512i c[4];
    philoxRoundsEight(seed, stream, step, i, j, c);
    _mm512_storeu_pd(first, wordsAsDoubles(c[0]));
    _mm512_storeu_pd(second, wordsAsDoubles(c[1]));
}

/** The first min(4, m) of four numbers to out. */
__attribute__((target("avx2"), always_inline)) inline void storeFour(__m256d x, double* out, int m) {
    if (m >= 4) {
        _mm256_storeu_pd(out, x);
        return;
    }
    alignas(32) double last[4];
    _mm256_store_pd(last, x);
    std::copy(last, last + m, out);
}

/**
 * PairRandomBatch::normals (and their partners, given partnerOut) for n <= NORMALS_BLOCK
 * pairs: all their words first (eight or four draws at a time), then Box-Muller four at a
 * time.  (Each four's normals made straight from its draw measured slower: one long chain of
 * dependent steps, where a block's draws overlap.)
 */
__attribute__((target("avx2"))) void normalBlockAVX2(const PairRandom& random, uint32_t stream, long long step, const int* i,
                                                     const int* j, int n, double* out, double* partnerOut) {
    alignas(32) double first[NORMALS_BLOCK], second[NORMALS_BLOCK];
    int k = 0;
    if (haveAVX512())
        for (; k + 8 <= n; k += 8)
            firstWordsEight(random.getSeed(), stream, step, i + k, j + k, first + k, second + k);
    for (; k + 4 <= n; k += 4)
        firstWordsFour(random.getSeed(), stream, step, i + k, j + k, first + k, second + k);
    for (; k < n; k++) {
        const Counter words = random.bits((PairRandom::Stream) stream, step, i[k], j[k]);
        first[k] = words[0];
        second[k] = words[1];
    }
    // The last four's lanes past n repeat the last number, so that it too goes through libmvec.
    for (; k % 4 != 0; k++) {
        first[k] = first[n - 1];
        second[k] = second[n - 1];
    }
    for (k = 0; k < n; k += 4) {
        __m256d y = _mm256_setzero_pd();
        const __m256d x = boxMullerOf(_mm256_load_pd(first + k), _mm256_load_pd(second + k), partnerOut ? &y : nullptr);
        storeFour(x, out + k, n - k);
        if (partnerOut)
            storeFour(y, partnerOut + k, n - k);
    }
}

/** PairRandomBatch::normalVectors for n <= NORMALS_BLOCK pairs: their words (bits()), then the three numbers four pairs at a time. */
__attribute__((target("avx2"))) void normalVectorBlockAVX2(const PairRandom& random, uint32_t stream, long long step, const int* i,
                                                           const int* j, int n, double* out) {
    Counter words[NORMALS_BLOCK];
    PairRandomBatch::bits(random, (PairRandom::Stream) stream, step, i, j, n, words);
    alignas(32) double w[4][NORMALS_BLOCK], number[3][NORMALS_BLOCK];
    int k = 0;
    for (; k < n; k++)
        for (int c = 0; c < 4; c++)
            w[c][k] = words[k][c];
    for (; k % 4 != 0; k++)  // the last four's lanes past n repeat the last pair (as normalBlockAVX2's)
        for (int c = 0; c < 4; c++)
            w[c][k] = w[c][n - 1];
    for (k = 0; k < n; k += 4) {
        __m256d partner;
        _mm256_store_pd(number[0] + k, boxMullerOf(_mm256_load_pd(w[0] + k), _mm256_load_pd(w[1] + k), &partner));
        _mm256_store_pd(number[1] + k, partner);
        _mm256_store_pd(number[2] + k, boxMullerOf(_mm256_load_pd(w[2] + k), _mm256_load_pd(w[3] + k), nullptr));
    }
    for (k = 0; k < n; k++) {
        const double sign = (i[k] < j[k] ? 1.0 : -1.0);  // as PairRandom::normalVector
        for (int c = 0; c < 3; c++)
            out[3 * k + c] = sign * number[c][k];
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

void PairRandomBatch::normals(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j,
                              int n, double* out) {
    normalsAndPartners(random, stream, step, i, j, n, out, nullptr);
}

void PairRandomBatch::normalVectors(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i, const int* j,
                                    int n, double* out) {
    for (int start = 0; start < n; start += NORMALS_BLOCK) {
        const int m = std::min(NORMALS_BLOCK, n - start);
#ifdef OPENMMDPD_BOX_MULLER_AVX2
        if (haveAVX2()) {
            normalVectorBlockAVX2(random, (uint32_t) stream, step, i + start, j + start, m, out + 3 * start);
            continue;
        }
#endif
        for (int k = start; k < start + m; k++)
            random.normalVector(stream, step, i[k], j[k], out + 3 * k);
    }
}

void PairRandomBatch::normalsAndPartners(const PairRandom& random, PairRandom::Stream stream, long long step, const int* i,
                                         const int* j, int n, double* out, double* partnerOut) {
    for (int start = 0; start < n; start += NORMALS_BLOCK) {
        const int m = std::min(NORMALS_BLOCK, n - start);
#ifdef OPENMMDPD_BOX_MULLER_AVX2
        if (haveAVX2()) {
            normalBlockAVX2(random, (uint32_t) stream, step, i + start, j + start, m, out + start,
                            partnerOut ? partnerOut + start : nullptr);
            continue;
        }
#endif
        for (int k = start; k < start + m; k++) {
            const r123::Philox4x32::ctr_type words = random.bits(stream, step, i[k], j[k]);
            out[k] = PairRandom::boxMuller(words);
            if (partnerOut)
                partnerOut[k] = PairRandom::boxMullerPartner(words);
        }
    }
}
