/* Active disks and spheres: the orientation autocorrelation C(t) = <e_i(0).e_i(t)>
 * (orientation.tsv; per species for mixtures) from the frames' unit vectors, at the MSD's
 * lags with its origins and blocks: for unit vectors e(0).e(t) = 1 - |e(t) - e(0)|^2 / 2,
 * so the MSD accumulator of the orientations' components gives it. Free rotation gives
 * exp(-(d-1) D_r t) (docs/active.md). */
#include <stdlib.h>
#include <string.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"

typedef struct orientation {
    int dimension;
    size_t nspecies; /* correlations per species (0: none) */
    hsbd_msd *all, *species[HSBD_MAX_SPECIES];
    double *values; /* d N components of one sample */
} orientation;

static void release(void *state) {
    orientation *o = state;
    if (!o) return;
    hsbd_msd_free(o->all);
    for (size_t k = 0; k < o->nspecies; ++k)
        hsbd_msd_free(o->species[k]);
    free(o->values);
    free(o);
}

static hsbd_msd *accumulator(const run *r, size_t items, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    return hsbd_msd_alloc(items, cfg->run.dt * (double)cfg->sample.every,
                          hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every,
                          cfg->sample.msd_max_lag, (int)cfg->sample.msd_points_per_decade,
                          (size_t)cfg->sample.blocks, err);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_frame *f = run_frame(r);
    if (!f->orientation) return HSBD_OK;
    orientation *o = calloc(1, sizeof *o);
    if (!o) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = o;
    o->dimension = f->dimension;
    const size_t d = (size_t)f->dimension, items = d * f->n;
    o->nspecies = r->cfg->species.n > 1 ? r->cfg->species.n : 0;
    o->values = malloc(items * sizeof *o->values);
    size_t *idx = malloc(items * sizeof *idx);
    if (!o->values || !idx || !(o->all = accumulator(r, items, err)))
        return free(idx),
               err->status ? err->status : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < o->nspecies && rc == HSBD_OK; ++k) {
        size_t count = 0;
        for (size_t i = 0; i < f->n; ++i)
            for (size_t a = 0; f->species && (size_t)f->species[i] == k && a < d; ++a)
                idx[count++] = d * i + a;
        rc = (o->species[k] = accumulator(r, items, err))
                 ? hsbd_msd_set_members(o->species[k], count, idx, err)
                 : err->status;
    }
    free(idx);
    return rc;
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    orientation *o = state;
    const hsbd_frame *f = run_frame(r);
    const size_t d = (size_t)o->dimension;
    for (size_t i = 0; i < f->n; ++i)
        for (size_t a = 0; a < d; ++a)
            o->values[d * i + a] = f->orientation[3 * i + a];
    hsbd_msd_sample_values(o->all, o->values);
    for (size_t k = 0; k < o->nspecies; ++k)
        hsbd_msd_sample_values(o->species[k], o->values);
    return HSBD_OK;
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const orientation *o = state;
    const size_t pairs = 1 + o->nspecies, d = (size_t)o->dimension;
    char columns[64 + HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)] = "t\tC\tC_err\torigins";
    for (size_t q = 0; q < o->nspecies; ++q) {
        const size_t len = strlen(columns);
        snprintf(columns + len, sizeof columns - len, "\tC_%s\tC_%s_err", r->cfg->species.name[q],
                 r->cfg->species.name[q]);
    }
    const size_t nl = hsbd_msd_lags(o->all);
    double *t = malloc(nl * sizeof *t), *val = malloc(2 * pairs * nl * sizeof *val);
    size_t *origins = malloc(nl * sizeof *origins);
    int rc = t && val && origins
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing orientation.tsv");
    for (size_t k = 0; k < nl && rc == HSBD_OK; ++k)
        for (size_t p = 0; p < pairs; ++p) {
            double tk, m, e;
            size_t n;
            hsbd_msd_result(p ? o->species[p - 1] : o->all, k, &tk, &m, &e, &n);
            if (!p) t[k] = tk, origins[k] = n;
            /* m: the mean square change of one component; |de|^2 = d m */
            val[2 * p * nl + k] = 1 - 0.5 * (double)d * m;
            val[(2 * p + 1) * nl + k] = 0.5 * (double)d * e;
        }
    if (rc == HSBD_OK)
        rc =
            hsbd_write_lag_table(r->cfg->output.dir, "orientation.tsv", r->cfg,
                                 "orientation autocorrelation C(t) = <e_i(0).e_i(t)> of the "
                                 "particles' unit vectors, all particles and per species (free "
                                 "rotation: exp(-(d-1) D_r t)); errors from blocks of time origins",
                                 columns, nl, t, origins, pairs, val, err);
    free(t), free(val), free(origins);
    return rc;
}

static int end_replica(run *r, void *state, hsbd_error *err) {
    (void)r, (void)err;
    orientation *o = state;
    hsbd_msd_restart(o->all);
    for (size_t k = 0; k < o->nspecies; ++k)
        hsbd_msd_restart(o->species[k]);
    return HSBD_OK;
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    const orientation *o = state;
    hsbd_msd_save(o->all, w);
    for (size_t k = 0; k < o->nspecies; ++k)
        hsbd_msd_save(o->species[k], w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    orientation *o = state;
    if (hsbd_msd_load(o->all, rd)) return -1;
    for (size_t k = 0; k < o->nspecies; ++k)
        if (hsbd_msd_load(o->species[k], rd)) return -1;
    return 0;
}

const run_observer_ops run_observe_orientation = {.name = "orientation",
                                                  .build = build,
                                                  .sample = sample,
                                                  .end_replica = end_replica,
                                                  .save = save,
                                                  .load = load,
                                                  .write_tables = write_tables,
                                                  .free = release};
