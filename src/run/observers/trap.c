/* Rods in a harmonic trap (field.type with harmonic): the centre of mass X against the
 * trap's centre c(t) (summary "trap_offset" <X - c> and "trap_variance", its variance),
 * for dragged or oscillating traps. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/rods_model.h"

typedef struct trap {
    hsbd_blocks *blocks; /* X - c and its square at the samples */
    double *rows;        /* its block means, for the summary (2 per block) */
} trap;

static void release(void *state) {
    trap *t = state;
    if (!t) return;
    hsbd_blocks_free(t->blocks);
    free(t->rows);
    free(t);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    if (!(cfg->field.type & HSBD_FIELD_HARMONIC)) return HSBD_OK;
    const size_t blocks = (size_t)cfg->sample.blocks;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    trap *t = calloc(1, sizeof *t);
    if (t) *state = t;
    if (!t || !(t->blocks = hsbd_blocks_alloc(2, blocks, samples)) ||
        !(t->rows = malloc(2 * blocks * sizeof *t->rows)))
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    return HSBD_OK;
}

/* The centre of mass minus the trap's centre at the state's time (each rod's nearest image
 * on a ring, as in the trap's force), and its square. */
static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    trap *t = state;
    const hsbd_rods *rods = rods_model_of(r)->rods;
    const hsbd_rods_view v = hsbd_rods_get_view(rods);
    hsbd_field now;
    const hsbd_field *field = hsbd_field_at(&hsbd_rods_get_params(rods)->field, v.time, &now);
    double center = NAN, e = 0;
    for (size_t k = 0; k < field->nterms; ++k)
        if (!strcmp(field->term[k].ops->name, "harmonic"))
            center = field->term[k].p[field->term[k].ops->position - 1];
    for (size_t i = 0; i < v.n; ++i) {
        const double d = v.z[i] + v.offset[i] + v.unwrap - center;
        e += v.periodic ? d - v.length * floor(d / v.length + 0.5) : d;
    }
    e /= (double)v.n;
    double *acc = hsbd_blocks_acc(t->blocks);
    acc[0] += e, acc[1] += e * e;
    hsbd_blocks_end_sample(t->blocks);
    return HSBD_OK;
}

/* trap_offset: <X - c>; trap_variance: the variance of X - c, per block about the overall
 * mean (errors from the blocks' scatter) */
static void write_summary(const run *r, const void *state, FILE *f) {
    (void)r;
    const trap *t = state;
    const size_t nb = hsbd_blocks_count(t->blocks);
    double mean[2], err[2], *rows = t->rows;
    hsbd_blocks_result(t->blocks, mean, err);
    hsbd_blocks_block_means(t->blocks, 0, rows);
    double var = NAN, var_err = NAN, s = 0, ss = 0;
    size_t used = 0;
    for (size_t k = 0; k < nb; ++k) {
        const double vb = rows[2 * k + 1] - 2 * mean[0] * rows[2 * k] + mean[0] * mean[0];
        if (isfinite(vb)) s += vb, ss += vb * vb, ++used;
    }
    if (used > 1) {
        var = s / (double)used;
        var_err = sqrt(fmax(ss / (double)used - var * var, 0) / (double)(used - 1));
    }
    hsbd_json_number(f, "trap_offset", mean[0], 1);
    hsbd_json_number(f, "trap_offset_err", err[0], 1);
    hsbd_json_number(f, "trap_variance", var, 1);
    hsbd_json_number(f, "trap_variance_err", var_err, 1);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_blocks_save(((const trap *)state)->blocks, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    trap *t = state;
    if (hsbd_blocks_load(t->blocks, rd)) return -1;
    double *rows = realloc(t->rows, 2 * hsbd_blocks_count(t->blocks) * sizeof *rows);
    if (!rows) return hsbd_reader_oom(rd, "the trap's block means"); /* an extension: more */
    t->rows = rows;
    return 0;
}

const run_observer_ops run_observe_trap = {.name = "trap",
                                           .build = build,
                                           .sample = sample,
                                           .save = save,
                                           .load = load,
                                           .write_summary = write_summary,
                                           .free = release};
