/* The reflect rule's passes over a batch of gaps (see gaps.h). The AVX2 versions test four
 * gaps per vector, turn the answers of a block into bits, and store the places of the set
 * bits of each byte, taken from a table, in one go: no branch on the answers, whose pattern
 * is random. */
#include "rods1d/gaps.h"

#include <math.h>
#include <string.h>

#include "core/vmath.h"
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

/* the gaps of block b that may cross (bit j - j0 for gap j), their products into g0g1 */
static unsigned block_may_cross(const double *restrict z, const double *restrict y,
                                const double *restrict d, double d_one, size_t b, size_t m,
                                double *restrict g0g1) {
    const size_t j0 = GAP_BLOCK * b, j1 = j0 + GAP_BLOCK < m ? j0 + GAP_BLOCK : m;
    unsigned bits = 0;
    for (size_t j = j0; j < j1; ++j) {
        const double g0 = z[j + 1] - z[j], g1 = y[j + 1] - y[j];
        g0g1[j] = g0 * g1;
        bits |= (unsigned)bridge_may_cross(g0, g1, d ? d[j] : d_one) << (j - j0);
    }
    return bits;
}

size_t gap_blocks_may_cross_scalar(const double *z, const double *y, const double *d, double d_one,
                                   size_t m, uint16_t *mask, unsigned *blocks, double *g0g1) {
    size_t count = 0;
    for (size_t b = 0; GAP_BLOCK * b < m; ++b) {
        const unsigned bits = block_may_cross(z, y, d, d_one, b, m, g0g1);
        mask[b] = (uint16_t)bits;
        blocks[count] = (unsigned)b;
        count += bits != 0;
    }
    return count;
}

size_t gap_candidates_scalar(const double *g0g1, const double *d, double d_one, size_t m,
                             const uint16_t *mask, const unsigned *blocks, size_t nblocks,
                             const uint8_t *bytes, unsigned *idx) {
    size_t count = 0;
    for (size_t k = 0; k < nblocks; ++k) {
        const size_t j0 = GAP_BLOCK * (size_t)blocks[k];
        const size_t j1 = j0 + GAP_BLOCK < m ? j0 + GAP_BLOCK : m;
        for (size_t j = j0; j < j1; ++j) {
            const int candidate = bridge_byte_candidate(g0g1[j], d ? d[j] : d_one, bytes[j]);
            idx[count] = (unsigned)j;
            count += (size_t)((mask[blocks[k]] >> (j - j0) & 1u) & (unsigned)candidate);
        }
    }
    return count;
}

size_t gap_candidates_all_scalar(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, const uint8_t *bytes, unsigned *idx, size_t *listed) {
    size_t count = 0;
    *listed = 0;
    for (size_t j0 = 0; j0 < m; j0 += GAP_BLOCK) {
        int any = 0;
        for (size_t j = j0; j < m && j < j0 + GAP_BLOCK; ++j) {
            const double g0 = z[j + 1] - z[j], g1 = y[j + 1] - y[j], dj = d ? d[j] : d_one;
            const int may = bridge_may_cross(g0, g1, dj);
            any |= may;
            idx[count] = (unsigned)j;
            count += (size_t)(may & bridge_byte_candidate(g0 * g1, dj, bytes[j]));
        }
        *listed += (size_t)any;
    }
    return count;
}

/* the push of one gap (gap_pushes), -m or 0 */
static inline double bridge_push_of(double sum, double sq, double d_rel_dt, double ln_u) {
    const double push = 0.5 * (sqrt(sq - 4.0 * d_rel_dt * ln_u) - sum); /* -m, Skorokhod */
    return push > 0 ? push : 0.0;                                       /* as maxpd */
}

void gap_pushes_scalar(size_t count, const double *sum, const double *sq, const double *d,
                       double d_one, double *ln_u) {
    for (size_t k = 0; k < count; ++k)
        ln_u[k] = bridge_push_of(sum[k], sq[k], d ? d[k] : d_one, ln_u[k]);
}

void gap_half_pushes_scalar(size_t n, const double *restrict y, const double *restrict push,
                            double *restrict out) {
    for (size_t i = 0; i < n; ++i)
        out[i] = y[i] + 0.5 * push[i - 1] - 0.5 * push[i];
}

void gap_half_pushes_at(size_t m, const double *restrict y, const double *restrict push,
                        const unsigned *restrict idx, size_t count, double *restrict out) {
    gap_copy(m - 1, y + 1, out + 1);
    for (size_t k = 0; k < count; ++k) { /* rod j + 1 gets gap j's half before gap j + 1's */
        const size_t j = idx[k];
        if (j > 0) out[j] -= 0.5 * push[j];
        if (j + 1 < m) out[j + 1] += 0.5 * push[j];
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
/* The places of the set bits of a byte b, packed three bits each: the r-th lowest set bit's
 * place in bits 3r .. 3r + 2 (a table of all 256 bytes made by the compiler). */
#define BIT_PLACE(b, k)                                                                            \
    (((unsigned)(b) >> (k)&1u) *                                                                   \
     ((unsigned)(k) << (3 * __builtin_popcount((b) & ((1u << (k)) - 1u)))))
#define SET_BIT_PLACES(b)                                                                          \
    (BIT_PLACE(b, 0) | BIT_PLACE(b, 1) | BIT_PLACE(b, 2) | BIT_PLACE(b, 3) | BIT_PLACE(b, 4) |     \
     BIT_PLACE(b, 5) | BIT_PLACE(b, 6) | BIT_PLACE(b, 7))
#define PLACES_4(b)                                                                                \
    SET_BIT_PLACES(b), SET_BIT_PLACES(b + 1u), SET_BIT_PLACES(b + 2u), SET_BIT_PLACES(b + 3u)
#define PLACES_16(b) PLACES_4(b), PLACES_4(b + 4u), PLACES_4(b + 8u), PLACES_4(b + 12u)
#define PLACES_64(b) PLACES_16(b), PLACES_16(b + 16u), PLACES_16(b + 32u), PLACES_16(b + 48u)
static const uint32_t set_bit_places[256] = {PLACES_64(0u), PLACES_64(64u), PLACES_64(128u),
                                             PLACES_64(192u)};

/* The places of the set bits of the byte `bits` plus j, stored at idx + count at once (room:
 * eight entries); returns the new count. */
__attribute__((target("avx2,popcnt"))) static inline size_t
store_places(unsigned bits, size_t j, size_t count, unsigned *restrict idx) {
    const __m256i shifts = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
    const __m256i places =
        _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32((int)set_bit_places[bits]), shifts),
                         _mm256_set1_epi32(7));
    _mm256_storeu_si256((__m256i *)(void *)(idx + count),
                        _mm256_add_epi32(places, _mm256_set1_epi32((int)j)));
    return count + (size_t)__builtin_popcount(bits);
}

/* the lanes below `valid` of four */
__attribute__((target("avx2"))) static inline __m256i lanes_below(int valid) {
    return _mm256_cmpgt_epi64(_mm256_set1_epi64x(valid), _mm256_setr_epi64x(0, 1, 2, 3));
}

/* p[0 .. 3], or the first `valid` of them (the others 0) when valid < 4 */
__attribute__((target("avx2"))) static inline __m256d load4(const double *p, int valid) {
    return valid >= 4 ? _mm256_loadu_pd(p) : _mm256_maskload_pd(p, lanes_below(valid));
}

/* bridge_may_cross of gaps j .. j + 3 as four bits (the same products and comparisons),
 * their products g0 g1 into g0g1[j ..]; gaps from j + valid on read and write no memory, and
 * their bits are to be ignored */
__attribute__((target("avx2,no-fma"))) static inline unsigned
may_cross4(const double *restrict z, const double *restrict y, const double *restrict d,
           double d_one, size_t j, int valid, double *restrict g0g1) {
    const __m256d g0 = _mm256_sub_pd(load4(z + j + 1, valid), load4(z + j, valid));
    const __m256d g1 = _mm256_sub_pd(load4(y + j + 1, valid), load4(y + j, valid));
    const __m256d dj = d ? load4(d + j, valid) : _mm256_set1_pd(d_one);
    const __m256d product = _mm256_mul_pd(g0, g1);
    if (valid >= 4)
        _mm256_storeu_pd(g0g1 + j, product);
    else
        _mm256_maskstore_pd(g0g1 + j, lanes_below(valid), product);
    const __m256d may = /* !(g1 > 0) | !(g0 g1 > 20 d) */
        _mm256_or_pd(_mm256_cmp_pd(g1, _mm256_setzero_pd(), _CMP_NGT_UQ),
                     _mm256_cmp_pd(product, _mm256_mul_pd(_mm256_set1_pd(20.0), dj), _CMP_NGT_UQ));
    return (unsigned)_mm256_movemask_pd(may);
}

/* bridge_byte_candidate of four gaps, given their products, their 2^23 log2(e) / D_rel dt and
 * their bytes: the same operations lane by lane */
__attribute__((target("avx2,no-fma"))) static inline unsigned
candidate_of(__m256d product, __m256d scale, const uint8_t *restrict bytes) {
    const __m256d e = _mm256_mul_pd(product, scale);
    int four;
    __builtin_memcpy(&four, bytes, sizeof four);
    const __m128 b = _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(four)));
    const __m256d bits = _mm256_cvtepi32_pd(_mm_castps_si128(b)); /* < 2^31: exact */
    return (unsigned)_mm256_movemask_pd(_mm256_cmp_pd(
        _mm256_add_pd(e, bits), _mm256_set1_pd(0x1p23 * (135.0 + 0x1p-16)), _CMP_LT_OQ));
}

/* 2^23 log2(e) / D_rel dt of gaps j .. j + 3: per gap, or scale_one for one species */
__attribute__((target("avx2,no-fma"))) static inline __m256d
candidate_scale(const double *restrict d, __m256d scale_one, size_t j, int valid) {
    return d ? _mm256_div_pd(_mm256_set1_pd(0x1p23 * 1.4426950408889634), load4(d + j, valid))
             : scale_one;
}

/* bridge_byte_candidate of gaps j .. j + 3 as four bits, from their stored products (the
 * bytes of the whole block are there, products only below j + valid) */
__attribute__((target("avx2,no-fma"))) static inline unsigned
candidate4(const double *restrict g0g1, const double *restrict d, __m256d scale_one, size_t j,
           int valid, const uint8_t *restrict bytes) {
    return candidate_of(load4(g0g1 + j, valid), candidate_scale(d, scale_one, j, valid), bytes + j);
}

/* both tests of gaps j .. j + 3 from the positions: the may-cross bits into *may, the
 * candidates returned (gap_candidates_all) */
__attribute__((target("avx2,no-fma"))) static inline unsigned
both4(const double *restrict z, const double *restrict y, const double *restrict d, double d_one,
      __m256d scale_one, size_t j, int valid, const uint8_t *restrict bytes, unsigned *may) {
    const __m256d g0 = _mm256_sub_pd(load4(z + j + 1, valid), load4(z + j, valid));
    const __m256d g1 = _mm256_sub_pd(load4(y + j + 1, valid), load4(y + j, valid));
    const __m256d dj = d ? load4(d + j, valid) : _mm256_set1_pd(d_one);
    const __m256d product = _mm256_mul_pd(g0, g1);
    const __m256d may_cross = /* !(g1 > 0) | !(g0 g1 > 20 d) */
        _mm256_or_pd(_mm256_cmp_pd(g1, _mm256_setzero_pd(), _CMP_NGT_UQ),
                     _mm256_cmp_pd(product, _mm256_mul_pd(_mm256_set1_pd(20.0), dj), _CMP_NGT_UQ));
    *may = (unsigned)_mm256_movemask_pd(may_cross);
    return *may & candidate_of(product, candidate_scale(d, scale_one, j, valid), bytes + j);
}

/* the bits of the gaps j = GAP_BLOCK b .. j + valid - 1 of a block (valid <= GAP_BLOCK, the
 * constant GAP_BLOCK for whole blocks): may they cross; are they candidates */
__attribute__((target("avx2,no-fma"))) static inline unsigned
block_may_cross4(const double *restrict z, const double *restrict y, const double *restrict d,
                 double d_one, size_t j, int valid, double *restrict g0g1) {
    unsigned bits = 0;
    for (int h = 0; h < GAP_BLOCK && h < valid; h += 4)
        bits |= may_cross4(z, y, d, d_one, j + (size_t)h, valid - h, g0g1) << h;
    return valid < GAP_BLOCK ? bits & ((1u << valid) - 1u) : bits;
}

__attribute__((target("avx2,no-fma"))) static inline unsigned
block_candidates4(const double *restrict g0g1, const double *restrict d, __m256d scale_one,
                  size_t j, int valid, const uint8_t *restrict bytes) {
    unsigned bits = 0;
    for (int h = 0; h < GAP_BLOCK && h < valid; h += 4)
        bits |= candidate4(g0g1, d, scale_one, j + (size_t)h, valid - h, bytes) << h;
    return bits;
}

__attribute__((target("avx2,popcnt,no-fma"), always_inline)) static inline size_t
gap_blocks_may_cross_with(const double *restrict z, const double *restrict y,
                          const double *restrict d, double d_one, size_t m, uint16_t *restrict mask,
                          unsigned *restrict blocks, double *restrict g0g1) {
    size_t count = 0, b = 0;
    for (; GAP_BLOCK * b < m; ++b) {
        const size_t j = GAP_BLOCK * b;
        const unsigned bits = j + GAP_BLOCK <= m
                                  ? block_may_cross4(z, y, d, d_one, j, GAP_BLOCK, g0g1)
                                  : block_may_cross4(z, y, d, d_one, j, (int)(m - j), g0g1);
        mask[b] = (uint16_t)bits;
        blocks[count] = (unsigned)b;
        count += bits != 0;
    }
    return count;
}

/* one species (d NULL) and mixtures in two copies: no test of d per vector */
__attribute__((target("avx2,popcnt,no-fma"))) size_t
gap_blocks_may_cross_avx2(const double *restrict z, const double *restrict y,
                          const double *restrict d, double d_one, size_t m, uint16_t *restrict mask,
                          unsigned *restrict blocks, double *restrict g0g1) {
    return d ? gap_blocks_may_cross_with(z, y, d, d_one, m, mask, blocks, g0g1)
             : gap_blocks_may_cross_with(z, y, NULL, d_one, m, mask, blocks, g0g1);
}

__attribute__((target("avx2,popcnt,no-fma"), always_inline)) static inline size_t
gap_candidates_with(const double *restrict g0g1, const double *restrict d, double d_one, size_t m,
                    const uint16_t *restrict mask, const unsigned *restrict blocks, size_t nblocks,
                    const uint8_t *restrict bytes, unsigned *restrict idx) {
    const __m256d scale_one = _mm256_set1_pd(0x1p23 * 1.4426950408889634 / d_one);
    size_t count = 0;
    for (size_t k = 0; k < nblocks; ++k) {
        const size_t b = blocks[k], j = GAP_BLOCK * b;
        const unsigned bits =
            mask[b] &
            (j + GAP_BLOCK <= m ? block_candidates4(g0g1, d, scale_one, j, GAP_BLOCK, bytes)
                                : block_candidates4(g0g1, d, scale_one, j, (int)(m - j), bytes));
        if (!bits) continue; /* no candidate: the common block in dilute systems */
        /* count <= j, and idx has room for whole blocks: eight stores from count fit */
        count = store_places(bits & 0xffu, j, count, idx);
        count = store_places(bits >> 8, j + 8, count, idx);
    }
    return count;
}

/* one species (d NULL) and mixtures in two copies: no test of d per vector */
__attribute__((target("avx2,popcnt,no-fma"))) size_t
gap_candidates_avx2(const double *restrict g0g1, const double *restrict d, double d_one, size_t m,
                    const uint16_t *restrict mask, const unsigned *restrict blocks, size_t nblocks,
                    const uint8_t *restrict bytes, unsigned *restrict idx) {
    return d ? gap_candidates_with(g0g1, d, d_one, m, mask, blocks, nblocks, bytes, idx)
             : gap_candidates_with(g0g1, NULL, d_one, m, mask, blocks, nblocks, bytes, idx);
}
__attribute__((target("avx2,popcnt,no-fma"), always_inline)) static inline size_t
gap_candidates_all_with(const double *restrict z, const double *restrict y,
                        const double *restrict d, double d_one, size_t m,
                        const uint8_t *restrict bytes, unsigned *restrict idx, size_t *listed) {
    const __m256d scale_one = _mm256_set1_pd(0x1p23 * 1.4426950408889634 / d_one);
    size_t count = 0, blocks = 0;
    for (size_t j = 0; j < m; j += GAP_BLOCK) {
        unsigned bits = 0, may = 0, may4;
        if (j + GAP_BLOCK <= m) { /* a whole block: four vectors, unrolled */
            for (int h = 0; h < GAP_BLOCK; h += 4) {
                bits |= both4(z, y, d, d_one, scale_one, j + (size_t)h, 4, bytes, &may4) << h;
                may |= may4 << h;
            }
        } else { /* a short last block */
            const int valid = (int)(m - j);
            for (int h = 0; h < valid; h += 4) {
                bits |= both4(z, y, d, d_one, scale_one, j + (size_t)h, valid - h, bytes, &may4)
                        << h;
                may |= may4 << h;
            }
            bits &= (1u << valid) - 1u;
            may &= (1u << valid) - 1u;
        }
        blocks += may != 0; /* no branch on bits: their pattern is random here */
        count = store_places(bits & 0xffu, j, count, idx);
        count = store_places(bits >> 8, j + 8, count, idx);
    }
    *listed = blocks;
    return count;
}

/* one species (d NULL) and mixtures in two copies: no test of d per vector */
__attribute__((target("avx2,popcnt,no-fma"))) size_t
gap_candidates_all_avx2(const double *restrict z, const double *restrict y,
                        const double *restrict d, double d_one, size_t m,
                        const uint8_t *restrict bytes, unsigned *restrict idx, size_t *listed) {
    return d ? gap_candidates_all_with(z, y, d, d_one, m, bytes, idx, listed)
             : gap_candidates_all_with(z, y, NULL, d_one, m, bytes, idx, listed);
}

__attribute__((target("avx2,no-fma"))) void gap_half_pushes_avx2(size_t n, const double *restrict y,
                                                                 const double *restrict push,
                                                                 double *restrict out) {
    const __m256d half = _mm256_set1_pd(0.5);
    size_t i = 0;
    for (; i + 4 <= n; i += 4) { /* the same operations in the same order */
        const __m256d left = _mm256_mul_pd(half, _mm256_loadu_pd(push + i - 1));
        const __m256d right = _mm256_mul_pd(half, _mm256_loadu_pd(push + i));
        _mm256_storeu_pd(out + i,
                         _mm256_sub_pd(_mm256_add_pd(_mm256_loadu_pd(y + i), left), right));
    }
    gap_half_pushes_scalar(n - i, y + i, push + i, out + i);
}

__attribute__((target("avx2"))) void gap_copy_avx2(size_t n, const double *from, double *to) {
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
        _mm256_storeu_pd(to + i, from ? _mm256_loadu_pd(from + i) : _mm256_setzero_pd());
    for (; i < n; ++i) /* not masked stores: slow on some CPUs */
        to[i] = from ? from[i] : 0.0;
}

__attribute__((target("avx2,no-fma"))) void gap_pushes_avx2(size_t count, const double *sum,
                                                            const double *sq, const double *d,
                                                            double d_one, double *ln_u) {
    size_t k = 0;
    for (; k + 4 <= count; k += 4) { /* the same operations; the square root correctly rounded */
        const __m256d four_d =
            _mm256_mul_pd(_mm256_set1_pd(4.0), d ? _mm256_loadu_pd(d + k) : _mm256_set1_pd(d_one));
        const __m256d root = _mm256_sqrt_pd(_mm256_sub_pd(
            _mm256_loadu_pd(sq + k), _mm256_mul_pd(four_d, _mm256_loadu_pd(ln_u + k))));
        const __m256d push =
            _mm256_mul_pd(_mm256_set1_pd(0.5), _mm256_sub_pd(root, _mm256_loadu_pd(sum + k)));
        _mm256_storeu_pd(ln_u + k, _mm256_max_pd(push, _mm256_setzero_pd()));
    }
    gap_pushes_scalar(count - k, sum + k, sq + k, d ? d + k : NULL, d_one, ln_u + k);
}
#else /* built without AVX2: the scalar versions */
size_t gap_blocks_may_cross_avx2(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, uint16_t *mask, unsigned *blocks, double *g0g1) {
    return gap_blocks_may_cross_scalar(z, y, d, d_one, m, mask, blocks, g0g1);
}
size_t gap_candidates_avx2(const double *g0g1, const double *d, double d_one, size_t m,
                           const uint16_t *mask, const unsigned *blocks, size_t nblocks,
                           const uint8_t *bytes, unsigned *idx) {
    return gap_candidates_scalar(g0g1, d, d_one, m, mask, blocks, nblocks, bytes, idx);
}
size_t gap_candidates_all_avx2(const double *z, const double *y, const double *d, double d_one,
                               size_t m, const uint8_t *bytes, unsigned *idx, size_t *listed) {
    return gap_candidates_all_scalar(z, y, d, d_one, m, bytes, idx, listed);
}
void gap_pushes_avx2(size_t count, const double *sum, const double *sq, const double *d,
                     double d_one, double *ln_u) {
    gap_pushes_scalar(count, sum, sq, d, d_one, ln_u);
}
void gap_half_pushes_avx2(size_t n, const double *y, const double *push, double *out) {
    gap_half_pushes_scalar(n, y, push, out);
}
void gap_copy_avx2(size_t n, const double *from, double *to) {
    if (from)
        memcpy(to, from, n * sizeof *to);
    else
        memset(to, 0, n * sizeof *to);
}
#endif

size_t gap_blocks_may_cross(const double *z, const double *y, const double *d, double d_one,
                            size_t m, uint16_t *mask, unsigned *blocks, double *g0g1) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (hsbd_cpu_has_avx2())
        return gap_blocks_may_cross_avx2(z, y, d, d_one, m, mask, blocks, g0g1);
#endif
    return gap_blocks_may_cross_scalar(z, y, d, d_one, m, mask, blocks, g0g1);
}

size_t gap_candidates(const double *g0g1, const double *d, double d_one, size_t m,
                      const uint16_t *mask, const unsigned *blocks, size_t nblocks,
                      const uint8_t *bytes, unsigned *idx) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (hsbd_cpu_has_avx2())
        return gap_candidates_avx2(g0g1, d, d_one, m, mask, blocks, nblocks, bytes, idx);
#endif
    return gap_candidates_scalar(g0g1, d, d_one, m, mask, blocks, nblocks, bytes, idx);
}

void gap_pushes(size_t count, const double *sum, const double *sq, const double *d, double d_one,
                double *ln_u) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (hsbd_cpu_has_avx2()) {
        gap_pushes_avx2(count, sum, sq, d, d_one, ln_u);
        return;
    }
#endif
    gap_pushes_scalar(count, sum, sq, d, d_one, ln_u);
}

size_t gap_candidates_all(const double *z, const double *y, const double *d, double d_one, size_t m,
                          const uint8_t *bytes, unsigned *idx, size_t *listed) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (hsbd_cpu_has_avx2()) return gap_candidates_all_avx2(z, y, d, d_one, m, bytes, idx, listed);
#endif
    return gap_candidates_all_scalar(z, y, d, d_one, m, bytes, idx, listed);
}

void gap_half_pushes(size_t n, const double *y, const double *push, double *out) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (hsbd_cpu_has_avx2()) {
        gap_half_pushes_avx2(n, y, push, out);
        return;
    }
#endif
    gap_half_pushes_scalar(n, y, push, out);
}

void gap_copy(size_t n, const double *from, double *to) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (hsbd_cpu_has_avx2()) {
        gap_copy_avx2(n, from, to);
        return;
    }
#endif
    if (from)
        memcpy(to, from, n * sizeof *to);
    else
        memset(to, 0, n * sizeof *to);
}
