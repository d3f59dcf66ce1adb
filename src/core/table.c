/* Cubic spline tables, natural or periodic (see include/hsbd/table.h). */
#include "hsbd/table.h"

#include "core/input.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct hsbd_table {
    size_t n;
    double *x, *y, *m; /* knots, values, second derivatives of the spline */
    double *cum;       /* integral of the spline from x[0] to x[k] */
};

void hsbd_table_free(hsbd_table *t) {
    if (!t) return;
    free(t->x);
    free(t->y);
    free(t->m);
    free(t->cum);
    free(t);
}

/* Second derivatives of the natural spline (M_0 = M_{n-1} = 0): tridiagonal solve. */
static void spline_second_derivatives(hsbd_table *t, double *scratch) {
    const size_t n = t->n;
    const double *x = t->x, *y = t->y;
    double *m = t->m, *c = scratch;
    m[0] = m[n - 1] = 0.0;
    if (n < 3) return;
    /* rows i = 1..n-2: h0 M_{i-1} + 2 (h0 + h1) M_i + h1 M_{i+1} = 6 (s1 - s0) */
    c[0] = 0.0;
    for (size_t i = 1; i + 1 < n; ++i) {
        const double h0 = x[i] - x[i - 1], h1 = x[i + 1] - x[i];
        const double rhs = 6.0 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
        const double diag = 2.0 * (h0 + h1) - h0 * c[i - 1];
        c[i] = h1 / diag;
        m[i] = (rhs - h0 * m[i - 1]) / diag;
    }
    for (size_t i = n - 2; i >= 1; --i)
        m[i] -= c[i] * m[i + 1];
}

/* Thomas algorithm for the tridiagonal rows lo[i] u_{i-1} + d[i] u_i + up[i] u_{i+1} =
 * rhs[i] (lo[0], up[m-1] unused), in place in rhs; c: m scratch values. */
static void solve_tridiagonal(size_t m, const double *lo, const double *d, const double *up,
                              double *rhs, double *c) {
    c[0] = up[0] / d[0];
    rhs[0] /= d[0];
    for (size_t i = 1; i < m; ++i) {
        const double den = d[i] - lo[i] * c[i - 1];
        c[i] = i + 1 < m ? up[i] / den : 0.0;
        rhs[i] = (rhs[i] - lo[i] * rhs[i - 1]) / den;
    }
    for (size_t i = m - 1; i-- > 0;)
        rhs[i] -= c[i] * rhs[i + 1];
}

/* Second derivatives of the periodic spline through y_0 .. y_{n-1} = y_0: with m = n - 1
 * intervals h_i, rows i = 0..m-1 read h_{i-1} M_{i-1} + 2 (h_{i-1} + h_i) M_i + h_i M_{i+1}
 * = 6 (s_i - s_{i-1}) with indices modulo m (s_i the slope of interval i). The cyclic
 * system is solved as a tridiagonal one plus a rank-one correction (Sherman-Morrison).
 * Returns -1 when out of memory. */
static int spline_second_derivatives_periodic(hsbd_table *t) {
    const size_t m = t->n - 1;
    const double *x = t->x, *y = t->y;
    double *M = t->m;
    if (m < 2) { /* one interval: both ends hold the same value, a constant */
        M[0] = M[1] = 0.0;
        return 0;
    }
    double *w = malloc(6 * m * sizeof *w);
    if (!w) return -1;
    double *lo = w, *d = w + m, *up = w + 2 * m, *z = w + 3 * m, *c = w + 4 * m, *h = w + 5 * m;
    for (size_t i = 0; i < m; ++i)
        h[i] = x[i + 1] - x[i];
    for (size_t i = 0; i < m; ++i) {
        const size_t prev = i ? i - 1 : m - 1;
        lo[i] = h[prev];
        d[i] = 2.0 * (h[prev] + h[i]);
        up[i] = h[i];
        M[i] = 6.0 * ((y[i + 1] - y[i]) / h[i] - (y[prev + 1] - y[prev]) / h[prev]);
    }
    if (m == 2) { /* both off-diagonals couple the same two unknowns */
        const double a = d[0], b = lo[0] + up[0], e = d[1], r0 = M[0], r1 = M[1];
        const double det = a * e - b * b;
        M[0] = (r0 * e - b * r1) / det;
        M[1] = (a * r1 - b * r0) / det;
    } else { /* corners: row 0 has lo[0] on M_{m-1}, row m-1 has up[m-1] on M_0 */
        const double beta = lo[0], alpha = up[m - 1], gamma = -d[0];
        d[0] -= gamma;
        d[m - 1] -= alpha * beta / gamma;
        for (size_t i = 0; i < m; ++i)
            z[i] = 0.0;
        z[0] = gamma;
        z[m - 1] = alpha;
        solve_tridiagonal(m, lo, d, up, M, c);
        solve_tridiagonal(m, lo, d, up, z, c);
        const double fact =
            (M[0] + beta * M[m - 1] / gamma) / (1.0 + z[0] + beta * z[m - 1] / gamma);
        for (size_t i = 0; i < m; ++i)
            M[i] -= fact * z[i];
    }
    M[m] = M[0];
    free(w);
    return 0;
}

/* Integral of the spline over [x_k, x_k + a] inside interval k. */
static double interval_integral(const hsbd_table *t, size_t k, double a) {
    const double h = t->x[k + 1] - t->x[k], b = h - a;
    const double c = t->y[k] / h - t->m[k] * h / 6.0, d = t->y[k + 1] / h - t->m[k + 1] * h / 6.0;
    return t->m[k] * (h * h * h * h - b * b * b * b) / (24.0 * h) +
           t->m[k + 1] * a * a * a * a / (24.0 * h) + c * (h * h - b * b) / 2.0 + d * a * a / 2.0;
}

/* cum[k]: integral of the spline from x[0] to x[k] */
static void cumulative_integrals(hsbd_table *t) {
    t->cum[0] = 0.0;
    for (size_t k = 0; k + 1 < t->n; ++k)
        t->cum[k + 1] = t->cum[k] + interval_integral(t, k, t->x[k + 1] - t->x[k]);
}

hsbd_table *hsbd_table_alloc(size_t n, const double *x, const double *y, const char *what,
                             hsbd_error *err) {
    if (n < 2)
        return hsbd_error_set(err, HSBD_EINPUT, "%s: a table needs at least 2 points, got %zu",
                              what, n),
               NULL;
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(x[i]) || !isfinite(y[i]))
            return hsbd_error_set(err, HSBD_EINPUT, "%s: point %zu is not finite (%g, %g)", what,
                                  i + 1, x[i], y[i]),
                   NULL;
        if (i > 0 && !(x[i] > x[i - 1]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: x must increase strictly, but point %zu has x = %.17g "
                                  "after %.17g",
                                  what, i + 1, x[i], x[i - 1]),
                   NULL;
    }
    hsbd_table *t = calloc(1, sizeof *t);
    double *scratch = malloc(n * sizeof *scratch);
    if (t) {
        t->n = n;
        t->x = malloc(n * sizeof *t->x);
        t->y = malloc(n * sizeof *t->y);
        t->m = malloc(n * sizeof *t->m);
        t->cum = malloc(n * sizeof *t->cum);
    }
    if (!t || !scratch || !t->x || !t->y || !t->m || !t->cum) {
        hsbd_table_free(t);
        free(scratch);
        return hsbd_error_set(err, HSBD_ENOMEM, "%s: out of memory for %zu points", what, n), NULL;
    }
    memcpy(t->x, x, n * sizeof *x);
    memcpy(t->y, y, n * sizeof *y);
    spline_second_derivatives(t, scratch);
    free(scratch);
    cumulative_integrals(t);
    return t;
}

int hsbd_table_make_periodic(hsbd_table *t, const char *what, hsbd_error *err) {
    const size_t n = t->n;
    double scale = 0.0;
    for (size_t i = 0; i < n; ++i)
        scale = fmax(scale, fabs(t->y[i]));
    if (fabs(t->y[n - 1] - t->y[0]) > 1e-9 * scale)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: a periodic table needs equal values at its ends, but the "
                              "value at x = %.17g is %.17g and at x = %.17g it is %.17g; allowed: "
                              "a difference of at most 1e-9 of the largest |value| (%g)",
                              what, t->x[0], t->y[0], t->x[n - 1], t->y[n - 1], scale);
    t->y[n - 1] = t->y[0];
    if (spline_second_derivatives_periodic(t) != 0)
        return hsbd_error_set(err, HSBD_ENOMEM, "%s: out of memory for %zu points", what, n);
    cumulative_integrals(t);
    return HSBD_OK;
}

static int is_blank(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* a decimal number at *s followed by a blank or the end of the line; advances *s */
static int scan_column(const char **s, double *v) {
    while (is_blank(**s))
        ++*s;
    const size_t len = hsbd_scan_decimal(*s, v);
    if (len == 0 || !isfinite(*v) || !(is_blank((*s)[len]) || (*s)[len] == '\0')) return -1;
    *s += len;
    return 0;
}

hsbd_table *hsbd_table_read(FILE *f, const char *name, hsbd_error *err) {
    size_t n = 0, cap = 0;
    double *x = NULL, *y = NULL;
    hsbd_lines in;
    hsbd_lines_init(&in, f, name);
    int ok = 1, got;
    while (ok && (got = hsbd_lines_next(&in, err)) > 0) {
        const char *s = in.text;
        while (is_blank(*s))
            ++s;
        if (*s == '#' || *s == '\0') continue;
        const char *p = s;
        double a, b;
        if (scan_column(&p, &a) != 0 || scan_column(&p, &b) != 0) {
            hsbd_error_set(err, HSBD_EINPUT,
                           "%s:%ld: expected two finite numbers 'x value', got '%.60s'", name,
                           in.number, s);
            ok = 0;
            break;
        }
        if (n > 0 && !(a > x[n - 1])) {
            hsbd_error_set(err, HSBD_EINPUT,
                           "%s:%ld: x = %.17g does not increase (previous x = %.17g); the first "
                           "column must be strictly increasing",
                           name, in.number, a, x[n - 1]);
            ok = 0;
            break;
        }
        if (n == cap) {
            cap = cap ? 2 * cap : 256;
            double *nx = realloc(x, cap * sizeof *x), *ny = nx ? realloc(y, cap * sizeof *y) : NULL;
            if (nx) x = nx;
            if (ny) y = ny;
            if (!nx || !ny) {
                hsbd_error_set(err, HSBD_ENOMEM, "%s: out of memory", name);
                ok = 0;
                break;
            }
        }
        x[n] = a, y[n] = b, ++n;
    }
    if (ok && got < 0) ok = 0;
    hsbd_lines_free(&in);
    hsbd_table *t = NULL;
    if (ok) t = hsbd_table_alloc(n, x, y, name, err);
    free(x);
    free(y);
    return t;
}

hsbd_table *hsbd_table_load(const char *path, hsbd_error *err) {
    FILE *f = hsbd_input_open(path, "table", err);
    if (!f) return NULL;
    hsbd_table *t = hsbd_table_read(f, path, err);
    fclose(f);
    return t;
}

size_t hsbd_table_size(const hsbd_table *t) {
    return t->n;
}
double hsbd_table_x_min(const hsbd_table *t) {
    return t->x[0];
}
double hsbd_table_x_max(const hsbd_table *t) {
    return t->x[t->n - 1];
}
double hsbd_table_last_value(const hsbd_table *t) {
    return t->y[t->n - 1];
}

/* interval k with x[k] <= x <= x[k+1], x clamped */
static size_t find_interval(const hsbd_table *t, double *x) {
    if (*x <= t->x[0]) return *x = t->x[0], 0;
    if (*x >= t->x[t->n - 1]) return *x = t->x[t->n - 1], t->n - 2;
    size_t lo = 0, hi = t->n - 1;
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        if (t->x[mid] <= *x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

double hsbd_table_value(const hsbd_table *t, double x) {
    const size_t k = find_interval(t, &x);
    const double h = t->x[k + 1] - t->x[k], a = x - t->x[k], b = t->x[k + 1] - x;
    return (t->m[k] * b * b * b + t->m[k + 1] * a * a * a) / (6.0 * h) +
           (t->y[k] / h - t->m[k] * h / 6.0) * b + (t->y[k + 1] / h - t->m[k + 1] * h / 6.0) * a;
}

double hsbd_table_derivative(const hsbd_table *t, double x) {
    const size_t k = find_interval(t, &x);
    const double h = t->x[k + 1] - t->x[k], a = x - t->x[k], b = t->x[k + 1] - x;
    return (t->m[k + 1] * a * a - t->m[k] * b * b) / (2.0 * h) + (t->y[k + 1] - t->y[k]) / h -
           (t->m[k + 1] - t->m[k]) * h / 6.0;
}

double hsbd_table_integral(const hsbd_table *t, double x) {
    const size_t k = find_interval(t, &x);
    return t->cum[k] + interval_integral(t, k, x - t->x[k]);
}
