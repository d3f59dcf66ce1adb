/* Philox4x32-10 for four or twelve counters at once (AVX2, see CMakeLists.txt): the same function
 * as Random123's philox4x32 (tests/unit/test_rng.c compares them bit for bit), each 32-bit word in
 * the low half of a 64-bit lane so that _mm256_mul_epu32 gives the full product. */
#include "core/vmath.h"

#if defined(__AVX2__)
#include <immintrin.h>

/* One Philox round on the words x[0..3] with key (k0, k1): Random123's _philox4x32round.
 * Only the low halves of the lanes are the words: the high halves may hold anything, since
 * x[0] and x[2] only enter the multiplies (which read the low halves) and x[1], x[3] and
 * the keys only enter x[0] and x[2]; the words are masked once, at the end. */
static inline void philox_round(__m256i x[4], __m256i k0, __m256i k1) {
    const __m256i p0 = _mm256_mul_epu32(x[0], _mm256_set1_epi64x(0xD2511F53));
    const __m256i p1 = _mm256_mul_epu32(x[2], _mm256_set1_epi64x(0xCD9E8D57));
    x[0] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p1, 32), x[1]), k0);
    x[1] = p1; /* low half: lo(p1) */
    x[2] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p0, 32), x[3]), k1);
    x[3] = p0;
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
enum { PHILOX_GROUPS = 3 };

/* The 53-bit uniform of the words (hi, lo) in the low halves of the lanes, as in
 * src/core/rng.c: (a + 1/2) 2^-53. */
static inline __m256d uniform_of_words(__m256i hi, __m256i lo) {
    lo = _mm256_and_si256(lo, _mm256_set1_epi64x(0xffffffff));
    const __m256i a = _mm256_srli_epi64(_mm256_or_si256(_mm256_slli_epi64(hi, 32), lo), 11);
    return _mm256_mul_pd(_mm256_add_pd(exact_u53_to_double(a), _mm256_set1_pd(0.5)),
                         _mm256_set1_pd(0x1.0p-53));
}

/* What every counter of one call shares: the key of the first round (the later ones add
 * the Weyl bumps, modulo 2^32 in the low halves) and the other three words. */
typedef struct philox_setup {
    __m256i key0, key1;
    __m256i step_lo, step_hi, stream;
} philox_setup;

static philox_setup philox_setup_of(uint64_t seed, uint32_t stream, uint64_t step) {
    philox_setup s;
    s.key0 = _mm256_set1_epi64x((uint32_t)seed);
    s.key1 = _mm256_set1_epi64x((uint32_t)(seed >> 32));
    s.step_lo = _mm256_set1_epi64x((uint32_t)step);
    s.step_hi = _mm256_set1_epi64x((uint32_t)(step >> 32));
    s.stream = _mm256_set1_epi64x(stream);
    return s;
}

/* Ten rounds on the `groups` counters x[][4], the round keys made on the way in registers
 * (32-bit adds: the bump is modulo 2^32). */
static inline void philox_rounds(const philox_setup *s, __m256i x[][4], int groups) {
    const __m256i bump0 = _mm256_set1_epi64x(0x9E3779B9), bump1 = _mm256_set1_epi64x(0xBB67AE85);
    __m256i k0 = s->key0, k1 = s->key1;
    for (int round = 0; round < 10; ++round) {
        for (int g = 0; g < groups; ++g)
            philox_round(x[g], k0, k1);
        k0 = _mm256_add_epi32(k0, bump0);
        k1 = _mm256_add_epi32(k1, bump1);
    }
}

/* The uniform pairs of the 4 `groups` counters c[] (index pairs) into u1[], u2[];
 * groups <= PHILOX_GROUPS, a constant at each call. */
static inline void philox_pairs(const philox_setup *s, const uint64_t *c, int groups,
                                double *restrict u1, double *restrict u2) {
    __m256i x[PHILOX_GROUPS][4];
    for (int g = 0; g < groups; ++g) {
        const uint64_t *cg = c + 4 * g; /* the multiplies read the low 32 bits */
        x[g][0] =
            _mm256_setr_epi64x((int64_t)cg[0], (int64_t)cg[1], (int64_t)cg[2], (int64_t)cg[3]);
        x[g][1] = s->step_lo;
        x[g][2] = s->step_hi;
        x[g][3] = s->stream;
    }
    philox_rounds(s, x, groups);
    for (int g = 0; g < groups; ++g) { /* 53 bits from (v0, v1) and from (v2, v3) */
        _mm256_storeu_pd(u1 + 4 * g, uniform_of_words(x[g][0], x[g][1]));
        _mm256_storeu_pd(u2 + 4 * g, uniform_of_words(x[g][2], x[g][3]));
    }
}

void hsbd_philox_uniform_pairs_avx2(uint64_t seed, uint32_t stream, uint64_t step, uint64_t k0,
                                    size_t npairs, double *restrict u1, double *restrict u2) {
    const philox_setup s = philox_setup_of(seed, stream, step);
    uint64_t c[4 * PHILOX_GROUPS];
    size_t j = 0;
    for (; j + 4 * PHILOX_GROUPS <= npairs; j += 4 * PHILOX_GROUPS) {
        for (int q = 0; q < 4 * PHILOX_GROUPS; ++q)
            c[q] = k0 + j + (uint64_t)q;
        philox_pairs(&s, c, PHILOX_GROUPS, u1 + j, u2 + j);
    }
    const size_t tail = npairs - j; /* 0, 4 or 8: a tail of eight runs both groups at once */
    for (size_t q = 0; q < tail; ++q)
        c[q] = k0 + j + q;
    if (tail == 8)
        philox_pairs(&s, c, 2, u1 + j, u2 + j);
    else if (tail == 4)
        philox_pairs(&s, c, 1, u1 + j, u2 + j);
}

/* The uniforms of the indices base + offset[k], k < valid <= 4 `groups`, into out[]: index i
 * is the first word pair of counter i / 2 when i is even, the second when odd (as
 * src/core/rng.c hands the pairs out). groups <= PHILOX_GROUPS is a constant at each call;
 * a short run (valid < 4 groups) reads and writes only its entries, through masks. */
static inline void philox_listed(const philox_setup *s, uint64_t base, const unsigned *offset,
                                 int groups, size_t valid, double *restrict out) {
    const int whole = valid == (size_t)(4 * groups);
    __m256i x[PHILOX_GROUPS][4], odd[PHILOX_GROUPS];
    __m128i below[PHILOX_GROUPS]; /* the lanes with 4 g + lane < valid */
    for (int g = 0; g < groups; ++g) {
        const int *og = (const int *)(const void *)(offset + 4 * g);
        below[g] = _mm_cmpgt_epi32(_mm_set1_epi32((int)valid - 4 * g), _mm_setr_epi32(0, 1, 2, 3));
        const __m128i o = whole ? _mm_loadu_si128((const __m128i *)(const void *)og)
                                : _mm_maskload_epi32(og, below[g]);
        const __m256i index =
            _mm256_add_epi64(_mm256_set1_epi64x((int64_t)base), _mm256_cvtepu32_epi64(o));
        odd[g] = _mm256_cmpeq_epi64(_mm256_and_si256(index, _mm256_set1_epi64x(1)),
                                    _mm256_set1_epi64x(1));
        x[g][0] = _mm256_srli_epi64(index, 1); /* the counter; the multiplies read 32 bits */
        x[g][1] = s->step_lo;
        x[g][2] = s->step_hi;
        x[g][3] = s->stream;
    }
    philox_rounds(s, x, groups);
    for (int g = 0; g < groups; ++g) { /* (v0, v1) for an even index, (v2, v3) for an odd */
        const __m256i hi = _mm256_blendv_epi8(x[g][0], x[g][2], odd[g]);
        const __m256i lo = _mm256_blendv_epi8(x[g][1], x[g][3], odd[g]);
        const __m256d u = uniform_of_words(hi, lo);
        if (whole)
            _mm256_storeu_pd(out + 4 * g, u);
        else
            _mm256_maskstore_pd(out + 4 * g, _mm256_cvtepi32_epi64(below[g]), u);
    }
}

void hsbd_philox_uniforms_at_avx2(uint64_t seed, uint32_t stream, uint64_t step, uint64_t base,
                                  const unsigned *offset, size_t n, double *restrict out) {
    const philox_setup s = philox_setup_of(seed, stream, step);
    size_t j = 0;
    for (; j + 4 * PHILOX_GROUPS <= n; j += 4 * PHILOX_GROUPS)
        philox_listed(&s, base, offset + j, PHILOX_GROUPS, 4 * PHILOX_GROUPS, out + j);
    const size_t tail = n - j; /* in one interleaved call of as few groups as hold it */
    if (tail > 8)
        philox_listed(&s, base, offset + j, 3, tail, out + j);
    else if (tail > 4)
        philox_listed(&s, base, offset + j, 2, tail, out + j);
    else if (tail > 0)
        philox_listed(&s, base, offset + j, 1, tail, out + j);
}
/* The counters of blocks base + block[l], l < valid <= 4 (the other lanes: base), read one by
 * one: the caller has just stored the blocks one by one, and a vector load of four such
 * stores waits for them to reach the cache. */
static inline void blocks_setup(const philox_setup *s, uint64_t base, const unsigned *block,
                                size_t valid, __m256i x[4]) {
    uint64_t c[4];
    for (size_t l = 0; l < 4; ++l)
        c[l] = base + (l < valid ? block[l] : 0u);
    x[0] = _mm256_setr_epi64x((int64_t)c[0], (int64_t)c[1], (int64_t)c[2], (int64_t)c[3]);
    x[1] = s->step_lo;
    x[2] = s->step_hi;
    x[3] = s->stream;
}

/* Their 16 bytes each to out + 16 block[l], l < valid: per lane the words (v0, v1) and
 * (v2, v3) as two 64-bit halves (least significant word first, so the bytes come out in the
 * order of src/core/rng.c), one 16-byte store per block. */
static inline void blocks_store(const __m256i x[4], const unsigned *block, size_t valid,
                                uint8_t *restrict out) {
    const __m256i low = _mm256_set1_epi64x(0xffffffff);
    const __m256i a = _mm256_or_si256(_mm256_and_si256(x[0], low), _mm256_slli_epi64(x[1], 32));
    const __m256i b = _mm256_or_si256(_mm256_and_si256(x[2], low), _mm256_slli_epi64(x[3], 32));
    const __m256i even = _mm256_unpacklo_epi64(a, b), odd = _mm256_unpackhi_epi64(a, b);
    const __m128i lane[4] = {_mm256_castsi256_si128(even), _mm256_castsi256_si128(odd),
                             _mm256_extracti128_si256(even, 1), _mm256_extracti128_si256(odd, 1)};
    for (size_t l = 0; l < valid && l < 4; ++l)
        _mm_storeu_si128((__m128i *)(void *)(out + 16 * (size_t)block[l]), lane[l]);
}

/* The bytes of blocks base + block[k], k < valid <= 4 `groups` (a constant at each call,
 * <= PHILOX_GROUPS), to out + 16 block[k]. */
static inline void philox_blocks(const philox_setup *s, uint64_t base, const unsigned *block,
                                 int groups, size_t valid, uint8_t *restrict out) {
    __m256i x[PHILOX_GROUPS][4];
    for (int g = 0; g < groups; ++g)
        blocks_setup(s, base, block + 4 * g, valid > (size_t)(4 * g) ? valid - (size_t)(4 * g) : 0,
                     x[g]);
    philox_rounds(s, x, groups);
    for (int g = 0; g < groups && valid > (size_t)(4 * g); ++g)
        blocks_store(x[g], block + 4 * g, valid - (size_t)(4 * g), out);
}

void hsbd_philox_bytes_at_avx2(uint64_t seed, uint32_t stream, uint64_t step, uint64_t base,
                               const unsigned *block, size_t n, uint8_t *restrict out) {
    const philox_setup s = philox_setup_of(seed, stream, step);
    size_t j = 0;
    for (; j + 4 * PHILOX_GROUPS <= n; j += 4 * PHILOX_GROUPS)
        philox_blocks(&s, base, block + j, PHILOX_GROUPS, 4 * PHILOX_GROUPS, out);
    const size_t tail = n - j; /* in one interleaved call of as few groups as hold it */
    if (tail > 8)
        philox_blocks(&s, base, block + j, 3, tail, out);
    else if (tail > 4)
        philox_blocks(&s, base, block + j, 2, tail, out);
    else if (tail > 0)
        philox_blocks(&s, base, block + j, 1, tail, out);
}

/* The bytes of blocks and four uniforms in one call (byte_groups a constant, 1 or 2): one
 * chain of multiplies for both, where two calls would wait for two. */
static inline void philox_blocks_and_four(const philox_setup *s, uint64_t base,
                                          const unsigned *block, size_t n, int byte_groups,
                                          uint8_t *restrict out, uint32_t stream, uint64_t index,
                                          double *restrict four) {
    __m256i x[PHILOX_GROUPS][4];
    for (int g = 0; g < byte_groups; ++g)
        blocks_setup(s, base, block + 4 * g, n > (size_t)(4 * g) ? n - (size_t)(4 * g) : 0, x[g]);
    __m256i *xu = x[byte_groups]; /* index + l: counter (index + l) / 2, half (index + l) % 2 */
    const __m256i indices =
        _mm256_add_epi64(_mm256_set1_epi64x((int64_t)index), _mm256_setr_epi64x(0, 1, 2, 3));
    const __m256i odd =
        _mm256_cmpeq_epi64(_mm256_and_si256(indices, _mm256_set1_epi64x(1)), _mm256_set1_epi64x(1));
    xu[0] = _mm256_srli_epi64(indices, 1);
    xu[1] = s->step_lo;
    xu[2] = s->step_hi;
    xu[3] = _mm256_set1_epi64x(stream);
    philox_rounds(s, x, byte_groups + 1);
    for (int g = 0; g < byte_groups && n > (size_t)(4 * g); ++g)
        blocks_store(x[g], block + 4 * g, n - (size_t)(4 * g), out);
    _mm256_storeu_pd(four, uniform_of_words(_mm256_blendv_epi8(xu[0], xu[2], odd),
                                            _mm256_blendv_epi8(xu[1], xu[3], odd)));
}

void hsbd_philox_bytes_and_four_avx2(uint64_t seed, uint64_t step, uint32_t byte_stream,
                                     uint64_t base, const unsigned *block, size_t n,
                                     uint8_t *restrict out, uint32_t uniform_stream, uint64_t index,
                                     double *restrict four) {
    const philox_setup s = philox_setup_of(seed, byte_stream, step);
    if (n > 4)
        philox_blocks_and_four(&s, base, block, n, 2, out, uniform_stream, index, four);
    else
        philox_blocks_and_four(&s, base, block, n, 1, out, uniform_stream, index, four);
}
#endif
