/* Rods: the mean velocity and the effective diffusion of tagged rods and of the centre of
 * mass, from time blocks (summary "mean_velocity", "d_eff_tagged", "d_eff_cm"; Reimann's
 * giant diffusion in a tilted washboard). */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "observe/checkpoint.h"
#include "run/observers.h"
#include "run/rods_model.h"

typedef struct drift {
    hsbd_drift *blocks;
    double *x; /* N unwrapped positions (scratch) */
} drift;

static void release(void *state) {
    drift *d = state;
    if (!d) return;
    hsbd_drift_free(d->blocks);
    free(d->x);
    free(d);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const size_t n = (size_t)cfg->system.n;
    const uint64_t samples = hsbd_config_steps(cfg) / (uint64_t)cfg->sample.every;
    drift *d = calloc(1, sizeof *d);
    if (!d) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = d;
    d->blocks = hsbd_drift_alloc(n, (size_t)cfg->sample.blocks, samples, err);
    if (!d->blocks) return err->status;
    d->x = malloc(n * sizeof *d->x);
    return d->x ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
}

static int sample(run *r, void *state, hsbd_error *err) {
    drift *d = state;
    const hsbd_rods_view v = hsbd_rods_get_view(rods_model_of(r)->rods);
    return hsbd_drift_sample(d->blocks, &v, d->x) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "out of memory sampling the drift");
}

/* a replica's time block ends with its last state */
static int end_replica(run *r, void *state, hsbd_error *err) {
    drift *d = state;
    const hsbd_rods_view end = hsbd_rods_get_view(rods_model_of(r)->rods);
    return hsbd_drift_close(d->blocks, &end, d->x) == HSBD_OK
               ? HSBD_OK
               : hsbd_error_set(err, HSBD_ENOMEM, "out of memory closing a drift block");
}

/* the time blocks' values, the open block counted up to now; the current's error is the
 * velocity's times N/L */
static void write_summary(const run *r, const void *state, FILE *f) {
    const drift *d = state;
    const hsbd_rods_view v = hsbd_rods_get_view(rods_model_of(r)->rods);
    for (size_t i = 0; i < v.n; ++i)
        d->x[i] = v.z[i] + v.offset[i] + v.unwrap;
    hsbd_drift_result res;
    hsbd_drift_get(d->blocks, v.time, d->x, &res);
    hsbd_json_number(f, "particle_current_err", res.velocity_err * (double)v.n / v.length, 1);
    hsbd_json_number(f, "mean_velocity", res.velocity, 1);
    hsbd_json_number(f, "mean_velocity_err", res.velocity_err, 1);
    hsbd_json_number(f, "d_eff_tagged", res.d_tagged, 1);
    hsbd_json_number(f, "d_eff_tagged_err", res.d_tagged_err, 1);
    hsbd_json_number(f, "d_eff_cm", res.d_cm, 1);
    hsbd_json_number(f, "d_eff_cm_err", res.d_cm_err, 1);
    hsbd_json_number(f, "drift_block_time", res.block_time, 1);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    hsbd_drift_save(((const drift *)state)->blocks, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return hsbd_drift_load(((drift *)state)->blocks, rd);
}

const run_observer_ops run_observe_drift = {.name = "drift",
                                            .build = build,
                                            .sample = sample,
                                            .end_replica = end_replica,
                                            .save = save,
                                            .load = load,
                                            .write_summary = write_summary,
                                            .free = release};
