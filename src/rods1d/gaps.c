/* The reflect rule's passes over a batch of gaps (see gaps.h). The AVX2 versions test
 * eight gaps at a time and turn the eight answers into a byte; the places of its set bits,
 * from a table, are stored in one go, and the values of the chosen lanes moved together by
 * a permutation made from the same table: no branch on the answers, whose pattern is
 * random. */
#include "rods1d/gaps.h"

#include <stdint.h>

#include "core/vmath.h"
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

static size_t may_cross_from(const double *restrict z, const double *restrict y,
                             const double *restrict d, double d_one, size_t j, size_t m,
                             size_t count, unsigned *restrict idx, double *restrict g0,
                             double *restrict g1) {
    for (; j < m; ++j) { /* without branches: write, then count or not */
        idx[count] = (unsigned)j;
        g0[count] = z[j + 1] - z[j];
        g1[count] = y[j + 1] - y[j];
        count += (size_t)bridge_may_cross(g0[count], g1[count], d ? d[j] : d_one);
    }
    return count;
}

static size_t uncertain_from(const double *restrict g0, const double *restrict g1,
                             const double *restrict d, double d_one, const double *restrict u,
                             size_t k, size_t count, size_t kept, unsigned *restrict keep) {
    for (; k < count; ++k) {
        keep[kept] = (unsigned)k;
        kept += (size_t)!bridge_surely_clear(g0[k], g1[k], d ? d[k] : d_one, u[k]);
    }
    return kept;
}

size_t gap_list_may_cross_scalar(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, unsigned *idx, double *g0, double *g1) {
    return may_cross_from(z, y, d, d_one, 0, m, 0, idx, g0, g1);
}

size_t gap_list_uncertain_scalar(const double *g0, const double *g1, const double *d, double d_one,
                                 const double *u, size_t count, unsigned *keep) {
    return uncertain_from(g0, g1, d, d_one, u, 0, count, 0, keep);
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

#define AVX2_FN __attribute__((target("avx2,popcnt,no-fma")))

/* base + the places of the set bits of byte `bits`, stored at out (eight entries: those
 * past the popcount are scratch that the next store overwrites) */
AVX2_FN static inline void store_places(unsigned bits, size_t base, unsigned *out) {
    const __m256i shifts = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
    const __m256i places =
        _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32((int)set_bit_places[bits]), shifts),
                         _mm256_set1_epi32(7));
    _mm256_storeu_si256((__m256i *)(void *)out,
                        _mm256_add_epi32(places, _mm256_set1_epi32((int)base)));
}

/* The lanes of v whose bits (four) are set, moved to the front in order, stored at out
 * (four entries, those past the popcount scratch). */
AVX2_FN static inline void store_lanes(__m256d v, unsigned bits, double *out) {
    const __m256i place = /* the lane each 32-bit half comes from, times two, plus the half */
        _mm256_and_si256(_mm256_srlv_epi32(_mm256_set1_epi32((int)set_bit_places[bits]),
                                           _mm256_setr_epi32(0, 0, 3, 3, 6, 6, 9, 9)),
                         _mm256_set1_epi32(7));
    const __m256i from =
        _mm256_add_epi32(_mm256_slli_epi32(place, 1), _mm256_setr_epi32(0, 1, 0, 1, 0, 1, 0, 1));
    _mm256_storeu_pd(out, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), from)));
}

/* Lists have room: every store at count writes no further than the lanes already read. */
AVX2_FN size_t gap_list_may_cross_avx2(const double *restrict z, const double *restrict y,
                                       const double *restrict d, double d_one, size_t m,
                                       unsigned *restrict idx, double *restrict g0,
                                       double *restrict g1) {
    size_t count = 0, j = 0;
    for (; j + 8 <= m; j += 8) {
        __m256d start[2], end[2];
        unsigned bits = 0;
        for (size_t h = 0; h < 2; ++h) {
            const double *zh = z + j + 4 * h, *yh = y + j + 4 * h;
            start[h] = _mm256_sub_pd(_mm256_loadu_pd(zh + 1), _mm256_loadu_pd(zh));
            end[h] = _mm256_sub_pd(_mm256_loadu_pd(yh + 1), _mm256_loadu_pd(yh));
            const __m256d dj = d ? _mm256_loadu_pd(d + j + 4 * h) : _mm256_set1_pd(d_one);
            const __m256d bound = _mm256_mul_pd(_mm256_set1_pd(20.0), dj);
            const __m256d may = /* !(g1 > 0) | !(g0 g1 > 20 d): bridge_may_cross */
                _mm256_or_pd(_mm256_cmp_pd(end[h], _mm256_setzero_pd(), _CMP_NGT_UQ),
                             _mm256_cmp_pd(_mm256_mul_pd(start[h], end[h]), bound, _CMP_NGT_UQ));
            bits |= (unsigned)_mm256_movemask_pd(may) << (4 * h);
        }
        if (!bits) continue; /* most bytes in dilute systems */
        store_places(bits, j, idx + count);
        const size_t low = (size_t)__builtin_popcount(bits & 15u);
        store_lanes(start[0], bits & 15u, g0 + count);
        store_lanes(end[0], bits & 15u, g1 + count);
        store_lanes(start[1], bits >> 4, g0 + count + low);
        store_lanes(end[1], bits >> 4, g1 + count + low);
        count += (size_t)__builtin_popcount(bits);
    }
    return may_cross_from(z, y, d, d_one, j, m, count, idx, g0, g1);
}

AVX2_FN size_t gap_list_uncertain_avx2(const double *restrict g0, const double *restrict g1,
                                       const double *restrict d, double d_one,
                                       const double *restrict u, size_t count,
                                       unsigned *restrict keep) {
    size_t kept = 0, k = 0;
    const __m256d one = _mm256_set1_pd(1.0), four = _mm256_set1_pd(4.0);
    for (; k + 8 <= count; k += 8) {
        unsigned bits = 0;
        for (size_t h = 0; h < 8; h += 4) { /* bridge_surely_clear, operation by operation */
            const __m256d a0 = _mm256_loadu_pd(g0 + k + h), a1 = _mm256_loadu_pd(g1 + k + h);
            const __m256d uk = _mm256_loadu_pd(u + k + h);
            const __m256d dk = d ? _mm256_loadu_pd(d + k + h) : _mm256_set1_pd(d_one);
            const __m256d a = _mm256_add_pd(a0, a1);
            const __m256d lhs = _mm256_add_pd(
                _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(four, dk), _mm256_sub_pd(one, uk)),
                              _mm256_set1_pd(1.0 + 1e-12)),
                _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(_mm256_set1_pd(1e-12), a), a), uk));
            const __m256d rhs = _mm256_mul_pd(_mm256_mul_pd(_mm256_mul_pd(four, a0), a1), uk);
            const __m256d clear = _mm256_cmp_pd(lhs, rhs, _CMP_LT_OQ);
            bits |= (unsigned)(~_mm256_movemask_pd(clear) & 15) << h;
        }
        store_places(bits, k, keep + kept);
        kept += (size_t)__builtin_popcount(bits);
    }
    return uncertain_from(g0, g1, d, d_one, u, k, count, kept, keep);
}
#else
size_t gap_list_may_cross_avx2(const double *z, const double *y, const double *d, double d_one,
                               size_t m, unsigned *idx, double *g0, double *g1) {
    (void)z, (void)y, (void)d, (void)d_one, (void)m, (void)idx, (void)g0, (void)g1;
    return 0;
}

size_t gap_list_uncertain_avx2(const double *g0, const double *g1, const double *d, double d_one,
                               const double *u, size_t count, unsigned *keep) {
    (void)g0, (void)g1, (void)d, (void)d_one, (void)u, (void)count, (void)keep;
    return 0;
}
#endif

size_t gap_list_may_cross(const double *z, const double *y, const double *d, double d_one, size_t m,
                          unsigned *idx, double *g0, double *g1) {
    if (hsbd_cpu_has_avx2()) return gap_list_may_cross_avx2(z, y, d, d_one, m, idx, g0, g1);
    return gap_list_may_cross_scalar(z, y, d, d_one, m, idx, g0, g1);
}

size_t gap_list_uncertain(const double *g0, const double *g1, const double *d, double d_one,
                          const double *u, size_t count, unsigned *keep) {
    if (hsbd_cpu_has_avx2()) return gap_list_uncertain_avx2(g0, g1, d, d_one, u, count, keep);
    return gap_list_uncertain_scalar(g0, g1, d, d_one, u, count, keep);
}
