/* A gap's Brownian motion with drift reflected at contact: the walls' bridges and the exact
 * pair rule (internal to src/spheres; the physics in docs/theory.md, "Pair collisions under
 * a relative drift", the scheme in docs/spheres.md). */
#include "spheres/reflect.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/rng.h"
#include "spheres/scan.h"

double sph_bridge_push(const hsbd_spheres *s, double g0, double g1, double d_dt, uint64_t index) {
    if (g0 * g1 >= SPH_BRIDGE_REACH * d_dt) return 0;
    double u;
    hsbd_rng_uniforms(s->par.seed, s->bridge_stream, s->step, index, 1, &u);
    /* the bridge minimum (docs/theory.md, Scala Eq. 9 sampled exactly) */
    const double m = 0.5 * (g0 + g1 - sqrt((g1 - g0) * (g1 - g0) - 4.0 * d_dt * log(u)));
    return m < 0 ? -m : 0;
}

/* ---- the exact gap of a pair: the quantile of the mirror's gap in Eq. 9's law ---- */

static const double SQRT_HALF = 0.70710678118654752440, INV_SQRT_2PI = 0.39894228040143267794;

static double normal_cdf(double z) {
    return 0.5 * erfc(-z * SQRT_HALF);
}

/* e^k times a probability p, 0 where p underflowed (k may be large where p is tiny) */
static double exp_times(double k, double p) {
    return k < 1 ? exp(k) * p : p > 0 ? exp(k + log(p)) : 0.0;
}

/* Eq. 9's law at x (mu = x0 + c dt, s = sqrt(2 d dt), k = c x / d, a = (x - mu) / s,
 * b = (-x - mu) / s): F = Phi(a) - e^k Phi(b), S = 1 - F = Phi(-a) + e^k Phi(b), each in
 * the form that keeps its digits (for b > 0, which needs c < 0, F = -expm1(k) - Phi(-a) +
 * e^k Phi(-b)), and the density F' = (phi(a) + e^k phi(b)) / s - (c / d) e^k Phi(b).
 * c = 0 gives the mirror's law of |Y|. */
typedef struct gap_law {
    double F, S, density;
} gap_law;
static gap_law exact_law(double x, double mu, double s, double c, double d) {
    const double a = (x - mu) / s, b = (-x - mu) / s, k = c * x / d;
    const double upper_b = normal_cdf(-b), lower_b = 1 - upper_b; /* Phi(-b), Phi(b) */
    const double tail = b > 0 ? exp_times(k, lower_b) : exp_times(k, normal_cdf(b));
    const double above = normal_cdf(-a);
    gap_law law = {.S = above + tail};
    law.F = b > 0 ? -expm1(k) - above + exp_times(k, upper_b) : normal_cdf(a) - tail;
    law.density = INV_SQRT_2PI * (exp(-0.5 * a * a) + exp(k - 0.5 * b * b)) / s - c / d * tail;
    return law;
}

double sph_exact_gap(double y, double x0, double c, double d, double dt) {
    if (c == 0 || !(d > 0) || !(dt > 0)) return y;
    const double s = sqrt(2 * d * dt), mu = x0 + c * dt, by = (-y - mu) / s, ky = c * y / d;
    /* the laws differ at y by (1 - e^(c y / d)) Phi(b_y): nothing where Phi(b_y) < 1e-17,
     * unless a separating drift makes e^(c y / d) large */
    if (by < -8.5 && ky < 1) return y;
    /* g(x), increasing, zero at X: F_e(x) - F_m(y) below the mirror's median, S_m(y) -
     * S_e(x) above it (the upper tail's digits are in S) */
    const gap_law mirror = exact_law(y, mu, s, 0.0, d);
    const int upper = mirror.F > 0.5;
    const double target = upper ? mirror.S : mirror.F;
    double g =
        ky < 1 ? -expm1(ky) * normal_cdf(by) : normal_cdf(by) - exp_times(ky, normal_cdf(by));
    const double scale = fmin(s, d / fabs(c)), ay = (y - mu) / s;
    /* the gap would move by about g / F_m'(y): nothing below the solution's own accuracy */
    const double mirror_density = INV_SQRT_2PI * (exp(-0.5 * ay * ay) + exp(-0.5 * by * by)) / s;
    if (!(fabs(g) > 1e-9 * scale * mirror_density)) return y;
    double lo = g > 0 ? 0 : y, hi = g > 0 ? y : INFINITY, x = y;
    /* far apart: start from the quantile of the drift's exponential law, F = 1 - e^(c x / d) */
    if (c < 0 && g > 0.01) {
        const double guess = -d / c * (upper ? -log(target) : -log1p(-target));
        if (guess > lo && guess < hi) x = guess;
    }
    for (int iteration = 0; iteration < 200; ++iteration) {
        const gap_law law = exact_law(x, mu, s, c, d);
        if (iteration > 0 || x != y) g = upper ? target - law.S : law.F - target;
        if (g == 0) break;
        if (g > 0)
            hi = fmin(hi, x);
        else
            lo = fmax(lo, x);
        /* Newton's error after a step h is about h^2 |F''| / (2 F'), at most about h^2 / l
         * for these laws, l = min(s, d / |c|) (the Gaussian's width, the drift's decay
         * length): below 1e-9 l after a step of 3e-5 l */
        const double step = g / law.density;
        if (fabs(step) <= 3e-5 * scale) {
            x = fmax(x - step, 0.0);
            break;
        }
        x -= step;
        if (!(x > lo && x < hi)) /* Newton left the bracket: bisect, or widen it */
            x = isfinite(hi) ? 0.5 * (lo + hi) : fmax(2 * lo, lo + s);
        if (hi - lo <= 1e-9 * scale) break;
    }
    return x;
}

double sph_pair_skin(const hsbd_spheres *s, double dt) {
    if (!s->pair_exact) return 0;
    double skin = sqrt(72 * s->diffusion_max * dt); /* 6 / sqrt(2) times sqrt(4 D_max dt) */
    for (int a = 0; a < s->dim; ++a)                /* what a small periodic box has room for */
        if (!s->walls[a])
            skin = fmin(skin, fmax(0.0, 0.5 * s->box[a] - s->sigma_max - 2 * s->shell));
    return skin;
}

static int ends_add(sph_pushes *b, sph_pair_end e) {
    if (b->len == b->cap) {
        const size_t cap = b->cap ? 2 * b->cap : 256;
        sph_pair_end *grown = realloc(b->p, cap * sizeof *grown);
        if (!grown) return -1;
        b->p = grown;
        b->cap = cap;
    }
    b->p[b->len++] = e;
    return 0;
}

/* The exact rule's change of pair (i, j)'s free end gap, when their drifts differ: each
 * mobile particle's share into out, its impulse to out's virial. Returns 0, or -1 when out
 * of memory. */
static int pair_correction(const hsbd_spheres *s, int32_t i, int32_t j, sph_pushes *out) {
    const double dt = s->dt, *xi = s->x + 3 * (size_t)i, *xj = s->x + 3 * (size_t)j;
    const double *vi = s->v + 3 * (size_t)i, *vj = s->v + 3 * (size_t)j;
    const double *gi = s->drift + 3 * (size_t)i, *gj = s->drift + 3 * (size_t)j;
    const double g[3] = {gj[0] - gi[0], gj[1] - gi[1], gj[2] - gi[2]}; /* relative drift */
    const double dr = s->diffusion[i] + s->diffusion[j];               /* the gap's diffusion */
    if ((g[0] == 0 && g[1] == 0 && g[2] == 0) || !(dr > 0)) return 0;  /* the mirror is exact */
    double r0[3], r1[3]; /* j - i at the start and at the free end */
    for (int a = 0; a < 3; ++a) {
        r0[a] = hsbd_wrap_delta(xj[a] - xi[a], s->box[a]);
        r1[a] = r0[a] + (vj[a] - vi[a]) * dt;
    }
    const double len1 = sqrt(hsbd_dot3(r1, r1)), sij = sph_contact_distance(s, i, j);
    if (!(len1 > 0)) return 0;
    const double n[3] = {r1[0] / len1, r1[1] / len1, r1[2] / len1}; /* the end separation */
    const double x0 = fmax(0.0, sqrt(hsbd_dot3(r0, r0)) - sij), end = len1 - sij;
    const double exact = sph_exact_gap(fabs(end), x0, hsbd_dot3(g, n), dr, dt);
    const double change = (end < 0 ? -exact : exact) - end; /* sign(Y) X - Y */
    if (change == 0) return 0;
    /* i moves by -D_i / (D_i + D_j) change n, j by D_j / (D_i + D_j) change n */
    const double fi = -change * s->diffusion[i] / dr, fj = change * s->diffusion[j] / dr;
    const sph_pair_end ei = {i, {fi * n[0], fi * n[1], fi * n[2]}};
    const sph_pair_end ej = {j, {fj * n[0], fj * n[1], fj * n[2]}};
    if ((s->diffusion[i] > 0 && ends_add(out, ei)) || (s->diffusion[j] > 0 && ends_add(out, ej)))
        return -1;
    out->pairs++;
    /* sigma_ij times j's displacement over D_j, the impulse / kT: with the collision that
     * may follow, the pair's whole impulse (X - Y) / (D_i + D_j) */
    out->virial += sph_exact_term(s->virial_scale, sij * change / dr);
    return 0;
}

/* The changes of rows [i0, i1), each pair once (from the row of its first particle), into
 * out. A row's pairs are screened first without branches (in a dense or pressed packing
 * about half pass, and a branch on it mispredicts): a pair farther than the skin's width
 * beyond contact at both ends of the step is left alone. Returns 0, or -1 when out of
 * memory. */
static int pair_range(const hsbd_spheres *s, size_t i0, size_t i1, sph_pushes *out) {
    const double dt = s->dt, screen = sqrt(72 * s->diffusion_max * dt); /* the skin's */
    out->len = 0;
    out->pairs = 0;
    out->virial = 0;
    if (out->near_cap < s->nb_cap) {
        int32_t *near = realloc(out->near, s->nb_cap * sizeof *near);
        if (!near) return -1;
        out->near = near;
        out->near_cap = s->nb_cap;
    }
    for (size_t i = i0; i < i1; ++i) {
        const int32_t *row = s->nb + i * s->nb_cap;
        const double *xi = s->x + 3 * i, *vi = s->v + 3 * i, half = 0.5 * s->sigma[i] + screen;
        uint32_t found = 0;
        for (uint32_t k = 0; k < s->nb_upper[i]; ++k) {
            const int32_t j = row[k];
            const double *xj = s->x + 3 * (size_t)j, *vj = s->v + 3 * (size_t)j;
            double q0 = 0, q1 = 0;
            for (int a = 0; a < 3; ++a) {
                const double d0 = hsbd_wrap_delta(xj[a] - xi[a], s->box[a]);
                const double d1 = d0 + (vj[a] - vi[a]) * dt;
                q0 += d0 * d0, q1 += d1 * d1;
            }
            const double near = half + 0.5 * s->sigma[j];
            out->near[found] = j;
            found += (q0 < near * near) | (q1 < near * near);
        }
        for (uint32_t k = 0; k < found; ++k)
            if (pair_correction(s, (int32_t)i, out->near[k], out)) return -1;
    }
    return 0;
}

int sph_pair_corrections(hsbd_spheres *s) {
    s->push_virial = 0;
    const int threads = sph_threads(s);
    if ((size_t)threads > s->push_nparts) {
        sph_pushes *parts =
            sph_grow_zeroed(s->push_parts, s->push_nparts, (size_t)threads, sizeof *parts);
        if (!parts) return -1;
        s->push_parts = parts;
        s->push_nparts = (size_t)threads;
    }
    if (!s->push_sum && !(s->push_sum = calloc(3 * s->n, sizeof *s->push_sum))) return -1;
    int failed = 0;
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)                 \
    reduction(|                                                                                    \
              : failed)
    for (int k = 0; k < threads; ++k)
        failed |= pair_range(s, sph_range_start(s->n, threads, k),
                             sph_range_start(s->n, threads, k + 1), &s->push_parts[k]) != 0;
    if (failed) return -1;
    /* each particle's changes summed exactly (sph_exact_sum): the same bits in any order,
     * so for any row order, spatial sort or thread count */
    const sph_exact_scale scale = sph_exact_scale_for(s->sigma_max);
    uint64_t pairs = 0;
    sph_exact_sum virial = 0;
    for (int k = 0; k < threads; ++k) {
        const sph_pushes *part = &s->push_parts[k];
        pairs += part->pairs;
        virial += part->virial;
        for (size_t q = 0; q < part->len; ++q)
            for (int a = 0; a < 3; ++a)
                s->push_sum[3 * (size_t)part->p[q].i + (size_t)a] +=
                    sph_exact_term(scale, part->p[q].d[a]);
    }
    const double dt = s->dt;
    for (int k = 0; k < threads; ++k) { /* into the velocities, each particle once */
        const sph_pushes *part = &s->push_parts[k];
        for (size_t q = 0; q < part->len; ++q) {
            const size_t i = (size_t)part->p[q].i;
            sph_exact_sum *sum = s->push_sum + 3 * i;
            for (int a = 0; a < 3; ++a) {
                s->v[3 * i + (size_t)a] += sph_exact_value(scale, sum[a]) / dt;
                sum[a] = 0;
            }
        }
    }
    s->stats.pair_corrections += pairs;
    s->push_virial = virial;
    return 0;
}
