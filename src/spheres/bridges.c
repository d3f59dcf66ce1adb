/* Brownian-bridge pushes at walls and between pairs (internal to src/spheres; the physics
 * in docs/theory.md, "Pair collisions under a relative drift", the scheme in
 * docs/spheres.md). */
#include "spheres/bridges.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/rng.h"
#include "spheres/scan.h"

double sph_bridge_push(const hsbd_spheres *s, double g0, double g1, double d_dt, double reach,
                       uint32_t stream, uint64_t index) {
    if (g0 * g1 >= reach * d_dt) return 0;
    double u;
    hsbd_rng_uniforms(s->par.seed, stream, s->step, index, 1, &u);
    /* the bridge minimum (docs/theory.md, Scala Eq. 9 sampled exactly) */
    const double m = 0.5 * (g0 + g1 - sqrt((g1 - g0) * (g1 - g0) - 4.0 * d_dt * log(u)));
    return m < 0 ? -m : 0;
}

double sph_pair_skin(const hsbd_spheres *s, double dt) {
    if (!s->pair_bridges) return 0;
    /* two gaps >= skin reach contact with probability below exp(-skin^2 / ((D_i + D_j) dt))
     * <= exp(-SPH_PAIR_REACH) for any pair */
    double skin = sqrt(SPH_PAIR_REACH * 2 * s->diffusion_max * dt);
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

static int pushes_add(sph_pushes *b, sph_pair_push p) {
    if (b->len == b->cap) {
        const size_t cap = b->cap ? 2 * b->cap : 256;
        sph_pair_push *grown = realloc(b->p, cap * sizeof *grown);
        if (!grown) return -1;
        b->p = grown;
        b->cap = cap;
    }
    b->p[b->len++] = p;
    return 0;
}

/* The bridge of pair (i, j): into out when it reaches contact, from the lower user label
 * to the higher (the same bits whichever row found the pair). Returns 0, or -1. */
static int pair_bridge(const hsbd_spheres *s, int32_t i, int32_t j, sph_pushes *out) {
    const double dt = s->dt, *xi = s->x + 3 * (size_t)i, *xj = s->x + 3 * (size_t)j;
    const double *vi = s->v + 3 * (size_t)i, *vj = s->v + 3 * (size_t)j;
    const double dr = s->diffusion[i] + s->diffusion[j]; /* the gap's diffusion */
    if (!(dr > 0)) return 0;
    double r0[3], r1[3]; /* j - i at the start and at the free end */
    for (int a = 0; a < 3; ++a) {
        r0[a] = hsbd_wrap_delta(xj[a] - xi[a], s->box[a]);
        r1[a] = r0[a] + (vj[a] - vi[a]) * dt;
    }
    const double sij = sph_contact_distance(s, i, j), q0 = hsbd_dot3(r0, r0);
    const double len1 = sqrt(hsbd_dot3(r1, r1)), g0 = fmax(0.0, sqrt(q0) - sij), g1 = len1 - sij;
    uint32_t stream;
    uint64_t index;
    pair_counter(s, i, j, &stream, &index);
    const double push = sph_bridge_push(s, g0, g1, dr * dt, SPH_PAIR_REACH, stream, index);
    if (!(push > 0)) return 0;
    /* along the end separation (the start's when the free ends coincide) */
    const double len = len1 > 0 ? len1 : sqrt(q0), *r = len1 > 0 ? r1 : r0;
    const int flip = s->label[i] > s->label[j];
    const int32_t a = flip ? j : i, b = flip ? i : j;
    sph_pair_push p = {
        .i = a, .j = b, .lo = (uint32_t)s->label[a], .hi = (uint32_t)s->label[b], .push = push};
    for (int k = 0; k < 3; ++k)
        p.n[k] = (flip ? -1.0 : 1.0) * (r[k] / len);
    return pushes_add(out, p);
}

/* The bridges of rows [i0, i1), each pair once (from the row of its first particle): those
 * that reach contact into out. A row's pairs are screened first without branches (in a
 * dense or pressed packing about half pass, and a branch on it mispredicts); a pair farther
 * than the screen beyond contact at both ends of the step is not drawn. Returns 0, or -1
 * when out of memory. */
static int pair_range(const hsbd_spheres *s, size_t i0, size_t i1, sph_pushes *out) {
    const double dt = s->dt, screen = sqrt(SPH_PAIR_REACH * 2 * s->diffusion_max * dt);
    out->len = 0;
    if (out->near_cap < s->nb_cap) {
        int32_t *near = realloc(out->near, s->nb_cap * sizeof *near);
        if (!near) return -1;
        out->near = near;
        out->near_cap = s->nb_cap;
    }
    for (size_t i = i0; i < i1; ++i) {
        const int32_t *row = s->nb + i * s->nb_cap;
        const double *xi = s->x + 3 * i, *vi = s->v + 3 * i, half = 0.5 * s->sigma[i] + screen;
        uint32_t found = 0;
        for (uint32_t k = 0; k < s->nb_upper[i]; ++k) {
            const int32_t j = row[k];
            const double *xj = s->x + 3 * (size_t)j, *vj = s->v + 3 * (size_t)j;
            double q0 = 0, q1 = 0;
            for (int a = 0; a < 3; ++a) {
                const double d0 = hsbd_wrap_delta(xj[a] - xi[a], s->box[a]);
                const double d1 = d0 + (vj[a] - vi[a]) * dt;
                q0 += d0 * d0, q1 += d1 * d1;
            }
            const double near = half + 0.5 * s->sigma[j];
            out->near[found] = j;
            found += (q0 < near * near) | (q1 < near * near);
        }
        for (uint32_t k = 0; k < found; ++k)
            if (pair_bridge(s, (int32_t)i, out->near[k], out)) return -1;
    }
    return 0;
}

/* The walls' bridges of particles [i0, i1) into out as pairs with an immobile partner
 * (i = -1; n the inward normal; hi = UINT32_MAX - wall, after every pair of the particle),
 * drawn as add_wall_pushes in edbd.c draws them (the same uniforms). Returns 0, or -1. */
static int wall_range(const hsbd_spheres *s, size_t i0, size_t i1, sph_pushes *out) {
    const double dt = s->dt;
    for (size_t i = i0; i < i1; ++i) {
        const double d = s->diffusion[i], half = 0.5 * s->sigma[i];
        if (!(d > 0)) continue;
        for (int a = 0; a < s->dim; ++a) {
            if (!s->walls[a]) continue;
            const double x = s->x[3 * i + a], dx = s->v[3 * i + a] * dt;
            const double gap[2] = {x - half, s->length[a] - half - x}, moved[2] = {dx, -dx};
            const uint64_t index = 2 * (3 * (uint64_t)s->label[i] + (uint64_t)a);
            for (int side = 0; side < 2; ++side) {
                const double push =
                    sph_bridge_push(s, gap[side], gap[side] + moved[side], d * dt, SPH_BRIDGE_REACH,
                                    s->bridge_stream, index + (uint64_t)side);
                if (!(push > 0)) continue;
                sph_pair_push p = {.i = -1,
                                   .j = (int32_t)i,
                                   .lo = (uint32_t)s->label[i],
                                   .hi = UINT32_MAX - (uint32_t)(2 * a + side),
                                   .push = push};
                p.n[a] = side ? -1.0 : 1.0;
                if (pushes_add(out, p)) return -1;
            }
        }
    }
    return 0;
}

static int compare_pairs(const void *a, const void *b) {
    const sph_pair_push *p = a, *q = b;
    if (p->lo != q->lo) return (p->lo > q->lo) - (p->lo < q->lo);
    return (p->hi > q->hi) - (p->hi < q->hi);
}

/* One projected Gauss-Seidel update of pair p: the impulse that brings its end gap to the
 * bridge's push, n.(d_j - d_i) = push, never below zero. Returns the change of the gap. */
static double relax_pair(hsbd_spheres *s, sph_pair_push *p) {
    static const double wall[3] = {0, 0, 0}; /* a wall's (i < 0) displacement */
    double *di = p->i < 0 ? NULL : s->push_delta + 3 * (size_t)p->i;
    double *dj = s->push_delta + 3 * (size_t)p->j;
    const double wi = p->i < 0 ? 0.0 : s->diffusion[p->i], wj = s->diffusion[p->j];
    const double *ci = di ? di : wall;
    const double opened =
        p->n[0] * (dj[0] - ci[0]) + p->n[1] * (dj[1] - ci[1]) + p->n[2] * (dj[2] - ci[2]);
    double change = (p->push - opened) / (wi + wj);
    if (p->impulse + change < 0) change = -p->impulse;
    if (change == 0) return 0;
    p->impulse += change;
    for (int a = 0; a < 3; ++a) {
        if (di) di[a] -= wi * change * p->n[a];
        dj[a] += wj * change * p->n[a];
    }
    return fabs(change) * (wi + wj);
}

/* Whether pair p shares a mobile particle with another pushed pair. */
static int coupled(const hsbd_spheres *s, const sph_pair_push *p) {
    return (p->i >= 0 && s->push_partners[p->i] == 2) || s->push_partners[p->j] == 2;
}

/* The pushes of the pairs in all->p, sorted by labels, jointly: the least displacement (in
 * the metric sum_k |d_k|^2 / D_k, friction 1 / D) that opens every pair's end gap by at
 * least its bridge's push (docs/theory.md). A pair alone takes its push in one update,
 * shared in proportion to D_i and D_j; pairs that share a mobile particle (moved to the
 * front, in an order fixed by the labels) are relaxed in turn, sweeping forwards and
 * backwards, until no gap changes by more than 10^-3 sqrt(2 D_max dt) in a sweep (at most
 * SPH_PUSH_SWEEPS sweeps: a particle pushed from two sides by immobile ones has no
 * solution); a sweep passes over the pairs neither of whose particles moved since the
 * pair's last update (it is still solved). What the pushes leave of an overlap, the events
 * take as a collision. */
enum { SPH_PUSH_SWEEPS = 200 };
static void solve_pushes(hsbd_spheres *s, sph_pushes *all) {
    for (size_t k = 0; k < all->len; ++k) { /* partners: 0, 1, 2 = several */
        const sph_pair_push *p = &all->p[k];
        if (p->i >= 0 && s->diffusion[p->i] > 0 && s->push_partners[p->i] < 2)
            s->push_partners[p->i]++;
        if (s->diffusion[p->j] > 0 && s->push_partners[p->j] < 2) s->push_partners[p->j]++;
    }
    size_t m = 0; /* the coupled pairs to the front, each pair relaxed once */
    for (size_t k = 0; k < all->len; ++k) {
        relax_pair(s, &all->p[k]);
        if (!coupled(s, &all->p[k])) continue;
        const sph_pair_push t = all->p[m];
        all->p[m++] = all->p[k];
        all->p[k] = t;
    }
    const double tol = 1e-3 * sqrt(2 * s->diffusion_max * s->dt);
    uint8_t *moved = s->push_moved; /* the last sweep that moved a particle (0 before) */
    for (int sweep = 1; sweep < SPH_PUSH_SWEEPS && m; ++sweep) {
        int changed = 0;
        for (size_t q = 0; q < m; ++q) {
            sph_pair_push *p = &all->p[sweep % 2 ? m - 1 - q : q];
            if (!((p->i >= 0 && moved[p->i] + 1 >= sweep) || moved[p->j] + 1 >= sweep)) continue;
            if (!(relax_pair(s, p) > tol)) continue;
            if (p->i >= 0) moved[p->i] = (uint8_t)sweep;
            moved[p->j] = (uint8_t)sweep;
            changed = 1;
        }
        if (!changed) break;
    }
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
    if (!s->push_delta) s->push_delta = calloc(3 * s->n, sizeof *s->push_delta);
    if (!s->push_partners) s->push_partners = calloc(s->n, sizeof *s->push_partners);
    if (!s->push_moved) s->push_moved = calloc(s->n, sizeof *s->push_moved);
    if (!s->push_delta || !s->push_partners || !s->push_moved) return -1;
    int failed = 0;
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)                 \
    reduction(|                                                                                    \
              : failed)
    for (int k = 0; k < threads; ++k) {
        const size_t i0 = sph_range_start(s->n, threads, k),
                     i1 = sph_range_start(s->n, threads, k + 1);
        failed |= pair_range(s, i0, i1, &s->push_parts[k]) != 0 ||
                  (s->any_walls && wall_range(s, i0, i1, &s->push_parts[k]) != 0);
    }
    if (failed) return -1;
    sph_pushes *all = &s->push_parts[0]; /* all pairs into the first buffer */
    for (int k = 1; k < threads; ++k)
        for (size_t q = 0; q < s->push_parts[k].len; ++q)
            if (pushes_add(all, s->push_parts[k].p[q])) return -1;
    if (!all->len) return 0;
    /* in the order of the user labels: the same bits for any row order, spatial sort or
     * thread count */
    qsort(all->p, all->len, sizeof *all->p, compare_pairs);
    solve_pushes(s, all);
    const double dt = s->dt;
    sph_exact_sum virial = 0;
    uint64_t pairs = 0;
    for (size_t k = 0; k < all->len; ++k) {
        const sph_pair_push *p = &all->p[k];
        if (p->i < 0) { /* a wall's impulse / kT (the displacement over D) to its sum */
            const size_t w = UINT32_MAX - p->hi;
            s->wall_step[6 * (size_t)s->species[p->j] + w] +=
                sph_exact_term(s->wall_scale, p->impulse);
            s->stats.wall_pushes++;
        } else { /* sigma_ij times the impulse / kT along n (j's displacement over D_j) */
            virial +=
                sph_exact_term(s->virial_scale, sph_contact_distance(s, p->i, p->j) * p->impulse);
            pairs++;
        }
        const int32_t ends[2] = {p->i, p->j};
        for (int e = 0; e < 2; ++e) {
            if (ends[e] < 0) continue;
            const size_t q = (size_t)ends[e];
            if (!s->push_partners[q] && s->diffusion[q] > 0) continue; /* applied already */
            double *d = s->push_delta + 3 * q, *v = s->v + 3 * q;
            for (int a = 0; a < s->dim; ++a)
                v[a] += d[a] / dt;
            d[0] = d[1] = d[2] = 0;
            s->push_partners[q] = s->push_moved[q] = 0;
        }
    }
    s->stats.pair_pushes += pairs;
    s->push_virial = virial;
    return 0;
}
