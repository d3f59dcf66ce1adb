#include "bcd_oracle.h"

#include <stdlib.h>

/* velocity of rods a..b-1 moving together: sum F / sum (1/mu) */
static double group_velocity(const double *force, const double *mob, size_t a, size_t b) {
    double f = 0, friction = 0;
    for (size_t k = a; k < b; ++k)
        f += force[k], friction += 1.0 / mob[k];
    return f / friction;
}

/* Split [a, b) at the cut with the largest positive velocity jump, recursively. */
static void fragment_range(const double *force, const double *mob, size_t a, size_t b,
                           size_t *sizes, size_t *count) {
    double best = 0.0;
    size_t cut = 0;
    for (size_t c = a + 1; c < b; ++c) {
        const double jump = group_velocity(force, mob, c, b) - group_velocity(force, mob, a, c);
        if (jump > best) best = jump, cut = c;
    }
    if (cut == 0) {
        sizes[(*count)++] = b - a;
        return;
    }
    fragment_range(force, mob, a, cut, sizes, count);
    fragment_range(force, mob, cut, b, sizes, count);
}

size_t oracle_fragment(size_t n, const double *force, const double *mob, size_t *sizes) {
    size_t count = 0;
    fragment_range(force, mob, 0, n, sizes, &count);
    return count;
}

static double gap(size_t n, const double *x, size_t i, double sigma, double L) {
    return i + 1 < n ? x[i + 1] - x[i] - sigma : x[0] + L - x[n - 1] - sigma;
}

size_t oracle_step(size_t n, double *x, const double *force, const double *mob, double sigma,
                   double L, double dt, double contact_tol) {
    int *label = malloc(n * sizeof *label);
    double *v = malloc(n * sizeof *v);
    double *f = malloc(n * sizeof *f), *m = malloc(n * sizeof *m);
    size_t *sizes = malloc(n * sizeof *sizes);
    size_t *idx = malloc(n * sizeof *idx);

    /* start at a rod whose left neighbour does not touch it */
    size_t start = 0;
    for (size_t i = 0; i < n; ++i)
        if (gap(n, x, (i + n - 1) % n, sigma, L) > contact_tol) {
            start = i;
            break;
        }
    /* clusters at time t, each fragmented (Eqs. 4-5 via the recursive rule) */
    int next_label = 0;
    size_t k = 0;
    while (k < n) {
        size_t len = 0;
        do {
            idx[len] = (start + k) % n;
            f[len] = force[idx[len]];
            m[len] = mob[idx[len]];
            ++len, ++k;
        } while (k < n && gap(n, x, idx[len - 1], sigma, L) <= contact_tol);
        const size_t parts = oracle_fragment(len, f, m, sizes);
        size_t pos = 0;
        for (size_t p = 0; p < parts; ++p) {
            const double vel = group_velocity(f, m, pos, pos + sizes[p]); /* Eq. (12) */
            for (size_t q = pos; q < pos + sizes[p]; ++q)
                label[idx[q]] = next_label, v[idx[q]] = vel;
            pos += sizes[p];
            ++next_label;
        }
    }

    /* time-ordered mergers, Eqs. (13)-(19) */
    size_t merges = 0;
    double remaining = dt;
    for (;;) {
        double t_first = remaining;
        size_t i_c = n;
        for (size_t i = 0; i < n; ++i) {
            const size_t j = (i + 1) % n;
            if (n == 1 || label[i] == label[j] || !(v[i] > v[j])) continue; /* Eq. (13) */
            double t = gap(n, x, i, sigma, L) / (v[i] - v[j]);              /* Eq. (14) */
            if (t < 0) t = 0;
            if (t < t_first) t_first = t, i_c = i; /* Eqs. (15)-(16) */
        }
        for (size_t i = 0; i < n; ++i)
            x[i] += v[i] * t_first; /* Eq. (18) / (19) */
        remaining -= t_first;
        if (i_c == n) break;
        const size_t j_c = (i_c + 1) % n;
        if (j_c == 0)
            x[0] = x[n - 1] + sigma - L; /* exact contact */
        else
            x[j_c] = x[i_c] + sigma;
        const int a = label[i_c], b = label[j_c];
        double fa = 0, fb = 0, wa = 0, wb = 0; /* friction-weighted merge, Eq. (17) */
        for (size_t i = 0; i < n; ++i) {
            if (label[i] == a) wa += 1.0 / mob[i], fa = v[i];
            if (label[i] == b) wb += 1.0 / mob[i], fb = v[i];
        }
        const double vel = (wa * fa + wb * fb) / (wa + wb);
        for (size_t i = 0; i < n; ++i)
            if (label[i] == a || label[i] == b) label[i] = a, v[i] = vel;
        ++merges;
    }
    free(label), free(v), free(f), free(m), free(sizes), free(idx);
    return merges;
}
