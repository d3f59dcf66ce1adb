/* Both models: the mean-squared displacement of the particles' unwrapped positions
 * (msd.tsv; per species for mixtures) from the run's frames, and for disks and spheres the
 * self-intermediate scattering function F_s(k, t) (fs.tsv) and the long-time diffusion
 * coefficient from the MSD's slope (summary "D_long"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"

typedef run_msd_set msd;

static hsbd_msd *accumulator(const run *r, size_t items, double fs_k, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    hsbd_msd *m = hsbd_msd_alloc(items, cfg->run.dt * (double)cfg->sample.every,
                                 hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every,
                                 cfg->sample.msd_max_lag, (int)cfg->sample.msd_points_per_decade,
                                 (size_t)cfg->sample.blocks, err);
    if (m && fs_k > 0 && hsbd_msd_set_wavenumber(m, fs_k, err) != HSBD_OK) {
        hsbd_msd_free(m);
        return NULL;
    }
    return m;
}

int run_msd_set_build(run_msd_set *s, run *r, size_t nspecies, double fs_k, hsbd_error *err) {
    const hsbd_frame *f = run_frame(r);
    const size_t d = (size_t)f->dimension, items = d * f->n;
    s->dimension = f->dimension;
    s->nspecies = nspecies;
    if (!(s->all = accumulator(r, items, fs_k, err))) return err->status;
    size_t *idx = nspecies ? malloc(items * sizeof *idx) : NULL;
    if (nspecies && !idx) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < nspecies && rc == HSBD_OK; ++k) { /* species k's components */
        size_t count = 0;
        for (size_t i = 0; i < f->n; ++i)
            for (size_t a = 0; f->species && (size_t)f->species[i] == k && a < d; ++a)
                idx[count++] = d * i + a;
        rc = (s->species[k] = accumulator(r, items, fs_k, err))
                 ? hsbd_msd_set_members(s->species[k], count, idx, err)
                 : err->status;
    }
    free(idx);
    return rc;
}

void run_msd_set_sample(run_msd_set *s, const double *values) {
    hsbd_msd_sample_values(s->all, values);
    for (size_t k = 0; k < s->nspecies; ++k)
        hsbd_msd_sample_values(s->species[k], values);
}

void run_msd_set_restart(run_msd_set *s) {
    hsbd_msd_restart(s->all);
    for (size_t k = 0; k < s->nspecies; ++k)
        hsbd_msd_restart(s->species[k]);
}

void run_msd_set_save(const run_msd_set *s, hsbd_writer *w) {
    hsbd_msd_save(s->all, w);
    for (size_t k = 0; k < s->nspecies; ++k)
        hsbd_msd_save(s->species[k], w);
}

int run_msd_set_load(run_msd_set *s, hsbd_reader *rd) {
    if (hsbd_msd_load(s->all, rd)) return -1;
    for (size_t k = 0; k < s->nspecies; ++k)
        if (hsbd_msd_load(s->species[k], rd)) return -1;
    return 0;
}

void run_msd_set_free(run_msd_set *s) {
    hsbd_msd_free(s->all);
    for (size_t k = 0; k < s->nspecies; ++k)
        hsbd_msd_free(s->species[k]);
}

int run_msd_set_write(const run_msd_set *s, const run *r, const char *name, const char *what,
                      const char *title, run_msd_value value, hsbd_error *err) {
    const size_t pairs = 1 + s->nspecies;
    char columns[64 + HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)];
    snprintf(columns, sizeof columns, "t\t%s\t%s_err\torigins", what, what);
    for (size_t q = 0; q < s->nspecies; ++q) {
        const size_t len = strlen(columns);
        snprintf(columns + len, sizeof columns - len, "\t%s_%s\t%s_%s_err", what,
                 r->cfg->species.name[q], what, r->cfg->species.name[q]);
    }
    const size_t nl = hsbd_msd_lags(s->all);
    double *t = malloc(nl * sizeof *t), *val = malloc(2 * pairs * nl * sizeof *val);
    size_t *origins = malloc(nl * sizeof *origins);
    int rc = t && val && origins
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    for (size_t k = 0; k < nl && rc == HSBD_OK; ++k)
        for (size_t p = 0; p < pairs; ++p) {
            const hsbd_msd *src = p ? s->species[p - 1] : s->all;
            double tk, unused_v, unused_e;
            size_t o;
            hsbd_msd_result(src, k, &tk, &unused_v, &unused_e, &o);
            if (!p) t[k] = tk, origins[k] = o;
            value(src, k, s->dimension, &val[2 * p * nl + k], &val[(2 * p + 1) * nl + k]);
        }
    if (rc == HSBD_OK)
        rc = hsbd_write_lag_table(r->cfg->output.dir, name, r->cfg, title, columns, nl, t, origins,
                                  pairs, val, err);
    free(t), free(val), free(origins);
    return rc;
}

static void release(void *state) {
    msd *m = state;
    if (!m) return;
    run_msd_set_free(m);
    free(m);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const hsbd_frame *f = run_frame(r);
    msd *m = calloc(1, sizeof *m);
    if (!m) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = m;
    /* per species: rods whenever species are named, disks and spheres for mixtures; F_s
     * at sample.fs_k for disks and spheres */
    const size_t ns = cfg->species.n, items = (size_t)f->dimension * f->n,
                 blocks = (size_t)cfg->sample.blocks;
    const int rc = run_msd_set_build(m, r, f->dimension == 1 || ns > 1 ? ns : 0,
                                     f->dimension > 1 ? cfg->sample.fs_k : 0, err);
    if (rc != HSBD_OK || cfg->sample.blocking != HSBD_BLOCKS_SPACE) return rc;
    return hsbd_msd_set_segments(m->all, blocks < items ? blocks : items, err);
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    run_msd_set_sample(state, run_frame(r)->unwrapped);
    return HSBD_OK;
}

/* no lag spans two replicas */
static int end_replica(run *r, void *state, hsbd_error *err) {
    (void)r, (void)err;
    run_msd_set_restart(state);
    return HSBD_OK;
}

/* per particle: the sum over the d coordinates */
static void msd_value(const hsbd_msd *m, size_t k, int dimension, double *v, double *e) {
    double t;
    size_t o;
    hsbd_msd_result(m, k, &t, v, e, &o);
    *v *= dimension, *e *= dimension;
}

static void fs_value(const hsbd_msd *m, size_t k, int dimension, double *v, double *e) {
    (void)dimension;
    hsbd_msd_fs(m, k, v, e);
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const run_msd_set *s = state;
    char title[256];
    if (s->dimension == 1)
        snprintf(title, sizeof title,
                 "tagged-particle mean-squared displacement (unwrapped positions), all rods and, "
                 "for mixtures, per species; errors from block averages over time origins");
    else
        snprintf(title, sizeof title,
                 "mean-squared displacement per particle (unwrapped, summed over the %d "
                 "dimensions), all particles and per species; errors from blocks of time origins",
                 s->dimension);
    int rc = run_msd_set_write(s, r, "msd.tsv", "msd", title, msd_value, err);
    if (rc != HSBD_OK || s->dimension < 2) return rc;
    snprintf(title, sizeof title,
             "self-intermediate scattering function F_s(k, t) at k = %g (k along each axis, "
             "averaged), all particles and per species; errors from blocks of time origins",
             r->cfg->sample.fs_k);
    return run_msd_set_write(s, r, "fs.tsv", "fs", title, fs_value, err);
}

/* disks and spheres: D_L of all particles and of each species */
static void write_summary(const run *r, const void *state, FILE *f) {
    const msd *m = state;
    if (m->dimension < 2) return;
    double dl, dle;
    hsbd_msd_long_time_diffusion(m->all, m->dimension, &dl, &dle);
    hsbd_json_number(f, "D_long", dl, 1);
    hsbd_json_number(f, "D_long_err", dle, 1);
    if (!m->nspecies) return;
    fprintf(f, "  \"D_long_species\": {");
    for (size_t k = 0; k < m->nspecies; ++k) {
        hsbd_msd_long_time_diffusion(m->species[k], m->dimension, &dl, &dle);
        fprintf(f, "%s\"%s\": [%.10g, %.4g]", k ? ", " : "", r->cfg->species.name[k],
                isfinite(dl) ? dl : 0, isfinite(dle) ? dle : 0);
    }
    fprintf(f, "},\n");
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    run_msd_set_save(state, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return run_msd_set_load(state, rd);
}

static void expose(const run *r, const void *state, hsbd_sim_parts *parts) {
    (void)r;
    const msd *m = state;
    parts->msd = m->all;
    for (size_t k = 0; k < m->nspecies; ++k)
        parts->msd_species[k] = m->species[k];
}

const run_observer_ops run_observe_msd = {.name = "msd",
                                          .build = build,
                                          .sample = sample,
                                          .end_replica = end_replica,
                                          .save = save,
                                          .load = load,
                                          .write_tables = write_tables,
                                          .write_summary = write_summary,
                                          .expose = expose,
                                          .free = release};
