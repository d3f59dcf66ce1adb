/* AVX2 version of sph_predict_row (compiled with -mavx2 and without FMA, see
 * CMakeLists.txt): four neighbours per pass, the same operations as the scalar kernel. */
#include "spheres/kernels.h"

#if defined(__AVX2__)
#include <immintrin.h>

static inline __m256d wrap4(__m256d d, __m256d box, __m256d half, __m256d neg_half) {
    d = _mm256_blendv_pd(d, _mm256_sub_pd(d, box), _mm256_cmp_pd(d, half, _CMP_GT_OQ));
    return _mm256_blendv_pd(d, _mm256_add_pd(d, box), _mm256_cmp_pd(d, neg_half, _CMP_LT_OQ));
}

/* Components 0..2 of the 3-vectors a + 3 idx[l] into out[0..2], lane l: four unaligned
 * loads (each reads one double past the vector: the arrays carry a padding entry) and a
 * transpose. */
static inline void load_transposed(const double *a, const int32_t idx[4], __m256d out[3]) {
    const __m256d r0 = _mm256_loadu_pd(a + 3 * (size_t)idx[0]);
    const __m256d r1 = _mm256_loadu_pd(a + 3 * (size_t)idx[1]);
    const __m256d r2 = _mm256_loadu_pd(a + 3 * (size_t)idx[2]);
    const __m256d r3 = _mm256_loadu_pd(a + 3 * (size_t)idx[3]);
    const __m256d t0 = _mm256_unpacklo_pd(r0, r1); /* x0 x1 z0 z1 */
    const __m256d t1 = _mm256_unpackhi_pd(r0, r1); /* y0 y1 .. .. */
    const __m256d t2 = _mm256_unpacklo_pd(r2, r3); /* x2 x3 z2 z3 */
    const __m256d t3 = _mm256_unpackhi_pd(r2, r3); /* y2 y3 .. .. */
    out[0] = _mm256_permute2f128_pd(t0, t2, 0x20);
    out[1] = _mm256_permute2f128_pd(t1, t3, 0x20);
    out[2] = _mm256_permute2f128_pd(t0, t2, 0x31);
}

static inline __m256d dot4(const __m256d a[3], const __m256d b[3]) {
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(a[0], b[0]), _mm256_mul_pd(a[1], b[1])),
                         _mm256_mul_pd(a[2], b[2]));
}

/* Broadcast constants of the contact test. */
typedef struct contact4 {
    __m256d box[3], half[3], neg_half[3];
    __m256d tmax, zero, two, one_half, sign; /* tmax: the half scan's */
} contact4;

static inline void contact4_init(contact4 *c, const double box[3], double tmax) {
    for (int a = 0; a < 3; ++a) {
        const double h = 0.5 * box[a];
        c->box[a] = _mm256_set1_pd(box[a]);
        c->half[a] = _mm256_set1_pd(h);
        c->neg_half[a] = _mm256_set1_pd(-h);
    }
    c->tmax = _mm256_set1_pd(tmax);
    c->zero = _mm256_setzero_pd();
    c->two = _mm256_set1_pd(2.0);
    c->one_half = _mm256_set1_pd(0.5);
    c->sign = _mm256_set1_pd(-0.0);
}

/* The lanes < lanes whose pair passes sph_contact_hit, from the separations d (wrapped
 * here, in place), relative velocities v, contact distances s and windows tmax, as bits. */
static inline int hit_mask4(const contact4 *c, __m256d d[3], const __m256d v[3], __m256d s,
                            __m256d tmax, uint32_t lanes) {
    for (int a = 0; a < 3; ++a)
        d[a] = wrap4(d[a], c->box[a], c->half[a], c->neg_half[a]);
    const __m256d b = dot4(d, v), vv = dot4(v, v);
    const __m256d g = _mm256_sub_pd(dot4(d, d), _mm256_mul_pd(s, s));
    /* sph_contact_hit, lane by lane */
    const __m256d vt = _mm256_mul_pd(vv, tmax);
    const __m256d f_end =
        _mm256_add_pd(g, _mm256_mul_pd(tmax, _mm256_add_pd(_mm256_mul_pd(c->two, b), vt)));
    const __m256d disc = _mm256_sub_pd(_mm256_mul_pd(b, b), _mm256_mul_pd(vv, g));
    const __m256d inside = _mm256_and_pd(_mm256_cmp_pd(_mm256_xor_pd(b, c->sign), vt, _CMP_LT_OQ),
                                         _mm256_cmp_pd(disc, c->zero, _CMP_GE_OQ));
    const __m256d hit =
        _mm256_and_pd(_mm256_cmp_pd(b, c->zero, _CMP_LT_OQ),
                      _mm256_or_pd(_mm256_cmp_pd(f_end, c->zero, _CMP_LE_OQ), inside));
    return _mm256_movemask_pd(hit) & ((1 << lanes) - 1);
}

/* Lanes < lanes whose pair reaches contact within tmax, from the unwrapped separations d
 * (wrapped here), relative velocities v and diameters sigma_i + sigma_j: bit l of the
 * result set and tc[l] the contact time (sph_contact_time on the lane). */
static inline int contact_times4(const contact4 *c, __m256d d[3], const __m256d v[3],
                                 __m256d sigma_sum, __m256d tmax, uint32_t lanes, double tc[4]) {
    const __m256d s = _mm256_mul_pd(c->one_half, sigma_sum);
    int mask = hit_mask4(c, d, v, s, tmax, lanes);
    if (__builtin_expect(!mask, 1)) return 0;
    double dl[3][4], vl[3][4], sl[4], tl[4];
    for (int a = 0; a < 3; ++a) {
        _mm256_storeu_pd(dl[a], d[a]);
        _mm256_storeu_pd(vl[a], v[a]);
    }
    _mm256_storeu_pd(sl, s);
    _mm256_storeu_pd(tl, tmax);
    int found = 0;
    for (; mask; mask &= mask - 1) {
        const int l = __builtin_ctz((unsigned)mask);
        const double rr[3] = {dl[0][l], dl[1][l], dl[2][l]};
        const double vr[3] = {vl[0][l], vl[1][l], vl[2][l]};
        tc[l] = sph_contact_time(rr, vr, sl[l], tl[l]);
        if (tc[l] >= 0) found |= 1 << l;
    }
    return found;
}

static inline __m256d load4(const double *a, const int32_t idx[4]) {
    return _mm256_setr_pd(a[idx[0]], a[idx[1]], a[idx[2]], a[idx[3]]);
}

uint32_t sph_predict_row_avx2(const sph_row_query *q, const int32_t *row, uint32_t m,
                              int32_t *hit_j, double *hit_t) {
    contact4 c;
    contact4_init(&c, q->box, 0); /* each pair has its own window */
    __m256d xi[3], vi[3];
    for (int a = 0; a < 3; ++a) {
        xi[a] = _mm256_set1_pd(q->xi[a]);
        vi[a] = _mm256_set1_pd(q->vi[a]);
    }
    const __m256d sigma_i = _mm256_set1_pd(q->sigma_i), ti = _mm256_set1_pd(q->ti);
    const __m256d dt = _mm256_set1_pd(q->dt);
    uint32_t hits = 0;
    for (uint32_t k = 0; k < m; k += 4) {
        const uint32_t lanes = m - k < 4 ? m - k : 4;
        int32_t idx[4]; /* the tail's missing lanes repeat the first and are masked out */
        for (uint32_t l = 0; l < 4; ++l)
            idx[l] = row[k + (l < lanes ? l : 0)];
        __m256d d[3], v[3];
        load_transposed(q->x, idx, d);
        load_transposed(q->v, idx, v);
        /* pair_geometry of kernels.c: the later start t0, both segments moved to it */
        const __m256d tj = load4(q->t_local, idx), t0 = _mm256_max_pd(ti, tj);
        const __m256d hj = _mm256_sub_pd(t0, tj), hi = _mm256_sub_pd(t0, ti);
        for (int a = 0; a < 3; ++a) {
            const __m256d pi = _mm256_add_pd(xi[a], _mm256_mul_pd(vi[a], hi));
            d[a] = _mm256_sub_pd(_mm256_add_pd(d[a], _mm256_mul_pd(v[a], hj)), pi);
            v[a] = _mm256_sub_pd(v[a], vi[a]);
        }
        double tc[4], t0l[4];
        int found = contact_times4(&c, d, v, _mm256_add_pd(sigma_i, load4(q->sigma, idx)),
                                   _mm256_sub_pd(dt, t0), lanes, tc);
        if (found) _mm256_storeu_pd(t0l, t0);
        for (; found; found &= found - 1) {
            const int l = __builtin_ctz((unsigned)found);
            hit_j[hits] = idx[l];
            hit_t[hits++] = t0l[l] + tc[l];
        }
    }
    return hits;
}

/* The places of the set bits of a 4-bit mask in order, one per byte (then zeros). */
static const uint32_t set_lane_places4[16] = {
    0x00000000, 0x00000000, 0x00000001, 0x00000100, 0x00000002, 0x00000200, 0x00000201, 0x00020100,
    0x00000003, 0x00000300, 0x00000301, 0x00030100, 0x00000302, 0x00030200, 0x00030201, 0x03020100};

/* The ids of the lanes set in mask (four bits) moved to the front, stored at out (four
 * entries, those past the popcount scratch): a compaction without branches. */
static inline void store_set_lanes(__m128i ids, int mask, int32_t *out) {
    const __m128i from = _mm_cvtepu8_epi32(_mm_cvtsi32_si128((int)set_lane_places4[mask]));
    _mm_storeu_si128((__m128i *)(void *)out,
                     _mm_castps_si128(_mm_permutevar_ps(_mm_castsi128_ps(ids), from)));
}

/* Four pairs (pi[l], pj[l]) of the half scan; lanes >= `lanes` repeat lane 0. The pairs
 * that pass the hit test are appended to ci, cj (no branch on the test, which about one
 * vector in six passes: their contact times come after, pair by pair); returns the new
 * count. */
static inline uint32_t half_scan4(const sph_scan_query *q, const contact4 *c, const int32_t pi[4],
                                  const int32_t pj[4], uint32_t lanes, uint32_t count, int32_t *ci,
                                  int32_t *cj) {
    __m256d xi[3], xj[3], vi[3], vj[3], d[3], v[3];
    load_transposed(q->x, pi, xi);
    load_transposed(q->x, pj, xj);
    load_transposed(q->v, pi, vi);
    load_transposed(q->v, pj, vj);
    for (int a = 0; a < 3; ++a) {
        d[a] = _mm256_sub_pd(xj[a], xi[a]);
        v[a] = _mm256_sub_pd(vj[a], vi[a]);
    }
    const __m256d sigma_sum = _mm256_add_pd(load4(q->sigma, pi), load4(q->sigma, pj));
    const int mask = hit_mask4(c, d, v, _mm256_mul_pd(c->one_half, sigma_sum), c->tmax, lanes);
    store_set_lanes(_mm_loadu_si128((const __m128i *)(const void *)pi), mask, ci + count);
    store_set_lanes(_mm_loadu_si128((const __m128i *)(const void *)pj), mask, cj + count);
    return count + (uint32_t)__builtin_popcount((unsigned)mask);
}

/* The pairs of the half scan go through a flat list, in row order: every row's first 16
 * entries (a row has room for at least 16) are copied with two vector stores and the list
 * advanced by the row's upper count, so no branch depends on the varying count; the pairs
 * then go four at a time, the same groups of four as pair by pair, and those that pass
 * the hit test get their contact times (sph_scan_pair_time, as the scalar scan). */
enum { SCAN_FLAT = 512 };

typedef struct scan_lists {
    int32_t fi[SCAN_FLAT + 16], fj[SCAN_FLAT + 16]; /* the pairs to test */
    int32_t ci[SCAN_FLAT + 4], cj[SCAN_FLAT + 4];   /* those that pass the hit test */
} scan_lists;

/* The contact times of the `passed` pairs that passed the hit test, the hits appended;
 * returns the new number of hits. */
static uint32_t scan_times(const sph_scan_query *q, const scan_lists *l, uint32_t passed,
                           uint32_t hits, int32_t *hit_i, int32_t *hit_j, double *hit_t) {
    for (uint32_t k = 0; k < passed; ++k) {
        const double tc = sph_scan_pair_time(q, (size_t)l->ci[k], l->cj[k]);
        if (tc >= 0) {
            hit_i[hits] = l->ci[k];
            hit_j[hits] = l->cj[k];
            hit_t[hits++] = tc;
        }
    }
    return hits;
}

/* The whole groups of four of the list's `count` pairs; the rest (< 4) moved to the front.
 * Returns the new count, hits appended. */
static inline uint32_t scan_flat(const sph_scan_query *q, const contact4 *c, scan_lists *l,
                                 uint32_t count, uint32_t *hits, int32_t *hit_i, int32_t *hit_j,
                                 double *hit_t) {
    uint32_t g = 0, passed = 0;
    for (; g + 4 <= count; g += 4)
        passed = half_scan4(q, c, l->fi + g, l->fj + g, 4, passed, l->ci, l->cj);
    *hits = scan_times(q, l, passed, *hits, hit_i, hit_j, hit_t);
    const uint32_t rest = count - g; /* < 4 */
    for (uint32_t k = 0; k < rest && k < 4; ++k)
        l->fi[k] = l->fi[g + k], l->fj[k] = l->fj[g + k];
    return rest;
}

uint32_t sph_half_scan_avx2(const sph_scan_query *q, size_t i0, size_t i1, int32_t *hit_i,
                            int32_t *hit_j, double *hit_t) {
    contact4 c;
    contact4_init(&c, q->box, q->tmax);
    scan_lists l = {.ci = {0}}; /* written through vector stores the compiler cannot follow */
    uint32_t count = 0, hits = 0;
    for (size_t i = i0; i < i1; ++i) {
        const int32_t *row = q->nb + i * q->nb_cap;
        const uint32_t m = q->nb_upper[i];
        if (count + 16 + m > SCAN_FLAT)
            count = scan_flat(q, &c, &l, count, &hits, hit_i, hit_j, hit_t);
        if (m <= 16) { /* the common case: without a branch on m */
            const __m256i self = _mm256_set1_epi32((int32_t)i);
            _mm256_storeu_si256((__m256i *)(void *)(l.fi + count), self);
            _mm256_storeu_si256((__m256i *)(void *)(l.fi + count + 8), self);
            _mm256_storeu_si256((__m256i *)(void *)(l.fj + count),
                                _mm256_loadu_si256((const __m256i *)(const void *)row));
            _mm256_storeu_si256((__m256i *)(void *)(l.fj + count + 8),
                                _mm256_loadu_si256((const __m256i *)(const void *)(row + 8)));
            count += m;
            continue;
        }
        for (uint32_t k = 0; k < m; ++k) {
            l.fi[count] = (int32_t)i;
            l.fj[count] = row[k];
            if (++count == SCAN_FLAT)
                count = scan_flat(q, &c, &l, count, &hits, hit_i, hit_j, hit_t);
        }
    }
    count = scan_flat(q, &c, &l, count, &hits, hit_i, hit_j, hit_t);
    if (count) { /* the last pairs, the missing lanes repeating the first */
        for (uint32_t k = count; k < 4; ++k)
            l.fi[k] = l.fi[0], l.fj[k] = l.fj[0];
        const uint32_t passed = half_scan4(q, &c, l.fi, l.fj, count, 0, l.ci, l.cj);
        hits = scan_times(q, &l, passed, hits, hit_i, hit_j, hit_t);
    }
    return hits;
}

uint32_t sph_cells_near_avx2(const hsbd_cells *cells, const int32_t *list, int nlist,
                             const double c[3], const double box_in[3], const double *sigma,
                             double reach_base, int32_t *out) {
    __m256d box[3], half[3], neg_half[3], centre[3];
    for (int a = 0; a < 3; ++a) {
        const double h = 0.5 * box_in[a];
        box[a] = _mm256_set1_pd(box_in[a]);
        half[a] = _mm256_set1_pd(h);
        neg_half[a] = _mm256_set1_pd(-h);
        centre[a] = _mm256_set1_pd(c[a]);
    }
    const __m256d base = _mm256_set1_pd(reach_base), one_half = _mm256_set1_pd(0.5);
    uint32_t found = 0;
    for (int q = 0; q < nlist; ++q) {
        const uint32_t m = hsbd_cells_count(cells, list[q]);
        /* The first chunk of every cell in one pass, even when fewer slots are filled: no
         * branch on the count, which varies from cell to cell and would mispredict; fuller
         * cells take more passes. */
        for (uint32_t u = 0; u == 0 || u < m; u += HSBD_CELL_CHUNK) {
            const hsbd_cell_chunk *chunk = hsbd_cells_chunk(cells, list[q], u / HSBD_CELL_CHUNK);
            const uint32_t lanes = m - u < 4 ? m - u : 4;
            static const int32_t slot[4] = {0, 1, 2, 3};
            const __m128i filled = /* the lanes below the count; empty slots read particle 0 */
                _mm_cmpgt_epi32(_mm_set1_epi32((int32_t)lanes), _mm_setr_epi32(0, 1, 2, 3));
            const __m128i who =
                _mm_and_si128(_mm_loadu_si128((const __m128i *)(const void *)chunk->id), filled);
            __m256d r[3];
            load_transposed(chunk->pos, slot, r);
            for (int a = 0; a < 3; ++a)
                r[a] = wrap4(_mm256_sub_pd(r[a], centre[a]), box[a], half[a], neg_half[a]);
            const __m256d reach = /* with one diameter, no gather (a miss per cell at large N) */
                sigma ? _mm256_add_pd(base,
                                      _mm256_mul_pd(one_half, _mm256_i32gather_pd(sigma, who, 8)))
                      : base;
            const __m256d near = _mm256_cmp_pd(dot4(r, r), _mm256_mul_pd(reach, reach), _CMP_LT_OQ);
            const int mask = _mm256_movemask_pd(near) & ((1 << lanes) - 1);
            store_set_lanes(who, mask, out + (size_t)found); /* the near ids, at once */
            found += (uint32_t)__builtin_popcount((unsigned)mask);
        }
    }
    return found;
}
#endif
