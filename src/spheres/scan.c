#include "spheres/scan.h"

#include <stdlib.h>

enum { SCAN_CHUNK = 4096 }; /* pairs per kernel call (at least one whole row) */

int sph_threads(const hsbd_spheres *s) {
    return s->threads > 1 && s->n >= SPH_THREADS_MIN_N ? s->threads : 1;
}

size_t sph_range_start(size_t n, int parts, int k) {
    return n * (size_t)k / (size_t)parts; /* n < 2^31, k <= parts <= 1024: no overflow */
}

/* Whether i's straight path from its start leaves the room between the walls: only if
 * its end point does (the room is convex); after the bridge pushes, rarely. */
static int leaves_walls(const hsbd_spheres *s, size_t i) {
    const double *x = s->x + 3 * i, *v = s->v + 3 * i, half = 0.5 * s->sigma[i];
    int out = 0;
    for (int a = 0; a < s->dim; ++a) {
        const double end = x[a] + v[a] * s->dt;
        out |= s->walls[a] & (end < half || end > s->length[a] - half);
    }
    return out;
}

static void flag_range(hsbd_spheres *s, size_t i0, size_t i1) {
    const double dt = s->dt, r2 = s->shell * s->shell;
    for (size_t i = i0; i < i1; ++i) {
        double d[3];
        sph_min_image(s, s->x + 3 * i, s->centre + 3 * i, d);
        const double *v = s->v + 3 * i;
        const double e[3] = {d[0] + v[0] * dt, d[1] + v[1] * dt, d[2] + v[2] * dt};
        uint8_t flag = hsbd_dot3(e, e) > r2 ? SPH_LEAVES_SHELL : 0;
        if (s->any_walls && leaves_walls(s, i)) flag |= SPH_LEAVES_WALLS;
        s->start_flag[i] = flag;
    }
}

void sph_scan_leaving(hsbd_spheres *s, int threads) {
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)
    for (int k = 0; k < threads; ++k)
        flag_range(s, sph_range_start(s->n, threads, k), sph_range_start(s->n, threads, k + 1));
}

/* Room for `more` hits after the h->len held. Returns 0, or -1 when out of memory. */
static int hits_reserve(sph_hits *h, size_t more) {
    if (h->len + more <= h->cap) return 0;
    size_t cap = h->cap ? 2 * h->cap : 4096;
    while (cap < h->len + more)
        cap *= 2;
    int32_t *i = realloc(h->i, cap * sizeof *i);
    if (i) h->i = i;
    int32_t *j = i ? realloc(h->j, cap * sizeof *j) : NULL;
    if (j) h->j = j;
    double *t = j ? realloc(h->t, cap * sizeof *t) : NULL;
    if (!t) return -1;
    h->t = t;
    h->cap = cap;
    return 0;
}

/* The hits of rows [i0, i1) appended to h in row order. Returns 0, or -1. */
static int scan_rows(const hsbd_spheres *s, const sph_scan_query *q, size_t i0, size_t i1,
                     sph_hits *h) {
    for (size_t a = i0; a < i1;) {
        size_t b = a, pairs = 0;
        while (b < i1 && (b == a || pairs + s->nb_upper[b] <= SCAN_CHUNK))
            pairs += s->nb_upper[b++];
        if (hits_reserve(h, pairs)) return -1;
        h->len += s->half_scan(q, a, b, h->i + h->len, h->j + h->len, h->t + h->len);
        a = b;
    }
    return 0;
}

int sph_scan_pairs(hsbd_spheres *s, int threads) {
    if ((size_t)threads > s->hit_nparts) {
        sph_hits *parts = realloc(s->hit_parts, (size_t)threads * sizeof *parts);
        if (!parts) return -1;
        for (size_t k = s->hit_nparts; k < (size_t)threads; ++k)
            parts[k] = (sph_hits){0};
        s->hit_parts = parts;
        s->hit_nparts = (size_t)threads;
    }
    const sph_scan_query q = {.x = s->x,
                              .v = s->v,
                              .sigma = s->sigma,
                              .nb = s->nb,
                              .nb_upper = s->nb_upper,
                              .nb_cap = s->nb_cap,
                              .box = {s->box[0], s->box[1], s->box[2]},
                              .tmax = s->dt};
    int failed = 0;
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)                 \
    reduction(|                                                                                    \
              : failed)
    for (int k = 0; k < threads; ++k) {
        sph_hits *h = &s->hit_parts[k];
        h->len = 0;
        failed |= scan_rows(s, &q, sph_range_start(s->n, threads, k),
                            sph_range_start(s->n, threads, k + 1), h) != 0;
    }
    return failed ? -1 : 0;
}
