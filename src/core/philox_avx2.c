/* Philox4x32-10 for four or eight counters at once (AVX2, see CMakeLists.txt): the same function as
 * Random123's philox4x32 (tests/unit/test_rng.c compares them bit for bit), each 32-bit
 * word in the low half of a 64-bit lane so that _mm256_mul_epu32 gives the full product. */
#include "core/vmath.h"

#if defined(__AVX2__)
#include <immintrin.h>

/* One Philox round on the words x[0..3] with key (k0, k1): Random123's _philox4x32round. */
static inline void philox_round(__m256i x[4], __m256i k0, __m256i k1) {
    const __m256i low = _mm256_set1_epi64x(0xffffffff);
    const __m256i p0 = _mm256_mul_epu32(x[0], _mm256_set1_epi64x(0xD2511F53));
    const __m256i p1 = _mm256_mul_epu32(x[2], _mm256_set1_epi64x(0xCD9E8D57));
    const __m256i hi0 = _mm256_srli_epi64(p0, 32), lo0 = _mm256_and_si256(p0, low);
    const __m256i hi1 = _mm256_srli_epi64(p1, 32), lo1 = _mm256_and_si256(p1, low);
    x[0] = _mm256_xor_si256(_mm256_xor_si256(hi1, x[1]), k0);
    x[1] = lo1;
    x[2] = _mm256_xor_si256(_mm256_xor_si256(hi0, x[3]), k1);
    x[3] = lo0;
}

/* (double) of a < 2^53 in each lane, exactly: two 32-bit halves through 2^52 + h. */
static inline __m256d exact_u53_to_double(__m256i a) {
    const __m256i magic = _mm256_set1_epi64x(0x4330000000000000); /* 2^52 */
    const __m256d two52 = _mm256_set1_pd(0x1.0p52), two32 = _mm256_set1_pd(0x1.0p32);
    const __m256i hi = _mm256_srli_epi64(a, 32);
    const __m256i lo = _mm256_and_si256(a, _mm256_set1_epi64x(0xffffffff));
    const __m256d dhi = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(hi, magic)), two52);
    const __m256d dlo = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(lo, magic)), two52);
    return _mm256_add_pd(_mm256_mul_pd(dhi, two32), dlo); /* exact: an integer < 2^53 */
}

/* Groups of four counters run together: their rounds interleave, since one group's chain
 * of ten rounds is bound by the multiplies' latency on its own. */
enum { PHILOX_GROUPS = 2 };

/* The 53-bit uniform of the words (hi, lo), as in src/core/rng.c: (a + 1/2) 2^-53. */
static inline __m256d uniform_of_words(__m256i hi, __m256i lo) {
    const __m256i a = _mm256_srli_epi64(_mm256_or_si256(_mm256_slli_epi64(hi, 32), lo), 11);
    return _mm256_mul_pd(_mm256_add_pd(exact_u53_to_double(a), _mm256_set1_pd(0.5)),
                         _mm256_set1_pd(0x1.0p-53));
}

/* The uniform pairs of the 4 `groups` counters c[] (index pairs) into u1[], u2[];
 * groups <= PHILOX_GROUPS, a constant at each call. */
static inline void philox_pairs(uint64_t seed, uint32_t stream, uint64_t step, const uint64_t *c,
                                int groups, double *restrict u1, double *restrict u2) {
    const __m256i low = _mm256_set1_epi64x(0xffffffff);
    const __m256i w0 = _mm256_set1_epi64x(0x9E3779B9), w1 = _mm256_set1_epi64x(0xBB67AE85);
    __m256i x[PHILOX_GROUPS][4];
    for (int g = 0; g < groups; ++g) {
        const uint64_t *cg = c + 4 * g;
        x[g][0] = _mm256_and_si256(
            _mm256_setr_epi64x((int64_t)cg[0], (int64_t)cg[1], (int64_t)cg[2], (int64_t)cg[3]),
            low);
        x[g][1] = _mm256_set1_epi64x((uint32_t)step);
        x[g][2] = _mm256_set1_epi64x((uint32_t)(step >> 32));
        x[g][3] = _mm256_set1_epi64x(stream);
    }
    __m256i key0 = _mm256_set1_epi64x((uint32_t)seed);
    __m256i key1 = _mm256_set1_epi64x((uint32_t)(seed >> 32));
    for (int round = 0; round < 10; ++round) {
        if (round) { /* the key bump, modulo 2^32 in the low halves */
            key0 = _mm256_and_si256(_mm256_add_epi64(key0, w0), low);
            key1 = _mm256_and_si256(_mm256_add_epi64(key1, w1), low);
        }
        for (int g = 0; g < groups; ++g)
            philox_round(x[g], key0, key1);
    }
    for (int g = 0; g < groups; ++g) { /* 53 bits from (v0, v1) and from (v2, v3) */
        _mm256_storeu_pd(u1 + 4 * g, uniform_of_words(x[g][0], x[g][1]));
        _mm256_storeu_pd(u2 + 4 * g, uniform_of_words(x[g][2], x[g][3]));
    }
}

void hsbd_philox_uniform_pairs_avx2(uint64_t seed, uint32_t stream, uint64_t step, uint64_t k0,
                                    size_t npairs, double *restrict u1, double *restrict u2) {
    uint64_t c[4 * PHILOX_GROUPS];
    size_t j = 0;
    for (; j + 4 * PHILOX_GROUPS <= npairs; j += 4 * PHILOX_GROUPS) {
        for (int q = 0; q < 4 * PHILOX_GROUPS; ++q)
            c[q] = k0 + j + (uint64_t)q;
        philox_pairs(seed, stream, step, c, PHILOX_GROUPS, u1 + j, u2 + j);
    }
    for (; j + 4 <= npairs; j += 4) {
        for (int q = 0; q < 4; ++q)
            c[q] = k0 + j + (uint64_t)q;
        philox_pairs(seed, stream, step, c, 1, u1 + j, u2 + j);
    }
}

void hsbd_philox_uniform_pairs_at_avx2(uint64_t seed, uint32_t stream, uint64_t step,
                                       const uint64_t *k, size_t npairs, double *restrict u1,
                                       double *restrict u2) {
    size_t j = 0;
    for (; j + 4 * PHILOX_GROUPS <= npairs; j += 4 * PHILOX_GROUPS)
        philox_pairs(seed, stream, step, k + j, PHILOX_GROUPS, u1 + j, u2 + j);
    for (; j + 4 <= npairs; j += 4)
        philox_pairs(seed, stream, step, k + j, 1, u1 + j, u2 + j);
}
#endif
