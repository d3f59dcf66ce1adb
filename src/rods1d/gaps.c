/* The reflect rule's list of the gaps that may cross (see gaps.h). The AVX2 version turns
 * the tests of eight gaps into a byte and stores the places of its set bits, taken from a
 * table, in one go: no branch on the flags, whose pattern is random. */
#include "rods1d/gaps.h"

#include <stdint.h>

#include "core/vmath.h"
#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

/* The gaps j .. m - 1 that may cross, appended to the count listed so far, without
 * branches; returns the new count. */
static size_t list_from(const double *restrict z, const double *restrict y,
                        const double *restrict d, double d_one, size_t j, size_t m, size_t count,
                        unsigned *restrict idx) {
    for (; j < m; ++j) {
        idx[count] = (unsigned)j;
        count += (size_t)bridge_may_cross(z[j + 1] - z[j], y[j + 1] - y[j], d ? d[j] : d_one);
    }
    return count;
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

/* The same with AVX2, eight gaps at a time: the same subtractions, products and comparisons
 * lane by lane (no FMA: the same answers), their eight bits a byte whose set bits' places
 * the table gives, added to j and stored at once (idx has room: count <= j). */
__attribute__((target("avx2,popcnt,no-fma"))) size_t
gap_list_may_cross_avx2(const double *restrict z, const double *restrict y,
                        const double *restrict d, double d_one, size_t m, unsigned *restrict idx) {
    const __m256i shifts = _mm256_setr_epi32(0, 3, 6, 9, 12, 15, 18, 21);
    size_t count = 0, j = 0;
    for (; j + 8 <= m; j += 8) {
        unsigned bits = 0;
        for (size_t h = 0; h < 8; h += 4) {
            const __m256d g0 =
                _mm256_sub_pd(_mm256_loadu_pd(z + j + h + 1), _mm256_loadu_pd(z + j + h));
            const __m256d g1 =
                _mm256_sub_pd(_mm256_loadu_pd(y + j + h + 1), _mm256_loadu_pd(y + j + h));
            const __m256d dj = d ? _mm256_loadu_pd(d + j + h) : _mm256_set1_pd(d_one);
            const __m256d bound = _mm256_mul_pd(_mm256_set1_pd(20.0), dj);
            const __m256d may = /* !(g1 > 0) | !(g0 g1 > 20 d): bridge_may_cross */
                _mm256_or_pd(_mm256_cmp_pd(g1, _mm256_setzero_pd(), _CMP_NGT_UQ),
                             _mm256_cmp_pd(_mm256_mul_pd(g0, g1), bound, _CMP_NGT_UQ));
            bits |= (unsigned)_mm256_movemask_pd(may) << h;
        }
        if (!bits) continue; /* most bytes in dilute systems */
        const __m256i places = _mm256_and_si256(
            _mm256_srlv_epi32(_mm256_set1_epi32((int)set_bit_places[bits]), shifts),
            _mm256_set1_epi32(7));
        _mm256_storeu_si256((__m256i *)(void *)(idx + count),
                            _mm256_add_epi32(places, _mm256_set1_epi32((int)j)));
        count += (size_t)__builtin_popcount(bits);
    }
    return list_from(z, y, d, d_one, j, m, count, idx);
}
#else
size_t gap_list_may_cross_avx2(const double *z, const double *y, const double *d, double d_one,
                               size_t m, unsigned *idx) {
    (void)z, (void)y, (void)d, (void)d_one, (void)m, (void)idx;
    return 0;
}
#endif

size_t gap_list_may_cross_scalar(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, unsigned *idx) {
    return list_from(z, y, d, d_one, 0, m, 0, idx);
}

size_t gap_list_may_cross(const double *z, const double *y, const double *d, double d_one, size_t m,
                          unsigned *idx) {
#if defined(__x86_64__) && defined(__GNUC__)
    if (hsbd_cpu_has_avx2()) return gap_list_may_cross_avx2(z, y, d, d_one, m, idx);
#endif
    return gap_list_may_cross_scalar(z, y, d, d_one, m, idx);
}
