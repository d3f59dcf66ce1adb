/* Percus functional and closed forms: limits that are known exactly. */
#include <math.h>

#include "../test_util.h"
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

int main(void) {
    test_uniform_is_tonks();
    test_point_particles_are_boltzmann();
    test_grid_convergence();
    test_sticky_limits();
    test_tonks_closed_forms();
    test_bad_input();
    return test_finish("test_theory");
}
