/* Hard disks and spheres between walls and in fields: the density profiles along every
 * walls or field axis, all particles and per species (density.tsv, density_<axis>.tsv),
 * and the contact density at each wall from its impulses (contact theorem) and from the
 * profiles (summary "walls"). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/spheres.h"
#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/spheres_model.h"

typedef struct walls_observers {
    hsbd_slab *slab[3];   /* per axis: walls or the field act along it; else NULL */
    hsbd_blocks *impulse; /* per sample: wall impulse increments, 6 (ns + 1) (the last: all) */
    double *impulse_last; /* 6 ns sums at the previous sample */
    double *scratch;      /* 6 ns */
    size_t ns;
} walls_observers;

static const char *species_label(const hsbd_config *cfg, size_t k) {
    return cfg->species.n ? cfg->species.name[k] : "S";
}

/* the wall's area: the product of the box lengths across the axis */
static double wall_area(const hsbd_config *cfg, int axis) {
    double area = 1;
    for (int a = 0; a < (int)cfg->system.dimension; ++a)
        if (a != axis) area *= cfg->system.box[a];
    return area;
}

static int profiled(const hsbd_config *cfg, int a) {
    return cfg->system.walls[a] || (cfg->field.type && cfg->field.axis == a);
}

static void release(void *state) {
    walls_observers *w = state;
    if (!w) return;
    for (int a = 0; a < 3; ++a)
        hsbd_slab_free(w->slab[a]);
    hsbd_blocks_free(w->impulse);
    free(w->impulse_last);
    free(w);
}

/* none without walls or a field */
static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    int any = 0;
    for (int a = 0; a < (int)cfg->system.dimension; ++a)
        any |= profiled(cfg, a);
    if (!any) return HSBD_OK;
    const hsbd_spheres_view view = hsbd_spheres_get_view(spheres_model_of(r)->sys), *v = &view;
    walls_observers *w = calloc(1, sizeof *w);
    if (!w) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = w;
    w->ns = cfg->species.n ? cfg->species.n : 1;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    const size_t blocks = (size_t)cfg->sample.blocks;
    int any_walls = 0;
    for (int a = 0; a < (int)cfg->system.dimension; ++a) {
        any_walls |= cfg->system.walls[a];
        if (!profiled(cfg, a)) continue;
        const double period =
            a == cfg->field.axis && cfg->field.type ? cfg->sample.period : cfg->system.box[a];
        w->slab[a] =
            hsbd_slab_alloc(v, a, period, cfg->sample.bin_width,
                            cfg->sample.contact_fit * cfg->system.sigma, blocks, samples, err);
        if (!w->slab[a]) return err->status;
    }
    if (!any_walls) return HSBD_OK;
    w->impulse = hsbd_blocks_alloc(6 * (w->ns + 1), blocks, samples);
    w->impulse_last = calloc(12 * w->ns, sizeof *w->impulse_last);
    if (!w->impulse || !w->impulse_last)
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory for the wall contacts");
    w->scratch = w->impulse_last + 6 * w->ns;
    return HSBD_OK;
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    walls_observers *w = state;
    const hsbd_spheres *sys = spheres_model_of(r)->sys;
    const hsbd_spheres_view v = hsbd_spheres_get_view(sys);
    for (int a = 0; a < 3; ++a)
        if (w->slab[a]) hsbd_slab_sample(w->slab[a], &v);
    if (!w->impulse) return HSBD_OK;
    hsbd_spheres_wall_impulses(sys, w->scratch);
    double *acc = hsbd_blocks_acc(w->impulse);
    for (size_t k = 0; k < w->ns; ++k)
        for (size_t q = 0; q < 6; ++q) {
            const double inc = w->scratch[6 * k + q] - w->impulse_last[6 * k + q];
            acc[6 * k + q] += inc;
            acc[6 * w->ns + q] += inc;
        }
    memcpy(w->impulse_last, w->scratch, 6 * w->ns * sizeof *w->scratch);
    hsbd_blocks_end_sample(w->impulse);
    return HSBD_OK;
}

/* production begins: the engine's sums were reset */
static void start_production(run *r, void *state) {
    (void)r;
    walls_observers *w = state;
    if (w->impulse_last) memset(w->impulse_last, 0, 6 * w->ns * sizeof *w->impulse_last);
}

/* density.tsv along the field's axis (or the first walls axis), density_<axis>.tsv along
 * the others */
static int write_tables(const run *r, const void *state, hsbd_error *err) {
    const walls_observers *w = state;
    const hsbd_config *cfg = r->cfg;
    int main_axis = cfg->field.type ? cfg->field.axis : -1; /* else the first with a slab */
    for (int a = 0; a < 3 && main_axis < 0; ++a)
        if (w->slab[a]) main_axis = a;
    for (int pass = 0; pass < 2; ++pass)
        for (int a = 0; a < 3; ++a) {
            if (!w->slab[a] || (a == main_axis) != (pass == 0)) continue;
            const size_t nb = hsbd_slab_bins(w->slab[a]), cols = 1 + (w->ns > 1 ? w->ns : 0);
            double *x = malloc(nb * sizeof *x), *val = malloc(2 * cols * nb * sizeof *val);
            if (!x || !val) {
                free(x), free(val);
                return hsbd_error_set(err, HSBD_ENOMEM, "out of memory writing the profiles");
            }
            char columns[64 + HSBD_MAX_SPECIES * (2 * HSBD_SPECIES_NAME + 16)] = "x\trho\trho_err";
            for (size_t c = 0; c < cols; ++c) {
                hsbd_slab_density(w->slab[a], c == 0 ? -1 : (int)c - 1, x, val + 2 * c * nb,
                                  val + (2 * c + 1) * nb);
                const size_t len = strlen(columns);
                if (c > 0)
                    snprintf(columns + len, sizeof columns - len, "\trho_%s\trho_%s_err",
                             species_label(cfg, c - 1), species_label(cfg, c - 1));
            }
            char name[32], what[160];
            snprintf(name, sizeof name, pass == 0 ? "density.tsv" : "density_%c.tsv", "xyz"[a]);
            snprintf(what, sizeof what,
                     "number density along %c (bin centres%s), all particles and per species; "
                     "errors from time blocks",
                     "xyz"[a],
                     cfg -> system.walls[a] ? ", walls at 0 and the box length"
                                            : ", folded into sample.period");
            const int rc = hsbd_write_columns_table(cfg->output.dir, name, cfg, what, columns, nb,
                                                    x, cols, val, err);
            free(x), free(val);
            if (rc != HSBD_OK) return rc;
        }
    return HSBD_OK;
}

/* The contact density at a wall from its impulses: kT rho = force per area, so rho = the
 * mean impulse / kT per sample over (sample interval x area); value index q of the blocks. */
static void impulse_contact(const run *r, const walls_observers *w, size_t q, int axis, double *val,
                            double *err) {
    const size_t nv = 6 * (w->ns + 1);
    double mean[6 * (HSBD_MAX_SPECIES + 1)], e[6 * (HSBD_MAX_SPECIES + 1)];
    hsbd_blocks_result(w->impulse, mean, e);
    const double per = r->cfg->run.dt * (double)r->cfg->sample.every * wall_area(r->cfg, axis);
    *val = q < nv ? mean[q] / per : NAN;
    *err = q < nv ? e[q] / per : NAN;
}

static void json_pair(FILE *f, const char *key, double v, double e) {
    fprintf(f, "\"%s\": %.10g, \"%s_err\": %.4g", key, isfinite(v) ? v : 0, key,
            isfinite(e) ? e : 0);
}

static void write_summary(const run *r, const void *state, FILE *f) {
    const walls_observers *w = state;
    const hsbd_config *cfg = r->cfg;
    if (!w->impulse) return;
    fprintf(f, "  \"walls\": [");
    int any = 0;
    for (int a = 0; a < (int)cfg->system.dimension; ++a)
        for (int side = 0; side < 2 && cfg->system.walls[a]; ++side) {
            const size_t q = (size_t)(2 * a + side);
            double v, e, pv, pe;
            impulse_contact(r, w, 6 * w->ns + q, a, &v, &e);
            hsbd_slab_wall_contact(w->slab[a], side, -1, &pv, &pe);
            fprintf(f, "%s\n    {\"axis\": \"%c\", \"side\": \"%s\", ", any ? "," : "", "xyz"[a],
                    side ? "high" : "low");
            json_pair(f, "contact_density", v, e);
            fprintf(f, ", ");
            json_pair(f, "contact_density_profile", pv, pe);
            fprintf(f, ", \"species\": [");
            for (size_t k = 0; k < w->ns; ++k) {
                impulse_contact(r, w, 6 * k + q, a, &v, &e);
                hsbd_slab_wall_contact(w->slab[a], side, (int)k, &pv, &pe);
                fprintf(f, "%s{\"name\": ", k ? ", " : "");
                hsbd_json_string(f, species_label(cfg, k));
                fprintf(f, ", ");
                json_pair(f, "contact_density", v, e);
                fprintf(f, ", ");
                json_pair(f, "contact_density_profile", pv, pe);
                fprintf(f, "}");
            }
            fprintf(f, "]}");
            any = 1;
        }
    fprintf(f, "\n  ],\n");
}

static void save(const run *r, const void *state, hsbd_writer *wr) {
    (void)r;
    const walls_observers *w = state;
    for (int a = 0; a < 3; ++a)
        if (w->slab[a]) hsbd_blocks_save(hsbd_slab_blocks(w->slab[a]), wr);
    if (!w->impulse) return;
    hsbd_blocks_save(w->impulse, wr);
    hsbd_put_f64s(wr, w->impulse_last, 6 * w->ns);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    walls_observers *w = state;
    for (int a = 0; a < 3; ++a)
        if (w->slab[a] && hsbd_blocks_load(hsbd_slab_blocks(w->slab[a]), rd)) return -1;
    if (!w->impulse) return 0;
    return hsbd_blocks_load(w->impulse, rd) || hsbd_get_f64s(rd, w->impulse_last, 6 * w->ns) ? -1
                                                                                             : 0;
}

static void expose(const run *r, const void *state, hsbd_sim_parts *parts) {
    (void)r;
    const walls_observers *w = state;
    for (int a = 0; a < 3; ++a)
        parts->slab[a] = w->slab[a];
}

const run_observer_ops run_observe_walls = {.name = "walls",
                                            .build = build,
                                            .sample = sample,
                                            .start_production = start_production,
                                            .save = save,
                                            .load = load,
                                            .write_tables = write_tables,
                                            .write_summary = write_summary,
                                            .expose = expose,
                                            .free = release};
