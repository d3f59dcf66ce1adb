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
    run_msd_set set; /* of the orientations' d components */
    double *values;  /* d N components of one sample */
} orientation;

static void release(void *state) {
    orientation *o = state;
    if (!o) return;
    run_msd_set_free(&o->set);
    free(o->values);
    free(o);
}

static int build(run *r, void **state, hsbd_error *err) {
    const hsbd_frame *f = run_frame(r);
    if (!f->orientation) return HSBD_OK;
    orientation *o = calloc(1, sizeof *o);
    if (!o) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = o;
    if (!(o->values = malloc((size_t)f->dimension * f->n * sizeof *o->values)))
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const size_t ns = r->cfg->species.n;
    return run_msd_set_build(&o->set, r, ns > 1 ? ns : 0, 0, err);
}

static int sample(run *r, void *state, hsbd_error *err) {
    (void)err;
    orientation *o = state;
    const hsbd_frame *f = run_frame(r);
    const size_t d = (size_t)f->dimension;
    for (size_t i = 0; i < f->n; ++i)
        for (size_t a = 0; a < d; ++a)
            o->values[d * i + a] = f->orientation[3 * i + a];
    run_msd_set_sample(&o->set, o->values);
    return HSBD_OK;
}

/* m, the mean square change of one component, gives C = 1 - |de|^2 / 2 = 1 - d m / 2 */
static void correlation(const hsbd_msd *m, size_t k, int dimension, double *v, double *e) {
    double t, ms, err;
    size_t o;
    hsbd_msd_result(m, k, &t, &ms, &err, &o);
    *v = 1 - 0.5 * dimension * ms, *e = 0.5 * dimension * err;
}

static int write_tables(const run *r, const void *state, hsbd_error *err) {
    return run_msd_set_write(&((const orientation *)state)->set, r, "orientation.tsv", "C",
                             "orientation autocorrelation C(t) = <e_i(0).e_i(t)> of the "
                             "particles' unit vectors, all particles and per species (free "
                             "rotation: exp(-(d-1) D_r t)); errors from blocks of time origins",
                             correlation, err);
}

static int end_replica(run *r, void *state, hsbd_error *err) {
    (void)r, (void)err;
    run_msd_set_restart(&((orientation *)state)->set);
    return HSBD_OK;
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    run_msd_set_save(&((const orientation *)state)->set, w);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    return run_msd_set_load(&((orientation *)state)->set, rd);
}

const run_observer_ops run_observe_orientation = {.name = "orientation",
                                                  .build = build,
                                                  .sample = sample,
                                                  .end_replica = end_replica,
                                                  .save = save,
                                                  .load = load,
                                                  .write_tables = write_tables,
                                                  .free = release};
