/* Walls and field drifts of the EDBD engine (docs/spheres.md, "Walls and fields").
 * - The exact wall-and-drift step: particles that start 1 from wall contact with D = 1 and
 *   a drift c = mu F = -1 towards it end, after t = 1 in steps dt = 1, 0.1, 0.01 and
 *   0.001, distributed as the corrected Scala Eq. 9 (hsbd_reflected_drift_density): the
 *   Kolmogorov-Smirnov distance sqrt(N) D_N stays below 1.95 (a false alarm once in a
 *   thousand) and the mean and mean square lie within 4 of their sampling errors (fixed
 *   seeds). Free particles (hard_core = 0) and, for dt = 1 and 0.1, hard spheres far apart
 *   (the event engine's path). The mirror rule (mean 1.13 instead of 0.850) fails both.
 * - Hard spheres between walls in gravity, 3D (walls on z), 2D (walls on both axes) and a
 *   mixture with immobile obstacles and per-species couplings: the global calendar and
 *   the groups give bit-identical positions, the same collisions and wall collisions,
 *   the same wall impulses (to round-off: they sum in another order), groups re-ran (AUTO
 *   too, whose steps given up part-way are handed to the global calendar), and
 *   no overlap with a wall or another particle after any step (brute force).
 * - g(r) refuses a box with walls. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/field.h"
#include "hsbd/observe.h"
#include "hsbd/spheres.h"
#include "hsbd/theory.h"

static const double PI = 3.14159265358979323846;

static int compare_doubles(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* sqrt(N) times the largest distance between the sorted sample's CDF and Eq. 9's (the
 * density integrated by the trapezoidal rule on a fine grid as the sample is swept). */
static double ks_statistic(double *gap, size_t n, double x0, double c, double t) {
    qsort(gap, n, sizeof *gap, compare_doubles);
    const double h = 1e-4;
    double x = 0, cdf = 0, worst = 0;
    double f = hsbd_reflected_drift_density(0, x0, c, 1.0, t);
    for (size_t k = 0; k < n; ++k) {
        while (x + h <= gap[k]) {
            const double f1 = hsbd_reflected_drift_density(x + h, x0, c, 1.0, t);
            cdf += 0.5 * h * (f + f1);
            f = f1;
            x += h;
        }
        const double at = cdf + (gap[k] - x) * f; /* the last partial interval */
        const double lo = fabs(at - (double)k / (double)n), hi = fabs(at - (double)(k + 1) / n);
        worst = fmax(worst, fmax(lo, hi));
    }
    return sqrt((double)n) * worst;
}

/* The end gaps of particles started x0 from the wall at 0 (2D, walls on x only, far wall
 * beyond reach, particles spaced 12 apart along y), after t = 1 in steps dt. */
static void wall_step_case(int hard_core, double dt, size_t n_per_run, int runs) {
    const double x0 = 1.0, c = -1.0, sigma = 1.0;
    const size_t total = n_per_run * (size_t)runs;
    double *gap = malloc(total * sizeof *gap), *x = calloc(3 * n_per_run, sizeof *x);
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_tilt(c)); /* kT = D = 1: c = mu F */
    const double spacing = hard_core ? 12.0 : 1.0;
    hsbd_spheres_params p = {.n = n_per_run,
                             .dimension = 2,
                             .box = {60.0, spacing * (double)n_per_run, 1},
                             .sigma = sigma,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = dt,
                             .hard_core = hard_core,
                             .walls = {1, 0, 0},
                             .field = &field,
                             .field_axis = 0,
                             .event_order = HSBD_EVENTS_GLOBAL};
    const int steps = (int)lround(1.0 / dt);
    size_t got = 0;
    for (int r = 0; r < runs && gap && x; ++r) {
        p.seed = 1000 + (uint64_t)r + (uint64_t)(1e6 * dt) + 77 * (uint64_t)hard_core;
        hsbd_error err;
        hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
        CHECK(s != NULL, "alloc: %s", err.message);
        if (!s) break;
        for (size_t i = 0; i < n_per_run; ++i)
            x[3 * i] = 0.5 * sigma + x0, x[3 * i + 1] = spacing * ((double)i + 0.5);
        CHECK(hsbd_spheres_set_positions(s, x, &err) == HSBD_OK, "positions: %s", err.message);
        for (int k = 0; k < steps; ++k)
            CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        for (size_t i = 0; i < n_per_run; ++i)
            gap[got++] = v.x[3 * i] - 0.5 * sigma;
        if (hard_core)
            CHECK(hsbd_spheres_get_stats(s).collisions == 0, "the spheres met each other");
        hsbd_spheres_free(s);
    }
    double m1 = 0, m2 = 0, m4 = 0;
    for (size_t k = 0; k < got; ++k)
        m1 += gap[k], m2 += gap[k] * gap[k], m4 += pow(gap[k], 4);
    m1 /= (double)got, m2 /= (double)got, m4 /= (double)got;
    const double e1 = sqrt((m2 - m1 * m1) / (double)got), e2 = sqrt((m4 - m2 * m2) / (double)got);
    const double t1 = hsbd_reflected_drift_moment(1, x0, c, 1.0, 1.0);
    const double t2 = hsbd_reflected_drift_moment(2, x0, c, 1.0, 1.0);
    const double ks = ks_statistic(gap, got, x0, c, 1.0);
    printf("wall step, %s, dt %g, %zu particles: mean %.5f +- %.5f (Eq. 9 %.5f, %+.2f error "
           "bars), mean square %.5f +- %.5f (%.5f, %+.2f), KS sqrt(N) D %.3f\n",
           hard_core ? "hard spheres" : "free", dt, got, m1, e1, t1, (m1 - t1) / e1, m2, e2, t2,
           (m2 - t2) / e2, ks);
    CHECK(got == total, "samples %zu of %zu", got, total);
    CHECK(fabs(m1 - t1) < 4 * e1, "mean %.5f vs %.5f +- %.5f", m1, t1, e1);
    CHECK(fabs(m2 - t2) < 4 * e2, "mean square %.5f vs %.5f +- %.5f", m2, t2, e2);
    CHECK(ks < 1.95, "KS statistic %.3f", ks);
    free(gap);
    free(x);
}

static void test_exact_wall_step(void) {
    CHECK(fabs(hsbd_reflected_drift_moment(0, 1, -1, 1, 1) - 1) < 1e-9, "Eq. 9 normalised");
    CHECK(fabs(hsbd_reflected_drift_moment(1, 1, -1, 1, 1) - 0.8504) < 1e-4, "Eq. 9 mean");
    wall_step_case(0, 1.0, 100000, 1);
    wall_step_case(0, 0.1, 50000, 1);
    wall_step_case(0, 0.01, 20000, 1);
    wall_step_case(0, 0.001, 4000, 1);
    wall_step_case(1, 1.0, 200, 50);
    wall_step_case(1, 0.1, 200, 20);
}

/* Smallest gap to another particle (minimum image along periodic axes only) or a wall,
 * relative to the diameters, by brute force. */
static double brute_min_gap_walls(const hsbd_spheres_view *v) {
    double worst = INFINITY;
    for (size_t i = 0; i < v->n; ++i) {
        for (int a = 0; a < v->dimension; ++a)
            if (v->walls[a]) {
                const double half = 0.5 * v->sigma[i], x = v->x[3 * i + a];
                worst = fmin(worst, fmin(x - half, v->box[a] - half - x) / v->sigma[i]);
            }
        for (size_t j = i + 1; j < v->n; ++j) {
            double r2 = 0;
            for (int a = 0; a < v->dimension; ++a) {
                double d = v->x[3 * j + a] - v->x[3 * i + a];
                if (!v->walls[a]) d -= v->box[a] * nearbyint(d / v->box[a]);
                r2 += d * d;
            }
            const double sij = 0.5 * (v->sigma[i] + v->sigma[j]);
            worst = fmin(worst, (sqrt(r2) - sij) / sij);
        }
    }
    return worst;
}

static void compare_with_walls(const char *name, hsbd_spheres_params p, int steps,
                               uint64_t min_reruns, hsbd_spheres_event_order order) {
    hsbd_error err;
    p.event_order = HSBD_EVENTS_GLOBAL;
    hsbd_spheres *a = hsbd_spheres_alloc(&p, &err);
    p.event_order = order;
    hsbd_spheres *b = hsbd_spheres_alloc(&p, &err);
    CHECK(a && b, "%s: alloc: %s", name, err.message);
    if (!a || !b) return;
    CHECK(hsbd_spheres_init_lattice(a, &err) == HSBD_OK, "%s: init: %s", name, err.message);
    CHECK(hsbd_spheres_init_lattice(b, &err) == HSBD_OK, "%s: init: %s", name, err.message);
    hsbd_spheres_view va = hsbd_spheres_get_view(a);
    CHECK(brute_min_gap_walls(&va) >= -1e-9, "%s: initial overlap", name);
    double worst = INFINITY;
    for (int k = 0; k < steps; ++k) {
        CHECK(hsbd_spheres_step(a) == HSBD_OK, "step");
        CHECK(hsbd_spheres_step(b) == HSBD_OK, "step");
        if (k % 10 == 9) {
            va = hsbd_spheres_get_view(a);
            worst = fmin(worst, brute_min_gap_walls(&va));
        }
    }
    va = hsbd_spheres_get_view(a);
    const hsbd_spheres_view vb = hsbd_spheres_get_view(b);
    CHECK(!memcmp(va.x, vb.x, 3 * p.n * sizeof *va.x) &&
              !memcmp(va.image, vb.image, 3 * p.n * sizeof *va.image),
          "%s: global calendar and groups differ", name);
    const hsbd_spheres_stats sa = hsbd_spheres_get_stats(a), sb = hsbd_spheres_get_stats(b);
    CHECK(sa.collisions == sb.collisions && sa.wall_collisions == sb.wall_collisions &&
              sa.wall_pushes == sb.wall_pushes && sa.pair_corrections == sb.pair_corrections,
          "%s: collisions %llu / %llu, wall collisions %llu / %llu", name,
          (unsigned long long)sa.collisions, (unsigned long long)sb.collisions,
          (unsigned long long)sa.wall_collisions, (unsigned long long)sb.wall_collisions);
    CHECK(sa.wall_collisions > 0 && sa.wall_pushes > 0, "%s: no wall events", name);
    /* the exact pair rule acts where drifts differ (couplings per species, obstacles) */
    CHECK(p.nspecies ? sa.pair_corrections > 0 : sa.pair_corrections == 0, "%s: %llu pair pushes",
          name, (unsigned long long)sa.pair_corrections);
    CHECK(sb.group_reruns >= min_reruns, "%s: %llu re-runs", name,
          (unsigned long long)sb.group_reruns);
    const size_t ns = va.nspecies;
    double wa[6 * 4], wb[6 * 4];
    hsbd_spheres_wall_impulses(a, wa);
    hsbd_spheres_wall_impulses(b, wb);
    for (size_t k = 0; k < 6 * ns; ++k) /* exact sums: bit for bit in any event order */
        CHECK(wa[k] == wb[k], "%s: wall impulse %zu: %.17g vs %.17g", name, k, wa[k], wb[k]);
    CHECK(sa.virial == sb.virial && sa.shell_updates == sb.shell_updates,
          "%s: virial %.17g / %.17g, shell updates %llu / %llu", name, sa.virial, sb.virial,
          (unsigned long long)sa.shell_updates, (unsigned long long)sb.shell_updates);
    printf("%s: %llu collisions, %llu wall collisions, %llu bridge pushes, %llu pair pushes, "
           "%llu re-runs, min gap %.3g\n",
           name, (unsigned long long)sa.collisions, (unsigned long long)sa.wall_collisions,
           (unsigned long long)sa.wall_pushes, (unsigned long long)sa.pair_corrections,
           (unsigned long long)sb.group_reruns, worst);
    CHECK(worst >= -1e-9, "%s: overlap %g", name, worst);
    hsbd_spheres_free(a);
    hsbd_spheres_free(b);
}

static void test_event_orders_with_walls(void) {
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(-3.0));
    const double side = 8.0, height = 600 * PI / 6 / 0.45 / (side * side);
    hsbd_spheres_params p = {.n = 600,
                             .dimension = 3,
                             .box = {side, side, height},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 2e-3,
                             .seed = 11,
                             .hard_core = 1,
                             .walls = {0, 0, 1},
                             .field = &gravity,
                             .field_axis = 2};
    compare_with_walls("3D phi 0.45, walls on z, gravity", p, 200, 5, HSBD_EVENTS_GROUPS);
    p.groups_min_n = 1; /* AUTO: steps given up part-way go to the global calendar */
    compare_with_walls("3D phi 0.45, walls on z, gravity (auto)", p, 200, 1, HSBD_EVENTS_AUTO);
    p.groups_min_n = 0;
    hsbd_spheres_params d = p;
    d.n = 500, d.dimension = 2, d.walls[0] = d.walls[1] = 1, d.walls[2] = 0;
    d.box[0] = d.box[1] = sqrt(500 * PI / 4 / 0.6), d.field_axis = 1, d.seed = 12;
    compare_with_walls("2D phi 0.6, walls on x and y, gravity along y", d, 200, 5,
                       HSBD_EVENTS_GROUPS);
    static int species[600];
    for (int i = 0; i < 600; ++i)
        species[i] = i % 3 == 0 ? 1 : i % 50 == 7 ? 2 : 0;
    static const double sig[3] = {1.0, 1.4, 1.2}, dif[3] = {1.0, 1.0 / 1.4, 0.0};
    static const double coupling[3] = {1.0, 2.744, 0.0};
    hsbd_spheres_params m = p;
    m.nspecies = 3, m.species = species, m.species_sigma = sig, m.species_diffusion = dif;
    m.species_coupling = coupling, m.sigma = 0, m.seed = 13;
    m.box[2] = 600 * PI / 6 * (2.0 + 1.4 * 1.4 * 1.4) / 3 / 0.35 / (side * side);
    compare_with_walls("3D mixture phi 0.35 with obstacles, walls on z", m, 200, 1,
                       HSBD_EVENTS_GROUPS);
}

/* g(r) between walls: refused with walls on two axes (its reference would need the density
 * over a plane); on one axis the profile-weighted reference makes g = 1 for independent
 * particles from any profile. Here 200 particles per sample, uniform across a 6 x 6 area,
 * exponential in z (decay length 3, cut at the walls), 5000 independent samples (xorshift64*,
 * seed 5), 20 blocks: chi^2 of the 50 bins within 50 + 4 sqrt(100), every bin within 4.5
 * error bars, over the whole slab and for pairs in the window [4, 8); and along a periodic z
 * (no walls) with the density exp(-2 cos(2 pi z / 12)) of a cosine field (rejection
 * sampling), minimum images in z. */
static double uniform01(uint64_t *state) { /* xorshift64*: [0, 1) */
    *state ^= *state >> 12, *state ^= *state << 25, *state ^= *state >> 27;
    return (double)((*state * 0x2545F4914F6CDD1Dull) >> 11) * 0x1.0p-53;
}

static void test_gr_between_walls(void) {
    hsbd_spheres_params p = {.n = 10,
                             .dimension = 3,
                             .box = {8, 8, 8},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 1,
                             .hard_core = 1,
                             .walls = {0, 1, 1}};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s && hsbd_spheres_init_random(s, &err) == HSBD_OK, "init: %s", err.message);
    if (!s) return;
    hsbd_spheres_view v = hsbd_spheres_get_view(s);
    CHECK(hsbd_gr_alloc(&v, 2, 0.1, 0.1, 4, 100, &err) == NULL && err.status == HSBD_EINPUT,
          "g(r) between walls on two axes");
    hsbd_spheres_free(s);
    enum { N = 200, SAMPLES = 5000 };
    static double x[3 * N], sigma[N], dif[N];
    static int64_t image[3 * N];
    static int species[N];
    for (size_t i = 0; i < N; ++i)
        sigma[i] = dif[i] = 1;
    v = (hsbd_spheres_view){.n = N,
                            .dimension = 3,
                            .box = {6, 6, 12},
                            .walls = {0, 0, 1},
                            .x = x,
                            .image = image,
                            .sigma = sigma,
                            .diffusion = dif,
                            .species = species,
                            .nspecies = 1,
                            .kT = 1,
                            .dt = 1};
    for (int variant = 0; variant < 3; ++variant) {
        const int windowed = variant == 1, periodic = variant == 2;
        v.walls[2] = !periodic;
        hsbd_gr *g = hsbd_gr_alloc_profile(&v, 2, 2.5, 0.05, 0.1, 20, SAMPLES, &err);
        CHECK(g && (!windowed || hsbd_gr_set_window(g, 4, 8, &err) == HSBD_OK), "g(r): %s",
              err.message);
        if (!g) return;
        CHECK(hsbd_gr_profile_axis(g) == 2, "a profile along z");
        uint64_t rng = 5;
        int sampled = 1;
        for (int k = 0; k < SAMPLES; ++k) {
            for (size_t i = 0; i < N; ++i) {
                double z;
                if (periodic) do
                        z = 12 * uniform01(&rng);
                    while (uniform01(&rng) > exp(-2 * cos(2 * PI * z / 12) - 2));
                else
                    do
                        z = 0.5 - 3 * log(1 - uniform01(&rng));
                    while (z > 11.5);
                x[3 * i] = 6 * uniform01(&rng), x[3 * i + 1] = 6 * uniform01(&rng),
                      x[3 * i + 2] = z;
            }
            sampled &= hsbd_gr_sample(g, &v) == HSBD_OK;
        }
        CHECK(sampled, "sample");
        CHECK(hsbd_gr_set_window(g, 4, 8, &err) == HSBD_EINPUT, "window after sampling");
        double r[64], gr[64], ge[64], chi2 = 0, worst = 0;
        const size_t nb = hsbd_gr_bins(g);
        hsbd_gr_result(g, 0, r, gr, ge);
        for (size_t k = 0; k < nb; ++k) {
            const double d = (gr[k] - 1) / ge[k];
            chi2 += d * d, worst = fmax(worst, fabs(d));
        }
        printf("g(r) of independent particles %s: chi^2 %.1f over %zu bins, largest "
               "deviation %.2f error bars\n",
               periodic   ? "in a periodic cosine profile"
               : windowed ? "in a slab, window [4, 8)"
                          : "in a slab",
               chi2, nb, worst);
        CHECK(nb == 50 && chi2 < 90 && worst < 4.5, "g(r) of independent particles is not 1");
        hsbd_gr_free(g);
    }
}

int main(void) {
    test_gr_between_walls();
    test_exact_wall_step();
    test_event_orders_with_walls();
    return test_finish("test_spheres_walls");
}
