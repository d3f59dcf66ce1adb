/* Rods under a periodic drive (sample.phases = K): the density profile resolved by the
 * drive's phase, K profiles of t mod drive.period (density_phases.tsv, stroboscopic). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/rods_model.h"

typedef struct phases {
    size_t count;
    hsbd_profile *profile[]; /* one per phase bin */
} phases;

static void release(void *state) {
    phases *p = state;
    for (size_t k = 0; p && k < p->count; ++k)
        hsbd_profile_free(p->profile[k]);
    free(p);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const size_t count = (size_t)cfg->sample.phases;
    if (count == 0) return HSBD_OK;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    phases *p = calloc(1, sizeof *p + count * sizeof p->profile[0]);
    if (!p) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = p;
    p->count = count;
    for (size_t k = 0; k < count; ++k) {
        p->profile[k] =
            hsbd_profile_alloc(cfg->sample.period, cfg->sample.bin_width, cfg->sample.contact_width,
                               (size_t)cfg->sample.blocks, samples / count + 1, err);
        if (!p->profile[k]) return err->status;
    }
    return HSBD_OK;
}

/* the bin of t mod drive.period, K bins of the period */
static size_t phase_bin(const hsbd_config *cfg, double t) {
    const double period = cfg->drive.period, phase = t / period - floor(t / period);
    const size_t k = (size_t)(phase * (double)cfg->sample.phases);
    return k < (size_t)cfg->sample.phases ? k : (size_t)cfg->sample.phases - 1;
}

static int sample(run *r, void *state, hsbd_error *err) {
    phases *p = state;
    const hsbd_rods_view v = hsbd_rods_get_view(rods_model_of(r)->rods);
    return hsbd_profile_sample(p->profile[phase_bin(r->cfg, v.time)], &v) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "out of memory sampling the phase profiles");
}

/* the density in each phase bin, one value/error pair each */
static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const phases *p = state;
    const size_t nb = hsbd_profile_bins(p->profile[0]), count = p->count;
    double *x = malloc(nb * sizeof *x), *val = malloc(2 * count * nb * sizeof *val);
    char *columns = malloc(count * 48 + 8);
    int rc = x && val && columns
                 ? HSBD_OK
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing density_phases.tsv");
    if (rc == HSBD_OK) {
        strcpy(columns, "x");
        for (size_t k = 0; k < count; ++k) {
            hsbd_profile_density(p->profile[k], x, val + 2 * k * nb, val + (2 * k + 1) * nb);
            sprintf(columns + strlen(columns), "\trho_%zu\trho_%zu_err", k, k);
        }
        char what[320];
        snprintf(what, sizeof what,
                 "density profile resolved by the drive's phase (stroboscopic): column rho_k "
                 "holds the samples with t mod drive.period in [k, k+1) drive.period / %zu, "
                 "folded into one sample.period and normalised to mean N/L; block errors",
                 count);
        rc = hsbd_write_columns_table(r->cfg->output.dir, "density_phases.tsv", r->cfg, what,
                                      columns, nb, x, count, val, err);
    }
    free(x), free(val), free(columns);
    return rc;
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    const phases *p = state;
    for (size_t k = 0; k < p->count; ++k)
        hsbd_profile_save(p->profile[k], w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    phases *p = state;
    for (size_t k = 0; k < p->count; ++k)
        if (hsbd_profile_load(p->profile[k], rd)) return -1;
    return 0;
}

const run_observer_ops run_observe_phases = {.name = "phases",
                                             .build = build,
                                             .sample = sample,
                                             .save = save,
                                             .load = load,
                                             .write_tables = write_tables,
                                             .free = release};
