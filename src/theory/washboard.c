/* One overdamped Brownian particle in a tilted periodic potential V(x) = U(x) - f x: exact
 * stationary drift, effective diffusion and density (derivation in docs/theory.md).
 *
 * With psi = V / kT, c = 1 - exp(-f lambda / kT) and the two window integrals
 *   I+(x) = int_0^lambda exp(psi(x + y) - psi(x)) dy,
 *   I-(x) = int_0^lambda exp(psi(x) - psi(x - y)) dy,
 * the stationary density is p = I+ / S with S = int_0^lambda I+, the drift is
 * <v> = lambda D c / S (Stratonovich) and D_eff = D lambda^2 int_0^lambda I+ I-^2 / S^3
 * (Reimann et al. 2001). For f >= 0 every exponent above is bounded by the largest rise of
 * psi, so all sums below have positive terms of moderate size; f < 0 is solved in the
 * mirrored frame x -> -x, where the tilt is positive. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/theory.h"

static const double PI = 3.141592653589793238462643383280;

enum { WB_GAUSS = 8, WB_FIRST_GRID = 64, WB_MIN_POINTS = 16, WB_FIRST_PHASES = 8 };
static const double WB_DEFAULT_TOL = 1e-10, WB_MIN_TOL = 1e-14; /* rounding: ~1e-15 */
static const size_t WB_DEFAULT_MAX_POINTS = (size_t)1 << 20;
static const size_t WB_MAX_PHASES = (size_t)1 << 14;

typedef struct wb_problem {
    const hsbd_field *field;
    double beta, lambda, diffusion;
    double beta_f;                               /* |f| / kT */
    double mirror;                               /* +1, or -1 when f < 0: U is evaluated at -x */
    double gauss_t[WB_GAUSS], gauss_w[WB_GAUSS]; /* Gauss-Legendre rule on [0, 1] */
} wb_problem;

typedef struct wb_level {
    size_t m;
    double velocity, diffusion_eff; /* velocity in the mirrored frame */
    double *density;                /* m values, mirrored frame */
} wb_level;

/* Nodes and weights of the n-point Gauss-Legendre rule on [0, 1] (Newton on P_n). */
static void gauss_legendre_unit(int n, double *t, double *w) {
    for (int i = 0; i < n; ++i) {
        double z = cos(PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; ++k) {
                const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0); /* P_n'(z) */
            const double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-15) break;
        }
        t[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp); /* half the weight on [-1, 1] */
    }
}

/* U(x) / kT in the frame of the solve */
static double beta_u(const wb_problem *pb, double x) {
    return pb->field ? pb->beta * hsbd_field_potential(pb->field, pb->mirror * x) : 0.0;
}

/* The cell integrals over [x_j, x_{j+1}] (Gauss-Legendre): cplus_j of exp(psi(z) - psi_j) and
 * cminus_j of exp(psi_{j+1} - psi(z)); u_j = beta U(x_j). */
static void cell_integrals(const wb_problem *pb, size_t m, const double *u, double *cplus,
                           double *cminus) {
    const double h = pb->lambda / (double)m, bfh = pb->beta_f * h;
    for (size_t j = 0; j < m; ++j) {
        const double u0 = u[j], u1 = u[(j + 1) % m];
        double sp = 0.0, sm = 0.0;
        for (int q = 0; q < WB_GAUSS; ++q) {
            const double t = pb->gauss_t[q];
            const double uq = beta_u(pb, ((double)j + t) * h);
            sp += pb->gauss_w[q] * exp(uq - u0 - bfh * t);
            sm += pb->gauss_w[q] * exp(u1 - uq - bfh * (1.0 - t));
        }
        cplus[j] = h * sp;
        cminus[j] = h * sm;
    }
}

static size_t argmax(size_t m, const double *u, double sign) {
    size_t best = 0;
    for (size_t j = 1; j < m; ++j)
        if (sign * u[j] > sign * u[best]) best = j;
    return best;
}

/* I+(x_j) = sum_{k=j}^{j+m-1} cplus_k exp(psi_k - psi_j): summed directly where U is largest
 * (every exponent <= 0 there), then around the circle by the exact recursion
 * I+_j = c cplus_j + exp(psi_{j+1} - psi_j) I+_{j+1} (positive terms only). */
static void window_plus(const wb_problem *pb, size_t m, const double *u, const double *cplus,
                        double c, double *iplus) {
    const double bfh = pb->beta_f * pb->lambda / (double)m;
    const size_t j0 = argmax(m, u, 1.0);
    double w = 0.0;
    for (size_t k = 0; k < m; ++k) {
        const size_t j = (j0 + k) % m;
        w += cplus[j] * exp(u[j] - u[j0] - bfh * (double)k);
    }
    iplus[j0] = w;
    for (size_t s = 1; s < m; ++s) {
        const size_t j = (j0 + m - s) % m, jn = (j + 1) % m;
        iplus[j] = c * cplus[j] + exp(u[jn] - u[j] - bfh) * iplus[jn];
    }
}

/* I-(x_j) = sum_{k=j-m}^{j-1} cminus_k exp(psi_j - psi_{k+1}): summed directly where U is
 * smallest, then I-_{j+1} = c cminus_j + exp(psi_{j+1} - psi_j) I-_j. */
static void window_minus(const wb_problem *pb, size_t m, const double *u, const double *cminus,
                         double c, double *iminus) {
    const double bfh = pb->beta_f * pb->lambda / (double)m;
    const size_t j0 = argmax(m, u, -1.0);
    double w = 0.0;
    for (size_t i = 1; i <= m; ++i) {
        const size_t k = (j0 + m - i) % m, k1 = (k + 1) % m;
        w += cminus[k] * exp(u[j0] - u[k1] - bfh * (double)(i - 1));
    }
    iminus[j0] = w;
    for (size_t s = 1; s < m; ++s) {
        const size_t j = (j0 + s - 1) % m, jn = (j + 1) % m;
        iminus[jn] = c * cminus[j] + exp(u[jn] - u[j] - bfh) * iminus[j];
    }
}

static double max_of(size_t m, const double *a) {
    double r = a[0];
    for (size_t j = 1; j < m; ++j)
        r = fmax(r, a[j]);
    return r;
}

/* v, D_eff and p on a grid of m points (trapezoid rule over x: spectral for smooth U). */
static int level_solve(const wb_problem *pb, size_t m, wb_level *out, hsbd_error *err) {
    out->m = m;
    out->density = malloc(m * sizeof *out->density);
    double *work = malloc(5 * m * sizeof *work);
    if (!out->density || !work) {
        free(work);
        free(out->density);
        out->density = NULL;
        return hsbd_error_set(err, HSBD_ENOMEM, "washboard theory: out of memory (%zu points)", m);
    }
    double *u = work, *cplus = work + m, *cminus = work + 2 * m, *iplus = work + 3 * m,
           *iminus = work + 4 * m;
    const double h = pb->lambda / (double)m;
    for (size_t j = 0; j < m; ++j)
        u[j] = beta_u(pb, (double)j * h);
    cell_integrals(pb, m, u, cplus, cminus);
    const double c = -expm1(-pb->beta_f * pb->lambda);
    window_plus(pb, m, u, cplus, c, iplus);
    window_minus(pb, m, u, cminus, c, iminus);
    /* the products are formed from arrays scaled to maximum 1 so they cannot overflow */
    const double mp = max_of(m, iplus), mm = max_of(m, iminus);
    double s = 0.0, q = 0.0;
    for (size_t j = 0; j < m; ++j) {
        const double a = iplus[j] / mp, b = iminus[j] / mm;
        s += a;
        q += a * b * b;
    }
    s *= h;
    q *= h;
    const double l = pb->lambda, ratio = mm / mp;
    out->velocity = l * pb->diffusion * c / (mp * s); /* lambda D c / S */
    out->diffusion_eff = pb->diffusion * l * l * ratio * ratio * q / (s * s * s); /* Q / S^3 */
    for (size_t j = 0; j < m; ++j)
        out->density[j] = iplus[j] / mp / s;
    free(work);
    if (!isfinite(mp) || !isfinite(mm) || !isfinite(out->velocity) ||
        !isfinite(out->diffusion_eff) || !(out->diffusion_eff > 0)) {
        free(out->density);
        out->density = NULL;
        return hsbd_error_set(err, HSBD_ENUMERIC,
                              "washboard theory: the integrals overflow on %zu points (barrier "
                              "too high for double precision)",
                              m);
    }
    return HSBD_OK;
}

static double relative_change(double coarse, double fine) {
    if (coarse == fine) return 0.0;
    return fabs(fine - coarse) / fmax(fabs(fine), fabs(coarse));
}

/* largest relative change of v, D_eff and p (on the coarse points) from coarse to fine */
static double level_change(const wb_level *coarse, const wb_level *fine) {
    double e = fmax(relative_change(coarse->velocity, fine->velocity),
                    relative_change(coarse->diffusion_eff, fine->diffusion_eff));
    const double pmax = max_of(fine->m, fine->density);
    for (size_t j = 0; j < coarse->m; ++j)
        e = fmax(e, fabs(fine->density[2 * j] - coarse->density[j]) / pmax);
    return e;
}

static int check_params(const hsbd_washboard_params *p, hsbd_error *err) {
    if (!(p->diffusion > 0) || !isfinite(p->diffusion) || !(p->kT > 0) || !isfinite(p->kT) ||
        !(p->period > 0) || !isfinite(p->period) || !isfinite(p->force) ||
        !(p->tol == 0 || (p->tol >= WB_MIN_TOL && p->tol < 1)))
        return hsbd_error_set(
            err, HSBD_EINPUT,
            "washboard theory: need D > 0, kT > 0, period > 0, a finite force "
            "and tol = 0 or 1e-14 <= tol < 1 (D = %g, kT = %g, period = %g, force = %g, tol = "
            "%g)",
            p->diffusion, p->kT, p->period, p->force, p->tol);
    if (p->points && (p->points < WB_MIN_POINTS || p->points % 2))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "washboard theory: points must be 0 (automatic) or even and >= %d "
                              "(got %zu)",
                              WB_MIN_POINTS, p->points);
    if (p->max_points && p->max_points < 2 * WB_FIRST_GRID)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "washboard theory: max_points must be 0 (default) or >= %d (got "
                              "%zu)",
                              2 * WB_FIRST_GRID, p->max_points);
    if (!p->field) return HSBD_OK;
    for (int i = 0; i < 8; ++i) {
        const double x = p->period * (i + 0.37) / 8.0;
        const double u0 = hsbd_field_potential(p->field, x);
        const double u1 = hsbd_field_potential(p->field, x + p->period);
        if (!isfinite(u0) || !(fabs(u1 - u0) <= 1e-8 * (p->kT + fabs(u0))))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "washboard theory: the field is not periodic with period %g "
                                  "(U(%g) = %g, U(%g) = %g); give a constant tilt as the force",
                                  p->period, x, u0, x + p->period, u1);
    }
    return HSBD_OK;
}

static wb_problem make_problem(const hsbd_washboard_params *p, double force) {
    wb_problem pb = {.field = p->field,
                     .beta = 1.0 / p->kT,
                     .lambda = p->period,
                     .diffusion = p->diffusion,
                     .beta_f = fabs(force) / p->kT,
                     .mirror = force < 0 ? -1.0 : 1.0};
    gauss_legendre_unit(WB_GAUSS, pb.gauss_t, pb.gauss_w);
    return pb;
}

/* The converged level (automatic grids) or the requested one, with its error estimate. */
static int solve_levels(const hsbd_washboard_params *p, double force, wb_level *best, double *error,
                        hsbd_error *err) {
    const wb_problem pb = make_problem(p, force);
    const double tol = p->tol > 0 ? p->tol : WB_DEFAULT_TOL;
    const size_t max_points = p->max_points ? p->max_points : WB_DEFAULT_MAX_POINTS;
    wb_level coarse = {0}, fine = {0};
    size_t m = p->points ? p->points / 2 : WB_FIRST_GRID;
    int rc = level_solve(&pb, m, &coarse, err);
    while (rc == HSBD_OK) {
        rc = level_solve(&pb, 2 * m, &fine, err);
        if (rc) break;
        *error = level_change(&coarse, &fine);
        if (p->points || *error <= tol) {
            free(coarse.density);
            *best = fine;
            return HSBD_OK;
        }
        if (4 * m > max_points) {
            rc = hsbd_error_set(err, HSBD_ENUMERIC,
                                "washboard theory: estimated error %.3g > tol %.3g at %zu points "
                                "(max_points %zu)",
                                *error, tol, 2 * m, max_points);
            break;
        }
        free(coarse.density);
        coarse = fine;
        fine.density = NULL;
        m *= 2;
    }
    free(coarse.density);
    free(fine.density);
    return rc;
}

void hsbd_washboard_result_free(hsbd_washboard_result *r) {
    if (!r) return;
    free(r->x);
    free(r->density);
    r->x = r->density = NULL;
}

int hsbd_washboard_solve(const hsbd_washboard_params *p, hsbd_washboard_result *out,
                         hsbd_error *err) {
    memset(out, 0, sizeof *out);
    int rc = check_params(p, err);
    if (rc) return rc;
    wb_level lv = {0};
    double error = 0.0;
    rc = solve_levels(p, p->force, &lv, &error, err);
    if (rc) return rc;
    const size_t m = lv.m;
    out->x = malloc(m * sizeof *out->x);
    out->density = malloc(m * sizeof *out->density);
    if (!out->x || !out->density) {
        free(lv.density);
        hsbd_washboard_result_free(out);
        return hsbd_error_set(err, HSBD_ENOMEM, "washboard theory: out of memory (%zu points)", m);
    }
    const double mirror = p->force < 0 ? -1.0 : 1.0;
    for (size_t j = 0; j < m; ++j) {
        out->x[j] = p->period * (double)j / (double)m;
        /* p(x_j) = p_mirrored(-x_j) = p_mirrored(x_{m-j}) */
        out->density[j] = mirror > 0 ? lv.density[j] : lv.density[(m - j) % m];
    }
    free(lv.density);
    out->m = m;
    out->velocity = mirror * lv.velocity;
    out->diffusion_eff = lv.diffusion_eff;
    out->error = error;
    return HSBD_OK;
}

/* static drift at tilt force and its error estimate */
static int static_velocity(const hsbd_washboard_params *p, double force, double *v, double *error,
                           hsbd_error *err) {
    wb_level lv = {0};
    const int rc = solve_levels(p, force, &lv, error, err);
    if (rc) return rc;
    *v = (force < 0 ? -1.0 : 1.0) * lv.velocity;
    free(lv.density);
    return HSBD_OK;
}

/* Adds the static drift at the phases theta_k = pi k / n for k = first, first + step, ... <= n
 * (trapezoid weights: half at both ends) to sum and abs_sum; solve_error collects the largest
 * error estimate. */
static int add_phases(const hsbd_washboard_params *p, double f0, double f1, size_t n, size_t first,
                      size_t step, double *sum, double *abs_sum, double *solve_error,
                      hsbd_error *err) {
    for (size_t k = first; k <= n; k += step) {
        double v = 0.0, e = 0.0;
        const int rc = static_velocity(p, f0 + f1 * cos(PI * (double)k / (double)n), &v, &e, err);
        if (rc) return rc;
        const double weight = (k == 0 || k == n) ? 0.5 : 1.0;
        *sum += weight * v;
        *abs_sum += weight * fabs(v);
        *solve_error = fmax(*solve_error, e);
    }
    return HSBD_OK;
}

int hsbd_washboard_rocking(const hsbd_washboard_params *p, double f0, double f1,
                           hsbd_washboard_rocking_result *out, hsbd_error *err) {
    memset(out, 0, sizeof *out);
    hsbd_washboard_params q = *p;
    q.force = 0.0; /* unused */
    p = &q;
    int rc = check_params(p, err);
    if (rc) return rc;
    if (!isfinite(f0) || !isfinite(f1))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "washboard rocking: need finite f0 and f1 (got %g, %g)", f0, f1);
    const double tol = p->tol > 0 ? p->tol : WB_DEFAULT_TOL;
    double sum = 0.0, abs_sum = 0.0, solve_error = 0.0;
    size_t n = WB_FIRST_PHASES;
    rc = add_phases(p, f0, f1, n, 0, 1, &sum, &abs_sum, &solve_error, err);
    if (rc) return rc;
    double avg = sum / (double)n;
    while (n < WB_MAX_PHASES) {
        /* doubling keeps the old phases: only the odd ones of the finer rule are new */
        rc = add_phases(p, f0, f1, 2 * n, 1, 2, &sum, &abs_sum, &solve_error, err);
        if (rc) return rc;
        n *= 2;
        const double next = sum / (double)n, scale = fmax(fabs(next), abs_sum / (double)n);
        const double change = scale > 0 ? fabs(next - avg) / scale : 0.0;
        avg = next;
        if (change <= tol) {
            out->velocity = avg;
            out->error = fmax(change, solve_error);
            out->phases = n;
            return HSBD_OK;
        }
    }
    return hsbd_error_set(err, HSBD_ENUMERIC,
                          "washboard rocking: the phase average has not converged to %.3g with "
                          "%zu phases",
                          tol, n);
}
