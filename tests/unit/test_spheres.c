/* EDBD of hard spheres, deterministic checks: the Brownian collision rule (conservation
 * of sum v_i / D_i and of sum v_i^2 / D_i, reversal of the normal relative velocity, an
 * immobile partner acting as a wall), contact times against brute-force integration, no
 * overlap after any step (O(N^2) check, 2D and 3D, mixtures with immobile obstacles),
 * bit-identical reruns of one seed by two objects in one process, the engine's spatial
 * sort invisible (the same run bit for bit with and without it), the free-particle
 * mode, polydisperse diameters (moments within their sampling error), the compression to
 * dense states without overlaps (and its refusal near jamming), the g(r) weights of
 * the virial route, threads that change no bit (1, 2 and 4 threads, the global calendar,
 * groups, walls with a field), and the exact sums behind the virial and wall impulses. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "sphere_checks.h"
#include "hsbd/observe.h"
#include "hsbd/rng.h"
#include "hsbd/spheres.h"
#include "spheres/calendar.h"
#include "spheres/kernels.h"
#include "spheres/slab_queue.h"
#include "spheres/state.h"

static const double PI = 3.14159265358979323846;

static void test_collision_rule(void) {
    double u[8 * 64];
    hsbd_rng_normals(7, 99, 0, 0, 8 * 64, u);
    for (int k = 0; k < 64; ++k) {
        const double *g = u + 8 * k;
        const double di = k % 4 == 0 ? 0.0 : exp(g[0]), dj = exp(g[1]);
        double n[3] = {g[2], g[3], g[4]};
        const double nn = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        for (int a = 0; a < 3; ++a)
            n[a] /= nn;
        double vi[3] = {g[5], g[6], g[7]}, vj[3] = {-g[5], g[7], g[6]};
        if (di == 0) vi[0] = vi[1] = vi[2] = 0; /* an immobile particle has no velocity */
        /* make the pair approach along n (n points from i to j) */
        double un = 0;
        for (int a = 0; a < 3; ++a)
            un += (vj[a] - vi[a]) * n[a];
        if (un > 0)
            for (int a = 0; a < 3; ++a)
                vj[a] -= 2 * un * n[a];
        double before_u = 0, wi[3], wj[3];
        for (int a = 0; a < 3; ++a)
            before_u += (vj[a] - vi[a]) * n[a], wi[a] = vi[a], wj[a] = vj[a];
        hsbd_spheres_collide(di, dj, n, wi, wj);
        double after_u = 0;
        for (int a = 0; a < 3; ++a)
            after_u += (wj[a] - wi[a]) * n[a];
        CHECK_CLOSE(after_u, -before_u, 1e-12 * (1 + fabs(before_u)));
        if (di > 0) {
            for (int a = 0; a < 3; ++a) /* momentum with masses 1/D */
                CHECK_CLOSE(wi[a] / di + wj[a] / dj, vi[a] / di + vj[a] / dj,
                            1e-12 * (1 + fabs(vi[a] / di) + fabs(vj[a] / dj)));
            const double e0 = (vi[0] * vi[0] + vi[1] * vi[1] + vi[2] * vi[2]) / di +
                              (vj[0] * vj[0] + vj[1] * vj[1] + vj[2] * vj[2]) / dj;
            const double e1 = (wi[0] * wi[0] + wi[1] * wi[1] + wi[2] * wi[2]) / di +
                              (wj[0] * wj[0] + wj[1] * wj[1] + wj[2] * wj[2]) / dj;
            CHECK_CLOSE(e1, e0, 1e-12 * e0);
        } else { /* a wall: i stays, j's normal component is mirrored */
            for (int a = 0; a < 3; ++a) {
                CHECK(wi[a] == 0, "immobile particle moved: %g", wi[a]);
                CHECK_CLOSE(wj[a], vj[a] - 2 * before_u * n[a], 1e-12);
            }
        }
        /* only the normal components change: both changes are parallel to n */
        for (int side = 0; side < 2; ++side) {
            const double *w = side ? wj : wi, *v0 = side ? vj : vi;
            const double d[3] = {w[0] - v0[0], w[1] - v0[1], w[2] - v0[2]};
            const double cross = fabs(d[1] * n[2] - d[2] * n[1]) + fabs(d[2] * n[0] - d[0] * n[2]) +
                                 fabs(d[0] * n[1] - d[1] * n[0]);
            CHECK(cross < 1e-12 * (1 + fabs(before_u)), "change not along the normal: %g", cross);
        }
    }
}

/* first time |r + v t| = s by fine stepping (bisection on the first sign change) */
static double brute_contact_time(const double r[3], const double v[3], double s, double tmax) {
    const int steps = 200000;
    double prev = 0, fprev = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] - s * s;
    for (int k = 1; k <= steps; ++k) {
        const double t = tmax * k / steps;
        const double p[3] = {r[0] + v[0] * t, r[1] + v[1] * t, r[2] + v[2] * t};
        const double f = p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - s * s;
        if (f <= 0 && fprev > 0) {
            double lo = prev, hi = t;
            for (int it = 0; it < 100; ++it) {
                const double mid = 0.5 * (lo + hi);
                const double q[3] = {r[0] + v[0] * mid, r[1] + v[1] * mid, r[2] + v[2] * mid};
                if (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] - s * s > 0)
                    lo = mid;
                else
                    hi = mid;
            }
            return 0.5 * (lo + hi);
        }
        prev = t, fprev = f;
    }
    return -1;
}

static void test_contact_time(void) {
    double g[6 * 400];
    hsbd_rng_normals(11, 99, 1, 0, 6 * 400, g);
    int hits = 0, misses = 0;
    for (int k = 0; k < 400; ++k) {
        const double s = 1.0, tmax = 1e-2;
        double r[3] = {g[6 * k], g[6 * k + 1], g[6 * k + 2]};
        const double rn = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
        const double dist = s + 0.05 * fabs(g[6 * k + 3]); /* gaps up to ~0.15 */
        for (int a = 0; a < 3; ++a)
            r[a] *= dist / rn;
        const double v[3] = {10 * g[6 * k + 3], 10 * g[6 * k + 4], 10 * g[6 * k + 5]};
        const double t = hsbd_spheres_contact_time(r, v, s, tmax);
        const double tb = brute_contact_time(r, v, s, tmax);
        if (tb < 0) {
            CHECK(t < 0, "case %d: predicted %g, brute force finds none", k, t);
            ++misses;
        } else {
            CHECK_CLOSE(t, tb, 1e-9);
            ++hits;
        }
    }
    CHECK(hits > 20 && misses > 20, "cases cover both: %d hits, %d misses", hits, misses);
}

/* Random particles in a small periodic box for the kernel tests (+ 1: the padding entry
 * the vector kernels read past the last particle). */
enum { KN = 64 };
typedef struct kernel_fixture {
    double x[3 * KN + 1], v[3 * KN + 1], t_local[KN], sigma[KN], box[3];
} kernel_fixture;

static void kernel_fixture_fill(kernel_fixture *f) {
    double g[7 * KN];
    hsbd_rng_normals(12, 99, 1, 0, 7 * KN, g);
    for (int a = 0; a < 3; ++a)
        f->box[a] = 3.0;
    f->x[3 * KN] = f->v[3 * KN] = 0;
    for (int j = 0; j < KN; ++j) {
        for (int a = 0; a < 3; ++a) {
            f->x[3 * j + a] = fmod(fabs(g[7 * j + a]), 1.0) * f->box[a];
            f->v[3 * j + a] = 20 * g[7 * j + 3 + a];
        }
        f->t_local[j] = 0.004 * fabs(g[7 * j + 6]) / (1 + fabs(g[7 * j + 6]));
        f->sigma[j] = 0.8 + 0.1 * (j % 5);
    }
}

/* sph_contact_time of pair (i, j) with i at x_i + v_i hi and j at x_j + v_j hj, in the
 * kernels' operation order. */
static double kernel_pair_time(const kernel_fixture *f, int i, int j, double hi, double hj,
                               double tmax) {
    double r[3], w[3];
    for (int a = 0; a < 3; ++a) {
        const double pj = f->x[3 * j + a] + f->v[3 * j + a] * hj;
        const double pi = f->x[3 * i + a] + f->v[3 * i + a] * hi;
        r[a] = hsbd_wrap_delta(pj - pi, f->box[a]);
        w[a] = f->v[3 * j + a] - f->v[3 * i + a];
    }
    return sph_contact_time(r, w, 0.5 * (f->sigma[i] + f->sigma[j]), tmax);
}

/* The row kernels (scalar, AVX2) against pair-by-pair sph_contact_time on random rows of
 * every tail length, across the periodic boundary, segments of i and j starting at random
 * times (either later): the same hits in the same order with bit-identical times, each
 * from the later start. */
static void test_predict_row_kernels(void) {
    kernel_fixture f;
    kernel_fixture_fill(&f);
    const int avx2 = __builtin_cpu_supports("avx2") != 0;
    int hits_seen = 0;
    for (int row_id = 0; row_id < 300; ++row_id) {
        const int i = row_id % KN;
        const uint32_t m = (uint32_t)(row_id % 14);
        int32_t row[16];
        for (uint32_t k = 0; k < m; ++k)
            row[k] = (int32_t)((i + 1 + 7 * k + (uint32_t)row_id) % KN);
        sph_row_query q = {.x = f.x, .v = f.v, .t_local = f.t_local, .sigma = f.sigma};
        q.ti = f.t_local[i];
        q.dt = 0.01;
        q.sigma_i = f.sigma[i];
        for (int a = 0; a < 3; ++a) {
            q.box[a] = f.box[a];
            q.xi[a] = f.x[3 * i + a];
            q.vi[a] = f.v[3 * i + a];
        }
        int32_t ref_j[16], hj[2][16];
        double ref_t[16], ht[2][16];
        uint32_t ref = 0;
        for (uint32_t k = 0; k < m; ++k) {
            const double tj = f.t_local[row[k]], t0 = q.ti > tj ? q.ti : tj;
            const double tc = kernel_pair_time(&f, i, row[k], t0 - q.ti, t0 - tj, q.dt - t0);
            if (tc >= 0) ref_j[ref] = row[k], ref_t[ref++] = t0 + tc;
        }
        hits_seen += (int)ref;
        for (int kernel = 0; kernel < 1 + avx2; ++kernel) {
            const uint32_t got = kernel ? sph_predict_row_avx2(&q, row, m, hj[1], ht[1])
                                        : sph_predict_row_scalar(&q, row, m, hj[0], ht[0]);
            CHECK(got == ref, "row %d, kernel %d: %u hits, pair by pair %u", row_id, kernel, got,
                  ref);
            for (uint32_t k = 0; k < got && k < ref; ++k)
                CHECK(hj[kernel][k] == ref_j[k] && memcmp(&ht[kernel][k], &ref_t[k], 8) == 0,
                      "row %d, kernel %d, hit %u: j %d t %.17g, pair by pair j %d t %.17g", row_id,
                      kernel, k, hj[kernel][k], ht[kernel][k], ref_j[k], ref_t[k]);
        }
    }
    CHECK(hits_seen > 50, "the rows have hits: %d", hits_seen);
}

/* The half-scan kernels (scalar, AVX2) against pair-by-pair sph_contact_time over rows of
 * every length (0 to 13, so pairs of several rows share a vector and the last one is
 * partial), for several particle ranges. */
static void test_half_scan_kernels(void) {
    kernel_fixture f;
    kernel_fixture_fill(&f);
    enum { CAP = 16 };
    int32_t nb[KN * CAP];
    uint32_t upper[KN];
    for (int i = 0; i < KN; ++i) {
        upper[i] = (uint32_t)((i * 5) % 14);
        for (uint32_t k = 0; k < upper[i]; ++k)
            nb[i * CAP + (int)k] = (int32_t)((i + 1 + 3 * (int)k) % KN);
    }
    const sph_scan_query q = {.x = f.x,
                              .v = f.v,
                              .sigma = f.sigma,
                              .nb = nb,
                              .nb_upper = upper,
                              .nb_cap = CAP,
                              .box = {f.box[0], f.box[1], f.box[2]},
                              .tmax = 0.03};
    const int avx2 = __builtin_cpu_supports("avx2") != 0;
    static int32_t ri[KN * CAP], rj[KN * CAP], hi[2][KN * CAP], hj[2][KN * CAP];
    static double rt[KN * CAP], ht[2][KN * CAP];
    const size_t ranges[][2] = {{0, KN}, {3, 4}, {5, 17}, {10, 10}};
    int hits_seen = 0;
    for (size_t c = 0; c < sizeof ranges / sizeof ranges[0]; ++c) {
        const size_t i0 = ranges[c][0], i1 = ranges[c][1];
        uint32_t ref = 0;
        for (size_t i = i0; i < i1; ++i)
            for (uint32_t k = 0; k < upper[i]; ++k) {
                const int j = nb[i * CAP + k];
                const double tc = kernel_pair_time(&f, (int)i, j, 0.0, 0.0, q.tmax);
                if (tc >= 0) ri[ref] = (int32_t)i, rj[ref] = j, rt[ref++] = tc;
            }
        hits_seen += (int)ref;
        for (int kernel = 0; kernel < 1 + avx2; ++kernel) {
            const uint32_t got = kernel ? sph_half_scan_avx2(&q, i0, i1, hi[1], hj[1], ht[1])
                                        : sph_half_scan_scalar(&q, i0, i1, hi[0], hj[0], ht[0]);
            CHECK(got == ref, "range %zu, kernel %d: %u hits, pair by pair %u", c, kernel, got,
                  ref);
            for (uint32_t k = 0; k < got && k < ref; ++k)
                CHECK(hi[kernel][k] == ri[k] && hj[kernel][k] == rj[k] &&
                          memcmp(&ht[kernel][k], &rt[k], 8) == 0,
                      "range %zu, kernel %d, hit %u: (%d, %d) t %.17g, pair by pair (%d, %d) "
                      "t %.17g",
                      c, kernel, k, hi[kernel][k], hj[kernel][k], ht[kernel][k], ri[k], rj[k],
                      rt[k]);
        }
    }
    CHECK(hits_seen > 50, "the scan has hits: %d", hits_seen);
}

/* The bucket calendar pops in time order while events are pushed at or after the last
 * popped time, as in a step; checked against the earliest of all events still held. */
static void test_calendar_order(void) {
    enum { N = 3000 };
    double u[2 * N];
    hsbd_rng_uniforms(14, 99, 1, 0, 2 * N, u);
    sph_calendar c = {0};
    const double dt = 1e-3;
    for (int step = 0; step < 3; ++step) {
        CHECK(sph_calendar_start(&c, dt) == 0, "start");
        double held[N];
        int nheld = 0, used = 0, popped = 0;
        double now = 0;
        for (; used < N / 2; ++used) { /* the initial predictions */
            const sph_event e = {u[used] * dt, used, used + 1, 0, 0};
            CHECK(sph_calendar_push(&c, e) == 0, "push");
            held[nheld++] = e.t;
        }
        if (step == 1) { /* ties and the end of the step */
            for (int k = 0; k < 3; ++k) {
                const sph_event e = {k ? dt : 0.5 * dt, -1, -1, 0, 0};
                CHECK(sph_calendar_push(&c, e) == 0, "push");
                held[nheld++] = e.t;
            }
        }
        sph_event e;
        while (sph_calendar_pop(&c, &e)) {
            int at = -1;
            double least = INFINITY;
            for (int k = 0; k < nheld; ++k)
                if (held[k] < least) least = held[k], at = k;
            CHECK(e.t == least && e.t >= now, "pop %d: t %.17g, earliest held %.17g", popped, e.t,
                  least);
            held[at] = held[--nheld];
            now = e.t;
            ++popped;
            if (used < N && u[N + used] < 0.6) { /* new events later in the step */
                const sph_event f = {now + u[used] * (dt - now), used, -1, 0, 0};
                CHECK(sph_calendar_push(&c, f) == 0, "push");
                held[nheld++] = f.t;
                ++used;
            }
        }
        CHECK(nheld == 0 && c.size == 0, "step %d ends empty: %d held", step, nheld);
    }
    sph_calendar_free(&c);
}

/* The cell search kernels (scalar, AVX2) against brute force over all points: the same
 * points in the same order, including cells with more points than a vector holds. */
static void test_cells_near_kernels(void) {
    enum { N = 400 };
    double g[4 * N];
    hsbd_rng_normals(13, 99, 1, 0, 4 * N, g);
    const double box[3] = {5.0, 5.0, 4.0};
    double x[3 * N], sigma[N];
    hsbd_cells cells;
    CHECK(hsbd_cells_init(&cells, 3, box, 1.6, N) == 0, "cells allocated");
    for (int j = 0; j < N; ++j) {
        for (int a = 0; a < 3; ++a)
            x[3 * j + a] = fmod(fabs(g[4 * j + a]), 1.0) * box[a];
        sigma[j] = 0.6 + 0.2 * fmod(fabs(g[4 * j + 3]), 1.0);
        CHECK(hsbd_cells_insert(&cells, j, x + 3 * j) == 0, "insert %d", j);
    }
    CHECK(hsbd_cells_room(&cells) > HSBD_CELL_CHUNK, "some cell holds more than one chunk: room %u",
          hsbd_cells_room(&cells));
    const int avx2 = __builtin_cpu_supports("avx2") != 0;
    int32_t *out = malloc((27 * hsbd_cells_room(&cells) + SPH_NEAR_PAD) * sizeof *out), ref[N];
    int total = 0;
    /* every point with its own diameter, then all with one (sigma NULL, folded into the
     * base) */
    for (int pass = 0; pass < 2 * N; pass += 7) {
        const int one = pass >= N, i = pass % N;
        int32_t around[27];
        const int nc = hsbd_cells_around(&cells, x + 3 * i, around);
        const double base = 0.5 * sigma[i] + 0.6, common = 0.7;
        const double *point_sigma = one ? NULL : sigma;
        const double kernel_base = one ? base + 0.5 * common : base;
        uint32_t nref = 0;
        for (int q = 0; q < nc; ++q) /* brute force in the kernels' order: cell, then slot */
            for (int j = 0; j < N; ++j) {
                if (cells.cell_of[j] != around[q]) continue;
                double r2 = 0;
                for (int a = 0; a < 3; ++a) {
                    const double d = hsbd_wrap_delta(x[3 * j + a] - x[3 * i + a], box[a]);
                    r2 += d * d;
                }
                const double reach = base + 0.5 * (one ? common : sigma[j]);
                if (r2 < reach * reach) ref[nref++] = j;
            }
        for (int kernel = 0; kernel < 1 + avx2; ++kernel) {
            const uint32_t got = kernel ? sph_cells_near_avx2(&cells, around, nc, x + 3 * i, box,
                                                              point_sigma, kernel_base, out)
                                        : sph_cells_near_scalar(&cells, around, nc, x + 3 * i, box,
                                                                point_sigma, kernel_base, out);
            CHECK(got == nref, "point %d, kernel %d, one diameter %d: %u found, brute force %u", i,
                  kernel, one, got, nref);
            for (uint32_t k = 0; k < got && k < nref; ++k) {
                int seen = 0;
                for (uint32_t l = 0; l < nref; ++l)
                    seen |= out[k] == ref[l];
                CHECK(seen, "point %d, kernel %d: %d is not within reach", i, kernel, out[k]);
                if (k > 0 && cells.cell_of[out[k]] == cells.cell_of[out[k - 1]])
                    CHECK(cells.slot_of[out[k]] > cells.slot_of[out[k - 1]],
                          "point %d, kernel %d: slot order", i, kernel);
            }
        }
        total += (int)nref;
    }
    CHECK(total > 100, "points found: %d", total);
    free(out);
    hsbd_cells_free(&cells);
}

static void run_no_overlap(const char *name, hsbd_spheres_params p, int lattice, int steps) {
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s != NULL, "%s: alloc: %s", name, err.message);
    if (!s) return;
    const int rc = lattice ? hsbd_spheres_init_lattice(s, &err) : hsbd_spheres_init_random(s, &err);
    CHECK(rc == HSBD_OK, "%s: init: %s", name, err.message);
    hsbd_spheres_view v = hsbd_spheres_get_view(s);
    CHECK(brute_min_gap(&v) >= -1e-9, "%s: initial overlap %g", name, brute_min_gap(&v));
    double worst = INFINITY;
    for (int k = 0; k < steps; ++k) {
        CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
        if (k % 10 == 9) {
            v = hsbd_spheres_get_view(s);
            const double g = brute_min_gap(&v);
            if (g < worst) worst = g;
            int finite = 0;
            const double g_nb = hsbd_spheres_min_gap(s, &finite);
            CHECK(finite, "%s: non-finite position", name);
            CHECK(fabs(g_nb - g) <= 1e-12 || g_nb <= g, "%s: neighbour-list gap %g vs %g", name,
                  g_nb, g);
        }
    }
    const hsbd_spheres_stats st = hsbd_spheres_get_stats(s);
    printf("%s: %llu collisions in %d steps of %zu particles (%.3f per particle-step), %llu shell "
           "updates, min gap %.3g\n",
           name, (unsigned long long)st.collisions, steps, p.n,
           (double)st.collisions / steps / (double)p.n, (unsigned long long)st.shell_updates,
           worst);
    CHECK(worst >= -1e-9, "%s: overlap %g after a step", name, worst);
    CHECK(st.collisions > 0, "%s: no collisions", name);
    hsbd_spheres_free(s);
}

static void test_no_overlap(void) {
    const double phi3 = 0.35, n3 = 500;
    const double box3 = cbrt(n3 * PI / 6 / phi3);
    hsbd_spheres_params p = {.n = 500,
                             .dimension = 3,
                             .box = {box3, box3, box3},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 5,
                             .hard_core = 1};
    run_no_overlap("3D phi 0.35 (lattice)", p, 1, 300);
    p.dt = 1e-2; /* large steps: many collisions per step and shell exits within the step */
    p.seed = 6;
    run_no_overlap("3D phi 0.35, dt 1e-2", p, 1, 200);
    /* 2D dense disks */
    const double phi2 = 0.65;
    const double box2 = sqrt(400 * PI / 4 / phi2);
    hsbd_spheres_params q = p;
    q.n = 400, q.dimension = 2, q.box[0] = box2, q.box[1] = box2, q.dt = 1e-3, q.seed = 8;
    run_no_overlap("2D phi 0.65 (lattice)", q, 1, 300);
    /* binary mixture with immobile obstacles and a drift, random insertion */
    static int species[400];
    for (int i = 0; i < 400; ++i)
        species[i] = i % 4 == 0;
    static const double sig[2] = {1.0, 1.4}, dif[2] = {1.0, 0.0};
    hsbd_spheres_params m = p;
    m.n = 400, m.nspecies = 2, m.species = species, m.species_sigma = sig,
    m.species_diffusion = dif, m.dt = 2e-3, m.seed = 9;
    const double vol = 300 * PI / 6 + 100 * PI / 6 * 1.4 * 1.4 * 1.4;
    m.box[0] = m.box[1] = m.box[2] = cbrt(vol / 0.25);
    run_no_overlap("3D binary with immobile obstacles", m, 0, 200);
    static const double dif2[2] = {1.0, 0.5};
    m.species_diffusion = dif2, m.drift[0] = 3.0, m.seed = 10;
    run_no_overlap("3D binary with drift", m, 0, 200);
}

static void test_reproducible(void) {
    const double box = cbrt(300 * PI / 6 / 0.3);
    hsbd_spheres_params p = {.n = 300,
                             .dimension = 3,
                             .box = {box, box, box},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 77,
                             .hard_core = 1};
    hsbd_error err;
    hsbd_spheres *a = hsbd_spheres_alloc(&p, &err), *b = hsbd_spheres_alloc(&p, &err);
    CHECK(a && b, "alloc");
    if (!a || !b) return;
    CHECK(hsbd_spheres_init_random(a, &err) == HSBD_OK, "init: %s", err.message);
    CHECK(hsbd_spheres_init_random(b, &err) == HSBD_OK, "init: %s", err.message);
    for (int k = 0; k < 100; ++k) {
        CHECK(hsbd_spheres_step(a) == HSBD_OK, "step");
        if (k < 50) CHECK(hsbd_spheres_step(b) == HSBD_OK, "step");
    }
    for (int k = 50; k < 100; ++k)
        CHECK(hsbd_spheres_step(b) == HSBD_OK, "step");
    const hsbd_spheres_view va = hsbd_spheres_get_view(a), vb = hsbd_spheres_get_view(b);
    CHECK(!memcmp(va.x, vb.x, 3 * p.n * sizeof *va.x), "two objects, same seed: positions differ");
    CHECK(!memcmp(va.image, vb.image, 3 * p.n * sizeof *va.image), "image counters differ");
    hsbd_spheres_free(a);
    hsbd_spheres_free(b);
}

/* The engine's spatial sort is invisible: a mixture from random insertion (particles in
 * random order, so the sort moves nearly all of them) run with and without it gives
 * bit-identical positions and the same collisions (the shells stay put and a pair's
 * contact time does not depend on which partner comes first); views, parameters and a
 * later set_positions see the user's order. */
static double max_unwrapped_difference(const hsbd_spheres_view *a, const hsbd_spheres_view *b) {
    double worst = 0;
    for (size_t k = 0; k < 3 * a->n; ++k) {
        const double box = a->box[k % 3];
        const double d =
            (a->x[k] + (double)a->image[k] * box) - (b->x[k] + (double)b->image[k] * box);
        worst = fmax(worst, fabs(d));
    }
    return worst;
}

static void test_spatial_order(void) {
    static int species[600];
    for (int i = 0; i < 600; ++i)
        species[i] = i % 3 == 0;
    static const double sig[2] = {1.0, 1.4}, dif[2] = {1.0, 1.0 / 1.4};
    const double side = cbrt((400 * PI / 6 + 200 * PI / 6 * 1.4 * 1.4 * 1.4) / 0.3);
    hsbd_spheres_params p = {.n = 600,
                             .dimension = 3,
                             .box = {side, side, side},
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 21,
                             .hard_core = 1,
                             .nspecies = 2,
                             .species = species,
                             .species_sigma = sig,
                             .species_diffusion = dif,
                             .keep_order = 1};
    hsbd_error err;
    hsbd_spheres *a = hsbd_spheres_alloc(&p, &err);
    p.keep_order = 0;
    hsbd_spheres *b = hsbd_spheres_alloc(&p, &err);
    CHECK(a && b, "alloc");
    if (!a || !b) return;
    CHECK(hsbd_spheres_init_random(a, &err) == HSBD_OK, "init: %s", err.message);
    CHECK(hsbd_spheres_init_random(b, &err) == HSBD_OK, "init: %s", err.message);
    for (int k = 0; k < 400; ++k) { /* D t = 0.4: the order is sorted four times */
        CHECK(hsbd_spheres_step(a) == HSBD_OK, "step");
        CHECK(hsbd_spheres_step(b) == HSBD_OK, "step");
    }
    const hsbd_spheres_view va = hsbd_spheres_get_view(a), vb = hsbd_spheres_get_view(b);
    CHECK(!memcmp(va.x, vb.x, 3 * p.n * sizeof *va.x) &&
              !memcmp(va.image, vb.image, 3 * p.n * sizeof *va.image),
          "sorted and unsorted runs differ, by up to %.3g in a position",
          max_unwrapped_difference(&va, &vb));
    const hsbd_spheres_stats sa = hsbd_spheres_get_stats(a), sb = hsbd_spheres_get_stats(b);
    CHECK(sa.collisions == sb.collisions && sa.collisions > 0,
          "collisions: %llu unsorted, %llu sorted", (unsigned long long)sa.collisions,
          (unsigned long long)sb.collisions);
    CHECK(!memcmp(va.sigma, vb.sigma, p.n * sizeof *va.sigma) &&
              !memcmp(va.diffusion, vb.diffusion, p.n * sizeof *va.diffusion) &&
              !memcmp(va.species, vb.species, p.n * sizeof *va.species) &&
              !memcmp(hsbd_spheres_get_params(b)->species, species, sizeof species),
          "the sorted run's view or parameters are not in the user's order");
    /* new positions by user index, after the sort: the view returns them as given */
    double *x = malloc(3 * p.n * sizeof *x);
    memcpy(x, va.x, 3 * p.n * sizeof *x);
    CHECK(hsbd_spheres_set_positions(b, x, &err) == HSBD_OK, "set_positions: %s", err.message);
    const hsbd_spheres_view vc = hsbd_spheres_get_view(b);
    CHECK(!memcmp(vc.x, x, 3 * p.n * sizeof *x) && !memcmp(vc.sigma, va.sigma, p.n * sizeof *x),
          "set_positions after a sort: the view does not give the positions back");
    free(x);
    hsbd_spheres_free(a);
    hsbd_spheres_free(b);
}

/* The same run with the global calendar and group by group: bit-identical positions and
 * image counters, the same collisions, shell updates and virial (exact sums); at least min_reruns
 * groups ran again (so the joining and rewinding are exercised, not only the easy path). */
static void compare_event_orders(const char *name, hsbd_spheres_params p, int steps,
                                 uint64_t min_reruns, hsbd_spheres_event_order order) {
    hsbd_error err;
    p.event_order = HSBD_EVENTS_GLOBAL;
    hsbd_spheres *a = hsbd_spheres_alloc(&p, &err);
    p.event_order = order;
    hsbd_spheres *b = hsbd_spheres_alloc(&p, &err);
    CHECK(a && b, "%s: alloc", name);
    if (!a || !b) return;
    CHECK(hsbd_spheres_init_lattice(a, &err) == HSBD_OK, "%s: init: %s", name, err.message);
    CHECK(hsbd_spheres_init_lattice(b, &err) == HSBD_OK, "%s: init: %s", name, err.message);
    for (int k = 0; k < steps; ++k) {
        CHECK(hsbd_spheres_step(a) == HSBD_OK, "step");
        CHECK(hsbd_spheres_step(b) == HSBD_OK, "step");
    }
    const hsbd_spheres_view va = hsbd_spheres_get_view(a), vb = hsbd_spheres_get_view(b);
    CHECK(!memcmp(va.x, vb.x, 3 * p.n * sizeof *va.x) &&
              !memcmp(va.image, vb.image, 3 * p.n * sizeof *va.image),
          "%s: global calendar and groups differ, by up to %.3g in a position", name,
          max_unwrapped_difference(&va, &vb));
    const hsbd_spheres_stats sa = hsbd_spheres_get_stats(a), sb = hsbd_spheres_get_stats(b);
    CHECK(sa.collisions == sb.collisions && sa.collisions > 0,
          "%s: collisions %llu (global) vs %llu (groups)", name, (unsigned long long)sa.collisions,
          (unsigned long long)sb.collisions);
    CHECK(sa.virial == sb.virial && sa.shell_updates == sb.shell_updates,
          "%s: virial %.17g (global) vs %.17g (groups), shell updates %llu vs %llu", name,
          sa.virial, sb.virial, (unsigned long long)sa.shell_updates,
          (unsigned long long)sb.shell_updates);
    CHECK(sa.group_reruns == 0 && sb.group_reruns >= min_reruns,
          "%s: %llu groups re-ran (at least %llu expected)", name,
          (unsigned long long)sb.group_reruns, (unsigned long long)min_reruns);
    hsbd_spheres_free(a);
    hsbd_spheres_free(b);
}

/* Explicit GROUPS where the groups percolate (phi 0.47, a shell of 0.02 sigma, steps whose
 * displacements are several shells): every group meets the groups that ran, and before the
 * give-up a step re-ran groups until they covered the box: here 623340 stale events against
 * the global calendar's 5684 (at N 30000 a step ran for minutes). Now the step
 * goes to the global calendar once its re-runs exceed its predicted pairs: the same
 * positions, and stale events (the work thrown away) within a few times the global
 * calendar's. A count, not a time. */
static void test_groups_give_up(void) {
    hsbd_spheres_params p = {.n = 1000,
                             .dimension = 3,
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 4e-3,
                             .seed = 3,
                             .hard_core = 1,
                             .shell = 0.02};
    p.box[0] = p.box[1] = p.box[2] = cbrt(1000 * PI / 6 / 0.47);
    uint64_t stale[2] = {0, 0};
    double *x[2] = {NULL, NULL};
    for (int order = 0; order < 2; ++order) {
        p.event_order = order ? HSBD_EVENTS_GROUPS : HSBD_EVENTS_GLOBAL;
        hsbd_error err;
        hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
        CHECK(s && hsbd_spheres_init_lattice(s, &err) == HSBD_OK, "give-up: init");
        if (!s) return;
        for (int k = 0; k < 2; ++k)
            CHECK(hsbd_spheres_step(s) == HSBD_OK, "give-up: step");
        stale[order] = hsbd_spheres_get_stats(s).stale_events;
        x[order] = malloc(3 * p.n * sizeof *x[order]);
        if (x[order]) memcpy(x[order], hsbd_spheres_get_view(s).x, 3 * p.n * sizeof *x[order]);
        hsbd_spheres_free(s);
    }
    CHECK(x[0] && x[1] && !memcmp(x[0], x[1], 3 * p.n * sizeof *x[0]),
          "give-up: groups and the global calendar end at other positions");
    CHECK(stale[0] > 0 && stale[1] <= 4 * stale[0],
          "give-up: %llu stale events with groups, %llu with the global calendar",
          (unsigned long long)stale[1], (unsigned long long)stale[0]);
    free(x[0]);
    free(x[1]);
}

static void test_event_groups(void) {
    static int species[1000];
    for (int i = 0; i < 1000; ++i)
        species[i] = i % 3 == 0 ? 1 : i % 97 == 5 ? 2 : 0;
    /* a mixture with a few immobile obstacles, phi 0.3 */
    static const double sig[3] = {1.0, 1.4, 1.2}, dif[3] = {1.0, 1.0 / 1.4, 0.0};
    const double side = cbrt((1000 * PI / 6 * (2.0 + 1.4 * 1.4 * 1.4) / 3) / 0.3);
    hsbd_spheres_params p = {.n = 1000,
                             .dimension = 3,
                             .box = {side, side, side},
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 5,
                             .hard_core = 1,
                             .nspecies = 3,
                             .species = species,
                             .species_sigma = sig,
                             .species_diffusion = dif};
    compare_event_orders("mixture phi 0.3", p, 300, 1, HSBD_EVENTS_GROUPS);
    /* dense monodisperse spheres with long steps: the groups meet often */
    hsbd_spheres_params q = {.n = 864,
                             .dimension = 3,
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 6,
                             .hard_core = 1};
    const double side_q = cbrt(864 * PI / 6 / 0.5);
    q.box[0] = q.box[1] = q.box[2] = side_q;
    compare_event_orders("spheres phi 0.5", q, 200, 20, HSBD_EVENTS_GROUPS);
    /* AUTO at this N: steps whose groups percolate as they run are given up part-way and
     * handed to the global calendar, from the start of the step */
    q.groups_min_n = 1;
    compare_event_orders("spheres phi 0.5 (auto)", q, 200, 1, HSBD_EVENTS_AUTO);
    /* dense disks */
    hsbd_spheres_params d = {.n = 900,
                             .dimension = 2,
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 7,
                             .hard_core = 1};
    d.box[0] = d.box[1] = sqrt(900 * PI / 4 / 0.6);
    compare_event_orders("disks phi 0.6", d, 200, 20, HSBD_EVENTS_GROUPS);
    /* a long box, on two threads: 8 slabs along z, so the groups' first pass runs both its
     * rounds (taking in pending groups) and the shells move slab by slab */
    hsbd_spheres_params l = fluid_params(3, 4950, 0.3, 8);
    l.box[0] = l.box[1] = 12, l.box[2] = 60; /* phi 0.3 */
    l.threads = 2;
    compare_event_orders("spheres phi 0.3, a long box", l, 150, 1, HSBD_EVENTS_GROUPS);
    /* shells far below the default (about 0.3 here): every particle moves its shell
     * several times a step, and the two orders predict some pairs at other moments; a
     * contact time from the two paths alone keeps the bits (with times from the moment of
     * the prediction these differed from step 3 and 4 on) */
    hsbd_spheres_params t = fluid_params(3, 2048, 0.3, 1);
    t.shell = 0.05;
    compare_event_orders("spheres phi 0.3, shell 0.05", t, 100, 1, HSBD_EVENTS_GROUPS);
    t.shell = 0.02;
    t.threads = 2;
    compare_event_orders("spheres phi 0.3, shell 0.02, two threads", t, 60, 1, HSBD_EVENTS_GROUPS);
}

/* The same run on 1, 2 and 4 threads (oversubscribed on a small machine, which is fine):
 * bit-identical positions, image counters, collisions, shell updates and virial (the
 * events run on one thread in the same order; the threads share the noise, the start-of-
 * step scan and the final move). N is above SPH_THREADS_MIN_N, so every loop is split. */
static void compare_thread_counts(const char *name, hsbd_spheres_params p, int steps) {
    hsbd_error err;
    hsbd_spheres *s[3] = {0};
    static const int threads[3] = {1, 2, 4};
    for (int k = 0; k < 3; ++k) {
        p.threads = threads[k];
        s[k] = hsbd_spheres_alloc(&p, &err);
        CHECK(s[k] && hsbd_spheres_init_lattice(s[k], &err) == HSBD_OK, "%s: init: %s", name,
              err.message);
        for (int step = 0; s[k] && step < steps; ++step)
            CHECK(hsbd_spheres_step(s[k]) == HSBD_OK, "%s: step", name);
    }
    for (int k = 1; k < 3 && s[0] && s[k]; ++k) {
        const hsbd_spheres_view va = hsbd_spheres_get_view(s[0]), vb = hsbd_spheres_get_view(s[k]);
        CHECK(!memcmp(va.x, vb.x, 3 * p.n * sizeof *va.x) &&
                  !memcmp(va.image, vb.image, 3 * p.n * sizeof *va.image),
              "%s: %d threads differ from one, by up to %.3g in a position", name, threads[k],
              max_unwrapped_difference(&va, &vb));
        const hsbd_spheres_stats sa = hsbd_spheres_get_stats(s[0]);
        const hsbd_spheres_stats sb = hsbd_spheres_get_stats(s[k]);
        CHECK(sa.collisions == sb.collisions && sa.collisions > 0 &&
                  sa.shell_updates == sb.shell_updates && sa.virial == sb.virial &&
                  sa.group_reruns == sb.group_reruns && sa.wall_pushes == sb.wall_pushes,
              "%s: %d threads: collisions %llu vs %llu, virial %.17g vs %.17g", name, threads[k],
              (unsigned long long)sa.collisions, (unsigned long long)sb.collisions, sa.virial,
              sb.virial);
    }
    for (int k = 0; k < 3; ++k)
        hsbd_spheres_free(s[k]);
}

static void test_threads(void) {
    hsbd_spheres_params p = fluid_params(3, 4000, 0.3, 12);
    const double side = p.box[0];
    p.event_order = HSBD_EVENTS_GLOBAL;
    compare_thread_counts("global calendar, phi 0.3", p, 150);
    p.event_order = HSBD_EVENTS_GROUPS;
    compare_thread_counts("groups, phi 0.3", p, 150);
    /* a long box: 8 slabs along z, so the shells leaving at the start of a step move four
     * slabs at a time on the threads (src/spheres/scan.c) */
    p.n = 4950;
    p.box[0] = p.box[1] = 12;
    p.box[2] = 60;
    p.event_order = HSBD_EVENTS_GLOBAL;
    compare_thread_counts("global calendar, a long box", p, 150);
    p.event_order = HSBD_EVENTS_GROUPS;
    compare_thread_counts("groups, a long box", p, 150);
    p.n = 4000;
    p.box[0] = p.box[1] = p.box[2] = side;
    /* walls on z with gravity: the start flags for the walls, the bridge pushes */
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(-0.5));
    p.event_order = HSBD_EVENTS_AUTO;
    p.walls[2] = 1;
    p.field = &gravity;
    p.field_axis = 2;
    compare_thread_counts("walls and gravity", p, 150);
}

/* A busy wait that the compiler keeps: about `rounds` dependent multiplications. */
static double spin_work(long rounds) {
    volatile double x = 1.0;
    for (long r = 0; r < rounds; ++r)
        x = x * 1.0000001;
    return x;
}

/* The slab queue (src/spheres/slab_queue.h) on 1 to 4 threads (oversubscribed on two
 * cores): every slab handed out once; no slab starts while a neighbour runs; an odd slab
 * starts only after both even neighbours finished. Even slabs are made slow, so that a
 * queue that did not wait would hand out an odd slab beside a running one. A failed slab
 * stops the handing out. */
static void slab_queue_run(int nslabs, int threads, int fail_at) {
    sph_slab_queue q;
    sph_slab_queue_start(&q, nslabs);
    atomic_int state[SPH_SLAB_QUEUE_MAX]; /* 0 not started, 1 running, 2 finished */
    atomic_int taken[SPH_SLAB_QUEUE_MAX], violations, handed;
    for (int k = 0; k < nslabs; ++k) {
        atomic_init(&state[k], 0);
        atomic_init(&taken[k], 0);
    }
    atomic_init(&violations, 0);
    atomic_init(&handed, 0);
#pragma omp parallel num_threads(threads)
    for (int k; (k = sph_slab_queue_take(&q)) >= 0;) {
        const int left = (k + nslabs - 1) % nslabs, right = (k + 1) % nslabs;
        atomic_fetch_add(&taken[k], 1);
        atomic_fetch_add(&handed, 1);
        atomic_store(&state[k], 1);
        if (atomic_load(&state[left]) == 1 || atomic_load(&state[right]) == 1)
            atomic_fetch_add(&violations, 1);
        if (k % 2 && (atomic_load(&state[left]) != 2 || atomic_load(&state[right]) != 2))
            atomic_fetch_add(&violations, 1);
        spin_work(k % 2 ? 1000 : 200000);
        if (atomic_load(&state[left]) == 1 || atomic_load(&state[right]) == 1)
            atomic_fetch_add(&violations, 1);
        atomic_store(&state[k], 2);
        sph_slab_queue_finish(&q, k, k == fail_at);
    }
    CHECK(atomic_load(&violations) == 0,
          "slab queue, %d slabs, %d threads: %d neighbours ran at once", nslabs, threads,
          atomic_load(&violations));
    int once = 1;
    for (int k = 0; k < nslabs; ++k)
        once &= atomic_load(&taken[k]) <= 1 && (fail_at >= 0 || atomic_load(&taken[k]) == 1);
    CHECK(once, "slab queue, %d slabs, %d threads: a slab handed out twice or never", nslabs,
          threads);
    if (fail_at >= 0) /* the failed slab is even and all evens come first: no odd one runs */
        CHECK(atomic_load(&handed) <= nslabs / 2 + threads - 1,
              "slab queue, %d slabs, %d threads: %d slabs handed out after a failure", nslabs,
              threads, atomic_load(&handed));
}

static void test_slab_queue(void) {
    const int counts[] = {4, 6, 10, SPH_SLAB_QUEUE_MAX};
    for (size_t c = 0; c < sizeof counts / sizeof *counts; ++c)
        for (int threads = 1; threads <= 4; ++threads)
            slab_queue_run(counts[c], threads, -1);
    slab_queue_run(10, 2, 0);
}

static void test_bad_params(void) {
    hsbd_spheres_params p = {.n = 10,
                             .dimension = 3,
                             .box = {3, 3, 3},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .hard_core = 1};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(!s && err.status == HSBD_EINPUT && strstr(err.message, "twice the interaction range"),
          "a small box: %s", err.message);
    hsbd_spheres_free(s);
    p.box[0] = p.box[1] = p.box[2] = 10;
    p.dimension = 4;
    s = hsbd_spheres_alloc(&p, &err);
    CHECK(!s && err.status == HSBD_EINPUT, "dimension 4");
    hsbd_spheres_free(s);
    p.dimension = 3, p.diffusion = -1;
    s = hsbd_spheres_alloc(&p, &err);
    CHECK(!s && err.status == HSBD_EINPUT && strstr(err.message, "D = -1"), "D < 0: %s",
          err.message);
    hsbd_spheres_free(s);
    /* overlapping positions are refused, naming the pair */
    p.diffusion = 1, p.n = 2;
    s = hsbd_spheres_alloc(&p, &err);
    const double x[6] = {1, 1, 1, 1.5, 1, 1};
    CHECK(s && hsbd_spheres_set_positions(s, x, &err) == HSBD_EINPUT &&
              strstr(err.message, "particles 1 and 2 overlap"),
          "overlap: %s", err.message);
    hsbd_spheres_free(s);
}

/* Sample mean and standard deviation of the drawn diameters against mean 1 and width w,
 * within 4 standard errors (var of the sample variance: (kurtosis - 1) w^4 / n). */
static void check_diameters(hsbd_size_distribution dist, double kurtosis, double bound) {
    enum { N = 200000 };
    static double mean[N], sg[N], again[N];
    const double w = 0.1;
    for (size_t i = 0; i < N; ++i)
        mean[i] = 1.0;
    hsbd_error err;
    CHECK(hsbd_spheres_draw_diameters(77, N, mean, w, dist, sg, &err) == HSBD_OK, "draw: %s",
          err.message);
    hsbd_spheres_draw_diameters(77, N, mean, w, dist, again, &err);
    double m = 0, m2 = 0, lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < N; ++i)
        m += sg[i] / N, lo = fmin(lo, sg[i]), hi = fmax(hi, sg[i]);
    for (size_t i = 0; i < N; ++i)
        m2 += (sg[i] - m) * (sg[i] - m) / (N - 1);
    const double sd = sqrt(m2), sd_err = 0.5 * w * sqrt((kurtosis - 1) / N);
    printf("diameters (%s): mean %.5f (+- %.5f), sd %.5f (+- %.5f), range [%.4f, %.4f]\n",
           dist == HSBD_SIZES_UNIFORM ? "uniform" : "gaussian", m, w / sqrt(N), sd, sd_err, lo, hi);
    CHECK(fabs(m - 1) < 4 * w / sqrt(N), "mean diameter %g", m);
    CHECK(fabs(sd - w) < 4 * sd_err, "width %g, asked %g", sd, w);
    CHECK(lo >= 1 - bound * w - 1e-12 && hi <= 1 + bound * w + 1e-12, "range [%g, %g]", lo, hi);
    CHECK(!memcmp(sg, again, sizeof sg), "the same seed gives other diameters");
    CHECK(hsbd_spheres_draw_diameters(77, N, mean, 0.31, dist, sg, &err) == HSBD_EINPUT,
          "width 0.31 accepted");
}

static void test_diameters(void) {
    /* the truncated normal (|z| <= 3) has kurtosis 2.8; rescaled, it ends at 3.0407 widths */
    check_diameters(HSBD_SIZES_GAUSSIAN, 2.8, 3.0 / sqrt(0.9733369246625415));
    check_diameters(HSBD_SIZES_UNIFORM, 1.8, sqrt(3.0));
}

static void compress_case(const char *name, int dim, size_t n, double phi, double width,
                          int expect) {
    static double mean[1000], sg[1000];
    for (size_t i = 0; i < n; ++i)
        mean[i] = 1.0;
    hsbd_error err;
    hsbd_spheres_draw_diameters(3, n, mean, width, HSBD_SIZES_GAUSSIAN, sg, &err);
    double vp = 0;
    for (size_t i = 0; i < n; ++i)
        vp += dim == 3 ? PI / 6 * sg[i] * sg[i] * sg[i] : PI / 4 * sg[i] * sg[i];
    const double side = pow(vp / phi, 1.0 / dim);
    const hsbd_spheres_params p = {.n = n,
                                   .dimension = dim,
                                   .box = {side, side, side},
                                   .diffusion = 1,
                                   .kT = 1,
                                   .dt = 1e-3,
                                   .seed = 4,
                                   .hard_core = 1,
                                   .particle_sigma = sg};
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s != NULL, "%s: alloc: %s", name, err.message);
    if (!s) return;
    const int rc = hsbd_spheres_init_compress(s, &err);
    printf("%s: %s\n", name, rc == HSBD_OK ? "compressed" : err.message);
    CHECK(rc == expect, "%s: compression returned %d, expected %d", name, rc, expect);
    if (rc == HSBD_OK) {
        hsbd_spheres_view v = hsbd_spheres_get_view(s);
        CHECK(!memcmp(v.sigma, sg, n * sizeof *sg), "%s: diameters changed", name);
        CHECK(v.step == 0 && v.time == 0 && v.dt == 1e-3, "%s: clock or dt not reset", name);
        CHECK(brute_min_gap(&v) >= -1e-9, "%s: overlap %g", name, brute_min_gap(&v));
        for (int k = 0; k < 50; ++k)
            CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
        v = hsbd_spheres_get_view(s);
        CHECK(brute_min_gap(&v) >= -1e-9, "%s: overlap %g after 50 steps", name, brute_min_gap(&v));
    }
    hsbd_spheres_free(s);
}

static void test_compress(void) {
    compress_case("compress 3D phi 0.55, polydispersity 0.1", 3, 500, 0.55, 0.1, HSBD_OK);
    compress_case("compress 2D phi 0.70", 2, 400, 0.70, 0.0, HSBD_OK);
    compress_case("compress 3D phi 0.68 (beyond reach)", 3, 200, 0.68, 0.0, HSBD_EINPUT);
}

/* Z = 1 + sum C_ab g_ab: one species C = S_d sigma^d (N - 1) / (2 d V), i.e. 4 phi (N-1)/N
 * in 3D and 2 phi (N-1)/N in 2D; a mixture's weights add up to the moment sum. */
static void test_gr_weights(void) {
    for (int dim = 2; dim <= 3; ++dim) {
        const size_t n = 300;
        const double phi = 0.2;
        const hsbd_spheres_params p = fluid_params(dim, n, phi, 4);
        hsbd_error err;
        hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        hsbd_gr *g = hsbd_gr_alloc(&v, 2.0, 0.05, 0.1, 2, 2, &err);
        const double expect = (dim == 3 ? 4 : 2) * phi * (double)(n - 1) / (double)n;
        CHECK(g && fabs(hsbd_gr_contact_weight(g, 0) - expect) < 1e-12 * expect,
              "%dD: Z weight %.15g, expected %.15g", dim, g ? hsbd_gr_contact_weight(g, 0) : 0,
              expect);
        hsbd_gr_free(g);
        hsbd_spheres_free(s);
    }
}

/* AUTO ignores the thread count: from HSBD_SPHERES_GROUPS_MIN_N_THREADS on, in a box
 * without walls, it does the groups' work on one thread and on two alike (the stale events
 * and re-runs of GROUPS), and every result is the same bit for bit in all four runs (the
 * default shell: the global calendar's too). */
static void test_auto_ignores_threads(void) {
    enum { STEPS = 8 };
    const size_t n = HSBD_SPHERES_GROUPS_MIN_N_THREADS;
    hsbd_spheres_params p = fluid_params(3, n, 0.3, 21);
    static const hsbd_spheres_event_order order[4] = {HSBD_EVENTS_GLOBAL, HSBD_EVENTS_GROUPS,
                                                      HSBD_EVENTS_AUTO, HSBD_EVENTS_AUTO};
    static const int threads[4] = {1, 1, 1, 2};
    hsbd_spheres *s[4] = {0};
    hsbd_spheres_stats st[4];
    hsbd_error err;
    for (int k = 0; k < 4; ++k) {
        p.event_order = order[k];
        p.threads = threads[k];
        s[k] = hsbd_spheres_alloc(&p, &err);
        CHECK(s[k] && hsbd_spheres_init_lattice(s[k], &err) == HSBD_OK, "auto: init: %s",
              err.message);
        for (int step = 0; s[k] && step < STEPS; ++step)
            CHECK(hsbd_spheres_step(s[k]) == HSBD_OK, "auto: step");
        if (!s[k]) return;
        st[k] = hsbd_spheres_get_stats(s[k]);
    }
    const hsbd_spheres_view v0 = hsbd_spheres_get_view(s[0]);
    for (int k = 1; k < 4; ++k) {
        const hsbd_spheres_view v = hsbd_spheres_get_view(s[k]);
        CHECK(!memcmp(v0.x, v.x, 3 * n * sizeof *v.x) &&
                  !memcmp(v0.image, v.image, 3 * n * sizeof *v.image) &&
                  st[0].collisions == st[k].collisions && st[0].virial == st[k].virial &&
                  st[0].shell_updates == st[k].shell_updates,
              "auto: run %d differs from the global calendar's", k);
    }
    CHECK(st[1].group_reruns > 0, "auto: the groups did not re-run (nothing to tell them by)");
    for (int k = 2; k < 4; ++k)
        CHECK(st[k].stale_events == st[1].stale_events && st[k].group_reruns == st[1].group_reruns,
              "auto on %d thread(s) did not take the groups (stale events %llu, groups %llu; "
              "re-runs %llu, groups %llu)",
              threads[k], (unsigned long long)st[k].stale_events,
              (unsigned long long)st[1].stale_events, (unsigned long long)st[k].group_reruns,
              (unsigned long long)st[1].group_reruns);
    printf("auto: N %zu, %d steps: stale events %llu (global calendar), %llu (groups, %llu "
           "re-runs)\n",
           n, STEPS, (unsigned long long)st[0].stale_events, (unsigned long long)st[1].stale_events,
           (unsigned long long)st[1].group_reruns);
    for (int k = 0; k < 4; ++k)
        hsbd_spheres_free(s[k]);
}

/* The exact sums' terms (src/spheres/state.h): the nearest multiple of the quantum, ties to
 * even, as nearbyint gives it, from 2^-70 to 2^130 quanta of either sign (2^52 and 2^63
 * are where the rounding takes other paths), saturated beyond 2^120, NaN as 0; and a sum
 * of 10^4 terms the same bit for bit in reverse order and with the two halves swapped. */
static void test_exact_sums(void) {
    const sph_exact_scale unit = sph_exact_scale_for(1.0), odd = sph_exact_scale_for(3e-7);
    CHECK(unit.to_quanta == 0x1p64 && odd.to_quanta * 0x1p-22 == 0x1p64,
          "exact sums: the quantum of 3e-7 units is %g", odd.from_quanta);
    uint64_t state = 0x9E3779B97F4A7C15ull;
    int wrong = 0;
    for (int k = 0; k < 200000; ++k) {
        state ^= state << 13, state ^= state >> 7, state ^= state << 17;
        const double mantissa = 1.0 + (double)(state >> 11) * 0x1p-53;
        double q = ldexp(mantissa, (int)(state % 200) - 70) * (state & 1 << 20 ? -1 : 1);
        if (k % 7 == 0) q = trunc(q) + copysign(0.5, q); /* a tie */
        const double sat = fabs(q) <= 0x1p120 ? q : copysign(0x1p120, q);
        wrong += sph_exact_term(unit, q * 0x1p-64) != (sph_exact_sum)nearbyint(sat);
    }
    CHECK(!wrong, "exact sums: %d of 200000 terms not rounded as nearbyint", wrong);
    CHECK(sph_exact_term(unit, NAN) == 0 &&
              sph_exact_term(unit, INFINITY) == (sph_exact_sum)0x1p120,
          "exact sums: NaN or infinity");
    static double terms[10000];
    sph_exact_sum forward = 0, backward = 0, swapped = 0;
    double plain_forward = 0, plain_backward = 0;
    for (int k = 0; k < 10000; ++k) {
        state ^= state << 13, state ^= state >> 7, state ^= state << 17;
        terms[k] = ldexp((double)(state >> 11) * 0x1p-53, -(int)(state % 30));
        forward += sph_exact_term(odd, terms[k]);
        plain_forward += terms[k];
    }
    for (int k = 9999; k >= 0; --k) {
        backward += sph_exact_term(odd, terms[k]);
        plain_backward += terms[k];
        swapped += sph_exact_term(odd, terms[(k + 5000) % 10000]);
    }
    CHECK(forward == backward && forward == swapped, "exact sums: the order changed the sum");
    const double value = sph_exact_value(odd, forward);
    CHECK(fabs(value - plain_forward) <= 1e-12 * plain_forward,
          "exact sums: %.17g against the plain sum %.17g", value, plain_forward);
    printf("exact sums: 10^4 terms %.17g in either order (plain double sums %.17g and %.17g)\n",
           value, plain_forward, plain_backward);
}

int main(void) {
    test_exact_sums();
    test_collision_rule();
    test_contact_time();
    test_predict_row_kernels();
    test_half_scan_kernels();
    test_cells_near_kernels();
    test_calendar_order();
    test_no_overlap();
    test_reproducible();
    test_spatial_order();
    test_event_groups();
    test_groups_give_up();
    test_bad_params();
    test_diameters();
    test_compress();
    test_gr_weights();
    test_slab_queue();
    test_threads();
    test_auto_ignores_threads();
    return test_finish("test_spheres");
}
