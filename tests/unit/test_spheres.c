/* EDBD of hard spheres, deterministic checks: the Brownian collision rule (conservation
 * of sum v_i / D_i and of sum v_i^2 / D_i, reversal of the normal relative velocity, an
 * immobile partner acting as a wall), contact times against brute-force integration, no
 * overlap after any step (O(N^2) check, 2D and 3D, mixtures with immobile obstacles),
 * bit-identical reruns of one seed by two objects in one process, and the free-particle
 * mode. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/rng.h"
#include "hsbd/spheres.h"

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

/* smallest gap over all pairs, relative to sigma_ij (brute force, minimum image) */
static double brute_min_gap(const hsbd_spheres_view *v) {
    double worst = INFINITY;
    for (size_t i = 0; i < v->n; ++i)
        for (size_t j = i + 1; j < v->n; ++j) {
            double r2 = 0;
            for (int a = 0; a < v->dimension; ++a) {
                double d = v->x[3 * j + a] - v->x[3 * i + a];
                d -= v->box[a] * nearbyint(d / v->box[a]);
                r2 += d * d;
            }
            const double sij = 0.5 * (v->sigma[i] + v->sigma[j]);
            const double gap = (sqrt(r2) - sij) / sij;
            if (gap < worst) worst = gap;
        }
    return worst;
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
        hsbd_spheres_step(s);
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
        hsbd_spheres_step(a);
        if (k < 50) hsbd_spheres_step(b);
    }
    for (int k = 50; k < 100; ++k)
        hsbd_spheres_step(b);
    const hsbd_spheres_view va = hsbd_spheres_get_view(a), vb = hsbd_spheres_get_view(b);
    CHECK(!memcmp(va.x, vb.x, 3 * p.n * sizeof *va.x), "two objects, same seed: positions differ");
    CHECK(!memcmp(va.image, vb.image, 3 * p.n * sizeof *va.image), "image counters differ");
    hsbd_spheres_free(a);
    hsbd_spheres_free(b);
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

int main(void) {
    test_collision_rule();
    test_contact_time();
    test_no_overlap();
    test_reproducible();
    test_bad_params();
    return test_finish("test_spheres");
}
