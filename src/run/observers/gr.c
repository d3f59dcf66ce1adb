/* Hard disks and spheres: g(r) per species pair (gr.tsv) against the homogeneous reference
 * in a periodic box, or a profile-weighted one along the walls' or the field's axis; the
 * contact values g_ab(sigma_ab+) with the equation of state's (summary "contacts") and Z
 * from them by the virial route in a homogeneous box. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/theory.h"
#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/spheres_model.h"

/* The profile-weighted reference runs along the walls axis or the field's axis (ideal
 * particles too, whose g = 1 checks it), the homogeneous one in a periodic box without a
 * field; none between walls on more axes or with a field across the walls axis (the
 * reference would need the density over a plane), nor for ideal particles in a periodic
 * box without a field (g = 1): a warning says so. */
static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    int walls = 0, axis = cfg->field.type ? cfg->field.axis : -1;
    for (int a = 0; a < 3; ++a)
        if (cfg->system.walls[a]) walls++, axis = axis < 0 || axis == a ? a : 3;
    if (axis < 3 && walls <= 1 && (cfg->system.hard_core || axis >= 0)) {
        const hsbd_spheres_view v = hsbd_spheres_get_view(spheres_model_of(r)->sys);
        *state =
            hsbd_gr_alloc_profile(&v, axis, cfg->sample.gr_max, cfg->sample.gr_bin,
                                  cfg->sample.contact_fit, (size_t)cfg->sample.blocks,
                                  hsbd_config_steps(cfg) / (uint64_t)cfg->sample.gr_every, err);
        return *state ? HSBD_OK : err->status;
    }
    run_warn(r, "gr.tsv is not written (nor contact values or Z_virial): %s",
             axis < 3 && walls <= 1
                 ? "ideal particles (system.hard_core = off) in a periodic box without a field "
                   "have g(r) = 1"
                 : "its reference density would be a profile over a plane (walls on two or more "
                   "axes, or a field across the walls' axis); the density profiles along each "
                   "walls' axis are written");
    return HSBD_OK;
}

static uint64_t every(const run *r) {
    return (uint64_t)r->cfg->sample.gr_every;
}

static int sample(run *r, void *state, hsbd_error *err) {
    const hsbd_spheres_view v = hsbd_spheres_get_view(spheres_model_of(r)->sys);
    return hsbd_gr_sample(state, &v) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "g(r): out of memory for its cells");
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const hsbd_gr *g = state;
    const size_t nb = hsbd_gr_bins(g), np = hsbd_gr_pairs(g);
    double *x = malloc(nb * sizeof *x), *val = malloc(2 * np * nb * sizeof *val);
    if (!x || !val) {
        free(x), free(val);
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing gr.tsv");
    }
    char columns[64 + HSBD_MAX_SPECIES * HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)] = "r";
    for (size_t p = 0; p < np; ++p) {
        size_t a, b;
        hsbd_gr_pair_species(g, p, &a, &b);
        const char *na = spheres_species_name(r, a), *nb_ = spheres_species_name(r, b);
        const size_t len = strlen(columns);
        snprintf(columns + len, sizeof columns - len, "\tg_%s_%s\tg_%s_%s_err", na, nb_, na, nb_);
        hsbd_gr_result(g, p, x, val + 2 * p * nb, val + (2 * p + 1) * nb);
    }
    const int rc = hsbd_write_columns_table(r->cfg->output.dir, "gr.tsv", r->cfg,
                                            hsbd_gr_profile_axis(g) >= 0
                                                ? "radial distribution function per species "
                                                  "pair (bin centres) over the pairs of "
                                                  "independent particles with the density "
                                                  "profile sampled along the walls or field "
                                                  "axis; errors from time blocks"
                                                : "radial distribution function per species pair "
                                                  "(bin centres); errors from time blocks",
                                            columns, nb, x, np, val, err);
    free(x), free(val);
    return rc;
}

/* "contacts": g_ab(sigma_ab+) per pair with the equation of state's value; Z from them by
 * the virial route, Z = 1 + sum_ab C_ab g_ab, beside the equation of state's Z. Between
 * walls or in a field the values over all pairs against the profile-weighted reference, and
 * neither an equation of state nor Z (the density varies). */
static void write_summary(const run *r, const void *state, FILE *f) {
    const hsbd_gr *g = state;
    const hsbd_config *cfg = r->cfg;
    if (!cfg->system.hard_core) return;
    const int slab = hsbd_gr_profile_axis(g) >= 0;
    const int dim = (int)cfg->system.dimension;
    double vol = 1;
    for (int a = 0; a < dim; ++a)
        vol *= cfg->system.box[a];
    const double rho = (double)cfg->system.n / vol;
    const spheres_model *m = spheres_model_of(r);
    const hsbd_spheres_view v = hsbd_spheres_get_view(m->sys);
    hsbd_size_classes classes;
    hsbd_size_classes_build(&v, m->ns, &classes);
    const int mono = m->ns == 1 && !classes.polydisperse;
    double z = 1, var = 0, z_theory = 1;
    const char *eos = dim == 3 ? (mono ? "Carnahan-Starling" : "BMCSL")
                               : (mono ? "virial series B2-B10" : "none");
    fprintf(f, "  \"contacts\": [");
    for (size_t p = 0; p < hsbd_gr_pairs(g); ++p) {
        size_t a, b;
        hsbd_gr_pair_species(g, p, &a, &b);
        double val, err;
        hsbd_gr_contact(g, p, &val, &err);
        if (slab) {
            fprintf(f,
                    "%s\n    {\"a\": \"%s\", \"b\": \"%s\", \"g_contact\": %.10g, "
                    "\"g_contact_err\": %.4g, \"reference\": \"profile\"}",
                    p ? "," : "", spheres_species_name(r, a), spheres_species_name(r, b),
                    isfinite(val) ? val : 0, isfinite(err) ? err : 0);
            continue;
        }
        const double weight = hsbd_gr_contact_weight(g, p);
        z += weight * val, var += weight * weight * err * err;
        double theory = NAN;
        if (dim == 3)
            theory = mono ? hsbd_hs_contact_cs(cfg->system.packing_fraction)
                          : hsbd_size_classes_bmcsl_contact(&classes, rho, a, b);
        else if (mono)
            theory = hsbd_hd_contact_virial(cfg->system.packing_fraction); /* Henderson: +0.14 % */
        z_theory += weight * theory;
        fprintf(f,
                "%s\n    {\"a\": \"%s\", \"b\": \"%s\", \"g_contact\": %.10g, \"g_contact_err\": "
                "%.4g, \"theory\": %.10g, \"theory_eos\": \"%s\", \"Z_weight\": %.10g}",
                p ? "," : "", spheres_species_name(r, a), spheres_species_name(r, b), val,
                isfinite(err) ? err : 0, isfinite(theory) ? theory : 0, eos, weight);
    }
    fprintf(f, "\n  ],\n");
    if (slab) return;
    hsbd_json_number(f, "Z_contact", z, 1);
    hsbd_json_number(f, "Z_contact_err", sqrt(var), 1); /* pairs treated as independent */
    hsbd_json_number(f, "Z_theory", z_theory, 1);
    fprintf(f, "  \"Z_theory_eos\": \"%s\",\n", eos);
    if (dim == 3 && mono) { /* CS is 0.26 % low at phi 0.3 */
        hsbd_json_number(f, "Z_theory_klm", hsbd_hs_z_klm(cfg->system.packing_fraction), 1);
        hsbd_json_number(f, "g_contact_theory_klm",
                         hsbd_hs_contact_klm(cfg->system.packing_fraction), 1);
    }
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_gr_save(state, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return hsbd_gr_load(state, rd);
}

static void expose(const run *r, const void *state, hsbd_sim_parts *parts) {
    (void)r;
    parts->gr = state;
}

static void release(void *state) {
    hsbd_gr_free(state);
}

const run_observer_ops run_observe_gr = {.name = "g(r)",
                                         .build = build,
                                         .every = every,
                                         .sample = sample,
                                         .save = save,
                                         .load = load,
                                         .write_tables = write_tables,
                                         .write_summary = write_summary,
                                         .expose = expose,
                                         .free = release};
