/* Dynamics of Brownian hard spheres per species against the exact short-time law
 * (docs/theory.md, "Brownian hard spheres: mixture dynamics"), fixed seeds:
 *   MSD_a(t) = 2 d D_a t - c_a t^(3/2) + O(t^2),
 * c_a from the contact densities rho_b g_ab(sigma_ab+) of the equation of state (KLM for
 * one size, BMCSL for the binary) and the share D_a / (D_a + D_b) that the collision rule
 * of masses 1/D gives particle a. Each case equilibrates at dt 1e-3 from a lattice, then
 * steps at the small dt and records, at every step, the squared displacements over lags of
 * 1 .. LAGS steps. The run is cut into BLOCKS time blocks; in each block the deficit
 * y(t) = (2 d D_a t - MSD_a(t)) / t^(3/2) is fitted by c + e t^(1/2) over the lags,
 * weighted by t (the variance of y falls as 1/t; the e term takes up the next order), and
 * c's error is the scatter of the blocks' fits over sqrt(BLOCKS) (the lags of one block are
 * correlated, the blocks nearly not). Checks:
 *   - one size, phi 0.3, dt 1e-4 (lags 1e-4 .. 1e-3): c within 3 error bars of
 *     64 phi g D^(3/2) / (sqrt(2 pi) sigma);
 *   - binary, sizes 1 / 1.4, D 1 / 0.25 (D_A/D_B = 4), phi 0.3, dt 1e-4: each species' c
 *     within 3 error bars, and the rule of equal shares (s = 1/2, equal masses), whose
 *     prediction for the slow species has the opposite sign, more than 10 error bars away;
 *   - the same binary at dt 1e-5 (lags 1e-5 .. 1e-4), the same checks: the law holds at
 *     every dt, down to a lag of one step (the mirror rule of a straight path is the exact
 *     reflected propagator at a flat contact).
 * And the long-time D_L per species at low density against the first order in density,
 * D_L,a / D_a = 1 - sum_b rho_b v_d sigma_ab^d D_a / ((d - 1)(D_a + D_b)): a three-species
 * mixture of equal spheres, D 1 / 0.25 / 0 (immobile obstacles), packing fractions 0.024 /
 * 0.018 / 0.018, N 1000, dt 1e-3, 40 time units after 1, the run's estimator (the MSD slope
 * between the largest lag, 2 = one of 20 error blocks, and a tenth of it): each mobile
 * species within 3 error bars of the first order in density evaluated at those lags
 * (hsbd_hs_msd_slope_ratio: the two-body problem at all times; the slow species is still
 * in its transient there, 0.905 against the long-time 0.873). The O(phi^2) terms, about
 * 0.5 % at the obstacles' excluded fraction 0.14, are below the 0.6-0.8 % error bars; the
 * obstacles' share 1 (a D = 0 partner is a wall) puts the fast species 9 error bars below
 * equal D's 1 - 2 phi. 10 times longer under HSBD_VALIDATE=long.
 * Measured values in docs/validation.md section 19. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/observe.h"
#include "hsbd/spheres.h"
#include "hsbd/theory.h"

static const double PI = 3.14159265358979323846;
enum { BLOCKS = 20, LAGS = 10, NS = 2 };

typedef struct fit {
    double c[NS], c_err[NS], e[NS];
} fit;

/* Weighted least squares of y_k = c + e u_k over the lags; returns c (and e). The
 * weights u_k^2 = t_k follow the variance of y, which falls as 1/t. */
static double line_fit(const double *u, const double *y, int n, double *slope) {
    double sw = 0, su = 0, sy = 0, suu = 0, suy = 0;
    for (int k = 0; k < n; ++k) {
        const double w = u[k] * u[k];
        sw += w, su += w * u[k], sy += w * y[k], suu += w * u[k] * u[k], suy += w * u[k] * y[k];
    }
    const double den = sw * suu - su * su;
    *slope = (sw * suy - su * sy) / den;
    return (sy - *slope * su) / sw;
}

/* Runs p (equilibrated at dt 1e-3 for t_equil, then `steps` steps of p->dt in BLOCKS
 * blocks) and fits each species' deficit. */
static fit measure(const hsbd_spheres_params *p, double t_equil, long steps) {
    fit out;
    memset(&out, 0, sizeof out);
    hsbd_error err;
    hsbd_spheres_params q = *p;
    q.dt = 1e-3;
    hsbd_spheres *s = hsbd_spheres_alloc(&q, &err);
    CHECK(s && hsbd_spheres_init_lattice(s, &err) == HSBD_OK, "init: %s", err.message);
    if (!s) return out;
    int ok = 1;
    for (long k = 0; ok && k < lround(t_equil / q.dt); ++k)
        ok = hsbd_spheres_step(s) == HSBD_OK;
    hsbd_spheres_set_dt(s, p->dt);
    const size_t n = p->n, d = (size_t)p->dimension;
    double *hist = malloc((LAGS + 1) * 3 * n * sizeof *hist); /* ring of unwrapped positions */
    CHECK(hist != NULL, "out of memory");
    if (!hist) return hsbd_spheres_free(s), out;
    static double sum[BLOCKS][NS][LAGS];
    static double count[BLOCKS][NS];
    memset(sum, 0, sizeof sum), memset(count, 0, sizeof count);
    const long per_block = steps / BLOCKS;
    for (long k = -LAGS; ok && k < per_block * BLOCKS; ++k) {
        ok = hsbd_spheres_step(s) == HSBD_OK;
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        const long slot = (k + LAGS) % (LAGS + 1);
        double *now = hist + (size_t)slot * 3 * n;
        for (size_t i = 0; i < 3 * n; ++i)
            now[i] = v.x[i] + (double)v.image[i] * v.box[i % 3];
        if (k < 0) continue;
        const long b = k / per_block;
        for (size_t i = 0; i < n; ++i) {
            const int sp = v.species[i];
            count[b][sp] += 1;
            for (int l = 1; l <= LAGS; ++l) {
                const double *then = hist + (size_t)((slot + LAGS + 1 - l) % (LAGS + 1)) * 3 * n;
                double r2 = 0;
                for (size_t a = 0; a < d; ++a)
                    r2 += (now[3 * i + a] - then[3 * i + a]) * (now[3 * i + a] - then[3 * i + a]);
                sum[b][sp][l - 1] += r2;
            }
        }
    }
    CHECK(ok, "a step failed");
    int finite;
    CHECK(hsbd_spheres_min_gap(s, &finite) >= -1e-9 && finite, "overlap or NaN");
    for (size_t a = 0; a < (p->nspecies ? p->nspecies : 1); ++a) {
        double da = p->nspecies ? p->species_diffusion[a] : p->diffusion, m = 0, m2 = 0, me = 0;
        for (int b = 0; b < BLOCKS; ++b) {
            double u[LAGS], y[LAGS], slope;
            for (int l = 1; l <= LAGS; ++l) {
                const double t = l * p->dt, msd = sum[b][a][l - 1] / count[b][a];
                u[l - 1] = sqrt(t);
                y[l - 1] = (2 * (double)d * da * t - msd) / pow(t, 1.5);
            }
            const double c = line_fit(u, y, LAGS, &slope);
            m += c / BLOCKS, m2 += c * c / BLOCKS, me += slope / BLOCKS;
        }
        out.c[a] = m, out.e[a] = me;
        out.c_err[a] = sqrt(fmax(0, m2 - m * m) / (BLOCKS - 1));
    }
    free(hist);
    hsbd_spheres_free(s);
    return out;
}

static void check_c(const char *what, double c, double err, double theory, double tol) {
    printf("  %-44s %9.4f +- %.4f   theory %9.4f   (%+.2f error bars)\n", what, c, err, theory,
           (c - theory) / err);
    CHECK(err > 0 && fabs(c - theory) <= tol * err, "%s: %g +- %g vs %g", what, c, err, theory);
}

static void test_one_species(void) {
    const size_t n = 1000;
    const double phi = 0.3, side = cbrt((double)n * PI / 6 / phi);
    const hsbd_spheres_params p = {.n = n,
                                   .dimension = 3,
                                   .box = {side, side, side},
                                   .sigma = 1,
                                   .diffusion = 1,
                                   .kT = 1,
                                   .dt = 1e-4,
                                   .seed = 51,
                                   .hard_core = 1};
    const fit f = measure(&p, 2.0, 10000);
    const double g = hsbd_hs_contact_klm(phi), rho = n / (side * side * side), sig = 1, dif = 1;
    const hsbd_hs_mixture mix = {3, 1, &rho, &sig, &dif, &g};
    printf("one size, phi 0.3, N 1000, dt 1e-4, lags 1e-4 .. 1e-3, seed 51 (next order e = "
           "%.1f):\n",
           f.e[0]);
    check_c("c = (6 D t - MSD) / t^1.5 at t -> 0", f.c[0], f.c_err[0],
            hsbd_hs_msd_deficit(&mix, 0, -1), 3);
}

static void test_binary(double dt, long steps, unsigned seed) {
    enum { N = 1000 };
    static int species[N];
    const double sig[NS] = {1.0, 1.4}, dif[NS] = {1.0, 0.25}, phi = 0.3, x[NS] = {0.5, 0.5};
    for (int i = 0; i < N; ++i)
        species[i] = i >= N / 2;
    const double vol = N / 2 * PI / 6 * (1 + 1.4 * 1.4 * 1.4) / phi, side = cbrt(vol);
    const hsbd_spheres_params p = {.n = N,
                                   .dimension = 3,
                                   .box = {side, side, side},
                                   .kT = 1,
                                   .dt = dt,
                                   .seed = seed,
                                   .hard_core = 1,
                                   .nspecies = NS,
                                   .species = species,
                                   .species_sigma = sig,
                                   .species_diffusion = dif};
    const fit f = measure(&p, 2.0, steps);
    const double rho = N / vol, dens[NS] = {x[0] * rho, x[1] * rho};
    double g[NS * NS];
    for (size_t a = 0; a < NS; ++a)
        for (size_t b = 0; b < NS; ++b)
            g[a * NS + b] = hsbd_hs_contact_bmcsl(NS, x, sig, rho, a, b);
    const hsbd_hs_mixture mix = {3, NS, dens, sig, dif, g};
    printf("binary, sigma 1 / 1.4, D 1 / 0.25, phi 0.3, N 1000, dt %g, lags %g .. %g, seed %u "
           "(next order e = %.1f, %.1f):\n",
           dt, dt, LAGS * dt, seed, f.e[0], f.e[1]);
    static const char *const name[NS] = {"c_A (fast)", "c_B (slow)"};
    for (size_t a = 0; a < NS; ++a) {
        check_c(name[a], f.c[a], f.c_err[a], hsbd_hs_msd_deficit(&mix, a, -1), 3);
        const double equal = hsbd_hs_msd_deficit(&mix, a, 0.5);
        printf("  %-44s %9.4f: %+.1f error bars\n", "  equal shares (masses) would give", equal,
               (f.c[a] - equal) / f.c_err[a]);
        if (a == 1)
            CHECK(fabs(f.c[a] - equal) > 10 * f.c_err[a], "equal shares not excluded: %g vs %g",
                  f.c[a], equal);
    }
}

/* the sampled time: 10 times longer under HSBD_VALIDATE=long */
static double sampled_time(double t) {
    const char *v = getenv("HSBD_VALIDATE");
    return v && !strcmp(v, "long") ? 10 * t : t;
}

static void test_long_time(void) {
    enum { N = 1000, K = 3, EVERY = 10 };
    static int species[N];
    static double unwrapped[3 * N];
    static size_t members[3 * N];
    const double sig[K] = {1, 1, 1}, dif[K] = {1, 0.25, 0}, frac[K] = {0.4, 0.3, 0.3};
    const double phi = 0.06, vol = N * PI / 6 / phi, side = cbrt(vol), dt = 1e-3;
    for (int i = 0; i < N; ++i)
        species[i] = i < 400 ? 0 : i < 700 ? 1 : 2;
    const hsbd_spheres_params p = {.n = N,
                                   .dimension = 3,
                                   .box = {side, side, side},
                                   .kT = 1,
                                   .dt = dt,
                                   .seed = 1,
                                   .hard_core = 1,
                                   .nspecies = K,
                                   .species = species,
                                   .species_sigma = sig,
                                   .species_diffusion = dif};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s && hsbd_spheres_init_random(s, &err) == HSBD_OK, "init: %s", err.message);
    if (!s) return;
    const double t_total = sampled_time(40), max_lag = t_total / BLOCKS;
    const uint64_t samples = (uint64_t)llround(t_total / dt) / EVERY;
    hsbd_msd *msd[2];
    for (int a = 0; a < 2; ++a) {
        size_t c = 0;
        for (size_t i = 0; i < N; ++i)
            for (size_t x = 0; x < 3 && species[i] == a; ++x)
                members[c++] = 3 * i + x;
        msd[a] = hsbd_msd_alloc(3 * N, EVERY * dt, samples, max_lag, 10, BLOCKS, &err);
        CHECK(msd[a] && hsbd_msd_set_members(msd[a], c, members, &err) == HSBD_OK, "msd: %s",
              err.message);
    }
    int ok = 1;
    for (long k = 0; ok && k < lround(1.0 / dt); ++k)
        ok = hsbd_spheres_step(s) == HSBD_OK;
    for (uint64_t k = 0; ok && k < samples * EVERY; ++k) {
        ok = hsbd_spheres_step(s) == HSBD_OK;
        if ((k + 1) % EVERY) continue;
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        for (size_t i = 0; i < 3 * N; ++i)
            unwrapped[i] = v.x[i] + (double)v.image[i] * v.box[i % 3];
        for (int a = 0; a < 2; ++a)
            hsbd_msd_sample_values(msd[a], unwrapped);
    }
    CHECK(ok, "a step failed");
    double dens[K];
    for (int a = 0; a < K; ++a)
        dens[a] = frac[a] * N / vol;
    const hsbd_hs_mixture mix = {3, K, dens, sig, dif, NULL};
    printf("D_L, spheres D 1 / 0.25 / 0 (obstacles), phi 0.024 / 0.018 / 0.018, N 1000, dt 1e-3, "
           "%g time units, lags %g / %g, seed %u:\n",
           t_total, max_lag / 10, max_lag, (unsigned)p.seed);
    static const char *const name[2] = {"D_A slope / D_A (D 1)", "D_B slope / D_B (D 0.25)"};
    for (int a = 0; a < 2; ++a) {
        double dl, e, t0, t1;
        hsbd_msd_long_time_diffusion(msd[a], 3, &dl, &e);
        hsbd_msd_long_time_lags(msd[a], &t0, &t1);
        const double slope = hsbd_hs_msd_slope_ratio(&mix, (size_t)a, t0, t1);
        const double limit = hsbd_hs_long_time_ratio(&mix, (size_t)a);
        check_c(name[a], dl / dif[a], e / dif[a], slope, 3);
        printf("  %-44s %9.4f: %+.1f error bars\n", "  the long-time limit D_L,a / D_a", limit,
               (dl / dif[a] - limit) / (e / dif[a]));
        printf("  %-44s %9.4f: %+.1f error bars\n", "  1 - 2 phi (equal D) would give", 1 - 2 * phi,
               (dl / dif[a] - (1 - 2 * phi)) / (e / dif[a]));
        hsbd_msd_free(msd[a]);
    }
    hsbd_spheres_free(s);
}

int main(void) {
    test_one_species();
    test_binary(1e-4, 20000, 71);
    test_binary(1e-5, 20000, 61);
    test_long_time();
    return test_finish("test_mixture_dynamics");
}
