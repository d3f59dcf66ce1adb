/* Rods: the particle current J = sum of displacements / (L t) over the production (summary
 * "particle_current", replicas added up), and with sample.current_every its time series
 * (current.tsv, one interval per line). */
#include <math.h>
#include <stdlib.h>

#include "io/tables.h"
#include "run/observers.h"
#include "run/rods_model.h"

typedef struct current {
    double sum_start;   /* sum of unwrapped positions when production (a replica) began */
    double sum_last;    /* ... at the last line of current.tsv */
    double displaced;   /* sum of displacements of earlier replicas */
    uint64_t last_step; /* production step of the last line */
    run_stream *stream; /* current.tsv, or NULL */
} current;

static void header(const run *r, FILE *f) {
    hsbd_write_table_header(f, r->cfg,
                            "particle current J = sum of displacements / (L interval), per "
                            "interval ending at t",
                            "t\tJ");
}

static int build(run *r, void **state, hsbd_error *err) {
    current *c = calloc(1, sizeof *c);
    if (!c) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    *state = c;
    if (!(r->cfg->sample.current_every > 0)) return HSBD_OK;
    c->stream = run_add_stream(r, "current.tsv", err);
    if (!c->stream) return err->status;
    c->stream->header = header;
    return HSBD_OK;
}

static uint64_t every(const run *r) {
    return r->cfg->sample.current_every > 0 ? run_every(r->cfg, r->cfg->sample.current_every) : 0;
}

static int sample(run *r, void *state, hsbd_error *err) {
    current *c = state;
    const hsbd_config *cfg = r->cfg;
    const double sx = rods_sum_unwrapped(rods_model_of(r)->rods);
    const double span = (double)(r->steps_done - c->last_step) * cfg->run.dt;
    fprintf(c->stream->file.f, "%.10g\t%.10g\n", (double)r->steps_done * cfg->run.dt,
            (sx - c->sum_last) / (cfg->system.length * span));
    c->sum_last = sx;
    c->last_step = r->steps_done;
    return run_stream_check(c->stream, err);
}

/* production (or a replica's) starts from the positions now */
static void restart(run *r, void *state) {
    current *c = state;
    c->sum_start = c->sum_last = rods_sum_unwrapped(rods_model_of(r)->rods);
}

static int end_replica(run *r, void *state, hsbd_error *err) {
    (void)err;
    current *c = state;
    c->displaced += rods_sum_unwrapped(rods_model_of(r)->rods) - c->sum_start;
    return HSBD_OK;
}

static void write_summary(const run *r, const void *state, FILE *f) {
    const current *c = state;
    const hsbd_config *cfg = r->cfg;
    const double t_prod = (double)r->steps_done * cfg->run.dt;
    const double displaced =
        r->steps_done ? c->displaced + rods_sum_unwrapped(rods_model_of(r)->rods) - c->sum_start
                      : 0;
    hsbd_json_number(f, "particle_current",
                     t_prod > 0 ? displaced / (cfg->system.length * t_prod) : NAN, 1);
}

static void save(const run *r, const void *state, hsbd_writer *w) {
    (void)r;
    const current *c = state;
    const double sums[3] = {c->sum_start, c->sum_last, c->displaced};
    hsbd_put_f64s(w, sums, 3);
    hsbd_put_u64(w, c->last_step);
}

static int load(run *r, void *state, hsbd_reader *rd) {
    (void)r;
    current *c = state;
    double sums[3];
    if (hsbd_get_f64s(rd, sums, 3) || hsbd_get_u64(rd, &c->last_step)) return -1;
    c->sum_start = sums[0], c->sum_last = sums[1], c->displaced = sums[2];
    return 0;
}

const run_observer_ops run_observe_current = {.name = "current",
                                              .build = build,
                                              .every = every,
                                              .sample = sample,
                                              .start_production = restart,
                                              .end_replica = end_replica,
                                              .start_replica = restart,
                                              .replica_ready = restart,
                                              .save = save,
                                              .load = load,
                                              .write_summary = write_summary,
                                              .free = free};
