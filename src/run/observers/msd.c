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

typedef struct msd {
    int dimension;
    size_t nspecies; /* MSDs per species (0: none) */
    hsbd_msd *all, *species[HSBD_MAX_SPECIES];
} msd;

static void release(void *state) {
    msd *m = state;
    if (!m) return;
    hsbd_msd_free(m->all);
    for (size_t k = 0; k < m->nspecies; ++k)
        hsbd_msd_free(m->species[k]);
    free(m);
}

/* an MSD over the d N coordinates, with F_s at sample.fs_k for disks and spheres */
static hsbd_msd *msd_alloc(const run *r, size_t items, int dimension, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    hsbd_msd *m = hsbd_msd_alloc(items, cfg->run.dt * (double)cfg->sample.every,
                                 hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every,
                                 cfg->sample.msd_max_lag, (int)cfg->sample.msd_points_per_decade,
                                 (size_t)cfg->sample.blocks, err);
    if (m && dimension > 1 && hsbd_msd_set_wavenumber(m, cfg->sample.fs_k, err) != HSBD_OK) {
        hsbd_msd_free(m);
        return NULL;
    }
    return m;
}

/* species k's coordinates among the d N */
static int species_members(msd *m, const hsbd_frame *f, size_t k, size_t *idx, hsbd_error *err) {
    const size_t d = (size_t)m->dimension;
    size_t count = 0;
    for (size_t i = 0; i < f->n; ++i)
        if (f->species && (size_t)f->species[i] == k)
            for (size_t a = 0; a < d; ++a)
                idx[count++] = d * i + a;
    return hsbd_msd_set_members(m->species[k], count, idx, err);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const hsbd_frame *f = run_frame(r);
    msd *m = calloc(1, sizeof *m);
    if (!m) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = m;
    m->dimension = f->dimension;
    const size_t items = (size_t)f->dimension * f->n, blocks = (size_t)cfg->sample.blocks;
    if (!(m->all = msd_alloc(r, items, f->dimension, err))) return err->status;
    if (cfg->sample.blocking == HSBD_BLOCKS_SPACE &&
        hsbd_msd_set_segments(m->all, blocks < items ? blocks : items, err) != HSBD_OK)
        return err->status;
    /* per species: rods whenever species are named, disks and spheres for mixtures */
    const size_t ns = cfg->species.n;
    m->nspecies = f->dimension == 1 || ns > 1 ? ns : 0;
    size_t *idx = m->nspecies ? malloc(items * sizeof *idx) : NULL;
    if (m->nspecies && !idx) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < m->nspecies && rc == HSBD_OK; ++k)
        rc = (m->species[k] = msd_alloc(r, items, f->dimension, err))
                 ? species_members(m, f, k, idx, err)
                 : err->status;
    free(idx);
    return rc;
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    msd *m = state;
    const double *x = run_frame(r)->unwrapped;
    hsbd_msd_sample_values(m->all, x);
    for (size_t k = 0; k < m->nspecies; ++k)
        hsbd_msd_sample_values(m->species[k], x);
    return HSBD_OK;
}

/* no lag spans two replicas */
static int end_replica(run *r, void *state, hsbd_error *err) {
    (void)r, (void)err;
    msd *m = state;
    hsbd_msd_restart(m->all);
    for (size_t k = 0; k < m->nspecies; ++k)
        hsbd_msd_restart(m->species[k]);
    return HSBD_OK;
}

/* msd.tsv (per particle: the sum over the d coordinates) or fs.tsv (F_s) */
static int write_lag_table(const run *r, const msd *m, const char *name, int fs, hsbd_error *err) {
    const size_t pairs = 1 + m->nspecies, d = (size_t)m->dimension;
    const char *what = fs ? "fs" : "msd";
    char columns[64 + HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)];
    snprintf(columns, sizeof columns, "t\t%s\t%s_err\torigins", what, what);
    for (size_t q = 0; q < m->nspecies; ++q) {
        const size_t len = strlen(columns);
        snprintf(columns + len, sizeof columns - len, "\t%s_%s\t%s_%s_err", what,
                 r->cfg->species.name[q], what, r->cfg->species.name[q]);
    }
    char title[256];
    if (fs)
        snprintf(title, sizeof title,
                 "self-intermediate scattering function F_s(k, t) at k = %g (k along each axis, "
                 "averaged), all particles and per species; errors from blocks of time origins",
                 r->cfg->sample.fs_k);
    else if (d == 1)
        snprintf(title, sizeof title,
                 "tagged-particle mean-squared displacement (unwrapped positions), all rods and, "
                 "for mixtures, per species; errors from block averages over time origins");
    else
        snprintf(title, sizeof title,
                 "mean-squared displacement per particle (unwrapped, summed over the %zu "
                 "dimensions), all particles and per species; errors from blocks of time origins",
                 d);
    const double scale = fs ? 1.0 : (double)d;
    const size_t nl = hsbd_msd_lags(m->all);
    double *t = malloc(nl * sizeof *t), *val = malloc(2 * pairs * nl * sizeof *val);
    size_t *origins = malloc(nl * sizeof *origins);
    int rc = t && val && origins
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    for (size_t k = 0; k < nl && rc == HSBD_OK; ++k)
        for (size_t p = 0; p < pairs; ++p) {
            const hsbd_msd *src = p ? m->species[p - 1] : m->all;
            double tk, v, e;
            size_t o;
            hsbd_msd_result(src, k, &tk, &v, &e, &o);
            if (fs) hsbd_msd_fs(src, k, &v, &e);
            if (!p) t[k] = tk, origins[k] = o;
            val[2 * p * nl + k] = scale * v, val[(2 * p + 1) * nl + k] = scale * e;
        }
    if (rc == HSBD_OK)
        rc = hsbd_write_lag_table(r->cfg->output.dir, name, r->cfg, title, columns, nl, t, origins,
                                  pairs, val, err);
    free(t), free(val), free(origins);
    return rc;
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const msd *m = state;
    const int rc = write_lag_table(r, m, "msd.tsv", 0, err);
    return rc == HSBD_OK && m->dimension > 1 ? write_lag_table(r, m, "fs.tsv", 1, err) : rc;
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
    const msd *m = state;
    hsbd_msd_save(m->all, w);
    for (size_t k = 0; k < m->nspecies; ++k)
        hsbd_msd_save(m->species[k], w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    msd *m = state;
    if (hsbd_msd_load(m->all, rd)) return -1;
    for (size_t k = 0; k < m->nspecies; ++k)
        if (hsbd_msd_load(m->species[k], rd)) return -1;
    return 0;
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
