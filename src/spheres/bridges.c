/* Brownian-bridge pushes at walls and between pairs (internal to src/spheres; the physics
 * in docs/theory.md, "Pair collisions under a relative drift", the scheme in
 * docs/spheres.md). */
#include "spheres/bridges.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/rng.h"
#include "spheres/scan.h"

double sph_bridge_push(const hsbd_spheres *s, double g0, double g1, double d_dt, uint32_t stream,
                       uint64_t index) {
    if (g0 * g1 >= SPH_BRIDGE_REACH * d_dt) return 0;
    double u;
    hsbd_rng_uniforms(s->par.seed, stream, s->step, index, 1, &u);
    /* the bridge minimum (docs/theory.md, Scala Eq. 9 sampled exactly) */
    const double m = 0.5 * (g0 + g1 - sqrt((g1 - g0) * (g1 - g0) - 4.0 * d_dt * log(u)));
    return m < 0 ? -m : 0;
}

double sph_pair_skin(const hsbd_spheres *s, double dt) {
    if (!s->pair_bridges) return 0;
    /* two gaps >= skin reach contact with probability below exp(-skin^2 / ((D_i + D_j) dt))
     * <= exp(-SPH_SKIN_REACH) for any pair */
    double skin = sqrt(SPH_SKIN_REACH * 2 * s->diffusion_max * dt);
    for (int a = 0; a < s->dim; ++a) /* what a small periodic box has room for */
        if (!s->walls[a])
            skin = fmin(skin, fmax(0.0, 0.5 * s->box[a] - s->sigma_max - 2 * s->shell));
    return skin;
}

/* The uniform of pair (lo, hi), user labels lo < hi < 2^31: the Philox counter words are
 * (index / 2, step, step, stream) (src/core/rng.c), here (lo + c, step, step, 2^31 + hi),
 * c = 2^31 while the compression runs (its own bridge stream). No stream of hsbd/rng.h
 * has its top bit set, so no other draw shares these counters. */
static void pair_counter(const hsbd_spheres *s, int32_t a, int32_t b, uint32_t *stream,
                         uint64_t *index) {
    const uint32_t la = (uint32_t)s->label[a], lb = (uint32_t)s->label[b];
    const uint32_t lo = la < lb ? la : lb, hi = la < lb ? lb : la;
    const uint32_t phase = s->bridge_stream == HSBD_STREAM_CONTACT ? 0 : 0x80000000u;
    *stream = 0x80000000u | hi;
    *index = 2 * (uint64_t)(lo | phase);
}

static int pushes_add(sph_pushes *b, int32_t i, int32_t partner, const double d[3]) {
    if (b->len == b->cap) {
        const size_t cap = b->cap ? 2 * b->cap : 256;
        sph_push *p = realloc(b->p, cap * sizeof *p);
        if (!p) return -1;
        b->p = p;
        b->cap = cap;
    }
    b->p[b->len++] = (sph_push){i, partner, {d[0], d[1], d[2]}};
    return 0;
}

/* The bridges of rows [i0, i1) (each pair once, from the row of its first particle): the
 * pushes into out. Returns 0, or -1 when out of memory. */
static int pair_range(const hsbd_spheres *s, size_t i0, size_t i1, sph_pushes *out) {
    const double dt = s->dt;
    /* a pair farther than this beyond contact at both ends of the step: no draw */
    const double screen = sqrt(SPH_BRIDGE_REACH * 2 * s->diffusion_max * dt);
    out->len = 0;
    out->pairs = 0;
    out->virial = 0;
    for (size_t i = i0; i < i1; ++i) {
        const int32_t *row = s->nb + i * s->nb_cap;
        const double *xi = s->x + 3 * i, *vi = s->v + 3 * i, di = s->diffusion[i];
        for (uint32_t k = 0; k < s->nb_upper[i]; ++k) {
            const int32_t j = row[k];
            const double *xj = s->x + 3 * (size_t)j, *vj = s->v + 3 * (size_t)j;
            double r0[3], r1[3]; /* j - i at the start and at the free end */
            for (int a = 0; a < 3; ++a) {
                r0[a] = hsbd_wrap_delta(xj[a] - xi[a], s->box[a]);
                r1[a] = r0[a] + (vj[a] - vi[a]) * dt;
            }
            const double sij = sph_contact_distance(s, (int32_t)i, j), near = sij + screen;
            const double q0 = hsbd_dot3(r0, r0), q1 = hsbd_dot3(r1, r1);
            if (q0 >= near * near && q1 >= near * near) continue;
            const double dj = s->diffusion[j], dr = di + dj; /* the gap's diffusion */
            if (!(dr > 0)) continue;
            const double len1 = sqrt(q1), g0 = fmax(0.0, sqrt(q0) - sij), g1 = len1 - sij;
            uint32_t stream;
            uint64_t index;
            pair_counter(s, (int32_t)i, j, &stream, &index);
            const double push = sph_bridge_push(s, g0, g1, dr * dt, stream, index);
            if (!(push > 0)) continue;
            /* along the end separation (the start's when the free ends coincide) */
            const double len = len1 > 0 ? len1 : sqrt(q0);
            const double *r = len1 > 0 ? r1 : r0;
            const double fi = -push * di / (dr * len), fj = push * dj / (dr * len);
            const double di_push[3] = {fi * r[0], fi * r[1], fi * r[2]};
            const double dj_push[3] = {fj * r[0], fj * r[1], fj * r[2]};
            if ((di > 0 && pushes_add(out, (int32_t)i, s->label[j], di_push)) ||
                (dj > 0 && pushes_add(out, j, s->label[i], dj_push)))
                return -1;
            out->pairs++;
            /* sigma_ij times j's displacement by the push over D_j: impulse / kT */
            out->virial += sph_exact_term(s->virial_scale, sij * push / dr);
        }
    }
    return 0;
}

static int compare_pushes(const void *a, const void *b) {
    const sph_push *p = a, *q = b;
    if (p->i != q->i) return (p->i > q->i) - (p->i < q->i);
    return (p->partner > q->partner) - (p->partner < q->partner);
}

int sph_pair_pushes(hsbd_spheres *s) {
    s->push_virial = 0;
    const int threads = sph_threads(s);
    if ((size_t)threads > s->push_nparts) {
        sph_pushes *parts =
            sph_grow_zeroed(s->push_parts, s->push_nparts, (size_t)threads, sizeof *parts);
        if (!parts) return -1;
        s->push_parts = parts;
        s->push_nparts = (size_t)threads;
    }
    int failed = 0;
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)                 \
    reduction(|                                                                                    \
              : failed)
    for (int k = 0; k < threads; ++k)
        failed |= pair_range(s, sph_range_start(s->n, threads, k),
                             sph_range_start(s->n, threads, k + 1), &s->push_parts[k]) != 0;
    if (failed) return -1;
    /* all pushes into the first buffer */
    sph_pushes *all = &s->push_parts[0];
    uint64_t pairs = all->pairs;
    sph_exact_sum virial = all->virial;
    for (int k = 1; k < threads; ++k) {
        const sph_pushes *part = &s->push_parts[k];
        for (size_t q = 0; q < part->len; ++q)
            if (pushes_add(all, part->p[q].i, part->p[q].partner, part->p[q].d)) return -1;
        pairs += part->pairs;
        virial += part->virial;
    }
    if (!all->len) return 0;
    /* a particle's pushes summed in the order of its partners' user labels: the same bits
     * for any row order, spatial sort or thread count */
    qsort(all->p, all->len, sizeof *all->p, compare_pushes);
    const double dt = s->dt;
    for (size_t q = 0; q < all->len;) {
        const int32_t i = all->p[q].i;
        double d[3] = {0, 0, 0};
        for (; q < all->len && all->p[q].i == i; ++q)
            for (int a = 0; a < 3; ++a)
                d[a] += all->p[q].d[a];
        double *v = s->v + 3 * (size_t)i;
        for (int a = 0; a < s->dim; ++a)
            v[a] += d[a] / dt;
    }
    s->stats.pair_pushes += pairs;
    s->push_virial = virial;
    return 0;
}
