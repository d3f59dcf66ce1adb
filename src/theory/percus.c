/* Percus' exact density functional for hard rods in a periodic potential, hard
 * (Antonov Eqs. 20-23) and Baxter-sticky (Eqs. 34a-c), solved directly on a periodic grid:
 * the Euler-Lagrange equation written as a fixed point rho = G(rho) (canonical
 * normalisation, Eq. 22), iterated with Anderson acceleration on ln rho.
 *
 * Integrals: rho is taken piecewise linear between grid points and its cumulative
 * integral is evaluated exactly at any x (also off the grid, so sigma need not be a
 * multiple of the spacing): second-order accurate in the spacing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/theory.h"

typedef struct grid {
    size_t m;
    double h;
} grid;

static size_t wrap_index(long long n, size_t m) {
    long long j = n % (long long)m;
    return (size_t)(j < 0 ? j + (long long)m : j);
}

double hsbd_periodic_interp(const double *f, size_t m, double h, double x) {
    const double s = x / h;
    const double n = floor(s);
    const double t = s - n;
    const size_t j = wrap_index((long long)n, m), j1 = (j + 1) % m;
    return f[j] + t * (f[j1] - f[j]);
}

double hsbd_periodic_bin_average(const double *f, size_t m, double h, double x, double width) {
    enum { SUB = 64 };
    double s = 0;
    for (int i = 0; i < SUB; ++i)
        s += hsbd_periodic_interp(f, m, h, x - 0.5 * width + (i + 0.5) * width / SUB);
    return s / SUB;
}

/* cumulative trapezoid integral at the grid points; returns the integral over a period */
static double cumulate(const grid *g, const double *f, double *c) {
    c[0] = 0.0;
    for (size_t j = 1; j < g->m; ++j)
        c[j] = c[j - 1] + 0.5 * g->h * (f[j - 1] + f[j]);
    return c[g->m - 1] + 0.5 * g->h * (f[g->m - 1] + f[0]);
}

/* integral of the piecewise-linear f from 0 to x (any real x) */
static double cumulative_at(const grid *g, const double *f, const double *c, double total,
                            double x) {
    const double s = x / g->h;
    const double n = floor(s);
    const double t = s - n;
    const size_t j = wrap_index((long long)n, g->m), j1 = (j + 1) % g->m;
    const double periods = (n - (double)j) / (double)g->m;
    return periods * total + c[j] + g->h * t * (f[j] + 0.5 * t * (f[j1] - f[j]));
}

/* out_j = integral of f over [x_j + a, x_j + b] */
static void window_integral(const grid *g, const double *f, double *c, double a, double b,
                            double *out) {
    const double total = cumulate(g, f, c);
    for (size_t j = 0; j < g->m; ++j) {
        const double x = (double)j * g->h;
        out[j] = cumulative_at(g, f, c, total, x + b) - cumulative_at(g, f, c, total, x + a);
    }
}

typedef struct work {
    grid g;
    double sigma, gamma, rho_mean;
    double *beta_u;
    double *c, *eta, *eta_plus, *rho_plus, *q, *a_int, *khat, *kshift, *integrand, *ints;
} work;

/* rho' = G(rho) up to normalisation: fills out (unnormalised); returns 0, or -1 where a
 * packing fraction reaches 1 or a logarithm's argument is not positive. */
static int percus_map(work *w, const double *rho, double *out) {
    const grid *g = &w->g;
    const size_t m = g->m;
    window_integral(g, rho, w->c, -w->sigma, 0.0, w->eta); /* eta(x), Eq. 20b */
    for (size_t j = 0; j < m; ++j)
        if (!(w->eta[j] < 1.0) || !(rho[j] > 0)) return -1;
    if (w->gamma == 0.0) {
        for (size_t j = 0; j < m; ++j)
            w->q[j] = rho[j] / (1.0 - w->eta[j]);
        window_integral(g, w->q, w->c, 0.0, w->sigma, w->a_int); /* int_x^{x+s} rho/(1-eta) */
        for (size_t j = 0; j < m; ++j)
            out[j] = (1.0 - w->eta[j]) * exp(-w->beta_u[j] - w->a_int[j]);
        return 0;
    }
    /* sticky, Eqs. 34a-c, with everything at x + sigma interpolated */
    const double gm = w->gamma;
    for (size_t j = 0; j < m; ++j) {
        const double x = (double)j * g->h;
        w->rho_plus[j] = hsbd_periodic_interp(rho, m, g->h, x + w->sigma);
        w->eta_plus[j] = hsbd_periodic_interp(w->eta, m, g->h, x + w->sigma);
    }
    for (size_t j = 0; j < m; ++j) {
        const double inv = 1.0 / (1.0 - w->eta_plus[j]);
        const double a = (w->rho_plus[j] - rho[j]) * inv, b = w->rho_plus[j] * inv;
        const double bb = 1.0 - gm * a;
        w->khat[j] = 2.0 * b / (bb + sqrt(bb * bb + 4.0 * gm * b)); /* Eq. 34b, stable form */
        w->q[j] = a;                                                /* keep a_j */
        const double s = (w->rho_plus[j] + rho[j]) * inv;
        const double root = sqrt(1.0 + 2.0 * gm * s + gm * gm * a * a);
        w->integrand[j] = (s + 0.5 * gm * a * a) / (root + 1.0); /* (root - 1)/(2 gamma) */
    }
    window_integral(g, w->integrand, w->c, -w->sigma, 0.0, w->ints);
    for (size_t j = 0; j < m; ++j) {
        const double x = (double)j * g->h;
        w->kshift[j] = hsbd_periodic_interp(w->khat, m, g->h, x - w->sigma); /* Khat(x - s) */
    }
    for (size_t j = 0; j < m; ++j) {
        const double k_plus = w->khat[j] - w->q[j]; /* K(x + sigma), Eq. 34c */
        const double arg = k_plus * w->kshift[j] / rho[j];
        const double pack = (1.0 - w->eta[j]) * (1.0 - w->eta_plus[j]);
        if (!(arg > 0) || !(pack > 0)) return -1;
        const double r0 = log(arg) + w->beta_u[j] + 0.5 * log(pack) + w->ints[j];
        out[j] = rho[j] * exp(-r0);
    }
    return 0;
}

static double normalise(double *rho, size_t m, double mean) {
    double s = 0;
    for (size_t j = 0; j < m; ++j)
        s += rho[j];
    const double c = mean * (double)m / s;
    for (size_t j = 0; j < m; ++j)
        rho[j] *= c;
    return c;
}

/* Solve the small least-squares problem of Anderson mixing by normal equations. */
static int solve_small(int n, double *a, double *b) {
    for (int k = 0; k < n; ++k) {
        int piv = k;
        for (int i = k + 1; i < n; ++i)
            if (fabs(a[i * n + k]) > fabs(a[piv * n + k])) piv = i;
        if (fabs(a[piv * n + k]) < 1e-300) return -1;
        if (piv != k) {
            for (int j = 0; j < n; ++j) {
                const double t = a[k * n + j];
                a[k * n + j] = a[piv * n + j], a[piv * n + j] = t;
            }
            const double t = b[k];
            b[k] = b[piv], b[piv] = t;
        }
        for (int i = k + 1; i < n; ++i) {
            const double f = a[i * n + k] / a[k * n + k];
            for (int j = k; j < n; ++j)
                a[i * n + j] -= f * a[k * n + j];
            b[i] -= f * b[k];
        }
    }
    for (int k = n - 1; k >= 0; --k) {
        double s = b[k];
        for (int j = k + 1; j < n; ++j)
            s -= a[k * n + j] * b[j];
        b[k] = s / a[k * n + k];
    }
    return 0;
}

enum { DEPTH = 8 };

int hsbd_percus_solve(const hsbd_percus_params *p, hsbd_percus_result *out, hsbd_error *err) {
    memset(out, 0, sizeof *out);
    if (!(p->sigma >= 0) || !(p->rho_mean > 0) || !(p->rho_mean * p->sigma < 1))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "percus: need sigma >= 0, rho > 0 and rho*sigma < 1 (sigma = %g, "
                              "rho = %g)",
                              p->sigma, p->rho_mean);
    if (!(p->wavelength > 0) || !isfinite(p->amplitude) || !(p->gamma >= 0) || !isfinite(p->gamma))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "percus: need wavelength > 0, finite amplitude and gamma >= 0");
    if (p->points < 16 || p->points > 100000000)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "percus: points = %zu; allowed: 16 <= points <= 1e8", p->points);
    const size_t m = p->points;
    const double tol = p->tol > 0 ? p->tol : 1e-10;
    const int max_iter = p->max_iter > 0 ? p->max_iter : 20000;
    work w = {.g = {m, p->wavelength / (double)m},
              .sigma = p->sigma,
              .gamma = p->gamma,
              .rho_mean = p->rho_mean};
    const size_t nbuf = 11 + 4 * DEPTH + 4;
    double *mem = calloc(nbuf * m + DEPTH * DEPTH + DEPTH, sizeof *mem);
    if (!mem) return hsbd_error_set(err, HSBD_ENOMEM, "percus: out of memory");
    double **bufs[] = {&w.beta_u, &w.c,    &w.eta,    &w.eta_plus,  &w.rho_plus, &w.q,
                       &w.a_int,  &w.khat, &w.kshift, &w.integrand, &w.ints};
    for (size_t k = 0; k < sizeof bufs / sizeof bufs[0]; ++k)
        *bufs[k] = mem + k * m;
    double *rho = mem + 11 * m, *next = rho + m, *u = next + m, *f = u + m;
    double *du = f + m, *df = du + DEPTH * m; /* histories of differences */
    double *ata = df + DEPTH * m, *atb = ata + DEPTH * DEPTH;
    const double pi = 3.141592653589793238462643383280;
    for (size_t j = 0; j < m; ++j) /* Boltzmann start */
        w.beta_u[j] = 0.5 * p->amplitude * cos(2.0 * pi * (double)j / (double)m);
    for (size_t j = 0; j < m; ++j)
        rho[j] = exp(-w.beta_u[j]);
    normalise(rho, m, p->rho_mean);

    double alpha = 0.5, res = INFINITY, prev_res = INFINITY;
    int hist = 0, it = 0, status = HSBD_ENUMERIC;
    double *u_prev = calloc(2 * m, sizeof *u_prev);
    if (!u_prev) {
        free(mem);
        return hsbd_error_set(err, HSBD_ENOMEM, "percus: out of memory");
    }
    double *f_prev = u_prev + m;
    for (it = 0; it < max_iter; ++it) {
        if (percus_map(&w, rho, next) != 0) {
            /* the step went out of the physical domain: back off and restart mixing */
            if (it == 0 || alpha < 1e-6) break;
            alpha *= 0.5;
            hist = 0;
            for (size_t j = 0; j < m; ++j)
                rho[j] = exp(u_prev[j]);
            continue;
        }
        normalise(next, m, p->rho_mean);
        res = 0;
        for (size_t j = 0; j < m; ++j) {
            res = fmax(res, fabs(next[j] - rho[j]));
            u[j] = log(rho[j]);
            f[j] = log(next[j]) - u[j];
        }
        if (res < tol) {
            status = HSBD_OK;
            memcpy(rho, next, m * sizeof *rho);
            break;
        }
        if (res > 10 * prev_res) hist = 0, alpha = fmax(alpha * 0.5, 1e-3);
        prev_res = res;
        /* Anderson: differences to the previous iterate */
        if (it > 0) {
            const int slot = hist % DEPTH;
            for (size_t j = 0; j < m; ++j) {
                du[slot * m + j] = u[j] - u_prev[j];
                df[slot * m + j] = f[j] - f_prev[j];
            }
            ++hist;
        }
        memcpy(u_prev, u, m * sizeof *u);
        memcpy(f_prev, f, m * sizeof *f);
        const int k = hist < DEPTH ? hist : DEPTH;
        double gam[DEPTH] = {0};
        if (k > 0) {
            for (int a = 0; a < k; ++a) {
                for (int b = 0; b < k; ++b) {
                    double s = 0;
                    for (size_t j = 0; j < m; ++j)
                        s += df[a * m + j] * df[b * m + j];
                    ata[a * k + b] = s + (a == b ? 1e-12 * s + 1e-300 : 0);
                }
                double s = 0;
                for (size_t j = 0; j < m; ++j)
                    s += df[a * m + j] * f[j];
                atb[a] = s;
            }
            if (solve_small(k, ata, atb) == 0)
                for (int a = 0; a < k; ++a)
                    gam[a] = atb[a];
        }
        for (size_t j = 0; j < m; ++j) {
            double uj = u[j] + alpha * f[j];
            for (int a = 0; a < k; ++a)
                uj -= gam[a] * (du[a * m + j] + alpha * df[a * m + j]);
            rho[j] = exp(uj);
        }
        normalise(rho, m, p->rho_mean);
    }
    free(u_prev);
    if (status != HSBD_OK) {
        free(mem);
        return hsbd_error_set(err, HSBD_ENUMERIC,
                              "percus: no convergence after %d iterations (residual %.3g > %.3g; "
                              "sigma = %g, rho = %g, U0 = %g, gamma = %g)",
                              it, res, tol, p->sigma, p->rho_mean, p->amplitude, p->gamma);
    }
    /* results: profile, contact density (Eq. 23), chemical potential */
    out->m = m;
    out->x = malloc(3 * m * sizeof *out->x);
    if (!out->x) {
        free(mem);
        return hsbd_error_set(err, HSBD_ENOMEM, "percus: out of memory");
    }
    out->rho = out->x + m;
    out->rho2 = out->rho + m;
    memcpy(out->rho, rho, m * sizeof *rho);
    percus_map(&w, rho, next);
    const double c = normalise(next, m, p->rho_mean);
    out->beta_mu = log(c); /* rho = e^{beta mu} G_unnormalised(rho) at the fixed point */
    window_integral(&w.g, rho, w.c, -p->sigma, 0.0, w.eta);
    for (size_t j = 0; j < m; ++j) {
        const double x = (double)j * w.g.h;
        out->x[j] = x;
        if (p->gamma == 0.0) {
            const double rp = hsbd_periodic_interp(rho, m, w.g.h, x + p->sigma);
            const double ep = hsbd_periodic_interp(w.eta, m, w.g.h, x + p->sigma);
            out->rho2[j] = rho[j] * rp / (1.0 - ep);
        } else {
            out->rho2[j] = NAN;
        }
    }
    out->residual = res;
    out->iterations = it;
    free(mem);
    return HSBD_OK;
}

void hsbd_percus_result_free(hsbd_percus_result *r) {
    if (r) free(r->x);
    if (r) memset(r, 0, sizeof *r);
}
