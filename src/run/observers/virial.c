/* Hard disks and spheres in a homogeneous periodic box (no walls, no field): the
 * compressibility factor from the collisional virial, Z = 1 + <sum sigma_ij n . F_j> /
 * (d N kT) (summary "Z_virial"), each collision's impulse Delta r_j kT / D_j. */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/spheres_model.h"

typedef struct virial {
    hsbd_blocks *blocks; /* the virial per sampled interval */
    double last;         /* the engine's sum at the previous sample */
} virial;

static void release(void *state) {
    virial *v = state;
    if (v) hsbd_blocks_free(v->blocks);
    free(v);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    if (cfg->field.type || !cfg->system.hard_core) return HSBD_OK;
    for (int a = 0; a < 3; ++a)
        if (cfg->system.walls[a]) return HSBD_OK;
    virial *v = calloc(1, sizeof *v);
    if (v) *state = v;
    if (!v ||
        !(v->blocks = hsbd_blocks_alloc(1, (size_t)cfg->sample.blocks,
                                        hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every)))
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    return HSBD_OK;
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    virial *v = state;
    const double now = hsbd_spheres_get_stats(spheres_model_of(r)->sys).virial;
    hsbd_blocks_acc(v->blocks)[0] += now - v->last;
    hsbd_blocks_end_sample(v->blocks);
    v->last = now;
    return HSBD_OK;
}

/* production begins: the engine's sums were reset */
static void start_production(run *r, void *state) {
    (void)r;
    ((virial *)state)->last = 0;
}

static void write_summary(const run *r, const void *state, FILE *f) {
    const virial *v = state;
    const hsbd_config *cfg = r->cfg;
    double mean = NAN, err = NAN;
    hsbd_blocks_result(v->blocks, &mean, &err);
    const double per = cfg->run.dt * (double)cfg->sample.every * (double)cfg->system.dimension *
                       (double)cfg->system.n;
    hsbd_json_number(f, "Z_virial", 1 + mean / per, 1);
    hsbd_json_number(f, "Z_virial_err", err / per, 1);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    const virial *v = state;
    hsbd_put_f64(w, v->last);
    hsbd_blocks_save(v->blocks, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    virial *v = state;
    return hsbd_get_f64(rd, &v->last) || hsbd_blocks_load(v->blocks, rd) ? -1 : 0;
}

const run_observer_ops run_observe_virial = {.name = "virial",
                                             .build = build,
                                             .sample = sample,
                                             .start_production = start_production,
                                             .save = save,
                                             .load = load,
                                             .write_summary = write_summary,
                                             .free = release};
