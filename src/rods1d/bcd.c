/* Brownian cluster dynamics step: free end points, then one ring isotonic regression. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/isotonic.h"
#include "hsbd/rng.h"
#include "hsbd/rods.h"

enum { STEP_CHUNK = 256 }; /* rods per inner batch; even, so RNG pairs align */

struct hsbd_rods {
    hsbd_rods_params par;
    double mobility;    /* mu = D / kT */
    double free_length; /* L - N sigma */
    double contact_tol; /* gaps below this count as contact in the diagnostics */
    double *z;          /* contact-offset coordinates, ring order */
    double *offset;     /* z_i + offset_i = position (offset_i = i sigma) */
    double *y;          /* free end points of the current step */
    int64_t wraps;      /* unwrapped = z + offset + wraps * L */
    uint64_t step;
    double time;      /* sum of the steps' dt */
    size_t nclusters; /* blocks of the last step */
    hsbd_pava *pava;  /* the step's regression */
    hsbd_pava *frag;  /* per-cluster regressions for the fragmentation diagnostic */
    double *frag_v;   /* scratch for one cluster's velocities */
    double *push;     /* reflect rule: push per gap in the last step */
    double *ypush;    /* reflect rule: end points after the pushes (the regression's input) */
    double *fpair;    /* pair forces of the step (NULL without pair terms) */
    double pair_range;
};

hsbd_rods *hsbd_rods_alloc(const hsbd_rods_params *par, hsbd_error *err) {
    if (par->n < 1)
        return hsbd_error_set(err, HSBD_EINPUT, "rods: N = %zu must be >= 1", par->n), NULL;
    if (!(par->sigma >= 0) || !(par->length > 0) || !((double)par->n * par->sigma < par->length))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "rods: need sigma >= 0 and N sigma < L (N = %zu, sigma = %g, L = %g)",
                              par->n, par->sigma, par->length),
               NULL;
    if (!(par->diffusion > 0) || !(par->kT > 0) || !(par->dt > 0) || !isfinite(par->dt))
        return hsbd_error_set(err, HSBD_EINPUT, "rods: need D > 0, kT > 0, dt > 0"), NULL;
    const double range = hsbd_pair_range(&par->pair);
    if (par->pair.nterms > 0 && (!par->hard_core || !(range <= 0.5 * par->length)))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "rods: pair forces need the hard core and a range <= L/2 (range = "
                              "%g, L = %g)",
                              range, par->length),
               NULL;

    hsbd_rods *r = calloc(1, sizeof *r);
    if (!r) return hsbd_error_set(err, HSBD_ENOMEM, "rods: out of memory"), NULL;
    const size_t n = par->n;
    r->par = *par;
    r->mobility = par->diffusion / par->kT;
    r->free_length = par->length - (double)n * par->sigma;
    r->contact_tol = 1e-12 * par->length;
    r->z = calloc(n, sizeof *r->z);
    r->offset = malloc(n * sizeof *r->offset);
    r->y = malloc(n * sizeof *r->y);
    r->frag_v = malloc(n * sizeof *r->frag_v);
    r->pava = hsbd_pava_alloc(n);
    r->frag = hsbd_pava_alloc(n);
    if (par->contact_rule == HSBD_CONTACT_REFLECT) {
        r->push = calloc(n, sizeof *r->push);
        r->ypush = malloc(n * sizeof *r->ypush);
    }
    r->pair_range = range;
    if (par->pair.nterms > 0) r->fpair = malloc(n * sizeof *r->fpair);
    if (!r->z || !r->offset || !r->y || !r->frag_v || !r->pava || !r->frag ||
        (par->contact_rule == HSBD_CONTACT_REFLECT && (!r->push || !r->ypush)) ||
        (par->pair.nterms > 0 && !r->fpair)) {
        hsbd_rods_free(r);
        return hsbd_error_set(err, HSBD_ENOMEM, "rods: out of memory for N = %zu", n), NULL;
    }
    for (size_t i = 0; i < n; ++i)
        r->offset[i] = (double)i * par->sigma;
    return r;
}

void hsbd_rods_free(hsbd_rods *r) {
    if (!r) return;
    free(r->z);
    free(r->offset);
    free(r->y);
    free(r->frag_v);
    free(r->push);
    free(r->ypush);
    free(r->fpair);
    hsbd_pava_free(r->pava);
    hsbd_pava_free(r->frag);
    free(r);
}

/* Sorted uniforms from normalised partial sums of N+1 exponential spacings, O(N). */
void hsbd_rods_init_equilibrium(hsbd_rods *r) {
    const size_t n = r->par.n;
    double *u = r->y; /* scratch */
    double rotation;
    hsbd_rng_uniforms(r->par.seed, HSBD_STREAM_INIT, 0, 0, n, u);
    hsbd_rng_uniforms(r->par.seed, HSBD_STREAM_INIT, 1, 0, 1, &rotation);
    double last;
    hsbd_rng_uniforms(r->par.seed, HSBD_STREAM_INIT, 2, 0, 1, &last);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        sum += -log(u[i]);
        u[i] = sum;
    }
    sum += -log(last);
    const double scale = r->free_length / sum, shift = rotation * r->par.length;
    for (size_t i = 0; i < n; ++i)
        r->z[i] = u[i] * scale + shift;
    r->wraps = 0;
    r->nclusters = 0;
}

static int compare_doubles(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int hsbd_rods_set_positions(hsbd_rods *r, const double *x, hsbd_error *err) {
    const size_t n = r->par.n;
    const double L = r->par.length, sigma = r->par.sigma;
    double *w = r->y;
    for (size_t i = 0; i < n; ++i) {
        if (!isfinite(x[i]))
            return hsbd_error_set(err, HSBD_EINPUT, "initial position %zu is not finite", i + 1);
        w[i] = x[i] - L * floor(x[i] / L);
    }
    qsort(w, n, sizeof *w, compare_doubles);
    const double tol = 1e-12 * (sigma > 0 ? sigma : 1.0);
    for (size_t i = 0; i < n; ++i) {
        const double next = i + 1 < n ? w[i + 1] : w[0] + L;
        if (n > 1 && next - w[i] - sigma < -tol)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "initial positions overlap: rods at x = %.17g and %.17g are "
                                  "closer than sigma = %g",
                                  w[i], next - (i + 1 < n ? 0.0 : L), sigma);
    }
    for (size_t i = 0; i < n; ++i)
        r->z[i] = w[i] - r->offset[i];
    /* clamp rounding-level overlaps to exact contact, keeping ring order */
    for (size_t i = 1; i < n; ++i)
        if (r->z[i] < r->z[i - 1]) r->z[i] = r->z[i - 1];
    r->wraps = 0;
    return HSBD_OK;
}

/* Pair forces of rods closer than the range, Eq. (28): walk right from each rod in ring
 * order (rods keep their order, so the walk stops at the first one out of range). */
static void compute_pair_forces(hsbd_rods *r) {
    const size_t n = r->par.n;
    const double L = r->par.length, range = r->pair_range;
    const double *z = r->z, *off = r->offset;
    double *fp = r->fpair;
    memset(fp, 0, n * sizeof *fp);
    for (size_t i = 0; i < n; ++i) {
        const double xi = z[i] + off[i];
        for (size_t k = 1; k < n; ++k) {
            const size_t j = i + k < n ? i + k : i + k - n;
            const double d = z[j] + off[j] + (i + k < n ? 0.0 : L) - xi;
            if (d >= range) break;
            const double f = hsbd_pair_force(&r->par.pair, d); /* on j from i; -f on i */
            fp[j] += f;
            fp[i] -= f;
        }
    }
}

/* y_i = z_i + mu dt F_i + sqrt(2 D dt) N_i: the free end point of Eq. (10), i.e.
 * z_i + mu F_i dt with the total force of Eq. (11) (field plus pair forces, Eq. 28). */
static void compute_endpoints(hsbd_rods *r) {
    const size_t n = r->par.n;
    const double mu_dt = r->mobility * r->par.dt;
    const double noise = sqrt(2.0 * r->par.diffusion * r->par.dt);
    const int has_field = r->par.field.nterms > 0, has_pair = r->fpair != NULL;
    if (has_pair) compute_pair_forces(r);
    double x[STEP_CHUNK], f[STEP_CHUNK], g[STEP_CHUNK];
    for (size_t i0 = 0; i0 < n; i0 += STEP_CHUNK) {
        const size_t m = n - i0 < STEP_CHUNK ? n - i0 : STEP_CHUNK;
        const double *restrict z = r->z + i0;
        double *restrict y = r->y + i0;
        hsbd_rng_normals(r->par.seed, HSBD_STREAM_NOISE, r->step, i0, m, g);
        if (has_field || has_pair) {
            for (size_t j = 0; j < m; ++j)
                x[j] = z[j] + r->offset[i0 + j];
            hsbd_field_force(&r->par.field, m, x, f);
            if (has_pair)
                for (size_t j = 0; j < m; ++j)
                    f[j] += r->fpair[i0 + j];
            for (size_t j = 0; j < m; ++j)
                y[j] = z[j] + mu_dt * f[j] + noise * g[j];
        } else {
            for (size_t j = 0; j < m; ++j)
                y[j] = z[j] + noise * g[j];
        }
    }
}

static double ring_gap(const hsbd_rods *r, size_t i) {
    const size_t n = r->par.n;
    return i + 1 < n ? r->z[i + 1] - r->z[i] : r->z[0] + r->free_length - r->z[n - 1];
}

/* Fragmentation diagnostic: clusters touching at the start and the number of moving
 * clusters they split into (the isotonic regression of the velocities inside each
 * cluster, Eqs. 4-5) of the end points `target` (with the reflect rule: after the pushes).
 * Must run before z is overwritten. */
static void count_fragments(hsbd_rods *r, const double *target, hsbd_rods_step_stats *st) {
    const size_t n = r->par.n;
    const double inv_dt = 1.0 / r->par.dt;
    size_t start = 0; /* a rod whose left gap is open; else the one after the widest gap */
    double widest = -DBL_MAX;
    for (size_t i = 0; i < n; ++i) {
        const double g = ring_gap(r, (i + n - 1) % n);
        if (g > widest) widest = g, start = i;
        if (g > r->contact_tol) break;
    }
    st->clusters_start = 0;
    st->fragments = 0;
    size_t len = 0;
    for (size_t k = 0; k < n; ++k) {
        const size_t i = (start + k) % n;
        r->frag_v[len++] = (target[i] - r->z[i]) * inv_dt; /* mu F_i, Eq. (12) */
        if (k + 1 == n || ring_gap(r, i) > r->contact_tol) {
            st->clusters_start += 1;
            st->fragments +=
                len == 1 ? 1 : hsbd_pava_line(r->frag, len, r->frag_v, NULL, r->frag_v);
            len = 0;
        }
    }
}

/* Keep coordinates bounded: shift all z by L once rod 0 has left [-L, 2L). */
static void recenter(hsbd_rods *r) {
    const double L = r->par.length;
    const double z0 = r->z[0];
    if (z0 >= -L && z0 < 2 * L) return;
    const int64_t k = (int64_t)floor(z0 / L);
    for (size_t i = 0; i < r->par.n; ++i) {
        r->z[i] -= (double)k * L;
        r->y[i] -= (double)k * L; /* the step's end points stay in the frame of z */
        if (r->ypush) r->ypush[i] -= (double)k * L;
    }
    r->wraps += k;
}

/* Reflect rule: for every gap that may have touched zero during the step, draw the
 * minimum m of its Brownian bridge from the start gap g0 to the free end gap g1
 * (relative diffusion D_rel = 2D): m = (g0 + g1 - sqrt((g1 - g0)^2 - 4 D_rel dt ln U)) / 2. If
 * m < 0 the exact reflected end gap is g1 - m (Skorokhod; design note 7): the pair is
 * pushed apart by -m, shared equally (equal mobilities). Pushes are computed from the
 * free end points of all gaps first, so the result does not depend on the order. */
static void reflect_gaps(hsbd_rods *r) {
    const size_t n = r->par.n;
    const double d_rel_dt = 2.0 * r->par.diffusion * r->par.dt;
    const double lf = r->free_length;
    for (size_t i = 0; i < n; ++i) {
        const size_t j = i + 1 < n ? i + 1 : 0;
        const double wrap = i + 1 < n ? 0.0 : lf;
        const double g0 = r->z[j] + wrap - r->z[i], g1 = r->y[j] + wrap - r->y[i];
        r->push[i] = 0.0;
        /* crossing probability exp(-g0 g1 / (D_rel dt)) < 2e-9 otherwise */
        if (n < 2 || (g1 > 0 && g0 * g1 > 20.0 * d_rel_dt)) continue;
        double u;
        hsbd_rng_uniforms(r->par.seed, HSBD_STREAM_CONTACT, r->step, i, 1, &u);
        const double d = g1 - g0;
        /* bridge with increment variance v = 2 D_rel dt: P(min < m) = e^(-2 (g0-m)(g1-m)/v) */
        const double m = 0.5 * (g0 + g1 - sqrt(d * d - 4.0 * d_rel_dt * log(u)));
        if (m < 0) r->push[i] = -m;
    }
    for (size_t i = 0; i < n; ++i) {
        const double left = r->push[i > 0 ? i - 1 : n - 1]; /* gap on the left of rod i */
        r->ypush[i] = r->y[i] + 0.5 * left - 0.5 * r->push[i];
    }
}

void hsbd_rods_step(hsbd_rods *r, hsbd_rods_step_stats *stats) {
    compute_endpoints(r);
    if (r->par.hard_core) {
        const double *target = r->y;
        if (r->par.contact_rule == HSBD_CONTACT_REFLECT) {
            reflect_gaps(r);
            target = r->ypush;
        }
        if (stats) count_fragments(r, target, stats);
        r->nclusters = hsbd_pava_ring(r->pava, r->par.n, target, NULL, r->free_length, r->z);
        if (stats) stats->clusters_end = r->nclusters;
    } else {
        double *t = r->z;
        r->z = r->y;
        r->y = t;
        if (stats) stats->clusters_start = stats->fragments = stats->clusters_end = r->par.n;
    }
    r->step += 1;
    r->time += r->par.dt;
    recenter(r);
}

void hsbd_rods_set_dt(hsbd_rods *r, double dt) {
    if (dt > 0 && isfinite(dt)) r->par.dt = dt;
}

size_t hsbd_rods_cluster_count(const hsbd_rods *r) {
    return r->nclusters;
}

size_t hsbd_rods_cluster_size(const hsbd_rods *r, size_t k) {
    return hsbd_pava_block_size(r->pava, k);
}

hsbd_rods_view hsbd_rods_get_view(const hsbd_rods *r) {
    hsbd_rods_view v = {
        .n = r->par.n,
        .length = r->par.length,
        .sigma = r->par.sigma,
        .free_length = r->free_length,
        .z = r->z,
        .offset = r->offset,
        .y = r->par.hard_core && r->step > 0 ? r->y : NULL,
        .push = r->par.hard_core && r->step > 0 ? r->push : NULL,
        .unwrap = (double)r->wraps * r->par.length,
        .mobility = r->mobility,
        .kT = r->par.kT,
        .dt = r->par.dt,
        .step = r->step,
        .time = r->time,
        .hard_core = r->par.hard_core,
    };
    return v;
}

const hsbd_rods_params *hsbd_rods_get_params(const hsbd_rods *r) {
    return &r->par;
}

double hsbd_rods_min_gap(const hsbd_rods *r, int *all_finite) {
    double m = DBL_MAX;
    int finite = 1;
    for (size_t i = 0; i < r->par.n; ++i) {
        const double g = ring_gap(r, i);
        finite &= isfinite(r->z[i]);
        if (g < m) m = g;
    }
    if (all_finite) *all_finite = finite;
    return r->par.n > 1 ? m : r->free_length;
}
