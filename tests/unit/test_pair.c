/* Pair forces and spline tables: every force is minus the derivative of its potential,
 * vanishes continuously at its range, and has the closed-form values of its definition;
 * the sticky force's maximum matches the closed form of Eq. (32); spline tables reproduce
 * linear data exactly and smooth data to the expected order; a zero pair force leaves the
 * BCD step bit-identical. */
#include <math.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/pair.h"
#include "hsbd/rods.h"
#include "hsbd/table.h"

/* f = -dV/dr by central differences at a few points inside (sigma, range) */
static void check_force_is_gradient(const char *name, const hsbd_pair *p, double sigma) {
    const double range = hsbd_pair_range(p);
    for (int k = 1; k < 20; ++k) {
        const double r = sigma + (range - sigma) * k / 20.0, d = 1e-6 * (range - sigma);
        const double num =
            -(hsbd_pair_potential(p, r + d) - hsbd_pair_potential(p, r - d)) / (2 * d);
        const double f = hsbd_pair_force(p, r);
        CHECK(fabs(num - f) <= 1e-6 * (1 + fabs(f)), "%s: r = %g: f = %.12g, -dV/dr = %.12g", name,
              r, f, num);
    }
    /* continuous at the range: f, V -> 0 from below, exactly 0 beyond */
    const double below = range * (1 - 1e-9);
    CHECK(fabs(hsbd_pair_force(p, below)) < 1e-6, "%s: f(range-) = %g", name,
          hsbd_pair_force(p, below));
    CHECK(fabs(hsbd_pair_potential(p, below)) < 1e-9, "%s: V(range-) = %g", name,
          hsbd_pair_potential(p, below));
    CHECK(hsbd_pair_force(p, range) == 0 && hsbd_pair_potential(p, range * 1.01) == 0,
          "%s: nonzero beyond the range", name);
}

static void test_sticky(void) {
    const double sigma = 0.2, gamma = 1, eps = 0.05, p = 3;
    hsbd_pair pair = {0};
    hsbd_pair_add(&pair, hsbd_pair_sticky(sigma, gamma, p, eps, 1.0));
    check_force_is_gradient("sticky", &pair, sigma);
    /* Boltzmann factor at contact 1 + gamma (p+1)/eps (Eqs. 30-31) */
    CHECK_CLOSE(exp(-hsbd_pair_potential(&pair, sigma)), 1 + gamma * (p + 1) / eps, 1e-9);
    /* Eq. (32) at contact: -gamma p eps^(p-1) / (eps^(p+1)/(p+1) + gamma eps^p) */
    CHECK_CLOSE(hsbd_pair_force(&pair, sigma),
                -gamma * p * pow(eps, p - 1) / (pow(eps, p + 1) / (p + 1) + gamma * pow(eps, p)),
                1e-9);
    /* max |f|: w = eps - h solves w^p = (p-1) c / gamma, c = eps^(p+1)/(p+1) (stationary
     * point of w^(p-1)/(c + gamma w^p)); paper Fig. 5: about 137 for these parameters */
    const double c = pow(eps, p + 1) / (p + 1), w = pow((p - 1) * c / gamma, 1 / p);
    const double fmax = gamma * p * pow(w, p - 1) / (c + gamma * pow(w, p));
    CHECK_CLOSE(hsbd_pair_max_force(&pair, sigma, sigma + eps), fmax, 1e-6 * fmax);
    CHECK(fmax > 130 && fmax < 140, "fmax = %g", fmax);
    /* the integral of delta_eps is 1 (Eq. 31): int (e^{-V} - 1) dr = gamma */
    double s = 0;
    const int nq = 20000;
    for (int k = 0; k < nq; ++k) {
        const double r = sigma + eps * (k + 0.5) / nq;
        s += (exp(-hsbd_pair_potential(&pair, r)) - 1) * eps / nq;
    }
    CHECK_CLOSE(s, gamma, 1e-6);
}

static void test_analytic(void) {
    const double sigma = 0.5;
    hsbd_pair y = {0}, lj = {0};
    hsbd_pair_add(&y, hsbd_pair_yukawa(sigma, 2.0, 3.0, 0.9));
    hsbd_pair_add(&lj, hsbd_pair_lj(sigma, 1.5, 0.9));
    check_force_is_gradient("yukawa", &y, sigma);
    check_force_is_gradient("lj", &lj, sigma);
    /* force-shifted forms: f(r) = f_raw(r) - f_raw(rc) */
    const double r = 0.6, rc = 0.9;
    const double vy = 2.0 * sigma * exp(-3.0 * (r - sigma)) / r,
                 vyc = 2.0 * sigma * exp(-3.0 * (rc - sigma)) / rc;
    CHECK_CLOSE(hsbd_pair_force(&y, r), vy * (3 + 1 / r) - vyc * (3 + 1 / rc), 1e-12);
    /* the LJ well: minimum -depth at contact (before the shift), attractive outside */
    CHECK(hsbd_pair_force(&lj, 0.55) < 0 && hsbd_pair_force(&lj, 0.85) < 0, "lj not attractive");
}

static void test_table(void) {
    hsbd_error err;
    /* linear data: the natural spline is exact, integrals too */
    const double x[] = {0.0, 0.3, 0.4, 1.0, 1.7}, ylin[] = {1.0, 1.6, 1.8, 3.0, 4.4};
    hsbd_table *t = hsbd_table_alloc(5, x, ylin, "linear", &err);
    CHECK(t != NULL, "alloc: %s", err.message);
    for (double q = 0; q <= 1.7; q += 0.05) {
        CHECK_CLOSE(hsbd_table_value(t, q), 1 + 2 * q, 1e-12);
        CHECK_CLOSE(hsbd_table_derivative(t, q), 2.0, 1e-12);
        CHECK_CLOSE(hsbd_table_integral(t, q), q + q * q, 1e-12);
    }
    hsbd_table_free(t);
    /* sin on [0, pi], 201 points (f'' = 0 at both ends, as the natural spline assumes):
     * errors O(h^4) in the value, O(h^3) in the derivative */
    enum { NS = 201 };
    const double pi = 3.14159265358979323846;
    double xs[NS], ys[NS];
    for (int k = 0; k < NS; ++k)
        xs[k] = pi * k / (NS - 1), ys[k] = sin(xs[k]);
    t = hsbd_table_alloc(NS, xs, ys, "sin", &err);
    double emax = 0, dmax = 0;
    for (double q = 0.0; q <= pi; q += 0.001) {
        emax = fmax(emax, fabs(hsbd_table_value(t, q) - sin(q)));
        dmax = fmax(dmax, fabs(hsbd_table_derivative(t, q) - cos(q)));
    }
    CHECK(emax < 1e-8 && dmax < 1e-5, "spline of sin: value error %g, derivative error %g", emax,
          dmax);
    CHECK_CLOSE(hsbd_table_integral(t, pi), 2.0, 1e-8);
    /* a tabulated pair force: V = integral of f to the end */
    hsbd_pair pair = {0};
    hsbd_pair_add(&pair, hsbd_pair_table(t));
    CHECK_CLOSE(hsbd_pair_potential(&pair, 1.0), cos(1.0) + 1.0, 1e-8);
    hsbd_table_free(t);
    /* bad tables */
    const double xbad[] = {0, 1, 1}, ybad[] = {0, 1, 2}, ynan[] = {0, NAN, 1};
    CHECK(!hsbd_table_alloc(3, xbad, ybad, "dup", &err) && err.status == HSBD_EINPUT &&
              strstr(err.message, "increase"),
          "unsorted table accepted: %s", err.message);
    CHECK(!hsbd_table_alloc(3, x, ynan, "nan", &err) && strstr(err.message, "not finite"),
          "NaN table accepted");
}

/* a pair term whose force is zero everywhere leaves the step bit-identical */
/* Largest |spline - f| and |spline' - f'| of a table of cos(2 pi x) over [0, 1] (near
 * both ends included). */
static void cosine_table_errors(const hsbd_table *t, double *value_err, double *slope_err) {
    const double two_pi = 6.283185307179586;
    *value_err = *slope_err = 0;
    for (int k = 0; k <= 4000; ++k) {
        const double q = k / 4000.0;
        *value_err = fmax(*value_err, fabs(hsbd_table_value(t, q) - cos(two_pi * q)));
        *slope_err = fmax(*slope_err, fabs(hsbd_table_derivative(t, q) + two_pi * sin(two_pi * q)));
    }
}

/* The periodic spline of a periodic function: within the interpolation error bounds of
 * cubic splines with exact end conditions (Hall & Meyer 1976: |s - f| <= 5/384 h^4
 * max|f''''|, |s' - f'| <= 1/24 h^3 max|f''''|) everywhere, ends included, and its value,
 * slope and curvature continuous across x = 0 = 1. The natural spline of the same points
 * breaks the slope bound at the ends (it forces s'' = 0 where cos'' is largest), which is
 * why a ring needs the periodic one. Also: a non-uniform grid, the smallest tables, and
 * ends that disagree. */
static void test_periodic_table(void) {
    const double two_pi = 6.283185307179586, f4 = pow(two_pi, 4);
    enum { NP = 21 };
    double x[NP], y[NP];
    for (int i = 0; i < NP; ++i)
        x[i] = i / (NP - 1.0), y[i] = cos(two_pi * x[i]);
    const double h = 1.0 / (NP - 1);
    hsbd_error err;
    hsbd_table *natural = hsbd_table_alloc(NP, x, y, "cos", &err);
    hsbd_table *periodic = hsbd_table_alloc(NP, x, y, "cos", &err);
    CHECK(hsbd_table_make_periodic(periodic, "cos", &err) == HSBD_OK, "%s", err.message);
    double ev, es;
    cosine_table_errors(periodic, &ev, &es);
    printf("  periodic spline of cos, h = %g: |s - f| <= %.3g (bound %.3g), |s' - f'| <= %.3g "
           "(bound %.3g)\n",
           h, ev, 5.0 / 384 * pow(h, 4) * f4, es, pow(h, 3) * f4 / 24);
    CHECK(ev <= 5.0 / 384 * pow(h, 4) * f4, "periodic value error %g", ev);
    CHECK(es <= pow(h, 3) * f4 / 24, "periodic slope error %g", es);
    const double d = 1e-7;
    CHECK_CLOSE(hsbd_table_derivative(periodic, 0.0), hsbd_table_derivative(periodic, 1.0), 1e-12);
    CHECK_CLOSE((hsbd_table_derivative(periodic, d) - hsbd_table_derivative(periodic, 0)) / d,
                (hsbd_table_derivative(periodic, 1) - hsbd_table_derivative(periodic, 1 - d)) / d,
                1e-3);
    CHECK_CLOSE(hsbd_table_integral(periodic, 1.0), 0.0, 1e-6); /* cos integrates to 0 */
    double nv, ns;
    cosine_table_errors(natural, &nv, &ns);
    printf("  natural spline of the same points: |s' - f'| <= %.3g at the ends\n", ns);
    CHECK(ns > 10 * pow(h, 3) * f4 / 24, "the natural spline's end error %g should be large", ns);
    hsbd_table_free(natural);
    hsbd_table_free(periodic);
    /* non-uniform knots x_i = u_i + 0.03 sin(2 pi u_i): the same bounds with the largest h */
    double hmax = 0;
    for (int i = 0; i < NP; ++i) {
        const double u = i / (NP - 1.0);
        x[i] = u + 0.03 * sin(two_pi * u), y[i] = cos(two_pi * x[i]);
        if (i) hmax = fmax(hmax, x[i] - x[i - 1]);
    }
    x[NP - 1] = 1.0, y[NP - 1] = 1.0;
    periodic = hsbd_table_alloc(NP, x, y, "cos", &err);
    CHECK(hsbd_table_make_periodic(periodic, "cos", &err) == HSBD_OK, "%s", err.message);
    cosine_table_errors(periodic, &ev, &es);
    CHECK(ev <= 5.0 / 384 * pow(hmax, 4) * f4 && es <= pow(hmax, 3) * f4 / 24,
          "non-uniform: errors %g, %g", ev, es);
    CHECK_CLOSE(hsbd_table_derivative(periodic, 0.0), hsbd_table_derivative(periodic, 1.0), 1e-12);
    hsbd_table_free(periodic);
    /* three points (two intervals) and two points (a constant) */
    const double x3[3] = {0, 0.4, 1}, y3[3] = {1, -1, 1};
    hsbd_table *t3 = hsbd_table_alloc(3, x3, y3, "three", &err);
    CHECK(hsbd_table_make_periodic(t3, "three", &err) == HSBD_OK, "%s", err.message);
    CHECK_CLOSE(hsbd_table_value(t3, 0.4), -1.0, 1e-14);
    CHECK_CLOSE(hsbd_table_derivative(t3, 0.0), hsbd_table_derivative(t3, 1.0), 1e-12);
    hsbd_table_free(t3);
    const double x2[2] = {0, 1}, y2[2] = {2, 2};
    hsbd_table *t2 = hsbd_table_alloc(2, x2, y2, "two", &err);
    CHECK(hsbd_table_make_periodic(t2, "two", &err) == HSBD_OK && hsbd_table_value(t2, 0.3) == 2,
          "a two-point periodic table is a constant");
    hsbd_table_free(t2);
    /* ends that disagree are refused with both values named */
    const double yb[3] = {1, -1, 1.01};
    hsbd_table *tb = hsbd_table_alloc(3, x3, yb, "mismatch.tsv", &err);
    CHECK(hsbd_table_make_periodic(tb, "mismatch.tsv", &err) == HSBD_EINPUT &&
              strstr(err.message, "mismatch.tsv") && strstr(err.message, "1.01"),
          "mismatched ends: %s", err.message);
    hsbd_table_free(tb);
}

static void test_zero_pair_force_is_exact(void) {
    hsbd_rods_params a = {.n = 200,
                          .length = 200,
                          .sigma = 0.5,
                          .diffusion = 1,
                          .kT = 1,
                          .dt = 1e-4,
                          .seed = 5,
                          .hard_core = 1,
                          .contact_rule = HSBD_CONTACT_REFLECT};
    hsbd_field_add(&a.field, hsbd_field_cosine(6, 1));
    hsbd_rods_params b = a;
    hsbd_pair_add(&b.pair, hsbd_pair_yukawa(0.5, 0.0, 1.0, 0.9));
    hsbd_error err;
    hsbd_rods *ra = hsbd_rods_alloc(&a, &err), *rb = hsbd_rods_alloc(&b, &err);
    hsbd_rods_init_equilibrium(ra);
    hsbd_rods_init_equilibrium(rb);
    for (int k = 0; k < 2000; ++k)
        CHECK((hsbd_rods_step(ra, NULL) | hsbd_rods_step(rb, NULL)) == HSBD_OK, "step");
    const hsbd_rods_view va = hsbd_rods_get_view(ra), vb = hsbd_rods_get_view(rb);
    CHECK(!memcmp(va.z, vb.z, a.n * sizeof *va.z), "zero pair force changed the trajectory");
    hsbd_rods_free(ra);
    hsbd_rods_free(rb);
    /* pair forces without the hard core, or with a range beyond L/2, are refused */
    b.hard_core = 0;
    CHECK(!hsbd_rods_alloc(&b, &err) && err.status == HSBD_EINPUT, "pair without hard core");
}

/* max |V''| (the Euler warning's pair time scale): the LJ well's 72 depth / sigma^2 at
 * contact (the force shift does not change f'), Yukawa's A (kappa^2 + 2 kappa / sigma +
 * 2 / sigma^2) at contact (its largest), both to the sampling's accuracy. */
static void test_max_curvature(void) {
    hsbd_pair lj = {0}, yk = {0};
    hsbd_pair_add(&lj, hsbd_pair_lj(0.5, 2.0, 1.2));
    CHECK_CLOSE(hsbd_pair_max_curvature(&lj, 0.5, 1.2), 72 * 2.0 / 0.25, 0.01 * 72 * 2.0 / 0.25);
    const double a = 3.0, kappa = 2.0, s = 1.0;
    hsbd_pair_add(&yk, hsbd_pair_yukawa(s, a, kappa, 4.0));
    const double expect = a * (kappa * kappa + 2 * kappa / s + 2 / (s * s));
    CHECK_CLOSE(hsbd_pair_max_curvature(&yk, s, 4.0), expect, 0.01 * expect);
}

int main(void) {
    test_max_curvature();
    test_periodic_table();
    test_sticky();
    test_analytic();
    test_table();
    test_zero_pair_force_is_exact();
    return test_finish("test_pair");
}
