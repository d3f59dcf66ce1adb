/* Active disks and spheres in a homogeneous periodic box (no walls, no field): the
 * pressure's parts in summary.json (Solon et al., Nat. Phys. 11, 673 (2015); docs/active.md)
 *   P = rho kT + P_collisional + P_swim,
 *   P_collisional = <sum over collisions sigma_ij n . F_j> / (d V), the hard cores' virial,
 *   P_swim = (1 / d V) sum_i w_i <e_i . dr_i/dt>,  w_i = v0_i / ((d-1) mu_i D_r,i),
 * with <e_i . dr_i/dt> = v0_i + the collisions' share along e_i (the noise's averages to 0),
 * so that P_swim = rho v0^2 / (d (d-1) mu D_r) for ideal particles; the engine sums the
 * collisions' share exactly (stats.swim_collisional). Errors from time blocks. Also the
 * active parameters: v0, D_r, Pe = v0 sigma / D and the persistence length v0 / ((d-1) D_r)
 * per species. */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/spheres_model.h"

typedef struct active {
    hsbd_blocks *blocks; /* per sampled interval: P_collisional, P_swim's collisions' share */
    double last[2];      /* the engine's sums at the previous sample */
    double ideal_swim;   /* sum_i w_i v0_i / (d V) */
    double weight;       /* sum_i w_i v0_i */
    int swim_defined;    /* no particle swims straight (v0 > 0 with D_r = 0) */
    double volume;
} active;

static void release(void *state) {
    active *a = state;
    if (a) hsbd_blocks_free(a->blocks);
    free(a);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    if (!cfg->active.on || cfg->field.type) return HSBD_OK;
    for (int k = 0; k < 3; ++k)
        if (cfg->system.walls[k]) return HSBD_OK;
    active *a = calloc(1, sizeof *a);
    if (a) *state = a;
    if (!a ||
        !(a->blocks = hsbd_blocks_alloc(2, (size_t)cfg->sample.blocks,
                                        hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every)))
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const hsbd_spheres_view v = hsbd_spheres_get_view(spheres_model_of(r)->sys);
    const int d = v.dimension;
    a->volume = 1;
    for (int k = 0; k < d; ++k)
        a->volume *= v.box[k];
    a->swim_defined = 1;
    for (size_t i = 0; i < v.n; ++i) {
        if (v.v0[i] > 0 && v.rotational_diffusion[i] == 0) a->swim_defined = 0;
        if (v.v0[i] > 0 && v.rotational_diffusion[i] > 0) /* w_i v0_i, mu = D / kT */
            a->weight +=
                v.v0[i] * v.v0[i] * v.kT / ((d - 1) * v.rotational_diffusion[i] * v.diffusion[i]);
    }
    a->ideal_swim = a->weight / (d * a->volume);
    return HSBD_OK;
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    active *a = state;
    const hsbd_spheres_stats st = hsbd_spheres_get_stats(spheres_model_of(r)->sys);
    const double now[2] = {st.virial, st.swim_collisional};
    double *acc = hsbd_blocks_acc(a->blocks);
    for (int k = 0; k < 2; ++k)
        acc[k] += now[k] - a->last[k], a->last[k] = now[k];
    hsbd_blocks_end_sample(a->blocks);
    return HSBD_OK;
}

static void start_production(run *r, void *state) {
    (void)r;
    active *a = state;
    a->last[0] = a->last[1] = 0; /* the engine's sums were reset */
}

/* "name": [v per species] */
static void species_list(FILE *f, const char *name, const double *v, size_t ns) {
    fprintf(f, "\"%s\": [", name);
    for (size_t k = 0; k < ns; ++k)
        fprintf(f, "%s%.10g", k ? ", " : "", v[k]);
    fprintf(f, "]");
}

static void write_summary(const run *r, const void *state, FILE *f) {
    const active *a = state;
    const hsbd_config *cfg = r->cfg;
    const size_t ns = cfg->species.n ? cfg->species.n : 1;
    const int d = (int)cfg->system.dimension;
    double pe[HSBD_MAX_SPECIES], lp[HSBD_MAX_SPECIES], dr[HSBD_MAX_SPECIES];
    for (size_t k = 0; k < ns; ++k) {
        const double sig = cfg->species.n ? cfg->species.sigma[k] : cfg->system.sigma;
        const double dif = cfg->species.n ? cfg->species.diffusion[k] : cfg->system.diffusion;
        dr[k] = cfg->active.rotational_default ? 3 * dif / (sig * sig) : cfg->active.rotational[k];
        pe[k] = dif > 0 ? cfg->active.v0[k] * sig / dif : 0;
        lp[k] = dr[k] > 0 ? cfg->active.v0[k] / ((d - 1) * dr[k]) : INFINITY;
    }
    fprintf(f, "  \"active\": {");
    species_list(f, "v0", cfg->active.v0, ns);
    fprintf(f, ", ");
    species_list(f, "rotational_D", dr, ns); /* of the species' nominal sigma and D */
    fprintf(f, ", ");
    species_list(f, "Pe", pe, ns);
    fprintf(f, ", \"persistence_length\": [");
    for (size_t k = 0; k < ns; ++k) {
        if (isfinite(lp[k]))
            fprintf(f, "%s%.10g", k ? ", " : "", lp[k]);
        else
            fprintf(f, "%snull", k ? ", " : "");
    }
    fprintf(f, "]},\n");
    double mean[2] = {NAN, NAN}, err[2] = {NAN, NAN};
    hsbd_blocks_result(a->blocks, mean, err);
    const double per = cfg->run.dt * (double)cfg->sample.every; /* time of a sample */
    const double kt = cfg->system.kT, ideal = (double)cfg->system.n * kt / a->volume;
    const double coll = kt * mean[0] / (per * d * a->volume),
                 coll_err = kt * err[0] / (per * d * a->volume);
    const double swim = a->swim_defined ? a->ideal_swim + mean[1] / (per * d * a->volume) : NAN;
    const double swim_err = a->swim_defined ? err[1] / (per * d * a->volume) : NAN;
    hsbd_json_number(f, "pressure_ideal", ideal, 1);
    hsbd_json_number(f, "pressure_collisional", coll, 1);
    hsbd_json_number(f, "pressure_collisional_err", coll_err, 1);
    hsbd_json_number(f, "pressure_swim", swim, 1);
    hsbd_json_number(f, "pressure_swim_err", swim_err, 1);
    hsbd_json_number(f, "pressure_swim_ideal", a->swim_defined ? a->ideal_swim : NAN, 1);
    /* the two parts' blocks are correlated: the total's error from the sum's own blocks */
    double *rows = malloc(2 * hsbd_blocks_count(a->blocks) * sizeof *rows), sum = 0, sum2 = 0;
    const size_t nb = rows ? hsbd_blocks_block_means(a->blocks, 0, rows) : 0;
    size_t used = 0; /* blocks without samples (a short run) have NaN rows */
    for (size_t b = 0; b < nb; ++b) {
        const double x = (kt * rows[2 * b] + rows[2 * b + 1]) / (per * d * a->volume);
        if (isnan(x)) continue;
        sum += x, sum2 += x * x, ++used;
    }
    free(rows);
    const double total_err =
        used > 1 ? sqrt(fmax(0, sum2 / used - (sum / used) * (sum / used)) / (used - 1)) : NAN;
    hsbd_json_number(f, "pressure", ideal + coll + swim, 1);
    hsbd_json_number(f, "pressure_err", a->swim_defined ? total_err : NAN, 1);
    /* <e . dr/dt> / v0 weighted by w_i v0_i: 1 for ideal particles, below in a crowd */
    hsbd_json_number(f, "swim_speed_ratio",
                     a->swim_defined && a->weight > 0 ? 1 + mean[1] / (per * a->weight) : NAN, 1);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    const active *a = state;
    hsbd_put_f64s(w, a->last, 2);
    hsbd_blocks_save(a->blocks, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    active *a = state;
    return hsbd_get_f64s(rd, a->last, 2) || hsbd_blocks_load(a->blocks, rd) ? -1 : 0;
}

const run_observer_ops run_observe_active = {.name = "active",
                                             .build = build,
                                             .sample = sample,
                                             .start_production = start_production,
                                             .save = save,
                                             .load = load,
                                             .write_summary = write_summary,
                                             .free = release};
