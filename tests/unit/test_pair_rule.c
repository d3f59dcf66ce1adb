/* The pair rule of the EDBD engine (run.pair_rule; docs/spheres.md, "Pair collisions under a
 * relative drift"), deterministic checks:
 * - The exact gap (src/spheres/reflect.c): the quantile map from the mirror's law of the end
 *   gap to Eq. 9's, against the two laws in closed form (below).
 * - Where no two drifts can differ (one species in gravity between walls; a mixture with
 *   obstacles and no field; a common drift), the exact rule and the mirror rule give the
 *   same bits: positions, image counters, collisions, virial, and no pair push.
 * - Where they differ (a mixture in a cosine field with per-species couplings and immobile
 *   obstacles, 3D and 2D, strong enough that pairs are pushed every step): the exact rule
 *   pushes pairs, the mirror rule none; no overlap (brute force over all pairs, every fifth
 *   step); the same bits sorted in space or not (three sorts), on 1, 2 and 4 threads, with
 *   the global
 *   calendar, group by group and auto (the pushes summed per particle in the order of the
 *   partners' user labels, before any event).
 * - pair_rule outside {0, 1} is refused. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "sphere_checks.h"
#include "hsbd/field.h"
#include "hsbd/spheres.h"
#include "spheres/reflect.h"

static const double PI = 3.14159265358979323846;

/* Steps every engine of s[0 .. count) `steps` times from the same initial state (a lattice
 * for one species, random insertion for mixtures); with `gaps`, the smallest gap of the
 * first after every fifth step. */
static void run_all(hsbd_spheres **s, int count, int steps, double *gaps) {
    hsbd_error err;
    for (int k = 0; k < count; ++k)
        CHECK(s[k] && (hsbd_spheres_get_params(s[k])->nspecies
                           ? hsbd_spheres_init_random(s[k], &err)
                           : hsbd_spheres_init_lattice(s[k], &err)) == HSBD_OK,
              "init: %s", err.message);
    double worst = INFINITY;
    for (int q = 0; q < steps; ++q) {
        for (int k = 0; k < count; ++k)
            if (s[k]) CHECK(hsbd_spheres_step(s[k]) == HSBD_OK, "step");
        if (gaps && s[0] && q % 5 == 4) {
            const hsbd_spheres_view v = hsbd_spheres_get_view(s[0]);
            worst = fmin(worst, brute_min_gap(&v));
        }
    }
    if (gaps) *gaps = worst;
}

/* Whether two engines hold the same bits: positions, images, collisions, virial, pushes. */
static int same_bits(const hsbd_spheres *a, const hsbd_spheres *b) {
    const hsbd_spheres_view va = hsbd_spheres_get_view(a), vb = hsbd_spheres_get_view(b);
    const hsbd_spheres_stats sa = hsbd_spheres_get_stats(a), sb = hsbd_spheres_get_stats(b);
    return !memcmp(va.x, vb.x, 3 * va.n * sizeof *va.x) &&
           !memcmp(va.image, vb.image, 3 * va.n * sizeof *va.image) &&
           sa.collisions == sb.collisions && sa.pair_corrections == sb.pair_corrections &&
           sa.wall_pushes == sb.wall_pushes && !memcmp(&sa.virial, &sb.virial, sizeof sa.virial);
}

/* The exact and the mirror rule on p: the same bits and no push when `same`, else pushes
 * under the exact rule only. */
static void compare_rules(const char *name, hsbd_spheres_params p, int steps, int same) {
    hsbd_error err;
    hsbd_spheres *s[2];
    p.pair_rule = HSBD_PAIR_EXACT;
    s[0] = hsbd_spheres_alloc(&p, &err);
    p.pair_rule = HSBD_PAIR_MIRROR;
    s[1] = hsbd_spheres_alloc(&p, &err);
    CHECK(s[0] && s[1], "%s: alloc: %s", name, err.message);
    double gap;
    run_all(s, 2, steps, &gap);
    if (!s[0] || !s[1]) return;
    const hsbd_spheres_stats se = hsbd_spheres_get_stats(s[0]), sm = hsbd_spheres_get_stats(s[1]);
    printf("%s: exact %llu pushes, %llu collisions; mirror %llu collisions; min gap %.3g\n", name,
           (unsigned long long)se.pair_corrections, (unsigned long long)se.collisions,
           (unsigned long long)sm.collisions, gap);
    if (same)
        CHECK(same_bits(s[0], s[1]) && se.pair_corrections == 0 && se.collisions > 0,
              "%s: the rules differ without relative drift", name);
    else
        CHECK(se.pair_corrections > 0 && sm.pair_corrections == 0 && !same_bits(s[0], s[1]),
              "%s: pushes %llu (exact), %llu (mirror)", name,
              (unsigned long long)se.pair_corrections, (unsigned long long)sm.pair_corrections);
    CHECK(gap >= -1e-9, "%s: overlap %g", name, gap);
    hsbd_spheres_free(s[0]);
    hsbd_spheres_free(s[1]);
}

/* One field parameter changed at a time against the reference run: the same bits. */
typedef enum { VARY_SORT, VARY_THREADS, VARY_EVENTS } vary;

static void compare_variants(const char *name, hsbd_spheres_params p, int steps, vary what) {
    hsbd_error err;
    hsbd_spheres *s[3] = {0};
    static const int threads[3] = {1, 2, 4};
    static const hsbd_spheres_event_order orders[3] = {HSBD_EVENTS_GLOBAL, HSBD_EVENTS_GROUPS,
                                                       HSBD_EVENTS_AUTO};
    const int count = what == VARY_SORT ? 2 : 3;
    for (int k = 0; k < count; ++k) {
        hsbd_spheres_params q = p;
        if (what == VARY_SORT) q.keep_order = k == 0;
        if (what == VARY_THREADS) q.threads = threads[k];
        if (what == VARY_EVENTS) q.event_order = orders[k], q.groups_min_n = 1;
        s[k] = hsbd_spheres_alloc(&q, &err);
        CHECK(s[k] != NULL, "%s: alloc: %s", name, err.message);
    }
    run_all(s, count, steps, NULL);
    for (int k = 1; k < count; ++k)
        if (s[0] && s[k]) CHECK(same_bits(s[0], s[k]), "%s: variant %d differs", name, k);
    const uint64_t pushes = s[0] ? hsbd_spheres_get_stats(s[0]).pair_corrections : 0;
    CHECK(pushes > 0, "%s: no pair pushes", name);
    printf("%s: %d variants, %llu pair pushes: identical\n", name, count,
           (unsigned long long)pushes);
    for (int k = 0; k < count; ++k)
        hsbd_spheres_free(s[k]);
}

/* The laws of the end gap from x0 over dt (relative diffusion d, relative normal drift c):
 * the mirror rule's |Y| and Eq. 9's reflected one (docs/theory.md). */
static double cdf(double z) {
    return 0.5 * erfc(-z / sqrt(2.0));
}
static double law_mirror(double x, double x0, double c, double d, double dt) {
    const double s = sqrt(2 * d * dt), mu = x0 + c * dt;
    return cdf((x - mu) / s) - cdf((-x - mu) / s);
}
static double law_exact(double x, double x0, double c, double d, double dt) {
    const double s = sqrt(2 * d * dt), mu = x0 + c * dt;
    return cdf((x - mu) / s) - exp(c * x / d) * cdf((-x - mu) / s);
}

/* sph_exact_gap maps the mirror's gap y to the gap of Eq. 9's law at the same quantile:
 * F_exact(X) = F_mirror(y) to 1e-9 over a grid of gaps, drifts (pressing and separating,
 * Peclet numbers of a step from 0.003 to 20) and steps; X grows with y; c = 0 gives y to
 * the bit, and Scala's example (D 1, c -1, x0 1, dt 1) maps the mirror's mean 1.1284 to a
 * mean of 0.8504 (the average of X over the law of |Y|, by quadrature). */
static void test_exact_gap(void) {
    static const double drifts[] = {-20, -5, -1, -0.1, 0.1, 1, 5, 20};
    static const double steps[] = {1e-3, 1e-2, 1};
    double worst = 0;
    int monotone = 1, same = 1;
    for (size_t q = 0; q < sizeof steps / sizeof steps[0]; ++q) {
        const double dt = steps[q], d = 1.5, s = sqrt(2 * d * dt);
        for (size_t k = 0; k < sizeof drifts / sizeof drifts[0]; ++k)
            for (int m = 0; m < 6; ++m) {
                const double c = drifts[k], x0 = m * 0.7 * s;
                double last = -1;
                for (int e = 0; e <= 40; ++e) {
                    const double y = e * 0.2 * s, x = sph_exact_gap(y, x0, c, d, dt);
                    worst =
                        fmax(worst, fabs(law_exact(x, x0, c, d, dt) - law_mirror(y, x0, c, d, dt)));
                    monotone &= x >= last;
                    last = x;
                    same &= sph_exact_gap(y, x0, 0.0, d, dt) == y;
                }
            }
    }
    printf("exact gap: largest |F_exact(X) - F_mirror(y)| %.2g\n", worst);
    CHECK(worst < 1e-9, "the exact gap misses its quantile by %g", worst);
    CHECK(monotone, "the exact gap does not grow with the mirror's");
    CHECK(same, "c = 0 changes the gap");
    /* Scala's example: E[X] = integral of X(y) over the density of |Y| (midpoints) */
    double mean = 0, mirror = 0;
    const double h = 1e-4;
    for (double y = 0.5 * h; y < 12; y += h) {
        const double p =
            (law_mirror(y + 0.5 * h, 1, -1, 1, 1) - law_mirror(y - 0.5 * h, 1, -1, 1, 1));
        mean += sph_exact_gap(y, 1, -1, 1, 1) * p;
        mirror += y * p;
    }
    printf("exact gap: Scala's example, mean %.4f (Eq. 9 0.8504) from the mirror's %.4f\n", mean,
           mirror);
    CHECK(fabs(mean - 0.8504) < 1e-4 && fabs(mirror - 1.1284) < 1e-4, "means %g, %g", mean, mirror);
}

int main(void) {
    test_exact_gap();
    /* ---- no relative drift: both rules give the same bits ---- */
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(-2.0));
    const double side = 8.0;
    hsbd_spheres_params g = {.n = 400,
                             .dimension = 3,
                             .box = {side, side, 400 * PI / 6 / 0.35 / (side * side)},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 2e-3,
                             .seed = 41,
                             .hard_core = 1,
                             .walls = {0, 0, 1},
                             .field = &gravity,
                             .field_axis = 2};
    compare_rules("one species in gravity between walls", g, 150, 1);
    static int species[4000];
    for (int i = 0; i < 4000; ++i)
        species[i] = i % 7 == 3 ? 2 : i % 2;
    static const double sig[3] = {1.0, 1.3, 1.1}, dif[3] = {1.0, 0.6, 0.0};
    static const double coupling[3] = {1.0, 3.0, 0.0};
    hsbd_spheres_params m = {.n = 800,
                             .dimension = 3,
                             .box = {13, 13, 13}, /* phi 0.3 */
                             .kT = 1,
                             .dt = 2e-3,
                             .seed = 42,
                             .hard_core = 1,
                             .nspecies = 3,
                             .species = species,
                             .species_sigma = sig,
                             .species_diffusion = dif};
    compare_rules("a mixture with obstacles, no field", m, 150, 1);
    static const double mobile_d[3] = {1.0, 0.6, 0.8};
    hsbd_spheres_params c = m;
    c.species_diffusion = mobile_d, c.drift[0] = 2, c.drift[2] = -1, c.seed = 43;
    compare_rules("a mixture with a common drift", c, 150, 1);

    /* ---- relative drifts: a cosine field with per-species couplings, obstacles ---- */
    hsbd_field cosine = {0};
    hsbd_field_add(&cosine, hsbd_field_cosine(6.0, 13.0 / 3)); /* forces up to 4 kT / sigma */
    hsbd_spheres_params f = m;
    f.field = &cosine, f.field_axis = 2, f.species_coupling = coupling, f.seed = 44;
    compare_rules("3D mixture in a cosine field, couplings 1 / 3 / 0", f, 150, 0);
    hsbd_spheres_params d = f;
    d.dimension = 2, d.n = 2000, d.box[0] = 52, d.box[1] = 91, d.field_axis = 0, d.seed = 45;
    compare_rules("2D mixture in a cosine field, phi 0.45", d, 100, 0);
    compare_variants("3D mixture in a field, sorted in space or not", f, 160, VARY_SORT);
    hsbd_spheres_params big = f; /* above the threads' minimum N: every loop split */
    big.n = 4000, big.box[0] = big.box[1] = big.box[2] = cbrt(4000 / 800.0) * 13;
    compare_variants("3D mixture in a field, 1, 2 and 4 threads", big, 40, VARY_THREADS);
    big.threads = 2;
    compare_variants("3D mixture in a field, global calendar, groups, auto", big, 40, VARY_EVENTS);

    /* ---- bad parameters ---- */
    hsbd_spheres_params bad = m;
    bad.pair_rule = 2;
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&bad, &err);
    CHECK(!s && err.status == HSBD_EINPUT && strstr(err.message, "pair_rule = 2"),
          "pair_rule 2: %s", err.message);
    hsbd_spheres_free(s);
    return test_finish("test_pair_rule");
}
