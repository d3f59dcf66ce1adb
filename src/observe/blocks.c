/* Block averages: the production samples are cut into nblocks consecutive blocks; the
 * error of a mean is the standard deviation of the block means divided by
 * sqrt(nblocks), valid when blocks are longer than the correlation time. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/observe.h"
#include "observe/checkpoint.h"

struct hsbd_blocks {
    size_t nvalues, nblocks;
    int spatial; /* blocks are parts of the system, each seen in every sample */
    uint64_t nsamples_total, nsamples;
    /* an extended run (hsbd resume with a longer run.t_total): the first ext_start samples
     * keep their nblocks_first blocks, later ones fill more blocks of ext_len samples */
    size_t nblocks_first;
    uint64_t ext_start, ext_len;
    double *acc;       /* current block's running sums */
    double *block_sum; /* nblocks x nvalues */
    uint64_t *block_n;
};

hsbd_blocks *hsbd_blocks_alloc(size_t nvalues, size_t nblocks, uint64_t nsamples_total) {
    hsbd_blocks *b = calloc(1, sizeof *b);
    if (!b) return NULL;
    b->nvalues = nvalues;
    b->nblocks = b->nblocks_first = nblocks;
    b->nsamples_total = nsamples_total;
    b->acc = calloc(nvalues, sizeof *b->acc);
    b->block_sum = calloc(nvalues * nblocks, sizeof *b->block_sum);
    b->block_n = calloc(nblocks, sizeof *b->block_n);
    if (!b->acc || !b->block_sum || !b->block_n) {
        hsbd_blocks_free(b);
        return NULL;
    }
    return b;
}

void hsbd_blocks_free(hsbd_blocks *b) {
    if (!b) return;
    free(b->acc);
    free(b->block_sum);
    free(b->block_n);
    free(b);
}

double *hsbd_blocks_acc(hsbd_blocks *b) {
    return b->acc;
}

size_t hsbd_blocks_block_of(uint64_t sample, size_t nblocks, uint64_t nsamples_total) {
    const size_t k = (size_t)(sample * nblocks / (nsamples_total ? nsamples_total : 1));
    return k < nblocks ? k : nblocks - 1;
}

static size_t block_of(const hsbd_blocks *b, uint64_t sample) {
    if (b->ext_len && sample >= b->ext_start) {
        const uint64_t k = b->nblocks_first + (sample - b->ext_start) / b->ext_len;
        return k < b->nblocks ? (size_t)k : b->nblocks - 1;
    }
    return hsbd_blocks_block_of(sample, b->nblocks_first,
                                b->ext_len ? b->ext_start : b->nsamples_total);
}

size_t hsbd_blocks_current(const hsbd_blocks *b) {
    return b->spatial ? 0 : block_of(b, b->nsamples);
}

size_t hsbd_blocks_count(const hsbd_blocks *b) {
    return b->nblocks;
}

hsbd_blocks *hsbd_blocks_alloc_spatial(size_t nvalues, size_t nblocks) {
    hsbd_blocks *b = hsbd_blocks_alloc(nvalues, nblocks, 1);
    if (b) b->spatial = 1;
    return b;
}

double *hsbd_blocks_acc_block(hsbd_blocks *b, size_t k) {
    return b->block_sum + k * b->nvalues;
}

void hsbd_blocks_end_sample(hsbd_blocks *b) {
    if (b->spatial) {
        for (size_t k = 0; k < b->nblocks; ++k)
            b->block_n[k] += 1;
        b->nsamples += 1;
        return;
    }
    const size_t k = block_of(b, b->nsamples);
    b->block_n[k] += 1;
    b->nsamples += 1;
    if (b->nsamples == b->nsamples_total || block_of(b, b->nsamples) != k) {
        double *dst = b->block_sum + k * b->nvalues;
        for (size_t j = 0; j < b->nvalues; ++j)
            dst[j] += b->acc[j];
        memset(b->acc, 0, b->nvalues * sizeof *b->acc);
    }
}

uint64_t hsbd_blocks_samples(const hsbd_blocks *b) {
    return b->nsamples;
}

size_t hsbd_blocks_result(const hsbd_blocks *b, double *mean, double *err) {
    /* a partially filled block (interrupted run) is included with its own weight */
    const size_t cur = b->spatial ? b->nblocks : block_of(b, b->nsamples);
    size_t used = 0;
    uint64_t total = 0;
    for (size_t k = 0; k < b->nblocks; ++k)
        used += b->block_n[k] > 0, total += b->block_n[k];
    for (size_t j = 0; j < b->nvalues; ++j) {
        double sum = 0;
        for (size_t k = 0; k < b->nblocks; ++k)
            sum += b->block_sum[k * b->nvalues + j] + (k == cur ? b->acc[j] : 0.0);
        const double m = total ? sum / (double)total : NAN;
        double var = 0;
        for (size_t k = 0; k < b->nblocks; ++k) {
            if (!b->block_n[k]) continue;
            const double s = b->block_sum[k * b->nvalues + j] + (k == cur ? b->acc[j] : 0.0);
            const double d = s / (double)b->block_n[k] - m;
            var += d * d;
        }
        mean[j] = m;
        err[j] = used > 1 ? sqrt(var / ((double)used * (double)(used - 1))) : NAN;
    }
    return used;
}

size_t hsbd_blocks_result_shape(const hsbd_blocks *b, double *mean, double *err) {
    const size_t used = hsbd_blocks_result(b, mean, err);
    if (used < 2) return used;
    double total = 0;
    for (size_t j = 0; j < b->nvalues; ++j)
        total += mean[j];
    if (!(total > 0)) return used;
    for (size_t j = 0; j < b->nvalues; ++j)
        err[j] = 0;
    /* each block's values rescaled to the common total: the scatter of the shape (the
     * block being filled, of an interrupted run, with its samples as hsbd_blocks_result) */
    const size_t cur = b->spatial ? b->nblocks : block_of(b, b->nsamples);
    for (size_t k = 0; k < b->nblocks; ++k) {
        if (!b->block_n[k]) continue;
        const double *v = b->block_sum + k * b->nvalues, *open = k == cur ? b->acc : NULL;
        double sk = 0;
        for (size_t j = 0; j < b->nvalues; ++j)
            sk += v[j] + (open ? open[j] : 0.0);
        if (!(sk > 0)) continue;
        for (size_t j = 0; j < b->nvalues; ++j) {
            const double d = (v[j] + (open ? open[j] : 0.0)) * total / sk - mean[j];
            err[j] += d * d;
        }
    }
    for (size_t j = 0; j < b->nvalues; ++j)
        err[j] = sqrt(err[j] / ((double)used * (double)(used - 1)));
    return used;
}

size_t hsbd_blocks_block_means(const hsbd_blocks *b, int shape, double *out) {
    const size_t cur = b->spatial ? b->nblocks : block_of(b, b->nsamples);
    double total = 0;
    uint64_t count = 0;
    for (size_t k = 0; k < b->nblocks; ++k) {
        count += b->block_n[k];
        for (size_t j = 0; j < b->nvalues; ++j)
            total += b->block_sum[k * b->nvalues + j] + (k == cur ? b->acc[j] : 0.0);
    }
    const double mean_total = count ? total / (double)count : 0.0; /* per sample */
    for (size_t k = 0; k < b->nblocks; ++k) {
        double *row = out + k * b->nvalues, sk = 0;
        for (size_t j = 0; j < b->nvalues; ++j) {
            const double s = b->block_sum[k * b->nvalues + j] + (k == cur ? b->acc[j] : 0.0);
            row[j] = b->block_n[k] ? s / (double)b->block_n[k] : NAN;
            sk += row[j];
        }
        if (shape && b->block_n[k] && sk > 0)
            for (size_t j = 0; j < b->nvalues; ++j)
                row[j] *= mean_total / sk;
    }
    return b->nblocks;
}

/* ---- checkpoints ---- */
void hsbd_blocks_save(const hsbd_blocks *b, hsbd_writer *w) {
    hsbd_put_tag(w, "blocks");
    const uint64_t shape[7] = {b->nvalues,        b->nblocks_first, (uint64_t)b->spatial,
                               b->nsamples_total, b->ext_start,     b->ext_len,
                               b->nblocks};
    hsbd_put_u64s(w, shape, 7);
    hsbd_put_u64(w, b->nsamples);
    hsbd_put_f64s(w, b->acc, b->nvalues);
    hsbd_put_f64s(w, b->block_sum, b->nvalues * b->nblocks);
    hsbd_put_u64s(w, b->block_n, b->nblocks);
}

/* Room for nblocks blocks (the new ones empty). */
static int grow_blocks(hsbd_blocks *b, size_t nblocks) {
    if (nblocks <= b->nblocks) return 0;
    double *sum = realloc(b->block_sum, nblocks * b->nvalues * sizeof *sum);
    if (!sum) return -1;
    b->block_sum = sum;
    uint64_t *cnt = realloc(b->block_n, nblocks * sizeof *cnt);
    if (!cnt) return -1;
    b->block_n = cnt;
    memset(sum + b->nblocks * b->nvalues, 0, (nblocks - b->nblocks) * b->nvalues * sizeof *sum);
    memset(cnt + b->nblocks, 0, (nblocks - b->nblocks) * sizeof *cnt);
    b->nblocks = nblocks;
    return 0;
}

/* Into blocks of the same configuration; a longer planned run (an extension) keeps the
 * stored blocks and adds blocks of the stored run's block length. */
int hsbd_blocks_load(hsbd_blocks *b, hsbd_reader *r) {
    uint64_t shape[7];
    if (hsbd_get_tag(r, "blocks") || hsbd_get_u64s(r, shape, 7)) return -1;
    const uint64_t first = shape[1], total = shape[3], ext_start = shape[4], ext_len = shape[5];
    const uint64_t stored_blocks = shape[6];
    const uint64_t planned = b->spatial ? total : b->nsamples_total; /* the configuration's */
    if (shape[0] != b->nvalues || first != b->nblocks_first || shape[2] != (uint64_t)b->spatial ||
        (!ext_len && stored_blocks != first) ||
        (ext_len && (b->spatial || ext_start > total ||
                     stored_blocks > first + (total - ext_start) / ext_len + 1)))
        return hsbd_reader_fail(r, "error blocks of another shape");
    if (planned < total) return hsbd_reader_fail(r, "error blocks of a longer run");
    uint64_t ns;
    if (hsbd_get_u64(r, &ns)) return -1;
    if (!b->spatial && ns > total) return hsbd_reader_fail(r, "more samples than planned");
    if (!b->spatial && planned > total) { /* extended: more blocks of the same length */
        b->ext_start = ext_len ? ext_start : total;
        b->ext_len = ext_len ? ext_len : (total + first - 1) / first;
        if (b->ext_len < 1) b->ext_len = 1;
    } else {
        b->ext_start = ext_start, b->ext_len = ext_len;
    }
    const uint64_t want =
        b->ext_len ? first + (planned - b->ext_start + b->ext_len - 1) / b->ext_len : first;
    if (grow_blocks(b, (size_t)(want > stored_blocks ? want : stored_blocks)))
        return hsbd_reader_oom(r, "the error blocks");
    b->nsamples = ns;
    double *sum = b->block_sum;
    uint64_t *cnt = b->block_n;
    if (hsbd_get_f64s(r, b->acc, b->nvalues) ||
        hsbd_get_f64s(r, sum, b->nvalues * (size_t)stored_blocks) ||
        hsbd_get_u64s(r, cnt, (size_t)stored_blocks))
        return -1;
    return 0;
}
