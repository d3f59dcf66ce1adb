/* N hard rods between hard walls in an external field: the exact canonical density and
 * contact pair density from the nested configuration integral.
 *
 * With z_i = x_i - (i + 1/2) sigma the hard core and the walls become 0 <= z_0 <= ... <=
 * z_{N-1} <= l (l = L - N sigma), and the Boltzmann weight factorises into w_i(z_i) =
 * exp(-U(z_i + (i + 1/2) sigma)). With A_0 = 1, A_i(z) = int_0^z w_{i-1} A_{i-1} and
 * C_{N-1} = 1, C_i(z) = int_z^l w_{i+1} C_{i+1}, rod i has the marginal density
 * w_i A_i C_i / Z and the pair (i, i+1) the density at contact (z_i = z_{i+1} = z)
 * w_i A_i w_{i+1} C_{i+1} / Z, with Z = int w_i A_i C_i for any i. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/theory.h"

typedef struct box_grid {
    size_t m; /* intervals */
    double h; /* spacing in z */
} box_grid;

/* out_j = int_0^{z_j} f (trapezoid), scaled to max 1; returns the scale divided out */
static double cumulate_forward(const box_grid *g, const double *f, double *out) {
    out[0] = 0.0;
    for (size_t j = 1; j <= g->m; ++j)
        out[j] = out[j - 1] + 0.5 * g->h * (f[j - 1] + f[j]);
    const double s = out[g->m] > 0 ? out[g->m] : 1.0;
    for (size_t j = 0; j <= g->m; ++j)
        out[j] /= s;
    return s;
}

/* out_j = int_{z_j}^l f (trapezoid), scaled to max 1; returns the scale divided out */
static double cumulate_backward(const box_grid *g, const double *f, double *out) {
    out[g->m] = 0.0;
    for (size_t j = g->m; j-- > 0;)
        out[j] = out[j + 1] + 0.5 * g->h * (f[j] + f[j + 1]);
    const double s = out[0] > 0 ? out[0] : 1.0;
    for (size_t j = 0; j <= g->m; ++j)
        out[j] /= s;
    return s;
}

static double trapezoid(const box_grid *g, const double *f) {
    double s = 0.5 * (f[0] + f[g->m]);
    for (size_t j = 1; j < g->m; ++j)
        s += f[j];
    return s * g->h;
}

/* Add the integral of the piecewise-linear f(x_0 + j h) over each bin [k w, (k+1) w). */
static void add_to_bins(const box_grid *g, double x0, const double *f, double w, size_t nbins,
                        double *bins) {
    for (size_t j = 0; j < g->m; ++j) {
        const double xa = x0 + (double)j * g->h, xb = xa + g->h;
        const double slope = (f[j + 1] - f[j]) / g->h;
        double a = xa;
        while (a < xb) {
            double kf = floor(a / w);
            double b = (kf + 1.0) * w;
            if (b <= a) b = (kf += 1.0, (kf + 1.0) * w);
            if (b > xb) b = xb;
            if (kf >= 0 && kf < (double)nbins) {
                const double fa = f[j] + slope * (a - xa), fb = f[j] + slope * (b - xa);
                bins[(size_t)kf] += 0.5 * (b - a) * (fa + fb);
            }
            a = b;
        }
    }
}

/* w_i(z_j) = exp(-(U(z_j + offset) - U_min)): the constant cancels in every density */
static void boltzmann(const box_grid *g, const hsbd_field *field, double offset, double *w) {
    double umin = HUGE_VAL;
    for (size_t j = 0; j <= g->m; ++j) {
        w[j] = field ? hsbd_field_potential(field, (double)j * g->h + offset) : 0.0;
        if (w[j] < umin) umin = w[j];
    }
    for (size_t j = 0; j <= g->m; ++j)
        w[j] = exp(-(w[j] - umin));
}

void hsbd_box_result_free(hsbd_box_result *r) {
    if (!r) return;
    free(r->rho);
    free(r->rho2);
    r->rho = r->rho2 = NULL;
}

int hsbd_box_solve(const hsbd_box_params *p, double bin_width, hsbd_box_result *out,
                   hsbd_error *err) {
    memset(out, 0, sizeof *out);
    const size_t n = p->n;
    const double lf = p->length - (double)n * p->sigma;
    if (n < 1 || !(p->sigma >= 0) || !(lf > 0) || p->points < 2 || !(bin_width > 0) ||
        !(p->length / bin_width < 1e8))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "box theory: need N >= 1, sigma >= 0, N sigma < L, points >= 2 and "
                              "0 < bin width (N = %zu, sigma = %g, L = %g, points = %zu)",
                              n, p->sigma, p->length, p->points);
    const box_grid g = {p->points, lf / (double)p->points};
    const size_t m1 = g.m + 1;
    out->nbins = (size_t)ceil(p->length / bin_width - 1e-9);
    out->bin_width = bin_width;
    out->rho = calloc(out->nbins, sizeof *out->rho);
    out->rho2 = calloc(out->nbins, sizeof *out->rho2);
    double *a = malloc(n * m1 * sizeof *a); /* A_i, each scaled to max 1 */
    double *work = malloc(5 * m1 * sizeof *work);
    if (!out->rho || !out->rho2 || !a || !work) {
        free(a);
        free(work);
        hsbd_box_result_free(out);
        return hsbd_error_set(err, HSBD_ENOMEM, "box theory: out of memory (N = %zu, %zu points)",
                              n, p->points);
    }
    double *w = work, *wnext = work + m1, *c = work + 2 * m1, *cnext = work + 3 * m1,
           *f = work + 4 * m1;
    /* forward: A_i from w_{i-1} A_{i-1} */
    for (size_t j = 0; j < m1; ++j)
        a[j] = 1.0;
    for (size_t i = 1; i < n; ++i) {
        boltzmann(&g, p->field, (double)(i - 1) * p->sigma + 0.5 * p->sigma, w);
        for (size_t j = 0; j < m1; ++j)
            f[j] = w[j] * a[(i - 1) * m1 + j];
        cumulate_forward(&g, f, a + i * m1);
    }
    /* backward: C_i from w_{i+1} C_{i+1}, with each rod's densities on the way */
    for (size_t j = 0; j < m1; ++j)
        cnext[j] = 1.0;
    double scale_next = 1.0; /* C_{i+1} / C_i scale ratio of the normalised arrays */
    for (size_t i = n; i-- > 0;) {
        const double off = (double)i * p->sigma + 0.5 * p->sigma;
        boltzmann(&g, p->field, off, w);
        if (i + 1 < n) {
            for (size_t j = 0; j < m1; ++j)
                f[j] = wnext[j] * cnext[j];
            scale_next = cumulate_backward(&g, f, c);
        } else {
            memcpy(c, cnext, m1 * sizeof *c);
        }
        const double *ai = a + i * m1;
        for (size_t j = 0; j < m1; ++j)
            f[j] = w[j] * ai[j] * c[j];
        const double z = trapezoid(&g, f);
        for (size_t j = 0; j < m1; ++j)
            f[j] /= z;
        add_to_bins(&g, off, f, bin_width, out->nbins, out->rho);
        if (i == 0) out->wall_left = f[0];
        if (i + 1 == n) out->wall_right = f[g.m];
        if (i + 1 < n) { /* pair (i, i+1) at contact: w_i A_i w_{i+1} C_{i+1} / Z */
            for (size_t j = 0; j < m1; ++j)
                f[j] = w[j] * ai[j] * wnext[j] * cnext[j] / (scale_next * z);
            add_to_bins(&g, off, f, bin_width, out->nbins, out->rho2);
        }
        double *t = wnext;
        wnext = w;
        w = t;
        t = cnext;
        cnext = c;
        c = t;
    }
    for (size_t k = 0; k < out->nbins; ++k) {
        out->rho[k] /= bin_width;
        out->rho2[k] /= bin_width;
    }
    free(a);
    free(work);
    return HSBD_OK;
}
