/* One Brownian particle in a tilted periodic potential (src/theory/washboard.c): the exact
 * limits (free particle, Lifson-Jackson, linear response), grid convergence, symmetries,
 * the giant-diffusion peak near the critical tilt, an independent finite-difference solution
 * of the stationary Fokker-Planck equation and the adiabatic rocking average. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/field.h"
#include "hsbd/theory.h"

static const double PI = 3.141592653589793238462643383280;

/* ---- an asymmetric (ratchet) potential as a user-defined field term:
 * U(x) = A [sin(k x) + (1/4) sin(2 k x)] with k = 2 pi / lambda, p[2] = +1 or -1 for U(+-x) */
enum { RATCHET_A, RATCHET_LAMBDA, RATCHET_SIGN };

static double ratchet_potential(const hsbd_field_term *t, double x) {
    const double k = 2 * PI / t->p[RATCHET_LAMBDA], y = t->p[RATCHET_SIGN] * x;
    return t->p[RATCHET_A] * (sin(k * y) + 0.25 * sin(2 * k * y));
}

static void ratchet_add_force(const hsbd_field_term *t, size_t n, const double *restrict x,
                              double *restrict f) {
    const double k = 2 * PI / t->p[RATCHET_LAMBDA], s = t->p[RATCHET_SIGN];
    for (size_t i = 0; i < n; ++i) {
        const double y = s * x[i];
        f[i] -= s * t->p[RATCHET_A] * k * (cos(k * y) + 0.5 * cos(2 * k * y));
    }
}

static const hsbd_field_ops ratchet_ops = {
    .name = "ratchet", .add_force = ratchet_add_force, .potential = ratchet_potential};

static hsbd_field ratchet_field(double amplitude, double lambda, double sign) {
    hsbd_field field = {0};
    hsbd_field_term t = {.ops = &ratchet_ops, .p = {amplitude, lambda, sign, 0}};
    hsbd_field_add(&field, t);
    return field;
}

static hsbd_field cosine_field(double u0, double lambda) {
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_cosine(u0, lambda));
    return field;
}

static hsbd_washboard_params params(const hsbd_field *field, double force) {
    return (hsbd_washboard_params){
        .diffusion = 1, .kT = 1, .period = 1, .force = force, .field = field, .tol = 1e-12};
}

static hsbd_washboard_result solve(const hsbd_washboard_params *p) {
    hsbd_washboard_result r;
    hsbd_error err;
    const int rc = hsbd_washboard_solve(p, &r, &err);
    CHECK(rc == HSBD_OK, "solve(f = %g): %s", p->force, rc ? err.message : "");
    if (rc) { /* keep the checks below meaningful (they fail) without crashing */
        memset(&r, 0, sizeof r);
        r.velocity = r.diffusion_eff = NAN;
    }
    return r;
}

static double rel(double a, double b) {
    return fabs(a - b) / fmax(fabs(a), fabs(b));
}

/* U = 0: <v> = mu f, D_eff = D, p = 1 / lambda, for any tilt */
static void test_free_particle(void) {
    const hsbd_field zero = cosine_field(0.0, 2.0);
    const double forces[] = {0.0, 0.3, -2.0, 50.0, -1e3};
    for (int k = 0; k < 5; ++k)
        for (int with_field = 0; with_field < 2; ++with_field) {
            hsbd_washboard_params p = {.diffusion = 0.7,
                                       .kT = 1.3,
                                       .period = 2.0,
                                       .force = forces[k],
                                       .field = with_field ? &zero : NULL,
                                       .tol = 1e-13};
            hsbd_washboard_result r = solve(&p);
            const double mu_f = p.diffusion / p.kT * p.force;
            CHECK(fabs(r.velocity - mu_f) <= 1e-12 * fmax(fabs(mu_f), 1e-300),
                  "free particle f = %g: v = %.17g, mu f = %.17g", p.force, r.velocity, mu_f);
            CHECK_CLOSE(r.diffusion_eff / p.diffusion, 1.0, 1e-12);
            double worst = 0;
            for (size_t j = 0; j < r.m; ++j)
                worst = fmax(worst, fabs(r.density[j] * p.period - 1.0));
            CHECK(worst <= 1e-12, "free particle f = %g: density off 1/lambda by %.3g", p.force,
                  worst);
            hsbd_washboard_result_free(&r);
        }
}

/* I0(x) = sum_k (x/2)^(2k) / (k!)^2: all terms positive, so the sum is accurate to rounding */
static double bessel_i0(double x) {
    double term = 1.0, sum = 1.0;
    for (int k = 1; k < 500 && term > 1e-18 * sum; ++k) {
        term *= (0.5 * x) * (0.5 * x) / ((double)k * k);
        sum += term;
    }
    return sum;
}

/* f = 0: v = 0 exactly, the Boltzmann density and the Lifson-Jackson coefficient
 * D lambda^2 / (int e^{U/kT} int e^{-U/kT}). For U = (U0/2) cos(2 pi x / lambda) both
 * integrals are lambda I0(U0 / 2kT), so D_eff = D / I0(U0 / 2kT)^2. */
static void test_lifson_jackson(void) {
    const double u0s[] = {0.5, 2.0, 10.0, 20.0, 40.0};
    for (int k = 0; k < 5; ++k) {
        const hsbd_field field = cosine_field(u0s[k] * 0.8, 1.5);
        hsbd_washboard_params p = {.diffusion = 2.0,
                                   .kT = 0.8,
                                   .period = 1.5,
                                   .force = 0.0,
                                   .field = &field,
                                   .tol = 1e-13};
        hsbd_washboard_result r = solve(&p);
        const double i0 = bessel_i0(0.5 * u0s[k]);
        CHECK(r.velocity == 0.0, "f = 0: v = %g", r.velocity);
        CHECK(rel(r.diffusion_eff, p.diffusion / (i0 * i0)) <= 1e-12,
              "Lifson-Jackson U0 = %g kT: D_eff = %.17g, D / I0^2 = %.17g", u0s[k], r.diffusion_eff,
              p.diffusion / (i0 * i0));
        double worst = 0;
        for (size_t j = 0; j < r.m; ++j) {
            const double boltzmann =
                exp(-hsbd_field_potential(&field, r.x[j]) / p.kT) / (p.period * i0);
            worst = fmax(worst, rel(r.density[j], boltzmann));
        }
        CHECK(worst <= 1e-12, "f = 0, U0 = %g kT: density off Boltzmann by %.3g", u0s[k], worst);
        hsbd_washboard_result_free(&r);
    }
    /* a two-term potential against the integrals done here (trapezoid, spectral) */
    hsbd_field field = cosine_field(6.0, 1.0);
    hsbd_field_add(&field, hsbd_field_cosine(-3.0, 1.0 / 3.0));
    hsbd_washboard_params p = params(&field, 0.0);
    hsbd_washboard_result r = solve(&p);
    double a = 0, b = 0;
    const int n = 4096;
    for (int j = 0; j < n; ++j) {
        const double u = hsbd_field_potential(&field, (double)j / n);
        a += exp(u) / n;
        b += exp(-u) / n;
    }
    CHECK(rel(r.diffusion_eff, 1.0 / (a * b)) <= 1e-12, "two cosines: D_eff = %.17g, LJ = %.17g",
          r.diffusion_eff, 1.0 / (a * b));
    hsbd_washboard_result_free(&r);
}

/* Small tilt: v = (D_LJ / kT) f (1 + O(f^2)): the Einstein relation links the f = 0 diffusion
 * coefficient of one formula to the slope of the other. */
static void test_linear_response(void) {
    const hsbd_field field = cosine_field(8.0, 1.0);
    hsbd_washboard_params p = params(&field, 0.0);
    hsbd_washboard_result r0 = solve(&p);
    const double mobility = r0.diffusion_eff / p.kT;
    double dev[2];
    for (int k = 0; k < 2; ++k) {
        p.force = k ? 1e-3 : 1e-2;
        hsbd_washboard_result r = solve(&p);
        dev[k] = fabs(r.velocity / (mobility * p.force) - 1.0);
        hsbd_washboard_result_free(&r);
    }
    CHECK(dev[1] < 1e-6 && dev[1] < 0.02 * dev[0] && dev[1] > 0.005 * dev[0],
          "linear response: deviations %.3g (f = 1e-2), %.3g (f = 1e-3) not O(f^2)", dev[0],
          dev[1]);
    hsbd_washboard_result_free(&r0);
}

/* Fixed grids converge spectrally, the estimate (change from half the points) bounds the
 * error, and automatic grids meet the tolerance. U0 = 20 kT at ten times the critical tilt:
 * the case that needs the most points of those tested here. */
static void test_convergence(void) {
    const hsbd_field field = cosine_field(20.0, 1.0);
    hsbd_washboard_params p = params(&field, 10 * PI * 20.0);
    p.tol = 1e-14;
    hsbd_washboard_result ref = solve(&p);
    double last = INFINITY;
    for (size_t m = 16; m <= 256; m *= 2) {
        p.points = m;
        hsbd_washboard_result r = solve(&p);
        const double e =
            fmax(rel(r.velocity, ref.velocity), rel(r.diffusion_eff, ref.diffusion_eff));
        CHECK(e <= fmax(r.error, 1e-14), "m = %zu: error %.3g above its estimate %.3g", m, e,
              r.error);
        CHECK(e < last / 100 || e < 1e-13, "m = %zu: error %.3g not falling fast (%.3g before)", m,
              e, last);
        last = e;
        hsbd_washboard_result_free(&r);
    }
    CHECK(last < 1e-13, "256 points: error %.3g", last);
    p.points = 0;
    for (double tol = 1e-4; tol > 1e-13; tol *= 1e-4) {
        p.tol = tol;
        hsbd_washboard_result r = solve(&p);
        const double e =
            fmax(rel(r.velocity, ref.velocity), rel(r.diffusion_eff, ref.diffusion_eff));
        CHECK(r.error <= tol && e <= tol, "tol %.0e: estimate %.3g, error %.3g (m = %zu)", tol,
              r.error, e, r.m);
        hsbd_washboard_result_free(&r);
    }
    hsbd_washboard_result_free(&ref);
}

/* Only U/kT and f lambda/kT matter: scaling kT, U0 and f together changes nothing. */
static void test_scaling_invariance(void) {
    const hsbd_field base = cosine_field(7.0, 1.0);
    hsbd_washboard_params p = params(&base, 15.0);
    hsbd_washboard_result r0 = solve(&p);
    const double scales[] = {0.1, 3.0, 1e3};
    for (int k = 0; k < 3; ++k) {
        const double s = scales[k];
        const hsbd_field field = cosine_field(7.0 * s, 1.0);
        hsbd_washboard_params q = p;
        q.field = &field;
        q.kT = s;
        q.force = 15.0 * s;
        q.diffusion = p.diffusion; /* D fixed: the mobility D/kT changes with kT */
        hsbd_washboard_result r = solve(&q);
        CHECK(rel(r.velocity, r0.velocity) <= 1e-12 &&
                  rel(r.diffusion_eff, r0.diffusion_eff) <= 1e-12,
              "scale %g: v %.17g vs %.17g, D_eff %.17g vs %.17g", s, r.velocity, r0.velocity,
              r.diffusion_eff, r0.diffusion_eff);
        hsbd_washboard_result_free(&r);
    }
    hsbd_washboard_result_free(&r0);
}

/* U(-x) = U(x): v(-f) = -v(f), D_eff(-f) = D_eff(f), p_{-f}(x) = p_f(-x). Without that
 * symmetry (the ratchet) v(-f) != -v(f), and the mirror image holds only with U(-x). */
static void test_symmetry(void) {
    hsbd_field sym = cosine_field(6.0, 1.0);
    hsbd_field_add(&sym, hsbd_field_cosine(2.0, 0.5));
    const double forces[] = {0.5, 10.0, 40.0};
    for (int k = 0; k < 3; ++k) {
        hsbd_washboard_params p = params(&sym, forces[k]);
        hsbd_washboard_result a = solve(&p);
        p.force = -forces[k];
        hsbd_washboard_result b = solve(&p);
        CHECK(rel(a.velocity, -b.velocity) <= 1e-12 &&
                  rel(a.diffusion_eff, b.diffusion_eff) <= 1e-12,
              "symmetric U, f = %g: v %.17g / %.17g, D_eff %.17g / %.17g", forces[k], a.velocity,
              b.velocity, a.diffusion_eff, b.diffusion_eff);
        double worst = 0;
        for (size_t j = 0; a.m == b.m && j < a.m; ++j)
            worst = fmax(worst, fabs(b.density[j] - a.density[(a.m - j) % a.m]));
        CHECK(a.m == b.m && worst <= 1e-12, "symmetric U, f = %g: p(-f, x) - p(f, -x) = %.3g",
              forces[k], worst);
        hsbd_washboard_result_free(&a);
        hsbd_washboard_result_free(&b);
    }
    const hsbd_field ratchet = ratchet_field(3.0, 1.0, 1.0),
                     mirrored = ratchet_field(3.0, 1.0, -1.0);
    hsbd_washboard_params p = params(&ratchet, 8.0);
    hsbd_washboard_result plus = solve(&p);
    p.force = -8.0;
    hsbd_washboard_result minus = solve(&p);
    p.field = &mirrored;
    p.force = 8.0;
    hsbd_washboard_result image = solve(&p);
    CHECK(fabs(plus.velocity + minus.velocity) > 1e-3 * plus.velocity,
          "ratchet: v(f) = %.17g, v(-f) = %.17g should differ in size", plus.velocity,
          minus.velocity);
    CHECK(rel(minus.velocity, -image.velocity) <= 1e-12 &&
              rel(minus.diffusion_eff, image.diffusion_eff) <= 1e-12,
          "ratchet: v(-f; U) = %.17g, -v(f; U(-x)) = %.17g", minus.velocity, -image.velocity);
    hsbd_washboard_result_free(&plus);
    hsbd_washboard_result_free(&minus);
    hsbd_washboard_result_free(&image);
}

static double cosine_deff(double u0, double force) {
    const hsbd_field field = cosine_field(u0, 1.0);
    hsbd_washboard_params p = params(&field, force);
    hsbd_washboard_result r = solve(&p);
    const double d = r.diffusion_eff;
    hsbd_washboard_result_free(&r);
    return d;
}

/* golden-section search for the maximum of D_eff(f) on [a, b] (U = (U0/2) cos, lambda = 1) */
static double deff_peak(double u0, double a, double b, double *dmax) {
    const double g = 0.5 * (sqrt(5.0) - 1.0);
    double c = b - g * (b - a), d = a + g * (b - a);
    double fc = cosine_deff(u0, c), fd = cosine_deff(u0, d);
    while (b - a > 1e-7 * b) {
        if (fc > fd) {
            b = d, d = c, fd = fc;
            c = b - g * (b - a), fc = cosine_deff(u0, c);
        } else {
            a = c, c = d, fc = fd;
            d = a + g * (b - a), fd = cosine_deff(u0, d);
        }
    }
    *dmax = fmax(fc, fd);
    return 0.5 * (a + b);
}

/* Giant diffusion (docs/theory.md): near the critical tilt f_c = pi U0 / lambda the barrier
 * turns into an inflection point. For U0 >> kT the passage through it is universal after
 * scaling lengths with (kT/U0)^(1/3) lambda, so the peak sits at f_c [1 + g (kT/U0)^(2/3)]
 * with width of that order and height D_eff / D ~ (U0/kT)^(2/3), both with corrections that
 * fall like (kT/U0)^(2/3). Checked: at U0 = 10 kT the peak is within one scaling width of
 * f_c and 2000 times the f = 0 value; for U0 = 10, 40, 160, 640 kT the scaled offset and
 * the scaled height converge, each step of 4 in U0 shrinking the change by more than 2
 * (theory: 4^(2/3) = 2.5). */
static void test_giant_diffusion(void) {
    const double u0s[] = {10.0, 40.0, 160.0, 640.0};
    double offset[4], height[4];
    for (int k = 0; k < 4; ++k) {
        const double fc = PI * u0s[k], width = pow(u0s[k], -2.0 / 3.0);
        double dmax = 0;
        const double fmax_ = deff_peak(u0s[k], 0.5 * fc, 1.5 * fc, &dmax);
        offset[k] = (fmax_ / fc - 1.0) / width;
        height[k] = dmax * width;
        if (k == 0) {
            CHECK(fabs(fmax_ / fc - 1.0) < width, "U0 = 10 kT: peak at f/f_c = %.5f", fmax_ / fc);
            CHECK(dmax > 2.0 && dmax > 1e3 * cosine_deff(u0s[k], 0.0) &&
                      dmax > cosine_deff(u0s[k], 0.5 * fc) && dmax > cosine_deff(u0s[k], 2 * fc),
                  "U0 = 10 kT: peak D_eff/D = %.4g", dmax);
        }
    }
    for (int k = 2; k < 4; ++k) {
        CHECK(fabs(offset[k] - offset[k - 1]) < 0.5 * fabs(offset[k - 1] - offset[k - 2]),
              "scaled peak offset not converging: %.5f %.5f %.5f", offset[k - 2], offset[k - 1],
              offset[k]);
        CHECK(fabs(height[k] - height[k - 1]) < 0.5 * fabs(height[k - 1] - height[k - 2]),
              "scaled peak height not converging: %.5f %.5f %.5f", height[k - 2], height[k - 1],
              height[k]);
    }
}

/* ---- an independent solution: finite differences of the Fokker-Planck equation ----
 * Backward operator on the periodic grid x_j = j h: (L g)_j = D (g_{j+1} - 2 g_j + g_{j-1}) / h^2
 * + b_j (g_{j+1} - g_{j-1}) / (2h), b = mu F. The stationary density is the null vector of
 * L^T (central differences of D p'' - (b p)'), <v> = int b p, and the corrector chi with
 * L chi = -(b - <v>) gives D_eff = D int p (1 + chi')^2. Second order in h; Richardson's
 * extrapolation from m and 2m points is fourth order. */

/* Thomas algorithm: sub[i] x[i-1] + diag[i] x[i] + sup[i] x[i+1] = rhs[i], i < n (in place) */
static void tridiagonal_solve(size_t n, const double *sub, double *diag, const double *sup,
                              double *rhs) {
    for (size_t i = 1; i < n; ++i) {
        const double w = sub[i] / diag[i - 1];
        diag[i] -= w * sup[i - 1];
        rhs[i] -= w * rhs[i - 1];
    }
    rhs[n - 1] /= diag[n - 1];
    for (size_t i = n - 1; i-- > 0;)
        rhs[i] = (rhs[i] - sup[i] * rhs[i + 1]) / diag[i];
}

typedef struct fd_result {
    double velocity, diffusion_eff, density_at[4]; /* density at x = 0, 1/4, 1/2, 3/4 */
} fd_result;

static fd_result fd_solve(const hsbd_washboard_params *p, size_t m) {
    const double h = p->period / (double)m, d = p->diffusion, mu = d / p->kT;
    double *work = calloc(7 * m, sizeof *work);
    if (!work) {
        fprintf(stderr, "fd_solve: out of memory\n");
        exit(1);
    }
    double *x = work, *b = work + m, *dens = work + 2 * m, *chi = work + 3 * m, *sub = work + 4 * m,
           *diag = work + 5 * m, *sup = work + 6 * m;
    for (size_t j = 0; j < m; ++j)
        x[j] = (double)j * h;
    hsbd_field_force(p->field, m, x, b);
    for (size_t j = 0; j < m; ++j)
        b[j] = mu * (b[j] + p->force);
    const double dd = d / (h * h), bh = 0.5 / h;
    /* L^T p = 0 with p_0 = p_m = 1: unknowns p_1 .. p_{m-1} */
    for (size_t j = 1; j < m; ++j) {
        const size_t i = j - 1;
        sub[i] = dd + bh * b[j - 1];
        diag[i] = -2 * dd;
        sup[i] = dd - bh * b[(j + 1) % m];
        dens[j] = 0;
    }
    dens[1] -= dd + bh * b[0];
    dens[m - 1] -= dd - bh * b[0];
    tridiagonal_solve(m - 1, sub, diag, sup, dens + 1);
    dens[0] = 1;
    double z = 0, v = 0;
    for (size_t j = 0; j < m; ++j)
        z += dens[j] * h;
    for (size_t j = 0; j < m; ++j) {
        dens[j] /= z;
        v += dens[j] * b[j] * h;
    }
    /* L chi = -(b - v) with chi_0 = chi_m = 0 */
    for (size_t j = 1; j < m; ++j) {
        const size_t i = j - 1;
        sub[i] = dd - bh * b[j];
        diag[i] = -2 * dd;
        sup[i] = dd + bh * b[j];
        chi[j] = -(b[j] - v);
    }
    tridiagonal_solve(m - 1, sub, diag, sup, chi + 1);
    chi[0] = 0;
    double deff = 0;
    for (size_t j = 0; j < m; ++j) {
        const double w = 1.0 + (chi[(j + 1) % m] - chi[(j + m - 1) % m]) * bh;
        deff += d * dens[j] * w * w * h;
    }
    fd_result r = {v, deff, {0}};
    for (int q = 0; q < 4; ++q)
        r.density_at[q] = dens[(size_t)q * m / 4];
    free(work);
    return r;
}

static double richardson(double coarse, double fine) {
    return (4.0 * fine - coarse) / 3.0;
}

/* The library's result against the extrapolated finite differences from 1024/2048 and
 * 2048/4096 points; the tolerance is the change between those two extrapolations (an upper
 * bound of the finer one's error for a fourth-order method) plus 1e-11 for the rounding of the
 * finite-difference solves (condition number ~ m^2). */
static void check_fd(const char *what, double ours, double c, double f, double ff) {
    const double r1 = richardson(c, f), r2 = richardson(f, ff);
    const double tol = fabs(r2 - r1) + 1e-11 * fabs(r2);
    CHECK(fabs(ours - r2) <= tol, "%s = %.13g, finite differences %.13g (error bar %.3g)", what,
          ours, r2, tol);
}

static void compare_with_fd(const char *what, const hsbd_washboard_params *p) {
    const size_t m = 1024;
    const fd_result c = fd_solve(p, m), f = fd_solve(p, 2 * m), ff = fd_solve(p, 4 * m);
    hsbd_washboard_params q = *p;
    q.points = 256; /* a multiple of 4: the density at the same four points */
    hsbd_washboard_result r = solve(&q);
    printf("%s: v %.13g, D_eff %.13g; finite differences (4096 points, extrapolated) %.13g, "
           "%.13g\n",
           what, r.velocity, r.diffusion_eff, richardson(f.velocity, ff.velocity),
           richardson(f.diffusion_eff, ff.diffusion_eff));
    check_fd("v", r.velocity, c.velocity, f.velocity, ff.velocity);
    check_fd("D_eff", r.diffusion_eff, c.diffusion_eff, f.diffusion_eff, ff.diffusion_eff);
    for (int k = 0; k < 4 && r.m == 256; ++k)
        check_fd("p", r.density[(size_t)k * 64], c.density_at[k], f.density_at[k],
                 ff.density_at[k]);
    hsbd_washboard_result_free(&r);
}

static void test_against_finite_differences(void) {
    const hsbd_field cosine = cosine_field(4.0, 1.0);
    hsbd_washboard_params p = params(&cosine, 8.0);
    compare_with_fd("cosine U0 = 4, f = 8", &p);
    const hsbd_field ratchet = ratchet_field(2.5, 1.0, 1.0);
    p = params(&ratchet, -3.0);
    p.kT = 0.8;
    p.diffusion = 0.6;
    compare_with_fd("ratchet A = 2.5, f = -3", &p);
}

/* Adiabatic rocking: U = 0 gives mu f0 exactly; F1 = 0 the static drift; a symmetric U and
 * f0 = 0 no drift; the ratchet a drift that agrees with an average over a whole drive period
 * computed here by the midpoint rule in time. */
static double static_v(const hsbd_washboard_params *p, double force) {
    hsbd_washboard_params q = *p;
    q.force = force;
    hsbd_washboard_result r = solve(&q);
    const double v = r.velocity;
    hsbd_washboard_result_free(&r);
    return v;
}

static hsbd_washboard_rocking_result rocking(const hsbd_washboard_params *p, double f0, double f1) {
    hsbd_washboard_rocking_result out;
    hsbd_error err;
    const int rc = hsbd_washboard_rocking(p, f0, f1, &out, &err);
    CHECK(rc == HSBD_OK, "rocking(f0 = %g, f1 = %g): %s", f0, f1, rc ? err.message : "");
    if (rc) out.velocity = out.error = NAN;
    return out;
}

static void test_rocking(void) {
    hsbd_washboard_params p = params(NULL, 0.0);
    p.diffusion = 0.7;
    p.kT = 1.3;
    hsbd_washboard_rocking_result r = rocking(&p, 2.5, 7.0);
    CHECK(rel(r.velocity, 0.7 / 1.3 * 2.5) <= 1e-12, "free rocking: v = %.17g", r.velocity);

    const hsbd_field cosine = cosine_field(6.0, 1.0);
    p = params(&cosine, 0.0);
    r = rocking(&p, 5.0, 0.0);
    CHECK(rel(r.velocity, static_v(&p, 5.0)) <= 1e-12, "f1 = 0: v = %.17g", r.velocity);
    r = rocking(&p, 0.0, 30.0);
    CHECK(fabs(r.velocity) <= 1e-12 * fabs(static_v(&p, 30.0)),
          "symmetric U, f0 = 0: v = %.3g (v(f1) = %.3g)", r.velocity, static_v(&p, 30.0));

    const hsbd_field ratchet = ratchet_field(2.0, 1.0, 1.0);
    p = params(&ratchet, 0.0);
    const double f0 = 0.5, f1 = 15.0;
    r = rocking(&p, f0, f1);
    /* (1/2pi) int_0^2pi v(f0 + f1 cos s) ds by the midpoint rule on the whole period (other
     * nodes than the library's trapezoid on [0, pi]; spectral too, the integrand is periodic) */
    const int n = 200;
    double avg = 0;
    for (int k = 0; k < n; ++k)
        avg += static_v(&p, f0 + f1 * cos(2 * PI * (k + 0.5) / n)) / n;
    CHECK(fabs(r.velocity) > 0.01 * fabs(static_v(&p, f0)),
          "ratchet: rocking drift %.3g indistinguishable from zero", r.velocity);
    CHECK(rel(r.velocity, avg) <= 1e-9 && r.error <= 1e-12,
          "ratchet rocking: v = %.15g (error %.3g), midpoint rule in time %.15g", r.velocity,
          r.error, avg);
}

static void test_bad_input(void) {
    hsbd_error err;
    hsbd_washboard_result r;
    const hsbd_field cosine = cosine_field(4.0, 1.0);
    hsbd_washboard_params p = params(&cosine, 1.0);
    p.diffusion = 0;
    CHECK(hsbd_washboard_solve(&p, &r, &err) == HSBD_EINPUT, "D = 0 accepted");
    p = params(&cosine, 1.0);
    p.points = 17;
    CHECK(hsbd_washboard_solve(&p, &r, &err) == HSBD_EINPUT, "odd points accepted");
    p = params(&cosine, 1.0);
    p.tol = 1e-16;
    CHECK(hsbd_washboard_solve(&p, &r, &err) == HSBD_EINPUT, "tol 1e-16 accepted");
    hsbd_field tilted = cosine;
    hsbd_field_add(&tilted, hsbd_field_tilt(2.0));
    p = params(&tilted, 1.0);
    CHECK(hsbd_washboard_solve(&p, &r, &err) == HSBD_EINPUT && strstr(err.message, "periodic"),
          "a tilt term in the field accepted: %s", err.message);
    const hsbd_field wrong_period = cosine_field(4.0, 0.7);
    p = params(&wrong_period, 1.0);
    CHECK(hsbd_washboard_solve(&p, &r, &err) == HSBD_EINPUT, "period 0.7 field accepted as 1");
    /* a kinked potential (the trap's nearest image jumps at center + 1/2) converges only
     * algebraically: too few points is an error, not a result */
    hsbd_field trap = {0};
    hsbd_field_add(&trap, hsbd_field_harmonic(40.0, 0.3, 1.0));
    p = params(&trap, 5.0);
    p.max_points = 512;
    CHECK(hsbd_washboard_solve(&p, &r, &err) == HSBD_ENUMERIC && r.density == NULL,
          "unconverged solve returned HSBD_OK");
    hsbd_washboard_rocking_result rr;
    p = params(&cosine, 0.0);
    CHECK(hsbd_washboard_rocking(&p, NAN, 1.0, &rr, &err) == HSBD_EINPUT, "rocking f0 = NaN");
}

int main(void) {
    test_free_particle();
    test_lifson_jackson();
    test_linear_response();
    test_convergence();
    test_scaling_invariance();
    test_symmetry();
    test_giant_diffusion();
    test_against_finite_differences();
    test_rocking();
    test_bad_input();
    return test_finish("test_washboard");
}
