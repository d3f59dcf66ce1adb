/* Percus functional and closed forms: limits that are known exactly. */
#include <math.h>
#include <stdlib.h>

#include "../test_util.h"
#include "hsbd/rng.h"
#include "hsbd/theory.h"

static hsbd_percus_result solve(double sigma, double rho, double u0, double gamma, size_t m) {
    hsbd_percus_params p = {.sigma = sigma,
                            .rho_mean = rho,
                            .amplitude = u0,
                            .wavelength = 1,
                            .gamma = gamma,
                            .points = m};
    hsbd_percus_result r;
    hsbd_error err;
    const int rc = hsbd_percus_solve(&p, &r, &err);
    CHECK(rc == HSBD_OK, "solve(sigma %g, rho %g, U0 %g, gamma %g): %s", sigma, rho, u0, gamma,
          rc ? err.message : "");
    return r;
}

static void test_uniform_is_tonks(void) {
    const double cases[][2] = {{0.5, 0.2}, {0.5, 0.8}, {0.9, 1.0}, {0.1, 5.0}};
    for (int k = 0; k < 4; ++k) {
        const double s = cases[k][0], rho = cases[k][1];
        hsbd_percus_result r = solve(s, rho, 0.0, 0.0, 200);
        CHECK_CLOSE(r.beta_mu, hsbd_tonks_beta_mu(rho, s), 1e-9);
        for (size_t j = 0; j < r.m; j += 37) {
            CHECK_CLOSE(r.rho[j], rho, 1e-12);
            CHECK_CLOSE(r.rho2[j], hsbd_tonks_contact(rho, s), 1e-9);
        }
        hsbd_percus_result_free(&r);
    }
}

static void test_point_particles_are_boltzmann(void) {
    const double pi = 3.141592653589793;
    hsbd_percus_result r = solve(0.0, 0.5, 6.0, 0.0, 400);
    double z = 0;
    for (size_t j = 0; j < r.m; ++j)
        z += exp(-3.0 * cos(2 * pi * r.x[j])) / (double)r.m;
    double worst = 0;
    for (size_t j = 0; j < r.m; ++j)
        worst = fmax(worst, fabs(r.rho[j] - 0.5 * exp(-3.0 * cos(2 * pi * r.x[j])) / z));
    CHECK(worst < 1e-12, "sigma = 0 differs from Boltzmann by %.3g", worst);
    hsbd_percus_result_free(&r);
    /* and continuously: sigma = 1e-4 differs at O(sigma) */
    r = solve(1e-4, 0.5, 6.0, 0.0, 400);
    worst = 0;
    for (size_t j = 0; j < r.m; ++j)
        worst = fmax(worst, fabs(r.rho[j] - 0.5 * exp(-3.0 * cos(2 * pi * r.x[j])) / z));
    CHECK(worst < 1e-3 && worst > 1e-6, "sigma = 1e-4: deviation %.3g not O(sigma)", worst);
    hsbd_percus_result_free(&r);
}

/* second order in the grid spacing: halving h divides the error by ~4 */
static void test_grid_convergence(void) {
    const double sigma = 0.37, rho = 0.8; /* sigma off the grid on purpose */
    hsbd_percus_result ref = solve(sigma, rho, 6.0, 0.0, 8000);
    double err_prev = 0;
    for (size_t m = 250; m <= 2000; m *= 2) {
        hsbd_percus_result r = solve(sigma, rho, 6.0, 0.0, m);
        double e = 0;
        for (size_t j = 0; j < m; ++j)
            e = fmax(e, fabs(r.rho[j] -
                             hsbd_periodic_interp(ref.rho, ref.m, 1.0 / (double)ref.m, r.x[j])));
        printf("  grid %5zu points: max |rho - rho_8000| = %.3g\n", m, e);
        if (err_prev > 0)
            CHECK(e < err_prev / 3.0, "error %.3g vs %.3g: not second order", e, err_prev);
        err_prev = e;
        hsbd_percus_result_free(&r);
    }
    CHECK(err_prev < 1e-4, "2000 points still off by %.3g", err_prev);
    hsbd_percus_result_free(&ref);
}

static void test_sticky_limits(void) {
    /* gamma -> 0 is the hard functional: the two discretisations (the sticky one
     * interpolates values at x + sigma) differ only at second order in the spacing */
    double prev = 0;
    for (size_t m = 1000; m <= 2000; m *= 2) {
        hsbd_percus_result hard = solve(0.5, 0.8, 6.0, 0.0, m);
        hsbd_percus_result soft = solve(0.5, 0.8, 6.0, 1e-9, m);
        double worst = 0;
        for (size_t j = 0; j < hard.m; ++j)
            worst = fmax(worst, fabs(hard.rho[j] - soft.rho[j]));
        printf("  gamma = 1e-9 vs hard, %zu points: %.3g\n", m, worst);
        if (prev > 0) CHECK(worst < prev / 3 && worst < 1e-6, "sticky -> hard: %.3g", worst);
        prev = worst;
        hsbd_percus_result_free(&hard);
        hsbd_percus_result_free(&soft);
    }
    /* U0 = 0: the homogeneous sticky equation of state */
    const double gammas[] = {0.1, 1.0, 10.0};
    for (int k = 0; k < 3; ++k) {
        hsbd_percus_result r = solve(0.5, 0.8, 0.0, gammas[k], 100);
        CHECK_CLOSE(r.beta_mu, hsbd_sticky_beta_mu(0.8, 0.5, gammas[k]), 1e-9);
        hsbd_percus_result_free(&r);
    }
    /* stickiness lowers the pressure, gamma = 0 is Tonks */
    CHECK(hsbd_sticky_pressure(0.5, 0.5, 1.0) < hsbd_tonks_pressure(0.5, 0.5), "sticky P");
    CHECK_CLOSE(hsbd_sticky_pressure(0.5, 0.5, 0.0), hsbd_tonks_pressure(0.5, 0.5), 1e-15);
}

static void test_tonks_closed_forms(void) {
    const double rho = 0.6, s = 0.5;
    /* contact value of g: beta P / rho = 1/(1 - rho sigma); g -> 1 at large r */
    CHECK_CLOSE(hsbd_tonks_g(s * 1.0000001, rho, s), 1.0 / (1 - rho * s), 1e-5);
    CHECK(hsbd_tonks_g(0.99 * s, rho, s) == 0.0, "g inside the core");
    CHECK_CLOSE(hsbd_tonks_g(40.0, rho, s), 1.0, 1e-6);
    /* number of neighbours within R: rho int_0^R g = R rho - (fluctuation) ~ sum of k-th
     * neighbour probabilities; check int_sigma^R rho g(r) dr = E[#neighbours to the right in R] */
    double integ = 0;
    const double dr = 1e-3;
    for (double r = s + dr / 2; r < 3.0; r += dr)
        integ += rho * hsbd_tonks_g(r, rho, s) * dr;
    double expect = 0; /* P(k-th neighbour within 3) summed, k-th at k sigma + Gamma(k, bP) */
    const double bp = hsbd_tonks_pressure(rho, s);
    for (int k = 1; k * s < 3.0; ++k) {
        const double x = bp * (3.0 - k * s);
        double term = exp(-x), cdf_c = 0; /* P(Gamma(k,1) > x) = e^-x sum_{i<k} x^i/i! */
        for (int i = 0; i < k; ++i)
            cdf_c += term, term *= x / (i + 1);
        expect += 1 - cdf_c;
    }
    CHECK_CLOSE(integ, expect, 1e-5);
    CHECK_CLOSE(hsbd_tonks_ring_contact(20, 40, 0.5), 0.5 * 19 / 30, 1e-15);
}

/* Exact single-file MSD: the limits, and a direct Monte Carlo of the construction it
 * rests on (order-keeping walkers = relabelled free walkers). Points at density rho' in
 * [-W, W] around a tag at 0 (s = sqrt(2 D t) = 1), free Gaussian steps, the tag ends at
 * the final position of the same rank. Fixed seed; 4-sigma band from the sample error. */
static int cmp_double(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double single_file_monte_carlo(double rho_free, long samples, double *err) {
    enum { CAP = 512 };
    const double w = 12.0;
    double pos[CAP], u[CAP], g[CAP];
    double sum = 0, sum2 = 0;
    for (long k = 0; k < samples; ++k) {
        /* Poisson number of points on each side: counts of exponential spacings within w */
        size_t n = 0, left = 0;
        for (int side = -1; side <= 1; side += 2) {
            hsbd_rng_uniforms(77, 9, (uint64_t)k, side < 0 ? 0 : CAP, CAP, u);
            double x = 0;
            for (size_t i = 0; i < CAP && n < CAP - 1; ++i) {
                x += -log(u[i]) / rho_free;
                if (x > w) break;
                pos[n++] = side * x;
                if (side < 0) ++left;
            }
        }
        pos[n++] = 0.0; /* the tag */
        hsbd_rng_normals(77, 10, (uint64_t)k, 0, n, g);
        for (size_t i = 0; i < n; ++i)
            pos[i] += g[i];
        qsort(pos, n, sizeof *pos, cmp_double);
        const double y2 = pos[left] * pos[left];
        sum += y2, sum2 += y2 * y2;
    }
    const double mean = sum / (double)samples;
    *err = sqrt((sum2 / (double)samples - mean * mean) / (double)samples);
    return mean;
}

static void test_single_file_exact(void) {
    const double rho = 0.5, s = 0.5, rho_free = rho / (1 - rho * s);
    /* short times: free diffusion with the first-collision correction (validation sec. 3) */
    const double t0 = 1e-6;
    CHECK_CLOSE(hsbd_single_file_msd_exact(t0, rho, s, 1.0) /
                    hsbd_short_time_msd(t0, rho_free, 1.0),
                1.0, 1e-5);
    /* long times: the asymptotic law, approached like 1/(rho' sqrt(4 D t)) */
    const double t1 = 1e6, r1 = hsbd_single_file_msd_exact(t1, rho, s, 1.0) /
                                hsbd_single_file_msd(t1, rho, s, 1.0);
    CHECK(r1 < 1 && r1 > 1 - 2 / (rho_free * sqrt(4 * t1)), "long-time ratio %.8f", r1);
    /* intermediate: rho' s = 2 (t = 1/(2 D) with s = 1), Monte Carlo of the construction */
    const double t = 0.5, rho_mc = 2.0;
    double e;
    const double mc = single_file_monte_carlo(rho_mc, 200000, &e);
    const double exact = hsbd_single_file_msd_exact(t, rho_mc, 0.0, 1.0);
    printf("  single file, rho' s = 2: Monte Carlo %.5f +- %.5f, exact %.5f\n", mc, e, exact);
    CHECK(fabs(mc - exact) < 4 * e, "single file at rho' s = 2: MC %.5f +- %.5f vs exact %.5f", mc,
          e, exact);
    CHECK(exact < 0.6 && exact > 0.2, "exact %.4f outside the free/asymptotic bracket", exact);
}

static void test_bad_input(void) {
    hsbd_percus_params p = {
        .sigma = 0.5, .rho_mean = 2.0, .amplitude = 6, .wavelength = 1, .points = 100};
    hsbd_percus_result r;
    hsbd_error err;
    CHECK(hsbd_percus_solve(&p, &r, &err) == HSBD_EINPUT, "rho sigma >= 1 accepted");
    p.rho_mean = 0.5, p.gamma = -1;
    CHECK(hsbd_percus_solve(&p, &r, &err) == HSBD_EINPUT, "gamma < 0 accepted");
    p.gamma = 0, p.points = 3;
    CHECK(hsbd_percus_solve(&p, &r, &err) == HSBD_EINPUT, "3 points accepted");
    p.points = 100, p.max_iter = 1, p.tol = 1e-14;
    CHECK(hsbd_percus_solve(&p, &r, &err) == HSBD_ENUMERIC, "non-convergence not reported");
}

static double max_abs_diff(const double *a, const double *b, size_t m, size_t stride_b) {
    double d = 0;
    for (size_t j = 0; j < m; ++j)
        d = fmax(d, fabs(a[j] - b[j * stride_b]));
    return d;
}

/* The transfer operator between successive rods is an independent exact method: without
 * pair forces it must give Percus' profile and contact density (both second order in the
 * grid, so their difference must shrink about fourfold per doubling). */
static void test_transfer_is_percus(void) {
    hsbd_error err;
    const hsbd_pair none = {0};
    const double cases[][2] = {{0.5, 0.5}, {0.9, 0.8}, {0.1, 0.2}};
    for (size_t c = 0; c < 3; ++c) {
        double prev = 0;
        for (size_t m = 500; m <= 1000; m *= 2) {
            hsbd_percus_params p = {.sigma = cases[c][0],
                                    .rho_mean = cases[c][1],
                                    .amplitude = 6,
                                    .wavelength = 1,
                                    .points = m};
            hsbd_percus_result a, b;
            CHECK(hsbd_percus_solve(&p, &a, &err) == HSBD_OK, "%s", err.message);
            CHECK(hsbd_nn_transfer_solve(&p, &none, &b, &err) == HSBD_OK, "%s", err.message);
            const double d = max_abs_diff(a.rho, b.rho, m, 1) / a.rho[m / 2];
            const double d2 = max_abs_diff(a.rho2, b.rho2, m, 1) / a.rho2[m / 2];
            printf("  transfer vs Percus, sigma %.1f rho %.1f, %zu points: rho %.2e, rho2 %.2e\n",
                   cases[c][0], cases[c][1], m, d, d2);
            CHECK(d < 2e-4 && d2 < 2e-4, "transfer differs from Percus: %g, %g", d, d2);
            if (prev > 1e-12) CHECK(d < prev / 3, "not second order: %g then %g", prev, d);
            prev = d;
            hsbd_percus_result_free(&a);
            hsbd_percus_result_free(&b);
        }
    }
}

/* The delta_eps model (Eqs. 31-32) approaches Baxter's as epsilon -> 0, linearly: the
 * homogeneous pressure and the profile in the field (Eqs. 34) are reached by Richardson
 * extrapolation in epsilon. At U0 = 0 the transfer solution is the homogeneous one. */
static void test_sticky_eps_to_baxter(void) {
    hsbd_error err;
    const double sigma = 0.5, rho = 0.5, gamma = 1;
    double bp[2], c[2];
    const double eps[2] = {0.02, 0.01};
    for (int k = 0; k < 2; ++k) {
        hsbd_pair st = {0};
        hsbd_pair_add(&st, hsbd_pair_sticky(sigma, gamma, 3, eps[k], 1.0));
        CHECK(hsbd_nn_homogeneous_solve(&st, sigma, rho, &bp[k], &c[k], &err) == HSBD_OK, "%s",
              err.message);
    }
    const double baxter = hsbd_sticky_pressure(rho, sigma, gamma), extrap = 2 * bp[1] - bp[0];
    printf("  sticky beta P: eps 0.02 %.8f, 0.01 %.8f, extrapolated %.8f, Baxter %.8f\n", bp[0],
           bp[1], extrap, baxter);
    CHECK(fabs(bp[1] - baxter) < 0.6 * fabs(bp[0] - baxter), "not approaching Baxter");
    CHECK_CLOSE(extrap, baxter, 2e-6);
    /* hard core only: Tonks */
    const hsbd_pair none = {0};
    double bt, ct;
    hsbd_nn_homogeneous_solve(&none, sigma, rho, &bt, &ct, &err);
    CHECK_CLOSE(bt, hsbd_tonks_pressure(rho, sigma), 1e-10);
    CHECK_CLOSE(ct, hsbd_tonks_contact(rho, sigma), 1e-10);
    /* profile in the field against Eq. 34: the deviation of the delta_eps model shrinks
     * as eps halves (0.04, 0.02, 0.01; 80 or more grid points per eps), and the quadratic
     * Richardson extrapolation to eps = 0 lands closer than the smallest eps (the profile's
     * approach is linear with a large quadratic part: +7.2e-4, +5.7e-4, +3.2e-4 at the peak) */
    hsbd_percus_params p = {.sigma = sigma,
                            .rho_mean = rho,
                            .amplitude = 6,
                            .wavelength = 1,
                            .points = 4000,
                            .gamma = gamma};
    hsbd_percus_result bax, r[3];
    const double ef[3] = {0.04, 0.02, 0.01};
    CHECK(hsbd_percus_solve(&p, &bax, &err) == HSBD_OK, "%s", err.message);
    for (int k = 0; k < 3; ++k) {
        hsbd_pair st = {0};
        hsbd_pair_add(&st, hsbd_pair_sticky(sigma, gamma, 3, ef[k], 1.0));
        p.points = k < 2 ? 2000 : 4000;
        CHECK(hsbd_nn_transfer_solve(&p, &st, &r[k], &err) == HSBD_OK, "%s", err.message);
    }
    double d[3] = {0, 0, 0}, dx = 0;
    for (size_t j = 0; j < 4000; ++j) {
        const double x = (double)j / 4000, b = bax.rho[j];
        double f[3];
        for (int k = 0; k < 3; ++k) {
            f[k] = hsbd_periodic_interp(r[k].rho, r[k].m, 1.0 / (double)r[k].m, x);
            d[k] = fmax(d[k], fabs(f[k] - b));
        }
        dx = fmax(dx, fabs((8 * f[2] - 6 * f[1] + f[0]) / 3 - b));
    }
    printf("  sticky profile vs Eq. 34: eps 0.04 %.2e, 0.02 %.2e, 0.01 %.2e, extrapolated %.2e\n",
           d[0], d[1], d[2], dx);
    CHECK(d[1] < d[0] && d[2] < 0.7 * d[1] && dx < 0.5 * d[2],
          "profile not approaching Eq. 34: %g %g %g -> %g", d[0], d[1], d[2], dx);
    hsbd_percus_result_free(&bax);
    for (int k = 0; k < 3; ++k)
        hsbd_percus_result_free(&r[k]);
    hsbd_percus_result r2;
    hsbd_pair s2 = {0};
    hsbd_pair_add(&s2, hsbd_pair_sticky(sigma, gamma, 3, 0.02, 1.0));
    /* U0 = 0: uniform, contact density as the homogeneous solution */
    p.amplitude = 0;
    p.points = 2000;
    CHECK(hsbd_nn_transfer_solve(&p, &s2, &r2, &err) == HSBD_OK, "%s", err.message);
    double bh, ch;
    hsbd_nn_homogeneous_solve(&s2, sigma, rho, &bh, &ch, &err);
    CHECK_CLOSE(r2.rho[17], rho, 1e-9);
    /* the trapezoid rule's O(h^2) error on the sticky peak: 0.48 % at 10 points per eps */
    CHECK_CLOSE(r2.rho2[17], ch, 1e-3 * ch);
    hsbd_percus_result_free(&r2);
}

static hsbd_box_result box(size_t n, double length, double sigma, const hsbd_field *field,
                           size_t points, double bin_width) {
    hsbd_box_params p = {
        .n = n, .length = length, .sigma = sigma, .field = field, .points = points};
    hsbd_box_result r;
    hsbd_error err;
    const int rc = hsbd_box_solve(&p, bin_width, &r, &err);
    CHECK(rc == HSBD_OK, "box(N %zu, L %g, sigma %g): %s", n, length, sigma, rc ? err.message : "");
    return r;
}

static double bins_integral(const hsbd_box_result *r, const double *f) {
    double s = 0;
    for (size_t k = 0; k < r->nbins; ++k)
        s += f[k] * r->bin_width;
    return s;
}

/* Closed forms of the field-free box (N uniform points in the free length l = L - N sigma):
 * the first rod's gap to the wall has density N/l at zero, so does every neighbour gap. */
static void test_box_field_free(void) {
    const size_t n = 30;
    const double L = 50, sigma = 1, l = L - (double)n * sigma;
    const double contacts = (double)n * (double)(n - 1) / l;
    double dev[2][3];
    for (int pass = 0; pass < 2; ++pass) {
        hsbd_box_result r = box(n, L, sigma, NULL, pass ? 8000 : 4000, 0.1);
        CHECK_CLOSE(bins_integral(&r, r.rho), (double)n, 1e-9 * n);
        CHECK_CLOSE(r.wall_left, r.wall_right, 1e-12);
        dev[pass][0] = fabs(r.wall_left / (n / l) - 1);
        dev[pass][1] = fabs(bins_integral(&r, r.rho2) / contacts - 1);
        /* nothing outside [sigma/2, L - sigma/2] */
        CHECK(r.rho[0] + r.rho[4] + r.rho[r.nbins - 1] == 0, "density beyond the wall contact");
        hsbd_box_result_free(&r);
    }
    for (int q = 0; q < 2; ++q)
        CHECK(dev[1][q] < 1e-5 && dev[0][q] / dev[1][q] > 3.5,
              "field-free box, %s: relative deviation %.3g (4000 points), %.3g (8000): not "
              "second order",
              q ? "contact pairs" : "wall contact", dev[0][q], dev[1][q]);
}

/* One rod: the Boltzmann distribution exp(-U)/Z on [sigma/2, L - sigma/2] (here a harmonic
 * trap plus gravity); second order in the grid spacing. */
static void test_box_one_rod_is_boltzmann(void) {
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_harmonic(0.3, 4.0, 0.0));
    hsbd_field_add(&field, hsbd_field_tilt(-0.7));
    const double L = 10, sigma = 1, w = 0.25;
    double z = 0;
    const int sub = 20000;
    for (int k = 0; k < sub; ++k) {
        const double x = 0.5 * sigma + (L - sigma) * (k + 0.5) / sub;
        z += exp(-hsbd_field_potential(&field, x)) * (L - sigma) / sub;
    }
    double err_coarse = 0, err_fine = 0;
    for (int pass = 0; pass < 2; ++pass) {
        hsbd_box_result r = box(1, L, sigma, &field, pass ? 1800 : 900, w);
        double worst = 0;
        for (size_t k = 2; k + 2 < r.nbins; ++k) { /* bins fully inside */
            double avg = 0;
            for (int q = 0; q < 200; ++q) {
                const double x = (k + (q + 0.5) / 200) * w;
                avg += exp(-hsbd_field_potential(&field, x)) / z / 200;
            }
            worst = fmax(worst, fabs(r.rho[k] - avg));
        }
        CHECK_CLOSE(r.wall_left, exp(-hsbd_field_potential(&field, 0.5 * sigma)) / z, 1e-5);
        *(pass ? &err_fine : &err_coarse) = worst;
        hsbd_box_result_free(&r);
    }
    CHECK(err_fine < 2e-6 && err_coarse / err_fine > 3.0,
          "one rod: deviation %.3g (900 points), %.3g (1800): not second order", err_coarse,
          err_fine);
}

/* Force balance on the whole column: the walls' forces (kT times the densities at
 * contact) carry the total external force, wall_left - wall_right = -N f for a constant
 * force f (sedimentation; second order in the spacing). */
static void test_box_force_balance(void) {
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_tilt(-0.5));
    double dev[2];
    for (int pass = 0; pass < 2; ++pass) {
        hsbd_box_result r = box(30, 50, 1, &field, pass ? 20000 : 10000, 0.5);
        dev[pass] = fabs(r.wall_left - r.wall_right - 15.0);
        CHECK_CLOSE(bins_integral(&r, r.rho), 30.0, 1e-9);
        hsbd_box_result_free(&r);
    }
    CHECK(dev[1] < 5e-4 && dev[0] / dev[1] > 3.5,
          "force balance off by %.3g (10000 points), %.3g (20000): not second order", dev[0],
          dev[1]);
    printf("box force balance: off by %.3g and %.3g at 10000 and 20000 points\n", dev[0], dev[1]);
}

/* Many rods far from the other wall: Percus' profile at a single hard wall, which for hard
 * rods is the Tonks pair density seen from a fixed rod, rho(s) = rho_b g(s + sigma) at
 * distance s from wall contact (the wall acts as a rod at the origin), with rho_b and
 * beta P = rho_b / (1 - rho_b sigma) of the bulk. The box differs at O(1/N). */
static void test_box_wall_is_percus(void) {
    const size_t n = 400;
    const double L = 1000, sigma = 1, w = 0.05;
    hsbd_box_result r = box(n, L, sigma, NULL, 12000, w);
    double rho_b = 0;
    size_t nb = 0;
    for (size_t k = (size_t)(400 / w); k < (size_t)(600 / w); ++k)
        rho_b += r.rho[k], ++nb;
    rho_b /= (double)nb;
    double worst = 0;
    for (size_t k = (size_t)(0.5 / w); k < (size_t)(6.0 / w); ++k) {
        double avg = 0;
        for (int q = 0; q < 50; ++q) {
            const double s = (k + (q + 0.5) / 50) * w - 0.5 * sigma;
            avg += rho_b * hsbd_tonks_g(s + sigma, rho_b, sigma) / 50;
        }
        worst = fmax(worst, fabs(r.rho[k] - avg) / avg);
    }
    CHECK(worst < 2.0 / n, "box near the wall vs Percus: relative deviation %.3g > 2/N", worst);
    CHECK_CLOSE(r.wall_left, hsbd_tonks_pressure(rho_b, sigma), 2.0 / n * r.wall_left);
    printf("box vs Percus wall profile (N = %zu): max relative deviation %.3g within 6 sigma, "
           "wall contact %.6f vs beta P %.6f\n",
           n, worst, r.wall_left, hsbd_tonks_pressure(rho_b, sigma));
    hsbd_box_result_free(&r);
}

/* Hard disks: the virial series reproduces the exact B3 and B4 at low density, meets
 * Henderson where Henderson is accurate, and its geometric remainder is small */
static void test_hard_disk_virial(void) {
    const double pi = 3.14159265358979323846;
    const double b3 = (16.0 / 3.0 - 4.0 * sqrt(3.0) / pi) / 4.0;               /* B3/B2^2 */
    const double b4 = (16.0 - 36.0 * sqrt(3.0) / pi + 80.0 / (pi * pi)) / 8.0; /* B4/B2^3 */
    for (double phi = 1e-3; phi <= 4e-3; phi *= 2) {
        const double x = 2 * phi, fourth = hsbd_hd_z_virial(phi) - 1 - x - b3 * x * x;
        CHECK_CLOSE(fourth / (x * x * x), b4, 2 * x); /* next term b5 x^4 */
    }
    CHECK_CLOSE(hsbd_hd_z_virial(0.2), hsbd_hd_z_henderson(0.2), 1e-4 * hsbd_hd_z_virial(0.2));
    const double z4 = hsbd_hd_z_virial(0.4);
    CHECK(z4 > 2.827 && z4 < 2.831, "Z(0.4) = %.6f", z4); /* the series to B10 is 2.82726 */
    CHECK_CLOSE(hsbd_hd_contact_virial(0.4), (z4 - 1) / 0.8, 1e-14);
    printf("hard disks: virial-series Z(0.4) = %.5f, Henderson %.5f (%+.2f %%)\n", z4,
           hsbd_hd_z_henderson(0.4), 100 * (hsbd_hd_z_henderson(0.4) / z4 - 1));
}

/* Mixture dynamics of Brownian hard spheres (docs/theory.md): the first-collision integrals
 * of one reflected coordinate by quadrature, the closed forms of the one-species and the
 * obstacle limits, and the share rule. */
static double normal_pdf(double w) {
    return exp(-0.5 * w * w) / sqrt(2 * 3.14159265358979323846);
}

static void test_mixture_dynamics(void) {
    const double pi = 3.14159265358979323846, k = 4 / (3 * sqrt(2 * pi));
    /* unit variance: z = |z0 + W|, delta = z - z0 - W = 2 (z0 + W)^-; the integrals over
     * z0 > 0 of E[delta^2], E[W delta] and of the deficit 1 - E (z - z0)^2 are 2 K, -3/2 K
     * and K (midpoint rule in z0 and in W) */
    double d2 = 0, wd = 0, deficit = 0;
    const double h = 2e-3;
    for (double z0 = 0.5 * h; z0 < 9; z0 += h) {
        double e_d2 = 0, e_wd = 0, e_sq = 0;
        for (double w = -9 + 0.5 * h; w < 9; w += h) {
            const double x = z0 + w, delta = x < 0 ? -2 * x : 0, dz = fabs(x) - z0;
            e_d2 += h * normal_pdf(w) * delta * delta;
            e_wd += h * normal_pdf(w) * w * delta;
            e_sq += h * normal_pdf(w) * dz * dz;
        }
        d2 += h * e_d2, wd += h * e_wd, deficit += h * (1 - e_sq);
    }
    CHECK_CLOSE(d2, 2 * k, 1e-5);
    CHECK_CLOSE(wd, -1.5 * k, 1e-5);
    CHECK_CLOSE(deficit, k, 1e-5);
    /* one species, 3D: c = 64 phi g D^(3/2) / (sqrt(2 pi) sigma); D_L = 1 - 2 phi */
    const double phi = 0.3, g = hsbd_hs_contact_klm(phi), rho = 6 * phi / pi, sig = 1.3;
    const double dens = rho / (sig * sig * sig), dif = 0.7;
    const hsbd_hs_mixture one = {3, 1, &dens, &sig, &dif, &g};
    CHECK_CLOSE(hsbd_hs_msd_deficit(&one, 0, -1),
                64 * phi * g * pow(dif, 1.5) / (sqrt(2 * pi) * sig), 1e-12);
    CHECK_CLOSE(hsbd_hs_msd_deficit(&one, 0, 0.5), hsbd_hs_msd_deficit(&one, 0, -1), 1e-12);
    CHECK_CLOSE(hsbd_hs_long_time_ratio(&one, 0), 1 - 2 * phi, 1e-14);
    const double dens2 = 4 * phi / (pi * sig * sig); /* disks: also 1 - 2 phi */
    const hsbd_hs_mixture disks = {2, 1, &dens2, &sig, &dif, NULL};
    CHECK_CLOSE(hsbd_hs_long_time_ratio(&disks, 0), 1 - 2 * phi, 1e-14);
    /* tracers (species 0, dilute) among immobile obstacles: the share is 1, and D_L is
     * Maxwell's dilute limit 1 - phi_excluded / (d - 1), phi_excluded the obstacles'
     * volume fraction of excluded spheres of radius sigma_ab */
    const double dn[2] = {0, 0.05}, sg[2] = {0.5, 1}, df[2] = {1, 0}, gc[4] = {1, 1.1, 1.1, 1};
    const hsbd_hs_mixture obst = {3, 2, dn, sg, df, gc};
    const double sab = 0.75, excluded = dn[1] * 4 * pi / 3 * sab * sab * sab;
    CHECK_CLOSE(hsbd_hs_long_time_ratio(&obst, 0), 1 - excluded / 2, 1e-14);
    CHECK(isnan(hsbd_hs_long_time_ratio(&obst, 1)), "immobile species: NaN");
    CHECK_CLOSE(hsbd_hs_msd_deficit(&obst, 0, -1),
                dn[1] * 1.1 * 4 * pi * sab * sab * k * pow(2.0, 1.5), 1e-12);
    CHECK_CLOSE(hsbd_hs_msd_deficit(&obst, 1, -1), 0, 0);
    /* the two-body problem at all times: Gamma's short- and long-time forms, and the slope
     * ratio approaching the long-time one */
    const double tiny = 1e-6, huge = 1e6;
    CHECK_CLOSE(hsbd_hs_excluded_sphere_gamma(tiny) / (4 / (3 * sqrt(pi)) * pow(tiny, 1.5)), 1,
                2 * sqrt(tiny));
    CHECK_CLOSE(hsbd_hs_excluded_sphere_gamma(huge), huge / 2 - 0.25, 1 / sqrt(huge));
    CHECK_CLOSE(hsbd_hs_msd_slope_ratio(&obst, 0, 1e5, 1e6), hsbd_hs_long_time_ratio(&obst, 0),
                1e-4);
    CHECK(hsbd_hs_msd_slope_ratio(&obst, 0, 0.4, 4) > hsbd_hs_long_time_ratio(&obst, 0),
          "finite lags see less of the obstacles");
    CHECK(isnan(hsbd_hs_msd_slope_ratio(&disks, 0, 1, 10)), "2D: not built");
    printf("mixture dynamics: K = %.8f (quadrature %.8f), one species phi 0.3 c = %.4f\n", k,
           deficit, hsbd_hs_msd_deficit(&one, 0, -1));
}

int main(void) {
    test_mixture_dynamics();
    test_hard_disk_virial();
    test_uniform_is_tonks();
    test_point_particles_are_boltzmann();
    test_grid_convergence();
    test_sticky_limits();
    test_tonks_closed_forms();
    test_single_file_exact();
    test_transfer_is_percus();
    test_sticky_eps_to_baxter();
    test_bad_input();
    test_box_field_free();
    test_box_one_rod_is_boltzmann();
    test_box_wall_is_percus();
    test_box_force_balance();
    return test_finish("test_theory");
}
