/* Brownian cluster dynamics step: free end points, then one ring isotonic regression. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/vmath.h"
#include "hsbd/isotonic.h"
#include "hsbd/rng.h"
#include "hsbd/rods.h"
#include "rods1d/checkpoint.h"
#include "rods1d/gaps.h"

enum { STEP_CHUNK = 256 }; /* rods per inner batch; even, so RNG pairs align */
enum { GAP_CHUNK = 1024 }; /* gaps per batch of the reflect rule; a multiple of GAP_BLOCK */
enum { EARLY_GAPS = 8 * GAP_BLOCK, EARLY_DIGITS = 4 }; /* see push_gap_batch */

/* clusters starting in a part of the ring and the fragments they split into; a cluster
 * longer than the part's regression holds is left for later (at most one per part) */
typedef struct fragment_count {
    size_t clusters, fragments;
    size_t long_first, long_len; /* the long cluster (long_len 0: none) */
} fragment_count;

struct hsbd_rods {
    hsbd_rods_params par;
    int walls;          /* boundary == HSBD_RODS_WALLS */
    double mobility;    /* mu = D / kT (species 0 in mixtures) */
    double free_length; /* L - sum of sigma_i */
    /* mixtures (NULL for one species): per-rod species, friction 1/mu_i (the regression's
     * weights); per species sigma, D, mobility and the step's mu dt and noise amplitude */
    int *species;
    double *friction;
    double *sp_sigma, *sp_diffusion, *sp_mobility, *sp_mu_dt, *sp_noise;
    double contact_tol; /* gaps below this count as contact in the diagnostics */
    double *z;          /* contact-offset coordinates, in order along the line (n + 1) */
    double *offset;     /* z_i + offset_i = position (summed contact distances, docs) */
    double *y;          /* free end points of the current step (n + 1) */
    int64_t wraps;      /* unwrapped = z + offset + wraps * L */
    uint64_t step;
    double time;                /* sum of the steps' dt */
    size_t nclusters;           /* blocks of the last step */
    hsbd_pava *pava;            /* the step's regression */
    hsbd_pava *frag;            /* per-cluster regressions for the fragmentation diagnostic */
    double *frag_v;             /* scratch for the clusters' velocities */
    double *frag_w;             /* and their frictions 1/mu_i (mixtures; else NULL) */
    hsbd_pava **frag_part;      /* on threads: one regression per part of the ring (else NULL) */
    fragment_count *frag_count; /* and the counts of each part */
    int frag_parts;             /* their number, par.threads */
    double *push;               /* reflect rule: push per gap in the last step (N + 1 gaps) */
    size_t wall_blocks[2];      /* walls: regression blocks clamped to the left / right wall */
    size_t pava_blocks;         /* walls: blocks of the last regression */
    double *ypush;         /* reflect rule: end points after the pushes (the regression's input) */
    uint8_t *batch_listed; /* reflect rule: blocks each batch listed in its last step (<= 255) */
    double *fpair;         /* pair forces of the step (NULL without pair terms) */
    double pair_range;
};

static double rod_sigma(const hsbd_rods *r, size_t i) {
    return r->species ? r->sp_sigma[r->species[i]] : r->par.sigma;
}

static double rod_mobility(const hsbd_rods *r, size_t i) {
    return r->species ? r->sp_mobility[r->species[i]] : r->mobility;
}

/* offset_i: centre of rod i minus z_i, the summed contact distances to its left */
static void compute_offsets(hsbd_rods *r) {
    double off = r->walls ? 0.5 * rod_sigma(r, 0) : 0.0;
    for (size_t i = 0; i < r->par.n; ++i) {
        if (i > 0) off += 0.5 * (rod_sigma(r, i - 1) + rod_sigma(r, i));
        r->offset[i] = off;
        if (r->friction) r->friction[i] = 1.0 / rod_mobility(r, i);
    }
}

static int check_params(const hsbd_rods_params *par, hsbd_error *err) {
    if (par->n < 1) return hsbd_error_set(err, HSBD_EINPUT, "rods: N = %zu must be >= 1", par->n);
    if (par->boundary != HSBD_RODS_PERIODIC && par->boundary != HSBD_RODS_WALLS)
        return hsbd_error_set(err, HSBD_EINPUT, "rods: unknown boundary %d", par->boundary);
    double total = (double)par->n * par->sigma;
    if (par->nspecies > 0) {
        if (!par->species || !par->species_sigma || !par->species_diffusion)
            return hsbd_error_set(err, HSBD_EINPUT, "rods: a mixture needs its species arrays");
        for (size_t k = 0; k < par->nspecies; ++k)
            if (!(par->species_sigma[k] >= 0) || !(par->species_diffusion[k] > 0) ||
                !isfinite(par->species_sigma[k]) || !isfinite(par->species_diffusion[k]))
                return hsbd_error_set(err, HSBD_EINPUT,
                                      "rods: species %zu needs sigma >= 0 and D > 0 (sigma = %g, "
                                      "D = %g)",
                                      k, par->species_sigma[k], par->species_diffusion[k]);
        total = 0;
        for (size_t i = 0; i < par->n; ++i) {
            if (par->species[i] < 0 || (size_t)par->species[i] >= par->nspecies)
                return hsbd_error_set(err, HSBD_EINPUT, "rods: rod %zu has species %d of %zu", i,
                                      par->species[i], par->nspecies);
            total += par->species_sigma[par->species[i]];
        }
    }
    if (!(par->sigma >= 0) || !(par->length > 0) || !(total < par->length))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "rods: need sigma >= 0 and sum of sigma < L (N = %zu, sum = %g, L = "
                              "%g)",
                              par->n, total, par->length);
    if (!(par->diffusion > 0) || !(par->kT > 0) || !(par->dt > 0) || !isfinite(par->dt))
        return hsbd_error_set(err, HSBD_EINPUT, "rods: need D > 0, kT > 0, dt > 0");
    if (par->field_step != HSBD_FIELD_STEP_EULER && par->field_step != HSBD_FIELD_STEP_HEUN)
        return hsbd_error_set(err, HSBD_EINPUT, "rods: unknown field step %d", par->field_step);
    const double range = hsbd_pair_range(&par->pair);
    if (par->pair.nterms > 0 &&
        (!par->hard_core || par->nspecies > 1 || !(range <= 0.5 * par->length)))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "rods: pair forces need the hard core, one species and a range <= "
                              "L/2 (range = %g, L = %g)",
                              range, par->length);
    return HSBD_OK;
}

static int alloc_species(hsbd_rods *r, const hsbd_rods_params *par) {
    const size_t n = par->n, ns = par->nspecies;
    r->species = malloc(n * sizeof *r->species);
    r->friction = malloc(n * sizeof *r->friction);
    double **sp[] = {&r->sp_sigma, &r->sp_diffusion, &r->sp_mobility, &r->sp_mu_dt, &r->sp_noise};
    for (int k = 0; k < 5; ++k)
        *sp[k] = malloc(ns * sizeof **sp[k]);
    if (!r->species || !r->friction || !r->sp_sigma || !r->sp_diffusion || !r->sp_mobility ||
        !r->sp_mu_dt || !r->sp_noise)
        return -1;
    memcpy(r->species, par->species, n * sizeof *r->species);
    for (size_t k = 0; k < ns; ++k) {
        r->sp_sigma[k] = par->species_sigma[k];
        r->sp_diffusion[k] = par->species_diffusion[k];
        r->sp_mobility[k] = par->species_diffusion[k] / par->kT;
    }
    /* the caller's arrays need not outlive the call */
    r->par.species = r->species;
    r->par.species_sigma = r->sp_sigma;
    r->par.species_diffusion = r->sp_diffusion;
    r->par.sigma = r->sp_sigma[0];
    r->par.diffusion = r->sp_diffusion[0];
    return 0;
}

/* Threads for a loop over n rods: the configured number, one below a few chunks' worth
 * (a parallel region costs a few microseconds). */
static int threads_for(const hsbd_rods_params *par, size_t n) {
    return par->threads > 1 && n >= 4 * STEP_CHUNK ? par->threads : 1;
}

/* rods per part of the ring in the fragmentation diagnostic on threads */
static size_t fragment_part_length(const hsbd_rods *r) {
    return (r->par.n + (size_t)r->frag_parts - 1) / (size_t)r->frag_parts;
}

/* the fragmentation diagnostic on threads: a regression per thread for the clusters that
 * start in its part of the ring (ceil(N / threads) rods; longer clusters use frag) */
static int alloc_fragment_parts(hsbd_rods *r) {
    const int parts = threads_for(&r->par, r->par.n);
    if (parts == 1) return 0;
    r->frag_part = calloc((size_t)parts, sizeof *r->frag_part);
    r->frag_count = malloc((size_t)parts * sizeof *r->frag_count);
    if (!r->frag_part || !r->frag_count) return -1;
    r->frag_parts = parts;
    for (int t = 0; t < parts; ++t)
        if (!(r->frag_part[t] = hsbd_pava_alloc(fragment_part_length(r)))) return -1;
    hsbd_pava_set_threads(r->frag, parts);
    return 0;
}

hsbd_rods *hsbd_rods_alloc(const hsbd_rods_params *par, hsbd_error *err) {
    if (check_params(par, err) != HSBD_OK) return NULL;
    hsbd_rods *r = calloc(1, sizeof *r);
    if (!r) return hsbd_error_set(err, HSBD_ENOMEM, "rods: out of memory"), NULL;
    const size_t n = par->n;
    r->par = *par;
    r->walls = par->boundary == HSBD_RODS_WALLS;
    r->z = calloc(n + 1, sizeof *r->z); /* + 1: rod 0 one ring further (reflect_gaps) */
    r->offset = malloc(n * sizeof *r->offset);
    r->y = calloc(n + 1, sizeof *r->y);
    r->frag_v = malloc(n * sizeof *r->frag_v);
    if (par->nspecies > 0) r->frag_w = malloc(n * sizeof *r->frag_w);
    r->pava = hsbd_pava_alloc(n);
    r->frag = hsbd_pava_alloc(n);
    if (par->contact_rule == HSBD_CONTACT_REFLECT) {
        r->push = calloc(n + 1, sizeof *r->push);
        r->ypush = malloc(n * sizeof *r->ypush);
        r->batch_listed = calloc(n / GAP_CHUNK + 1, sizeof *r->batch_listed);
    }
    r->pair_range = hsbd_pair_range(&par->pair);
    if (par->pair.nterms > 0) r->fpair = malloc(n * sizeof *r->fpair);
    int species_ok = par->nspecies == 0;
    if (!species_ok) species_ok = alloc_species(r, par) == 0;
    if (!species_ok || !r->z || !r->offset || !r->y || !r->frag_v || !r->pava || !r->frag ||
        (par->nspecies > 0 && !r->frag_w) || alloc_fragment_parts(r) != 0 ||
        (par->contact_rule == HSBD_CONTACT_REFLECT &&
         (!r->push || !r->ypush || !r->batch_listed)) ||
        (par->pair.nterms > 0 && !r->fpair)) {
        hsbd_rods_free(r);
        return hsbd_error_set(err, HSBD_ENOMEM, "rods: out of memory for N = %zu", n), NULL;
    }
    hsbd_pava_set_threads(r->pava, par->threads);
    r->mobility = r->par.diffusion / par->kT;
    double total = 0;
    for (size_t i = 0; i < n; ++i)
        total += rod_sigma(r, i);
    r->free_length = par->length - total;
    r->contact_tol = 1e-12 * par->length;
    compute_offsets(r);
    return r;
}

void hsbd_rods_free(hsbd_rods *r) {
    if (!r) return;
    free(r->z);
    free(r->offset);
    free(r->y);
    free(r->frag_v);
    free(r->frag_w);
    for (int t = 0; r->frag_part && t < r->frag_parts; ++t)
        hsbd_pava_free(r->frag_part[t]);
    free(r->frag_part);
    free(r->frag_count);
    free(r->push);
    free(r->ypush);
    free(r->batch_listed);
    free(r->fpair);
    free(r->species);
    free(r->friction);
    free(r->sp_sigma);
    free(r->sp_diffusion);
    free(r->sp_mobility);
    free(r->sp_mu_dt);
    free(r->sp_noise);
    hsbd_pava_free(r->pava);
    hsbd_pava_free(r->frag);
    free(r);
}

/* Sorted uniforms from normalised partial sums of N+1 exponential spacings, O(N). */
void hsbd_rods_init_equilibrium(hsbd_rods *r) {
    hsbd_rods_init_equilibrium_draw(r, 0);
}

void hsbd_rods_init_equilibrium_draw(hsbd_rods *r, uint64_t draw) {
    const size_t n = r->par.n;
    double *u = r->y; /* scratch */
    double rotation;
    const uint64_t c = 3 * draw; /* three counters of the initial-state stream per draw */
    hsbd_rng_uniforms(r->par.seed, HSBD_STREAM_INIT, c, 0, n, u);
    hsbd_rng_uniforms(r->par.seed, HSBD_STREAM_INIT, c + 1, 0, 1, &rotation);
    double last;
    hsbd_rng_uniforms(r->par.seed, HSBD_STREAM_INIT, c + 2, 0, 1, &last);
    double sum = 0.0;
    for (size_t i = 0; i < n; ++i) {
        sum += -log(u[i]);
        u[i] = sum;
    }
    sum += -log(last);
    const double scale = r->free_length / sum, shift = r->walls ? 0.0 : rotation * r->par.length;
    for (size_t i = 0; i < n; ++i)
        r->z[i] = u[i] * scale + shift;
    r->wraps = 0;
    r->nclusters = 0;
}

typedef struct position_key {
    double x;
    int species;
} position_key;

static int compare_positions(const void *a, const void *b) {
    const double x = ((const position_key *)a)->x, y = ((const position_key *)b)->x;
    return (x > y) - (x < y);
}

int hsbd_rods_set_positions(hsbd_rods *r, const double *x, hsbd_error *err) {
    const size_t n = r->par.n;
    const double L = r->par.length;
    position_key *w = malloc(n * sizeof *w);
    if (!w) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t i = 0; i < n && rc == HSBD_OK; ++i) {
        w[i].species = r->species ? r->species[i] : 0;
        const double half = 0.5 * (r->species ? r->sp_sigma[w[i].species] : r->par.sigma);
        if (!isfinite(x[i]))
            rc = hsbd_error_set(err, HSBD_EINPUT, "initial position %zu is not finite", i + 1);
        else if (r->walls && (x[i] < half * (1 - 1e-12) || x[i] > L - half * (1 - 1e-12)))
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "initial position %zu, x = %.17g, is outside the walls: allowed "
                                "sigma/2 = %g <= x <= L - sigma/2 = %g",
                                i + 1, x[i], half, L - half);
        w[i].x = r->walls ? x[i] : x[i] - L * floor(x[i] / L);
    }
    if (rc == HSBD_OK) qsort(w, n, sizeof *w, compare_positions);
    for (size_t i = 0; i < n && rc == HSBD_OK; ++i)
        if (r->species) r->species[i] = w[i].species;
    if (rc == HSBD_OK) compute_offsets(r);
    const double tol = 1e-12 * (r->par.sigma > 0 ? r->par.sigma : 1.0);
    for (size_t i = 0; i < n && rc == HSBD_OK; ++i) {
        if (n < 2 || (r->walls && i + 1 == n)) break;
        const size_t j = i + 1 < n ? i + 1 : 0;
        const double next = i + 1 < n ? w[j].x : w[0].x + L;
        const double contact = 0.5 * (rod_sigma(r, i) + rod_sigma(r, j));
        if (next - w[i].x - contact < -tol)
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "initial positions overlap: rods at x = %.17g and %.17g are "
                                "closer than their contact distance %g",
                                w[i].x, next - (i + 1 < n ? 0.0 : L), contact);
    }
    if (rc == HSBD_OK) {
        for (size_t i = 0; i < n; ++i)
            r->z[i] = w[i].x - r->offset[i];
        /* clamp rounding-level overlaps to exact contact, keeping the order */
        for (size_t i = 1; i < n; ++i)
            if (r->z[i] < r->z[i - 1]) r->z[i] = r->z[i - 1];
        if (r->walls)
            for (size_t i = 0; i < n; ++i)
                r->z[i] = fmin(fmax(r->z[i], 0.0), r->free_length);
        r->wraps = 0;
    }
    free(w);
    return rc;
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
            if (r->walls && i + k >= n) break;
            const size_t j = i + k < n ? i + k : i + k - n;
            const double d = z[j] + off[j] + (i + k < n ? 0.0 : L) - xi;
            if (d >= range) break;
            const double f = hsbd_pair_force(&r->par.pair, d); /* on j from i; -f on i */
            fp[j] += f;
            fp[i] -= f;
        }
    }
}

static int step_threads(const hsbd_rods *r, size_t n) {
    return threads_for(&r->par, n);
}

/* Distance from rod i to rod j to its right as compute_pair_forces computes it (j
 * reached across the ring when wrapped), the same operations in the same order. */
static inline double pair_distance(const hsbd_rods *r, size_t i, size_t j, int wrapped) {
    const double xi = r->z[i] + r->offset[i];
    return r->z[j] + r->offset[j] + (wrapped ? r->par.length : 0.0) - xi;
}

/* The pair forces of compute_pair_forces on threads: each rod gathers its own, adding the
 * terms in the order the serial walk adds them to it (rods to its left that reach it,
 * from the farthest; then its own walk to the right; then, on a ring, rods that reach it
 * across the end), so the sums have the same bits. Each pair is evaluated twice. */
static void gather_pair_forces(hsbd_rods *r, int threads) {
    const size_t n = r->par.n;
    const double range = r->pair_range;
    const int ring = !r->walls;
#pragma omp parallel for schedule(static) num_threads(threads)
    for (long lt = 0; lt < (long)n; ++lt) {
        const size_t t = (size_t)lt;
        double acc = 0.0;
        size_t lo = t; /* rods lo .. t-1 reach t from the left */
        while (lo > 0 && pair_distance(r, lo - 1, t, 0) < range)
            --lo;
        for (size_t i = lo; i < t; ++i)
            acc += hsbd_pair_force(&r->par.pair, pair_distance(r, i, t, 0));
        for (size_t k = 1; k < n; ++k) { /* t's own walk */
            if (!ring && t + k >= n) break;
            const size_t j = t + k < n ? t + k : t + k - n;
            const double d = pair_distance(r, t, j, t + k >= n);
            if (d >= range) break;
            acc -= hsbd_pair_force(&r->par.pair, d);
        }
        if (ring) {        /* rods t+1 .. n-1 whose walk wraps to t: the nearest ones, ascending */
            size_t hi = n; /* rods hi .. n-1 reach t across the end */
            while (hi > t + 1 && pair_distance(r, hi - 1, t, 1) < range)
                --hi;
            for (size_t i = hi; i < n; ++i)
                acc += hsbd_pair_force(&r->par.pair, pair_distance(r, i, t, 1));
        }
        r->fpair[t] = acc;
    }
}

/* mixtures: each species' mu dt and noise amplitude sqrt(2 D dt) for the current dt */
static void species_step_factors(hsbd_rods *r) {
    for (size_t k = 0; k < r->par.nspecies; ++k) {
        r->sp_mu_dt[k] = r->sp_mobility[k] * r->par.dt;
        r->sp_noise[k] = sqrt(2.0 * r->sp_diffusion[k] * r->par.dt);
    }
}

/* The fields a step reads: at its start and, for Heun's predictor, at its end (a driven
 * field's parameters at t and t + dt; a static field is the same both times). */
typedef struct step_fields {
    const hsbd_field *start, *end; /* end: NULL for Euler */
} step_fields;

/* mu_i dt and sqrt(2 D_i dt) of rod i0 + j: its species', or the one species' */
static inline double rod_mu_dt(const hsbd_rods *r, const int *sp, size_t j, double mu_dt) {
    return sp ? r->sp_mu_dt[sp[j]] : mu_dt;
}
static inline double rod_noise(const hsbd_rods *r, const int *sp, size_t j, double noise) {
    return sp ? r->sp_noise[sp[j]] : noise;
}

/* Heun's field force of m rods (docs/algorithms.md, "The time step in a field"): the free
 * predictor x_p = x + mu (f + f_pair) dt + sqrt(2 D dt) g with the step's own normals g,
 * then f <- (f + F_end(x_p)) / 2 in place (force, energy / length). A force equal at both
 * ends gives back f to the bit, so a constant field steps as with Euler. */
static void heun_field_force(const hsbd_rods *r, const hsbd_field *end, size_t i0, size_t m,
                             const double *restrict x, const double *restrict g,
                             double *restrict f) {
    const double mu_dt = r->mobility * r->par.dt;
    const double noise = sqrt(2.0 * r->par.diffusion * r->par.dt);
    const int *sp = r->species ? r->species + i0 : NULL;
    double xp[STEP_CHUNK], fp[STEP_CHUNK];
    for (size_t j = 0; j < m; ++j) {
        const double pair = r->fpair ? r->fpair[i0 + j] : 0.0;
        xp[j] =
            x[j] + rod_mu_dt(r, sp, j, mu_dt) * (f[j] + pair) + rod_noise(r, sp, j, noise) * g[j];
    }
    hsbd_field_force(end, m, xp, fp);
    for (size_t j = 0; j < m; ++j)
        f[j] = 0.5 * (f[j] + fp[j]); /* trapezoid of the force over the step, Heun */
}

/* The free end points of rods i0 .. i0 + STEP_CHUNK - 1 (see compute_endpoints). */
static void endpoints_chunk(const hsbd_rods *r, step_fields fields, size_t i0) {
    const size_t n = r->par.n, m = n - i0 < STEP_CHUNK ? n - i0 : STEP_CHUNK;
    const double mu_dt = r->mobility * r->par.dt;
    const double noise = sqrt(2.0 * r->par.diffusion * r->par.dt);
    const int has_field = r->par.field.nterms > 0, has_pair = r->fpair != NULL;
    double x[STEP_CHUNK], f[STEP_CHUNK], g[STEP_CHUNK];
    const double *restrict z = r->z + i0;
    double *restrict y = r->y + i0;
    hsbd_rng_normals(r->par.seed, HSBD_STREAM_NOISE, r->step, i0, m, g);
    if (has_field || has_pair) {
        for (size_t j = 0; j < m; ++j)
            x[j] = z[j] + r->offset[i0 + j];
        hsbd_field_force(fields.start, m, x, f);
        if (has_field && fields.end) heun_field_force(r, fields.end, i0, m, x, g, f);
        if (has_pair)
            for (size_t j = 0; j < m; ++j)
                f[j] += r->fpair[i0 + j];
    } else if (r->species) {
        memset(f, 0, m * sizeof *f);
    }
    if (r->species) {
        const int *sp = r->species + i0;
        for (size_t j = 0; j < m; ++j)
            y[j] = z[j] + r->sp_mu_dt[sp[j]] * f[j] + r->sp_noise[sp[j]] * g[j];
    } else if (has_field || has_pair) {
        for (size_t j = 0; j < m; ++j)
            y[j] = z[j] + mu_dt * f[j] + noise * g[j];
    } else {
        for (size_t j = 0; j < m; ++j)
            y[j] = z[j] + noise * g[j];
    }
}

/* y_i = z_i + mu_i dt F_i + sqrt(2 D_i dt) N_i: the free end point of Eq. (10), i.e.
 * z_i + mu_i F_i dt with the total force of Eq. (11) (field plus pair forces, Eq. 28); the
 * field's part is Euler's F(x_i) or Heun's mean (heun_field_force). Chunks of rods are
 * independent (each rod's noise is its own Philox counter): threads share them out
 * without changing a bit; one thread enters no parallel region. */
static void compute_endpoints(hsbd_rods *r) {
    const size_t n = r->par.n;
    const int threads = step_threads(r, n);
    if (r->fpair && threads > 1)
        gather_pair_forces(r, threads);
    else if (r->fpair)
        compute_pair_forces(r);
    if (r->species) species_step_factors(r);
    hsbd_field now, next; /* a driven field at the step's start (and end), frozen in between */
    const step_fields fields = {.start = hsbd_field_at(&r->par.field, r->time, &now),
                                .end =
                                    r->par.field_step == HSBD_FIELD_STEP_HEUN
                                        ? hsbd_field_at(&r->par.field, r->time + r->par.dt, &next)
                                        : NULL};
    if (threads > 1) {
        const long nchunks = (long)((n + STEP_CHUNK - 1) / STEP_CHUNK);
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long c = 0; c < nchunks; ++c)
            endpoints_chunk(r, fields, (size_t)c * STEP_CHUNK);
    } else {
        for (size_t i0 = 0; i0 < n; i0 += STEP_CHUNK)
            endpoints_chunk(r, fields, i0);
    }
}

/* gap right of rod i; for the last rod: to rod 0 across the ring, or to the right wall */
static double ring_gap(const hsbd_rods *r, size_t i) {
    const size_t n = r->par.n;
    if (i + 1 < n) return r->z[i + 1] - r->z[i];
    return r->walls ? r->free_length - r->z[n - 1] : r->z[0] + r->free_length - r->z[n - 1];
}

/* gap between rods i and i+1 (ring order); between walls the last rod has no right
 * neighbour (infinite gap) */
static double rod_gap(const hsbd_rods *r, size_t i) {
    return r->walls && i + 1 == r->par.n ? HUGE_VAL : ring_gap(r, i);
}

/* Clusters touching at the start that begin at ring-order places a .. b-1 (place k is rod
 * first + k mod n) with the velocities of the end points `target`, each cluster's
 * fragments from the isotonic regression of its velocities (Eqs. 4-5) with `pava` (of
 * `cap` elements), weighted by the frictions 1/mu_i in a mixture (a cluster moves with
 * the friction-weighted mean velocity). The velocities are written to frag_v[k], the
 * frictions to frag_w[k]. */
static void count_fragments_in(hsbd_rods *r, const double *target, size_t first, size_t a, size_t b,
                               hsbd_pava *pava, size_t cap, fragment_count *out) {
    const size_t n = r->par.n;
    const double inv_dt = 1.0 / r->par.dt, tol = r->contact_tol;
    double *v = r->frag_v, *w = r->frag_w;
    size_t k = a, i = first + a < n ? first + a : first + a - n; /* rod at place k */
    *out = (fragment_count){0};
    if (k > 0) /* skip the end of a cluster that began before a */
        for (size_t left = i ? i - 1 : n - 1; k < b && !(rod_gap(r, left) > tol); ++k) {
            left = i;
            i = i + 1 < n ? i + 1 : 0;
        }
    while (k < b) {
        const size_t k0 = k;
        int open;
        do {
            if (w) w[k] = r->friction[i];
            v[k++] = (target[i] - r->z[i]) * inv_dt; /* mu F_i, Eq. (12) */
            open = rod_gap(r, i) > tol;
            i = i + 1 < n ? i + 1 : 0;
        } while (k < n && !open);
        const size_t len = k - k0;
        out->clusters += 1;
        if (len == 1)
            out->fragments += 1;
        else if (len <= cap)
            out->fragments += hsbd_pava_line(pava, len, v + k0, w ? w + k0 : NULL, v + k0);
        else
            out->long_first = k0, out->long_len = len;
    }
}

/* Fragmentation diagnostic: clusters touching at the start and the number of moving
 * clusters they split into (the isotonic regression of the velocities inside each
 * cluster, Eqs. 4-5) of the end points `target` (with the reflect rule: after the pushes).
 * On threads each part of the ring counts the clusters that begin in it; the counts are
 * integers, so their sum is the same for any split. Must run before z is overwritten. */
static void count_fragments(hsbd_rods *r, const double *target, hsbd_rods_step_stats *st) {
    const size_t n = r->par.n;
    size_t first = 0; /* a rod whose left gap is open; else the one after the widest gap */
    double widest = -DBL_MAX;
    for (size_t i = 0; i < n; ++i) {
        const double g = rod_gap(r, (i + n - 1) % n);
        if (g > widest) widest = g, first = i;
        if (g > r->contact_tol) break;
    }
    fragment_count one, *part = r->frag_part ? r->frag_count : &one;
    const int parts = r->frag_part ? r->frag_parts : 1;
    if (parts > 1) {
        const size_t cap = fragment_part_length(r);
#pragma omp parallel for schedule(static, 1) num_threads(parts)
        for (int t = 0; t < parts; ++t) {
            const size_t a = (size_t)t * cap, b = a + cap < n ? a + cap : n;
            count_fragments_in(r, target, first, a < n ? a : n, b, r->frag_part[t], cap, &part[t]);
        }
    } else {
        count_fragments_in(r, target, first, 0, n, r->frag, n, &part[0]);
    }
    st->clusters_start = st->fragments = 0;
    for (int t = 0; t < parts; ++t) {
        st->clusters_start += part[t].clusters;
        st->fragments += part[t].fragments;
        if (part[t].long_len > 0) /* longer than a part: frag, itself on the threads */
        {
            const size_t k0 = part[t].long_first;
            st->fragments += hsbd_pava_line(r->frag, part[t].long_len, r->frag_v + k0,
                                            r->frag_w ? r->frag_w + k0 : NULL, r->frag_v + k0);
        }
    }
}

/* Keep coordinates bounded: shift all z by L once rod 0 has left [-L, 2L). */
static void recenter(hsbd_rods *r) {
    const double L = r->par.length;
    const double z0 = r->z[0];
    if (r->walls || (z0 >= -L && z0 < 2 * L)) return;
    const int64_t k = (int64_t)floor(z0 / L);
    for (size_t i = 0; i < r->par.n; ++i) {
        r->z[i] -= (double)k * L;
        r->y[i] -= (double)k * L; /* the step's end points stay in the frame of z */
        if (r->ypush) r->ypush[i] -= (double)k * L;
    }
    r->wraps += k;
}

/* A gap's uniform is U = (b + V) / 256: its random byte b (stream HSBD_STREAM_CONTACT, byte
 * `gap` of hsbd_rng_bytes_at) and, only when b leaves a crossing possible
 * (bridge_byte_candidate), its low digits V (stream HSBD_STREAM_CONTACT_DEPTH). The push of
 * one gap outside the batches (a wall's: gap n - 1 on the right, n on the left), whose V is
 * the uniform of index `gap` (the batches' candidates take indices below n - 1). */
static double bridge_push(double g0, double g1, double d_rel_dt, uint64_t seed, uint64_t step,
                          size_t gap) {
    if (!bridge_may_cross(g0, g1, d_rel_dt)) return 0.0;
    const unsigned block = 0;
    uint8_t bytes[GAP_BLOCK];
    hsbd_rng_bytes_at(seed, HSBD_STREAM_CONTACT, step, gap / GAP_BLOCK, &block, 1, bytes);
    const unsigned byte = bytes[gap % GAP_BLOCK];
    if (!bridge_byte_candidate(g0 * g1, d_rel_dt, byte)) return 0.0;
    double u;
    hsbd_rng_uniforms(seed, HSBD_STREAM_CONTACT_DEPTH, step, gap, 1, &u);
    u = ((double)byte + u) * (1.0 / 256);
    hsbd_vmath_log(1, &u);
    const double sum = g0 + g1, sq = (g1 - g0) * (g1 - g0);
    gap_pushes(1, &sum, &sq, NULL, d_rel_dt, &u);
    return u;
}

/* 0, 1, 2, ...: the blocks of a batch, the indices of a batch's first candidates' low
 * digits */
static const unsigned counting[GAP_CHUNK / GAP_BLOCK] = {
    0,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
    22, 23, 24, 25, 26, 27, 28, 29, 30, 31, 32, 33, 34, 35, 36, 37, 38, 39, 40, 41, 42, 43,
    44, 45, 46, 47, 48, 49, 50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 60, 61, 62, 63};

/* Pushes of the rod-rod gaps first .. first+m-1 (first a multiple of GAP_CHUNK), with the
 * uniforms of bridge_push: the candidates among the gaps that may cross (gaps.h), then for
 * these alone the low digits (the k-th candidate of the batch takes the uniform of index
 * first + k), the logarithms (vectorised) and the bridge minima. The candidates come in one
 * of three ways, with the same answer: a short batch (m <= EARLY_GAPS) that listed gaps in
 * its last step draws the bytes of all its blocks and its first four low digits first, in one
 * generator call whose chain of multiplies runs beside the tests, and makes both tests in one
 * pass; a batch that listed at least 3/4 of its blocks in its last step (dense systems) draws
 * the bytes of all its blocks, then makes both tests in one pass; any other lists the blocks
 * of GAP_BLOCK gaps that hold a gap that may cross, then draws their bytes alone (one Philox
 * counter per block). The batch notes how many blocks it listed (its own entry: no race on
 * threads). With one species (out not NULL) the rods
 * between two of its gaps take half of each push into out at once, while the batch is in
 * cache (z is read no more by then, so out may be z). */
static void push_gap_batch(hsbd_rods *r, size_t first, size_t m, double kt_dt,
                           double *restrict push, double *out) {
    double u[GAP_CHUNK], d[GAP_CHUNK], g0g1[GAP_CHUNK], sq[GAP_CHUNK];
    unsigned blocks[GAP_CHUNK / GAP_BLOCK], idx[GAP_CHUNK];
    uint16_t mask[GAP_CHUNK / GAP_BLOCK];
    uint8_t bytes[GAP_CHUNK];
    const double *z = r->z + first, *y = r->y + first;
    const double d_one = 2.0 * r->mobility * kt_dt; /* one species: 2 D dt */
    double *dd = r->species ? d : NULL;
    if (r->species)
        for (size_t j = 0; j < m; ++j)
            d[j] =
                (rod_mobility(r, first + j) + rod_mobility(r, (first + j + 1) % r->par.n)) * kt_dt;
    gap_copy(m, NULL, push);
    const uint64_t seed = r->par.seed, step = r->step;
    uint8_t *listed_last = &r->batch_listed[first / GAP_CHUNK];
    const size_t nblocks = (m + GAP_BLOCK - 1) / GAP_BLOCK;
    const size_t early = m <= EARLY_GAPS && *listed_last ? EARLY_DIGITS : 0;
    size_t count, listed;
    if (early) {
        hsbd_rng_bytes_and_four(seed, step, HSBD_STREAM_CONTACT, first / GAP_BLOCK, counting,
                                nblocks, bytes, HSBD_STREAM_CONTACT_DEPTH, first, u);
        count = gap_candidates_all(z, y, dd, d_one, m, bytes, idx, &listed);
    } else if (4 * (size_t)*listed_last >= 3 * nblocks) { /* dense: (nearly) every block */
        hsbd_rng_bytes_at(seed, HSBD_STREAM_CONTACT, step, first / GAP_BLOCK, counting, nblocks,
                          bytes);
        count = gap_candidates_all(z, y, dd, d_one, m, bytes, idx, &listed);
    } else {
        listed = gap_blocks_may_cross(z, y, dd, d_one, m, mask, blocks, g0g1);
        if (listed > 0)
            hsbd_rng_bytes_at(seed, HSBD_STREAM_CONTACT, step, first / GAP_BLOCK, blocks, listed,
                              bytes);
        count = listed ? gap_candidates(g0g1, dd, d_one, m, mask, blocks, listed, bytes, idx) : 0;
    }
    *listed_last = (uint8_t)(listed < 255 ? listed : 255);
    if (count > early + 3 * GAP_BLOCK) /* a run of counters, two uniforms each */
        hsbd_rng_uniforms(seed, HSBD_STREAM_CONTACT_DEPTH, step, first + early, count - early,
                          u + early);
    else if (count > early) /* few: one counter each, the same numbers (less to set up) */
        hsbd_rng_uniforms_at(seed, HSBD_STREAM_CONTACT_DEPTH, step, first + early, counting,
                             count - early, u + early);
    double *sum = g0g1; /* the products are used up; the candidates' values packed in order */
    for (size_t k = 0; k < count; ++k) {
        const size_t j = idx[k]; /* >= k: d[j] is read before d[k] is written */
        const double g0 = z[j + 1] - z[j], g1 = y[j + 1] - y[j];
        u[k] = ((double)bytes[j] + u[k]) * (1.0 / 256);
        sum[k] = g0 + g1;
        sq[k] = (g1 - g0) * (g1 - g0);
        if (dd) d[k] = d[j];
    }
    hsbd_vmath_log(count, u);
    gap_pushes(count, sum, sq, dd, d_one, u);
    for (size_t k = 0; k < count; ++k)
        push[idx[k]] = u[k];
    if (!out || m < 2) return;
    if (8 * count > m) /* many pushes: every rod's halves, vectorised */
        gap_half_pushes(m - 1, y + 1, push + 1, out + first + 1);
    else /* few: y, then the pushes' halves */
        gap_half_pushes_at(m, y, push, idx, count, out + first);
}

/* The part of a gap's push that rod i takes: mu_i / (mu_i + mu_nb) against rod nb, all of
 * it against a wall (nb = i). */
static double push_share(const hsbd_rods *r, size_t i, size_t nb) {
    if (nb == i) return 1.0;
    if (!r->species) return 0.5;
    const double mi = rod_mobility(r, i);
    return mi / (mi + rod_mobility(r, nb));
}

/* The rod-rod gaps the batches take: on a ring all n, the last one (rod n - 1 to rod 0) through
 * the copies z[n], y[n] of rod 0 one ring further; between walls n - 1 (the walls' gaps apart). */
static size_t batch_gaps(const hsbd_rods *r) {
    return r->walls || r->par.n < 2 ? r->par.n - 1 : r->par.n;
}

/* The pushes of the rod-rod gaps lo .. hi-1 (hi capped at batch_gaps), in batches of
 * GAP_CHUNK from lo. With one species the rods between two gaps of a batch take their
 * halves at once, while the batch's end points and pushes are in cache; the first rod of
 * each batch waits for the batch before (take_batch_edges). */
static void push_gap_batches(hsbd_rods *r, size_t lo, size_t hi, double kt_dt, double *out) {
    if (hi > batch_gaps(r)) hi = batch_gaps(r);
    for (size_t first = lo; first < hi; first += GAP_CHUNK) {
        const size_t m = hi - first < GAP_CHUNK ? hi - first : GAP_CHUNK;
        push_gap_batch(r, first, m, kt_dt, r->push + first, r->species ? NULL : out);
    }
}

/* One species: the first rod of every batch but the first (its left gap is the last of
 * the batch before) takes half of each push. */
static void take_batch_edges(const hsbd_rods *r, double *out) {
    for (size_t i = GAP_CHUNK; i < batch_gaps(r); i += GAP_CHUNK)
        gap_half_pushes(1, r->y + i, r->push + i, out + i);
}

/* The pushed end point of rod i from its two gaps' pushes, shared by the mobilities
 * (push_share); a wall's gap is push[n] on the left, push[n - 1] on the right. */
static void take_pushes(const hsbd_rods *r, size_t i, double *out) {
    const size_t n = r->par.n, il = i > 0 ? i - 1 : n - 1, ir = i + 1 < n ? i + 1 : 0;
    const int wall_left = r->walls && i == 0, wall_right = r->walls && i + 1 == n;
    const double left = r->push[wall_left ? n : il], right = r->push[i];
    out[i] = r->y[i] + left * push_share(r, i, wall_left ? i : il) -
             right * push_share(r, i, wall_right ? i : ir);
}

/* Reflect rule: for every gap that may have touched zero during the step, draw the
 * minimum of its Brownian bridge; a crossing reflects the gap (exact for an isolated pair,
 * any dt and constant force). Rod-rod gaps have relative diffusion D_i + D_{i+1}, and the
 * push is shared in proportion to the mobilities, which keeps the pair's friction-weighted
 * centre; a wall gap has D_i and the rod takes all of it. Pushes are computed from the
 * free end points of all gaps first, so the result does not depend on the order. The
 * pushed end points go to out: r->ypush, or z itself (see hsbd_rods_step). Each batch
 * writes the rods between its gaps only after its own pushes, and no batch reads the
 * positions of another's rods but the first (written last, by take_batch_edges) and the
 * copy of rod 0, so out may be z on threads too. */
static void reflect_gaps(hsbd_rods *r, double *out) {
    const size_t n = r->par.n, gaps = batch_gaps(r);
    const double kt_dt = r->par.kT * r->par.dt, lf = r->free_length;
    double *push = r->push;
    if (!r->walls) { /* rod 0 one ring further: the ring's last gap in the last batch */
        r->z[n] = r->z[0] + lf;
        r->y[n] = r->y[0] + lf;
    }
    const int threads = step_threads(r, n);
    if (threads > 1) {
        const long nbatches = (long)((gaps + GAP_CHUNK - 1) / GAP_CHUNK);
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long b = 0; b < nbatches; ++b)
            push_gap_batches(r, (size_t)b * GAP_CHUNK, (size_t)(b + 1) * GAP_CHUNK, kt_dt, out);
    } else {
        push_gap_batches(r, 0, gaps, kt_dt, out);
    }
    if (!r->species) take_batch_edges(r, out);
    if (r->walls) { /* the rod's own D against each wall */
        const double *z = r->z, *y = r->y;
        const uint64_t seed = r->par.seed, step = r->step;
        const double d_last = rod_mobility(r, n - 1) * kt_dt, d_first = rod_mobility(r, 0) * kt_dt;
        push[n - 1] = bridge_push(lf - z[n - 1], lf - y[n - 1], d_last, seed, step, n - 1);
        push[n] = bridge_push(z[0], y[0], d_first, seed, step, n);
    } else {
        if (n < 2) push[0] = 0.0; /* one rod on a ring: no gap */
        push[n] = 0.0;
    }
    /* the rods the batches left out: all of a mixture, else rod 0 and, between walls, the
     * last rod */
    if (r->species) {
        for (size_t i = 0; i < n; ++i)
            take_pushes(r, i, out);
    } else {
        take_pushes(r, 0, out);
        if (r->walls && n > 1) take_pushes(r, n - 1, out);
    }
}

/* Between walls: clamp the line regression to [0, free length] (the exact solution of the
 * bounded isotonic regression). Only blocks at the ends can reach a wall (the fit is
 * sorted), so this costs O(clamped blocks). Blocks clamped to the same wall form one
 * cluster; their numbers are kept for the cluster sizes. Returns the number of clusters. */
static size_t clamp_to_walls(hsbd_rods *r, size_t nblocks) {
    const double lf = r->free_length;
    size_t lead = 0, trail = 0, start = 0, end = r->par.n;
    while (lead < nblocks && r->z[start] <= 0.0) {
        const size_t size = hsbd_pava_block_size(r->pava, lead++);
        for (size_t i = start; i < start + size; ++i)
            r->z[i] = 0.0;
        start += size;
    }
    while (trail < nblocks - lead && r->z[end - 1] >= lf) {
        const size_t size = hsbd_pava_block_size(r->pava, nblocks - 1 - trail++);
        for (size_t i = end - size; i < end; ++i)
            r->z[i] = lf;
        end -= size;
    }
    r->wall_blocks[0] = lead;
    r->wall_blocks[1] = trail;
    r->pava_blocks = nblocks;
    return nblocks - (lead > 1 ? lead - 1 : 0) - (trail > 1 ? trail - 1 : 0);
}

/* sum of the sizes of regression blocks [a, b) */
static size_t blocks_size(const hsbd_rods *r, size_t a, size_t b) {
    size_t total = 0;
    for (size_t k = a; k < b; ++k)
        total += hsbd_pava_block_size(r->pava, k);
    return total;
}

int hsbd_rods_step(hsbd_rods *r, hsbd_rods_step_stats *stats) {
    compute_endpoints(r);
    if (r->par.hard_core) {
        const double *target = r->y;
        if (r->par.contact_rule == HSBD_CONTACT_REFLECT) {
            /* The pushed end points into z itself, and the regression in place, unless the
             * fragment count needs the start positions or a mixture's weighted regression
             * would copy them anyway: 8 bytes per rod less to write and read back, which
             * beyond the caches is most of what the rule adds to a step. Same bits. */
            double *out = stats || r->species ? r->ypush : r->z;
            reflect_gaps(r, out);
            target = out;
        }
        if (stats) count_fragments(r, target, stats);
        if (r->walls)
            r->nclusters =
                clamp_to_walls(r, hsbd_pava_line(r->pava, r->par.n, target, r->friction, r->z));
        else
            r->nclusters =
                hsbd_pava_ring(r->pava, r->par.n, target, r->friction, r->free_length, r->z);
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
    return HSBD_OK;
}

void hsbd_rods_set_dt(hsbd_rods *r, double dt) {
    if (dt > 0 && isfinite(dt)) r->par.dt = dt;
}

size_t hsbd_rods_cluster_count(const hsbd_rods *r) {
    return r->nclusters;
}

size_t hsbd_rods_cluster_size(const hsbd_rods *r, size_t k) {
    if (!r->walls) return hsbd_pava_block_size(r->pava, k);
    const size_t lead = r->wall_blocks[0], trail = r->wall_blocks[1], nb = r->pava_blocks;
    if (lead > 0 && k == 0) return blocks_size(r, 0, lead); /* held by the left wall */
    if (trail > 0 && k + 1 == r->nclusters) return blocks_size(r, nb - trail, nb);
    return hsbd_pava_block_size(r->pava, k + (lead > 1 ? lead - 1 : 0));
}

hsbd_rods_view hsbd_rods_get_view(const hsbd_rods *r) {
    hsbd_rods_view v = {
        .n = r->par.n,
        .length = r->par.length,
        .sigma = r->par.sigma,
        .free_length = r->free_length,
        .periodic = !r->walls,
        .z = r->z,
        .offset = r->offset,
        .nspecies = r->species ? r->par.nspecies : 0,
        .species = r->species,
        .species_sigma = r->sp_sigma,
        .species_mobility = r->sp_mobility,
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
        if ((r->par.n > 1 || r->walls) && g < m) m = g;
    }
    if (r->walls && r->z[0] < m) m = r->z[0];
    if (all_finite) *all_finite = finite;
    return m < DBL_MAX ? m : r->free_length;
}

/* ---- checkpoints ---- */
void hsbd_rods_save(const hsbd_rods *r, hsbd_writer *w) {
    hsbd_put_tag(w, "rods");
    hsbd_put_u64(w, r->par.n);
    hsbd_put_f64s(w, r->z, r->par.n);
    hsbd_put_i64(w, r->wraps);
    hsbd_put_u64(w, r->step);
    hsbd_put_f64(w, r->time);
    hsbd_put_f64(w, r->par.dt);
    if (r->species) hsbd_put_ints(w, r->species, r->par.n);
}

int hsbd_rods_load(hsbd_rods *r, hsbd_reader *rd) {
    const size_t n = r->par.n;
    double dt;
    if (hsbd_get_tag(rd, "rods") || hsbd_get_count(rd, n, "rods") || hsbd_get_f64s(rd, r->z, n) ||
        hsbd_get_i64(rd, &r->wraps) || hsbd_get_u64(rd, &r->step) || hsbd_get_f64(rd, &r->time) ||
        hsbd_get_f64(rd, &dt))
        return -1;
    if (r->species && hsbd_get_ints(rd, r->species, n)) return -1;
    for (size_t i = 0; r->species && i < n; ++i)
        if (r->species[i] < 0 || (size_t)r->species[i] >= r->par.nspecies)
            return hsbd_reader_fail(rd, "rods: a species index out of range");
    for (size_t i = 0; i < n; ++i)
        if (!isfinite(r->z[i]) || (i > 0 && r->z[i] < r->z[i - 1]))
            return hsbd_reader_fail(rd, "rods: positions not finite or out of order");
    if (r->walls && (r->z[0] < 0 || r->z[n - 1] > r->free_length))
        return hsbd_reader_fail(rd, "rods: positions beyond the walls");
    if (!r->walls && r->z[n - 1] > r->z[0] + r->free_length + 1e-9 * r->par.length)
        return hsbd_reader_fail(rd, "rods: positions out of order around the ring");
    if (!(dt > 0) || !isfinite(dt) || !isfinite(r->time))
        return hsbd_reader_fail(rd, "rods: time step or time not valid");
    r->par.dt = dt;
    compute_offsets(r); /* the species along the line decide the offsets and frictions */
    return 0;
}
