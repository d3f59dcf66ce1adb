#include "bcd_oracle.h"

#include "hsbd/rng.h"
#include "hsbd/rods.h"

#include <math.h>
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

/* contact distance between rods i and j */
static double contact(const double *sig, size_t i, size_t j) {
    return 0.5 * (sig[i] + sig[j]);
}

/* gap right of rod i: to the next rod, across the ring, or to the right wall */
static double gap(size_t n, const double *x, size_t i, const double *sig, double L, int walls) {
    if (i + 1 < n) return x[i + 1] - x[i] - contact(sig, i, i + 1);
    return walls ? L - 0.5 * sig[n - 1] - x[n - 1] : x[0] + L - x[n - 1] - contact(sig, n - 1, 0);
}

enum { WALL_LEFT = -1, WALL_RIGHT = -2 };

size_t oracle_step_general(size_t n, double *x, const double *force, const double *mob,
                           const double *sig, double L, int walls, double dt, double contact_tol) {
    int *label = malloc(n * sizeof *label);
    double *v = malloc(n * sizeof *v);
    double *f = malloc(n * sizeof *f), *m = malloc(n * sizeof *m);
    size_t *sizes = malloc(n * sizeof *sizes);
    size_t *idx = malloc(n * sizeof *idx);

    /* start at a rod whose left neighbour does not touch it (between walls: rod 0) */
    size_t start = 0;
    for (size_t i = 0; i < n && !walls; ++i)
        if (gap(n, x, (i + n - 1) % n, sig, L, walls) > contact_tol) {
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
        } while (k < n && gap(n, x, idx[len - 1], sig, L, walls) <= contact_tol);
        const size_t parts = oracle_fragment(len, f, m, sizes);
        const int at_left = walls && idx[0] == 0 && x[0] - 0.5 * sig[0] <= contact_tol;
        const int at_right =
            walls && idx[len - 1] == n - 1 && gap(n, x, n - 1, sig, L, walls) <= contact_tol;
        size_t pos = 0;
        for (size_t p = 0; p < parts; ++p) {
            double vel = group_velocity(f, m, pos, pos + sizes[p]); /* Eq. (12) */
            int lab = next_label++;
            /* a wall is a cluster of infinite friction: the leading (trailing) fragments
             * that push into it stay with it */
            if (at_left && vel <= 0 && (p == 0 || label[idx[pos - 1]] == WALL_LEFT))
                vel = 0, lab = WALL_LEFT;
            for (size_t q = pos; q < pos + sizes[p]; ++q)
                label[idx[q]] = lab, v[idx[q]] = vel;
            pos += sizes[p];
        }
        if (at_right) /* from the right end: fragments moving into the right wall */
            for (size_t q = len; q-- > 0;) {
                const size_t i = idx[q];
                if (v[i] < 0 || label[i] == WALL_LEFT) break;
                v[i] = 0, label[i] = WALL_RIGHT;
            }
    }

    /* time-ordered mergers, Eqs. (13)-(19); walls as immovable clusters */
    size_t merges = 0;
    double remaining = dt;
    for (;;) {
        double t_first = remaining;
        size_t i_c = n + 2;
        for (size_t i = 0; i < n; ++i) {
            if (walls && i + 1 == n) continue;
            const size_t j = (i + 1) % n;
            if (n == 1 || label[i] == label[j] || !(v[i] > v[j])) continue; /* Eq. (13) */
            double t = gap(n, x, i, sig, L, walls) / (v[i] - v[j]);         /* Eq. (14) */
            if (t < 0) t = 0;
            if (t < t_first) t_first = t, i_c = i; /* Eqs. (15)-(16) */
        }
        if (walls && label[0] != WALL_LEFT && v[0] < 0) {
            const double t = fmax(0.0, (x[0] - 0.5 * sig[0]) / -v[0]);
            if (t < t_first) t_first = t, i_c = n; /* rod 0's cluster reaches the left wall */
        }
        if (walls && label[n - 1] != WALL_RIGHT && v[n - 1] > 0) {
            const double t = fmax(0.0, gap(n, x, n - 1, sig, L, walls) / v[n - 1]);
            if (t < t_first) t_first = t, i_c = n + 1;
        }
        for (size_t i = 0; i < n; ++i)
            x[i] += v[i] * t_first; /* Eq. (18) / (19) */
        remaining -= t_first;
        if (i_c == n + 2) break;
        ++merges;
        if (i_c >= n) { /* a wall stops the whole cluster */
            const int a = label[i_c == n ? 0 : n - 1], w = i_c == n ? WALL_LEFT : WALL_RIGHT;
            if (i_c == n)
                x[0] = 0.5 * sig[0];
            else
                x[n - 1] = L - 0.5 * sig[n - 1];
            for (size_t i = 0; i < n; ++i)
                if (label[i] == a) label[i] = w, v[i] = 0;
            continue;
        }
        const size_t j_c = (i_c + 1) % n;
        if (j_c == 0)
            x[0] = x[n - 1] + contact(sig, n - 1, 0) - L; /* exact contact */
        else
            x[j_c] = x[i_c] + contact(sig, i_c, j_c);
        const int a = label[i_c], b = label[j_c];
        if (a == WALL_LEFT || a == WALL_RIGHT || b == WALL_LEFT || b == WALL_RIGHT) {
            const int w = (a == WALL_LEFT || a == WALL_RIGHT) ? a : b, other = w == a ? b : a;
            for (size_t i = 0; i < n; ++i)
                if (label[i] == other) label[i] = w, v[i] = 0;
            continue;
        }
        double fa = 0, fb = 0, wa = 0, wb = 0; /* friction-weighted merge, Eq. (17) */
        for (size_t i = 0; i < n; ++i) {
            if (label[i] == a) wa += 1.0 / mob[i], fa = v[i];
            if (label[i] == b) wb += 1.0 / mob[i], fb = v[i];
        }
        const double vel = (wa * fa + wb * fb) / (wa + wb);
        for (size_t i = 0; i < n; ++i)
            if (label[i] == a || label[i] == b) label[i] = a, v[i] = vel;
    }
    free(label), free(v), free(f), free(m), free(sizes), free(idx);
    return merges;
}

size_t oracle_step(size_t n, double *x, const double *force, const double *mob, double sigma,
                   double L, double dt, double contact_tol) {
    double *sig = malloc(n * sizeof *sig);
    for (size_t i = 0; i < n; ++i)
        sig[i] = sigma;
    const size_t merges = oracle_step_general(n, x, force, mob, sig, L, 0, dt, contact_tol);
    free(sig);
    return merges;
}

double oracle_library_deviation(const hsbd_rods_params *par, int steps) {
    enum { NMAX = 64 };
    const size_t n = par->n;
    hsbd_error err;
    hsbd_rods *rods = n <= NMAX ? hsbd_rods_alloc(par, &err) : NULL;
    if (!rods) return NAN;
    hsbd_rods_init_equilibrium(rods);
    const double mu = par->diffusion / par->kT;
    double worst = 0;
    for (int s = 0; s < steps; ++s) {
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        double x[NMAX], force[NMAX], g[NMAX], mob[NMAX];
        hsbd_rng_normals(par->seed, HSBD_STREAM_NOISE, v.step, 0, n, g);
        for (size_t i = 0; i < n; ++i) {
            x[i] = v.z[i] + v.offset[i];
            mob[i] = mu;
        }
        hsbd_field now;
        hsbd_field_force(hsbd_field_at(&par->field, v.time, &now), n, x, force);
        for (size_t i = 0; i < n; ++i)
            force[i] += sqrt(2 * par->diffusion / par->dt) / mu * g[i];
        const double shift = v.unwrap;
        oracle_step(n, x, force, mob, par->sigma, par->length, par->dt, 1e-12);
        if (hsbd_rods_step(rods, NULL) != HSBD_OK) worst = NAN;
        const hsbd_rods_view w = hsbd_rods_get_view(rods);
        for (size_t i = 0; i < n; ++i) {
            const double d = fabs((w.z[i] + w.offset[i] + w.unwrap) - (x[i] + shift));
            if (d > worst) worst = d;
        }
    }
    hsbd_rods_free(rods);
    return worst;
}
