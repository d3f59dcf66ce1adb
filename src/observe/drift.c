/* Drift: the mean velocity and the effective diffusion coefficients of tagged particles
 * and of the centre of mass from the displacements over blocks of time (docs/observables.md).
 *
 * Over block b of length T_b every particle i moves by d_ib (unwrapped). With B blocks,
 * n particles, v the mean velocity and m_b = (1/n) sum_i d_ib the centre of mass's move:
 *   v = mean_b v_b,  v_b = m_b / T_b;
 *   D_cm = B/(B-1) mean_b (m_b - v T_b)^2 / (2 T_b)          (unbiased for the fitted v);
 *   D_tag = mean_b (1/n) sum_i (d_ib - v T_b)^2 / (2 T_b) + D_cm / B
 *     (the subtracted v has the variance of m over B blocks: E (d - vT)^2 = var d - var m / B);
 * errors: the blocks' standard error of v_b and of the per-block terms. These estimate
 * D_eff = lim var x(t) / 2t at t = T; the bias is of order (relaxation time) / T. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/observe.h"
#include "observe/checkpoint.h"

enum { DRIFT_S1, DRIFT_S2, DRIFT_T, DRIFT_FIELDS }; /* per block: sum d, sum d^2, T */

struct hsbd_drift {
    size_t n;
    double *x_start; /* positions at the open block's start */
    double t_start;
    size_t open;        /* 1 + the open block's index, 0: none */
    hsbd_blocks *clock; /* counts the samples into time blocks (extended runs too) */
    size_t nblocks, capacity;
    double *block; /* nblocks x DRIFT_FIELDS */
};

hsbd_drift *hsbd_drift_alloc(size_t n, size_t nblocks, uint64_t nsamples_total, hsbd_error *err) {
    hsbd_drift *d = calloc(1, sizeof *d);
    if (d) {
        d->n = n;
        d->capacity = nblocks > 0 ? nblocks : 1;
        d->x_start = malloc((n ? n : 1) * sizeof *d->x_start);
        d->block = calloc(d->capacity * DRIFT_FIELDS, sizeof *d->block);
        d->clock = hsbd_blocks_alloc(1, d->capacity, nsamples_total);
    }
    if (!d || !d->x_start || !d->block || !d->clock) {
        hsbd_drift_free(d);
        hsbd_error_set(err, HSBD_ENOMEM, "out of memory for the drift of %zu particles", n);
        return NULL;
    }
    return d;
}

void hsbd_drift_free(hsbd_drift *d) {
    if (!d) return;
    free(d->x_start);
    free(d->block);
    hsbd_blocks_free(d->clock);
    free(d);
}

/* the open block's row ended at time t with positions x: sum d, sum d^2, T */
static void block_row(const hsbd_drift *d, double t, const double *x, double *row) {
    double s1 = 0, s2 = 0;
    for (size_t i = 0; i < d->n; ++i) {
        const double dx = x[i] - d->x_start[i];
        s1 += dx, s2 += dx * dx;
    }
    row[DRIFT_S1] = s1, row[DRIFT_S2] = s2, row[DRIFT_T] = t - d->t_start;
}

/* the closing block's sums; HSBD_ENOMEM when its row cannot be allocated */
static int close_block(hsbd_drift *d, double t, const double *x) {
    if (!d->open) return HSBD_OK;
    d->open = 0;
    if (!(t > d->t_start)) return HSBD_OK; /* an empty block adds nothing */
    if (d->nblocks == d->capacity) {
        double *grown = realloc(d->block, 2 * d->capacity * DRIFT_FIELDS * sizeof *grown);
        if (!grown) return HSBD_ENOMEM;
        d->block = grown, d->capacity *= 2;
    }
    block_row(d, t, x, d->block + DRIFT_FIELDS * d->nblocks++);
    return HSBD_OK;
}

/* the block of this sample, and the sample counted */
static size_t next_block(hsbd_drift *d) {
    const size_t block = hsbd_blocks_current(d->clock);
    hsbd_blocks_end_sample(d->clock);
    return block;
}

static int open_block(hsbd_drift *d, double t, const double *x, size_t block) {
    const int rc = close_block(d, t, x);
    memcpy(d->x_start, x, d->n * sizeof *x);
    d->t_start = t;
    d->open = block + 1;
    return rc;
}

int hsbd_drift_sample_values(hsbd_drift *d, double t, const double *x) {
    const size_t block = next_block(d);
    return d->open == block + 1 ? HSBD_OK : open_block(d, t, x, block);
}

int hsbd_drift_close_values(hsbd_drift *d, double t, const double *x) {
    return close_block(d, t, x);
}

/* the unwrapped positions of the view into d->x_start's twin: computed on the fly */
static void unwrapped(const hsbd_rods_view *v, double *x) {
    for (size_t i = 0; i < v->n; ++i)
        x[i] = v->z[i] + v->offset[i] + v->unwrap;
}

int hsbd_drift_sample(hsbd_drift *d, const hsbd_rods_view *v, double *scratch) {
    const size_t block = next_block(d);
    if (d->open == block + 1) return HSBD_OK;
    unwrapped(v, scratch);
    return open_block(d, v->time, scratch, block);
}

int hsbd_drift_close(hsbd_drift *d, const hsbd_rods_view *v, double *scratch) {
    if (!d->open) return HSBD_OK;
    unwrapped(v, scratch);
    return close_block(d, v->time, scratch);
}

/* The rows of the closed blocks and, when extra != NULL, one more (the open block). */
typedef struct rows {
    const double *block, *extra;
    size_t nclosed;
} rows;

static const double *row_of(const rows *r, size_t k) {
    return k < r->nclosed ? r->block + DRIFT_FIELDS * k : r->extra;
}

/* per-block terms: 0 velocity v_b, 1 centre-of-mass term, 2 tagged term (given v) */
static double term_of(const rows *r, size_t k, int which, double n, double v, double bias) {
    const double *row = row_of(r, k), t = row[DRIFT_T], m = row[DRIFT_S1] / n, vt = v * t;
    if (which == 0) return m / t;
    if (which == 1) return bias * (m - vt) * (m - vt) / (2 * t);
    return (row[DRIFT_S2] / n - 2 * vt * m + vt * vt) / (2 * t);
}

/* mean and standard error of the mean of a term over the b blocks */
static void mean_err(const rows *r, size_t b, int which, double n, double v, double bias,
                     double *mean, double *err) {
    double s = 0, ss = 0;
    for (size_t k = 0; k < b; ++k)
        s += term_of(r, k, which, n, v, bias);
    *mean = s / (double)b;
    for (size_t k = 0; k < b; ++k) {
        const double dev = term_of(r, k, which, n, v, bias) - *mean;
        ss += dev * dev;
    }
    *err = sqrt(ss / (double)(b - 1) / (double)b);
}

int hsbd_drift_get(const hsbd_drift *d, double t, const double *x, hsbd_drift_result *out) {
    double extra[DRIFT_FIELDS];
    const int partial = x && d->open && t > d->t_start;
    if (partial) block_row(d, t, x, extra);
    const rows r = {d->block, partial ? extra : NULL, d->nblocks};
    const size_t b = d->nblocks + (partial ? 1 : 0);
    const double n = (double)d->n, bias = (double)b / ((double)b - 1);
    *out = (hsbd_drift_result){NAN, NAN, NAN, NAN, NAN, NAN, NAN, b};
    if (b < 2 || d->n == 0) return HSBD_OK;
    mean_err(&r, b, 0, n, 0, 0, &out->velocity, &out->velocity_err);
    mean_err(&r, b, 1, n, out->velocity, bias, &out->d_cm, &out->d_cm_err);
    mean_err(&r, b, 2, n, out->velocity, bias, &out->d_tagged, &out->d_tagged_err);
    out->d_tagged += out->d_cm / (double)b;
    double t_sum = 0;
    for (size_t k = 0; k < b; ++k)
        t_sum += row_of(&r, k)[DRIFT_T];
    out->block_time = t_sum / (double)b;
    return HSBD_OK;
}

void hsbd_drift_save(const hsbd_drift *d, hsbd_writer *w) {
    hsbd_put_tag(w, "drift");
    hsbd_put_u64(w, d->n);
    hsbd_put_u64(w, d->open);
    hsbd_put_f64(w, d->t_start);
    hsbd_put_f64s(w, d->x_start, d->n);
    hsbd_put_u64(w, d->nblocks);
    hsbd_put_f64s(w, d->block, d->nblocks * DRIFT_FIELDS);
    hsbd_blocks_save(d->clock, w);
}

int hsbd_drift_load(hsbd_drift *d, hsbd_reader *r) {
    uint64_t n, open, nblocks;
    if (hsbd_get_tag(r, "drift") || hsbd_get_u64(r, &n) || hsbd_get_u64(r, &open) ||
        hsbd_get_f64(r, &d->t_start))
        return -1;
    if (n != d->n) return hsbd_reader_fail(r, "drift: another number of particles");
    if (hsbd_get_f64s(r, d->x_start, d->n) || hsbd_get_u64(r, &nblocks)) return -1;
    if (nblocks > d->capacity) {
        if (nblocks > SIZE_MAX / (DRIFT_FIELDS * sizeof *d->block))
            return hsbd_reader_fail(r, "drift: too many blocks");
        double *grown = realloc(d->block, (size_t)nblocks * DRIFT_FIELDS * sizeof *grown);
        if (!grown) return hsbd_reader_oom(r, "the drift's blocks");
        d->block = grown, d->capacity = (size_t)nblocks;
    }
    d->open = (size_t)open, d->nblocks = (size_t)nblocks;
    if (hsbd_get_f64s(r, d->block, d->nblocks * DRIFT_FIELDS)) return -1;
    return hsbd_blocks_load(d->clock, r);
}
