/* Rods: the density and contact-density profiles folded into one period (Antonov Eqs.
 * 25-26; density.tsv, contact.tsv), the profile of each error block (density_blocks.tsv,
 * contact_blocks.tsv) and the smallest gap seen (summary "min_gap"). */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/rods_model.h"

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    const size_t blocks = (size_t)cfg->sample.blocks;
    hsbd_profile *p = cfg->sample.blocking == HSBD_BLOCKS_SPACE
                          ? hsbd_profile_alloc_spatial(cfg->sample.period, cfg->sample.bin_width,
                                                       cfg->sample.contact_width, blocks, err)
                          : hsbd_profile_alloc(cfg->sample.period, cfg->sample.bin_width,
                                               cfg->sample.contact_width, blocks, samples, err);
    *state = p;
    return p ? HSBD_OK : err->status;
}

static int sample(run *r, void *state, hsbd_error *err) {
    const hsbd_rods_view v = hsbd_rods_get_view(rods_model_of(r)->rods);
    if (hsbd_profile_sample(state, &v) != HSBD_OK)
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory sampling the profiles");
    if (hsbd_profile_nonfinite(state))
        return hsbd_error_set(err, HSBD_ENUMERIC,
                              "non-finite position after step %llu (time %g); check the "
                              "field parameters and dt. Results up to here are written.",
                              (unsigned long long)v.step, v.time);
    return HSBD_OK;
}

typedef void (*profile_getter)(const hsbd_profile *p, double *x, double *val, double *err);

/* Binned profiles as one table: x, then value and error of each getter. */
static int write_profile_table(const run *r, const hsbd_profile *p, const char *name,
                               const char *what, const char *columns, const profile_getter *get,
                               size_t nget, hsbd_error *err) {
    const size_t nb = hsbd_profile_bins(p);
    double *x = malloc(nb * sizeof *x), *val = malloc(2 * nget * nb * sizeof *val);
    int rc =
        x && val ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    for (size_t g = 0; g < nget && rc == HSBD_OK; ++g)
        get[g](p, x, val + 2 * g * nb, val + (2 * g + 1) * nb);
    if (rc == HSBD_OK)
        rc = hsbd_write_columns_table(r->cfg->output.dir, name, r->cfg, what, columns, nb, x, nget,
                                      val, err);
    free(x), free(val);
    return rc;
}

static int write_profiles(const run *r, const hsbd_profile *p, hsbd_error *err) {
    const profile_getter density[] = {hsbd_profile_density};
    /* the default rho2 is the estimator that is unbiased under the chosen contact rule
     * (docs/validation.md sections 8-11): the extrapolated gap density with reflect, the
     * contact theorem with sticky (whose O(sqrt dt) layer at contact spoils any gap count) */
    const int reflect = r->cfg->system.contact_rule == HSBD_CONTACT_REFLECT;
    const profile_getter contact[] = {
        reflect ? hsbd_profile_contact_extrapolated : hsbd_profile_contact, hsbd_profile_contact,
        hsbd_profile_contact_window, hsbd_profile_contact_extrapolated};
    int rc = write_profile_table(r, p, "density.tsv",
                                 "density profile folded into one period, Antonov Eq. 25, "
                                 "normalised to mean N/L; errors from block averages",
                                 "x\trho\trho_err", density, 1, err);
    char what[640];
    snprintf(what, sizeof what,
             "two-particle density at contact rho2(x, x+sigma), x = left rod. rho2: the default "
             "estimator, here %s (contact_rule = %s); rho2_theorem: contact theorem (mean "
             "contact impulse per time / kT); rho2_window: pairs with gaps in [0, contact_width], "
             "Antonov Eq. 26 (biased, docs/observables.md); rho2_extrap: the windowed gap density "
             "extrapolated linearly to zero gap from four sub-windows",
             reflect ? "rho2_extrap" : "rho2_theorem", reflect ? "reflect" : "sticky");
    if (rc == HSBD_OK && r->cfg->system.hard_core)
        rc = write_profile_table(r, p, "contact.tsv", what,
                                 "x\trho2\trho2_err\trho2_theorem\trho2_theorem_err\trho2_window\t"
                                 "rho2_window_err\trho2_extrap\trho2_extrap_err",
                                 contact, 4, err);
    return rc;
}

typedef void (*blocks_getter)(const hsbd_profile *p, double *out);

static int write_blocks(const run *r, const hsbd_profile *p, const char *name, const char *what,
                        blocks_getter get, hsbd_error *err) {
    const size_t nb = hsbd_profile_bins(p), nblk = hsbd_profile_blocks(p);
    double *val = malloc(nb * nblk * sizeof *val);
    if (!val) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing %s", name);
    get(p, val);
    const int rc = hsbd_write_blocks_table(r->cfg->output.dir, name, r->cfg, what, nb, nblk,
                                           r->cfg->sample.period / (double)nb, val, err);
    free(val);
    return rc;
}

static int write_profile_blocks(const run *r, const hsbd_profile *p, hsbd_error *err) {
    const int reflect = r->cfg->system.contact_rule == HSBD_CONTACT_REFLECT;
    const int blocking = r->cfg->sample.blocking;
    const char *unit = blocking == HSBD_BLOCKS_SPACE      ? "segment of the line"
                       : blocking == HSBD_BLOCKS_REPLICAS ? "independent replica"
                                                          : "block of time";
    char what[256];
    snprintf(what, sizeof what,
             "density profile of each %s (the estimates behind rho_err; their covariance "
             "gives correlated errors)",
             unit);
    int rc = write_blocks(r, p, "density_blocks.tsv", what, hsbd_profile_density_blocks, err);
    snprintf(what, sizeof what, "default contact density estimator (%s) of each %s",
             reflect ? "rho2_extrap" : "rho2_theorem", unit);
    if (rc == HSBD_OK && r->cfg->system.hard_core)
        rc = write_blocks(
            r, p, "contact_blocks.tsv", what,
            reflect ? hsbd_profile_contact_extrapolated_blocks : hsbd_profile_contact_blocks, err);
    return rc;
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const int rc = write_profiles(r, state, err);
    return rc == HSBD_OK ? write_profile_blocks(r, state, err) : rc;
}

static void write_summary(const run *r, const void *state, FILE *f) {
    hsbd_json_number(f, "min_gap", r->cfg->system.hard_core ? hsbd_profile_min_gap(state) : NAN, 1);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_profile_save(state, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return hsbd_profile_load(state, rd);
}

static void expose(const run *r, const void *state, hsbd_sim_parts *parts) {
    (void)r;
    parts->profile = state;
}

static void release(void *state) {
    hsbd_profile_free(state);
}

const run_observer_ops run_observe_profile = {.name = "profile",
                                              .build = build,
                                              .sample = sample,
                                              .save = save,
                                              .load = load,
                                              .write_tables = write_tables,
                                              .write_summary = write_summary,
                                              .expose = expose,
                                              .free = release};
