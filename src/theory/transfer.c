/* Exact equilibrium of rods with a nearest-neighbour pair potential (pair range <= 2
 * sigma), homogeneous (Takahashi) and in a periodic field (transfer operator). With no
 * pair term this is the hard-rod fluid again, an independent check of the Percus solver;
 * with the sticky delta_eps term it is the exact theory of the model the simulator runs
 * (Antonov Eqs. 31-32 at finite epsilon), which Eqs. 34 (Baxter's epsilon -> 0 limit)
 * approach as epsilon -> 0. Derivation: docs/theory.md. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/pair.h"
#include "hsbd/theory.h"

/* gap weight relative to the hard core: w(h) = exp(-V(sigma + h)), h >= 0 */
static double gap_weight(const hsbd_pair *pair, double sigma, double h) {
    return pair->nterms ? exp(-hsbd_pair_potential(pair, sigma + h)) : 1.0;
}

static double interaction_gap(const hsbd_pair *pair, double sigma) {
    const double r = hsbd_pair_range(pair) - sigma;
    return r > 0 ? r : 0.0;
}

/* ---- homogeneous fluid: isobaric nearest-neighbour gap law ---------------------------- */

/* Z = int_0^inf w(h) e^{-b h} dh and M = int h w e^{-b h} dh / Z: Simpson on [0, hc],
 * exact exponential tail beyond (w = 1 there). */
static void gap_moments(const hsbd_pair *pair, double sigma, double b, double *z, double *mean) {
    enum { PANELS = 4000 };
    const double hc = interaction_gap(pair, sigma);
    double s0 = 0, s1 = 0;
    if (hc > 0) {
        const double dh = hc / PANELS;
        for (int k = 0; k <= PANELS; ++k) {
            const double h = k * dh, c = (k == 0 || k == PANELS) ? 1.0 : (k % 2 ? 4.0 : 2.0);
            const double f = c * gap_weight(pair, sigma, h) * exp(-b * h);
            s0 += f;
            s1 += f * h;
        }
        s0 *= dh / 3.0;
        s1 *= dh / 3.0;
    }
    const double tail = exp(-b * hc);
    *z = s0 + tail / b;
    *mean = (s1 + tail * (hc / b + 1.0 / (b * b))) / *z;
}

int hsbd_nn_homogeneous_solve(const hsbd_pair *pair, double sigma, double rho, double *beta_p,
                              double *contact, hsbd_error *err) {
    if (!(sigma > 0) || !(rho > 0) || !(rho * sigma < 1))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "nearest-neighbour fluid: need sigma > 0, rho > 0, rho sigma < 1 "
                              "(sigma = %g, rho = %g)",
                              sigma, rho);
    if (hsbd_pair_range(pair) > 2.0 * sigma)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "nearest-neighbour fluid: pair range %g exceeds 2 sigma = %g",
                              hsbd_pair_range(pair), 2 * sigma);
    const double target = 1.0 / rho - sigma;       /* mean gap */
    double lo = -40.0, hi = 40.0, z = 0, mean = 0; /* bisection in ln(beta P) */
    for (int it = 0; it < 200; ++it) {
        const double mid = 0.5 * (lo + hi);
        gap_moments(pair, sigma, exp(mid), &z, &mean);
        if (mean > target)
            lo = mid; /* more pressure, smaller gaps */
        else
            hi = mid;
    }
    const double b = exp(0.5 * (lo + hi));
    gap_moments(pair, sigma, b, &z, &mean);
    *beta_p = b;
    *contact = rho * gap_weight(pair, sigma, 0.0) / z; /* rho p(0+) */
    return HSBD_OK;
}

/* ---- periodic field: transfer operator on a grid ------------------------------------- */

typedef struct transfer {
    size_t m;
    double h, lambda, sigma, range;
    const hsbd_pair *pair;
    double *bf;        /* e^{-beta U(x_j)} */
    double *c, *cd;    /* circulant kernel sum_k K(d) and sum_k d K(d), d = delta h + k lambda */
    double *r, *l, *t; /* right and left eigenvectors, scratch */
    double eig;
} transfer;

/* K(d) = w(d - sigma) e^{-b (d - sigma)} for d > sigma (0 below); the jump at d = sigma
 * gets the half weight of the trapezoid rule when it falls on a node. */
static void build_kernel(transfer *t, double b) {
    const double q = exp(-b * t->lambda), tol = 1e-9 * t->h;
    for (size_t dl = 0; dl < t->m; ++dl) {
        double s = 0, sd = 0, d = (double)dl * t->h;
        for (;; d += t->lambda) {
            if (d >= t->range && d >= t->sigma + tol) { /* free tail: w = 1, geometric sum */
                const double e = exp(-b * (d - t->sigma));
                s += e / (1.0 - q);
                sd += e * (d / (1.0 - q) + t->lambda * q / ((1.0 - q) * (1.0 - q)));
                break;
            }
            if (d < t->sigma - tol) continue;
            double k = gap_weight(t->pair, t->sigma, d - t->sigma > 0 ? d - t->sigma : 0.0) *
                       exp(-b * (d - t->sigma));
            if (fabs(d - t->sigma) <= tol) k *= 0.5;
            s += k;
            sd += k * d;
        }
        t->c[dl] = s;
        t->cd[dl] = sd;
    }
}

/* out_i = sum_j kern[(j - i) mod m] bf_j h v_j (right) or out_j = bf_j h sum_i v_i kern[...] */
static void apply(const transfer *t, const double *kern, const double *v, double *out, int left) {
    const size_t m = t->m;
    for (size_t i = 0; i < m; ++i) {
        double s = 0;
        if (!left) {
            for (size_t j = 0; j < m; ++j)
                s += kern[j >= i ? j - i : j + m - i] * t->bf[j] * v[j];
            out[i] = s * t->h;
        } else {
            for (size_t k = 0; k < m; ++k)
                s += v[k] * kern[i >= k ? i - k : i + m - k];
            out[i] = s * t->bf[i] * t->h;
        }
    }
}

/* Perron vector by power iteration; returns the eigenvalue, or NAN without convergence. */
static double perron(const transfer *t, double *v, int left, double tol, int max_iter) {
    double eig = 0;
    for (int it = 0; it < max_iter; ++it) {
        apply(t, t->c, v, t->t, left);
        double norm = 0;
        for (size_t i = 0; i < t->m; ++i)
            norm = fmax(norm, t->t[i]);
        double change = 0;
        for (size_t i = 0; i < t->m; ++i) {
            const double nv = t->t[i] / norm;
            change = fmax(change, fabs(nv - v[i]));
            v[i] = nv;
        }
        eig = norm;
        if (change < tol && it > 2) return eig;
    }
    return NAN;
}

/* Mean density 1/E for pressure b, with the eigenvectors left in t (warm start). */
static double mean_density(transfer *t, double b, double tol, int max_iter) {
    build_kernel(t, b);
    const double er = perron(t, t->r, 0, tol, max_iter), el = perron(t, t->l, 1, tol, max_iter);
    if (!isfinite(er) || !isfinite(el)) return NAN;
    t->eig = er;
    apply(t, t->cd, t->r, t->t, 0);
    double num = 0, den = 0;
    for (size_t i = 0; i < t->m; ++i) {
        num += t->l[i] * t->t[i];
        den += t->l[i] * t->r[i];
    }
    return den * er / num; /* 1 / E, E = sum_i pi_i (cd R)_i / (Lambda R_i) */
}

int hsbd_nn_transfer_solve(const hsbd_percus_params *p, const hsbd_pair *pair,
                           hsbd_percus_result *out, hsbd_error *err) {
    memset(out, 0, sizeof *out);
    const size_t m = p->points;
    if (!(p->sigma > 0) || !(p->rho_mean > 0) || !(p->rho_mean * p->sigma < 1) || m < 16 ||
        !(p->wavelength > 0) || !isfinite(p->amplitude))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "transfer: need sigma > 0, rho > 0, rho sigma < 1, points >= 16, "
                              "wavelength > 0 (sigma = %g, rho = %g, points = %zu)",
                              p->sigma, p->rho_mean, m);
    if (hsbd_pair_range(pair) > 2.0 * p->sigma)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "transfer: pair range %g exceeds 2 sigma = %g (nearest neighbours "
                              "only)",
                              hsbd_pair_range(pair), 2 * p->sigma);
    transfer t = {.m = m,
                  .h = p->wavelength / (double)m,
                  .lambda = p->wavelength,
                  .sigma = p->sigma,
                  .range = hsbd_pair_range(pair) > p->sigma ? hsbd_pair_range(pair) : p->sigma,
                  .pair = pair};
    double *mem = malloc(7 * m * sizeof *mem);
    if (!mem) return hsbd_error_set(err, HSBD_ENOMEM, "transfer: out of memory");
    t.bf = mem, t.c = mem + m, t.cd = mem + 2 * m, t.r = mem + 3 * m, t.l = mem + 4 * m;
    t.t = mem + 5 * m;
    double *rho = mem + 6 * m;
    const double two_pi = 6.283185307179586476925286766559;
    for (size_t j = 0; j < m; ++j) {
        t.bf[j] = exp(-0.5 * p->amplitude * cos(two_pi * (double)j / (double)m));
        t.r[j] = t.l[j] = 1.0;
    }
    const double tol = p->tol > 0 ? p->tol : 1e-12;
    const int max_iter = p->max_iter > 0 ? p->max_iter : 200000;
    /* solve ln(rho(b)) = ln(rho_mean) for ln b: bracket, then Illinois regula falsi */
    double bp0, c0;
    hsbd_nn_homogeneous_solve(pair, p->sigma, p->rho_mean, &bp0, &c0, NULL);
    double a = log(bp0) - 0.5, fb, fa = log(mean_density(&t, exp(a), tol, max_iter) / p->rho_mean);
    double b = log(bp0) + 0.5;
    fb = log(mean_density(&t, exp(b), tol, max_iter) / p->rho_mean);
    for (int k = 0; k < 60 && isfinite(fa) && isfinite(fb) && fa * fb > 0; ++k) {
        if (fa > 0) {
            b = a, fb = fa, a -= 1.0;
            fa = log(mean_density(&t, exp(a), tol, max_iter) / p->rho_mean);
        } else {
            a = b, fa = fb, b += 1.0;
            fb = log(mean_density(&t, exp(b), tol, max_iter) / p->rho_mean);
        }
    }
    int side = 0, it = 0;
    double x = b, fx = fb;
    for (; it < 200 && isfinite(fa) && isfinite(fb) && fabs(fx) > 1e-13; ++it) {
        x = (a * fb - b * fa) / (fb - fa);
        fx = log(mean_density(&t, exp(x), tol, max_iter) / p->rho_mean);
        if (!isfinite(fx)) break;
        if (fx * fb > 0) {
            b = x, fb = fx;
            if (side == -1) fa *= 0.5;
            side = -1;
        } else {
            a = x, fa = fx;
            if (side == 1) fb *= 0.5;
            side = 1;
        }
    }
    if (!isfinite(fx) || fabs(fx) > 1e-13) {
        free(mem);
        return hsbd_error_set(err, HSBD_ENUMERIC,
                              "transfer: no convergence (sigma = %g, rho = %g, U0 = %g, points = "
                              "%zu; eigenvector tolerance %g, %d iterations)",
                              p->sigma, p->rho_mean, p->amplitude, m, tol, max_iter);
    }
    const double inv_rho = 1.0 / exp(fx) / p->rho_mean; /* E at the solution */
    /* density: rho_i = lambda pi_i / (h E), pi_i = l_i r_i / sum l r */
    double lr = 0;
    for (size_t j = 0; j < m; ++j)
        lr += t.l[j] * t.r[j];
    for (size_t j = 0; j < m; ++j)
        rho[j] = p->wavelength * t.l[j] * t.r[j] / (lr * t.h * inv_rho);
    out->m = m;
    out->x = malloc(3 * m * sizeof *out->x);
    if (!out->x) {
        free(mem);
        return hsbd_error_set(err, HSBD_ENOMEM, "transfer: out of memory");
    }
    out->rho = out->x + m;
    out->rho2 = out->rho + m;
    /* pair density at contact: rho(x) K(sigma+) bf(x + sigma) R(x + sigma) / (Lambda R(x)) */
    const double k_contact = gap_weight(pair, p->sigma, 0.0);
    for (size_t j = 0; j < m; ++j) {
        const double x0 = (double)j * t.h;
        out->x[j] = x0;
        out->rho[j] = rho[j];
        const double bf_plus =
            exp(-0.5 * p->amplitude * cos(two_pi * (x0 + p->sigma) / p->wavelength));
        const double r_plus = hsbd_periodic_interp(t.r, m, t.h, x0 + p->sigma);
        out->rho2[j] = rho[j] * k_contact * bf_plus * r_plus / (t.eig * t.r[j]);
    }
    out->beta_mu = NAN;
    out->residual = fabs(fx);
    out->iterations = it;
    free(mem);
    return HSBD_OK;
}
