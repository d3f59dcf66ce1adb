/* One run lifecycle for every model: equilibrate, then produce, with operations that run on
 * triggers (sampling, g(r), trajectory frames, currents), replicas, checkpoints, progress,
 * stop on a signal, and the final tables. A model (src/run/rods.c, spheres.c) only builds
 * its system and observers and registers its operations; everything about the run's life
 * is here, once. */
#ifndef HSBD_RUN_RUN_H
#define HSBD_RUN_RUN_H

#include <stdint.h>
#include <stdio.h>

#include "core/serial.h"
#include "hsbd/config.h"
#include "hsbd/error.h"
#include "hsbd/field.h"
#include "hsbd/frame.h"
#include "hsbd/io.h"
#include "hsbd/observe.h"
#include "hsbd/run.h"
#include "hsbd/sim.h"

typedef struct run run;

/* An operation: called after every `every`-th production step (counted from the start of
 * production over all replicas), in registration order. */
typedef int (*run_action)(run *r, void *ctx, hsbd_error *err);
typedef struct run_op {
    const char *name;
    uint64_t every;
    run_action act;
    void *ctx;
} run_op;

/* A file the run appends to while it goes (trajectory frames, currents): written under
 * its temporary name, flushed and cut back at checkpoints, renamed at the end. */
typedef struct run_stream {
    const char *name;
    hsbd_outfile file;
    int64_t committed; /* bytes on disk at the last checkpoint */
    /* writes the file's header when a run opens it (may be NULL) */
    void (*header)(const struct run *r, FILE *f);
    /* a GSD file (also written in place: its index layout goes into checkpoints) */
    int is_gsd;
    hsbd_gsd gsd;
} run_stream;

/* An observer: what it measures, built for a run from its configuration and fed at its
 * samples. Each is one file under src/run/observers/ and one line in a model's list
 * (src/run/models.c); the lifecycle calls it at every stage. Every function but build may
 * be NULL; `state` is what build made. */
typedef struct run_observer_ops {
    const char *name; /* also its section's tag in checkpoints */
    /* its state for this run in *state, or NULL when it does not apply to the run (HSBD_OK
     * both); an error refuses the input */
    int (*build)(run *r, void **state, hsbd_error *err);
    /* steps between its samples (NULL: sample.every; 0: it takes none) */
    uint64_t (*every)(const run *r);
    int (*sample)(run *r, void *state, hsbd_error *err);
    /* production begins (the model's statistics were just reset) */
    void (*start_production)(run *r, void *state);
    /* sample.blocking = replicas: the last replica ends (its state still there), then the
     * next one's state is made, then its equilibration ends */
    int (*end_replica)(run *r, void *state, hsbd_error *err);
    void (*start_replica)(run *r, void *state);
    void (*replica_ready)(run *r, void *state);
    /* checkpoints: its accumulators */
    void (*save)(const run *r, const void *state, hsbd_writer *w);
    int (*load)(run *r, void *state, hsbd_reader *rd);
    /* results: its tables, and its lines of summary.json ("key": value,) */
    int (*write_tables)(const run *r, const void *state, hsbd_error *err);
    void (*write_summary)(const run *r, const void *state, FILE *f);
    /* what hsbd_sim shows of it */
    void (*expose)(const run *r, const void *state, hsbd_sim_parts *parts);
    void (*free)(void *state);
} run_observer_ops;

typedef struct run_observer {
    const run_observer_ops *ops;
    void *state;
} run_observer;

/* What a model provides. Every function gets the run; the model's own state is r->m. */
typedef struct run_model {
    const char *name; /* "rods", "spheres" */
    double particles; /* particle-steps per step, for rates */
    /* one step (r->stage and r->steps_done say which: the model may collect extra
     * statistics for a step its sampling follows) */
    int (*step)(run *r, hsbd_error *err);
    /* the equilibration's own time step on (1) or off (0); may be NULL */
    void (*equilibration_dt)(run *r, int on);
    /* the state is sane (finite, no overlap when `strict`) */
    int (*check)(run *r, int strict, hsbd_error *err);
    /* replicas: a fresh initial state for replica k >= 1, and origins of time-dependent
     * observers cut; may be NULL when the model has no replicas */
    int (*start_replica)(run *r, size_t k, hsbd_error *err);
    /* a replica's equilibration is over (its reference sums); may be NULL */
    void (*replica_ready)(run *r);
    /* production begins (statistics reset, reference sums); may be NULL */
    void (*start_production)(run *r);
    /* checkpoints: the state and the observers' accumulators */
    void (*save)(const run *r, hsbd_writer *w);
    int (*load)(run *r, hsbd_reader *rd);
    /* final tables and the model's part of summary.json */
    int (*write_tables)(run *r, hsbd_error *err);
    /* the state, for hsbd_sim */
    void (*expose)(const run *r, hsbd_sim_parts *parts);
    /* the particles now as a frame (into memory of the model's) */
    void (*frame)(const run *r, hsbd_frame *frame);
    void (*write_summary)(run *r, FILE *f);
    /* warnings of its own on stderr once the whole input is accepted, after those of
     * run_warn (a fresh run, not a resume; none with opt->quiet_warnings); may be NULL */
    void (*warn_start)(const run *r);
    void (*release)(run *r);
} run_model;

enum {
    RUN_MAX_OPS = 16,
    RUN_MAX_STREAMS = 4,
    RUN_MAX_INPUTS = 4,
    RUN_MAX_OBSERVERS = 16,
    RUN_MAX_WARNINGS = 8
};

/* An input file the run read while it was built (tables): a resumed run must read the
 * same bytes. */
typedef struct run_input {
    char path[HSBD_PATH_MAX];
    uint64_t crc; /* CRC-64 of its contents */
} run_input;
enum run_stage { RUN_EQUILIBRATING = 0, RUN_PRODUCING = 1, RUN_DONE = 2 };

struct run {
    const hsbd_config *cfg;
    const hsbd_run_options *opt;
    run_model model;
    void *m;
    run_op ops[RUN_MAX_OPS];
    size_t nops;
    run_observer observers[RUN_MAX_OBSERVERS];
    size_t nobservers;
    hsbd_frame frame; /* run_frame's, while frame_valid (until the next step) */
    int frame_valid;
    char warnings[RUN_MAX_WARNINGS][HSBD_WARNING_LEN]; /* run_warn's */
    int nwarnings;
    run_stream streams[RUN_MAX_STREAMS];
    size_t nstreams;
    run_input inputs[RUN_MAX_INPUTS];
    size_t ninputs;
    char cwd[HSBD_PATH_MAX];       /* where the run started (relative paths of the inputs) */
    const hsbd_run_source *source; /* the configuration's source, into every checkpoint */
    /* where the run is; all of it goes into a checkpoint */
    int stage;
    uint64_t stage_steps;    /* steps done in the current equilibration */
    uint64_t steps_done;     /* production steps */
    uint64_t equil_done;     /* equilibration steps over all replicas */
    size_t replicas_started; /* sample.blocking = replicas: blocks begun */
    double wall_equil, wall_prod, cpu_equil, cpu_prod;
    uint64_t resumes; /* times this run was continued from a checkpoint */
    int resuming;     /* built to load a checkpoint: no initial state is made */
    /* hsbd_sim_alloc_from: the caller's initial state in place of init.positions and
     * init.method (positions N x 3; species and diameters per particle, or NULL) */
    const double *start_x, *start_sigma;
    const int *start_species;
    int newest_unusable; /* resumed from checkpoint.prev.hsbd: the newest is not to be kept */
    int completed;
    int started; /* the dynamics began: stream files are kept for a resume */
    /* an extension of a finished run (its summary says so): stopped or failed before its
     * end, it leaves that run's results as they are, its checkpoint goes on from there */
    int extends_finished;
};

/* Registration, for the models' build functions. */
int run_add_op(run *r, const char *name, uint64_t every, run_action act, void *ctx,
               hsbd_error *err);
/* A stream file in the run directory; returns it (NULL and an error when full). */
run_stream *run_add_stream(run *r, const char *name, hsbd_error *err);
/* After writing to a stream: HSBD_EIO naming its file when a write failed (disk full). */
int run_stream_check(const run_stream *s, hsbd_error *err);
/* Steps between calls for a period of simulated time (at least 1); 0 for period 0. */
uint64_t run_every(const hsbd_config *cfg, double period);

/* Builders of the two models: fill r->model and r->m (called before the run directory is
 * touched: everything that can refuse the input happens here). */
/* The field terms of field.type along a line of length L (periodic, or between walls),
 * named length_key in messages; a table is loaded into *table (the caller frees it). */
int run_build_field(const hsbd_config *cfg, double L, int periodic, const char *length_key,
                    hsbd_table **table, hsbd_field *field, hsbd_error *err);
/* The relative distortion of a stationary density by a step of the force frozen at its
 * start (Euler) or averaged over the start and a free predictor's end (Heun), in a force of
 * curvature k = mu max|U''| (1 / time). In a harmonic well Euler widens the variance by
 * k dt / 2, so the peak drops by k dt / 4; Heun narrows it by (k dt)^2 / 4, so the peak
 * rises by (k dt)^2 / 8 (docs/algorithms.md: the Percus case follows both). */
double run_step_density_error(int heun, double k, double dt);
/* Above this estimate a run warns (stderr at the start, "warnings" in summary.json). */
#define RUN_STEP_ERROR_MAX 0.01
/* The warning for an estimate above RUN_STEP_ERROR_MAX ("the field's Euler step ..."),
 * with the dt of 1 % and 0.1 %, into msg; 1 when written, 0 when below. `what` names the
 * force ("field"), `where` what it distorts ("stationary density"), `curvature` the
 * curvature's formula ("mu max|U''|"). */
int run_step_warning(int heun, double k, double dt, const char *what, const char *where,
                     const char *curvature, char *msg, size_t len);
/* The threads a run uses: run.threads, or when 0 the default's value (the cores the
 * process may use, or what the CLI set for an MPI rank). */
int run_threads(const hsbd_config *cfg);
/* The input files the configuration reads (at most 3): their keys and paths; the count. */
size_t run_input_files(const hsbd_config *cfg, const char *key[3], const char *path[3]);
int run_rods_build(run *r, hsbd_error *err);
int run_spheres_build(run *r, hsbd_error *err);
/* The model of r->cfg (src/run/models.c): its system, state and observers. */
int run_build(run *r, hsbd_error *err);
/* The name of the configuration's model ("rods", "spheres"). */
const char *run_model_name(const hsbd_config *cfg);

/* The observers of a run (src/run/observer.c): built from a NULL-terminated list (each that
 * applies, with its sampling registered as an operation), and called at each stage, in
 * the list's order. */
int run_observers_build(run *r, const run_observer_ops *const *list, hsbd_error *err);
void run_observers_start_production(run *r);
int run_observers_end_replica(run *r, hsbd_error *err);
void run_observers_start_replica(run *r);
void run_observers_replica_ready(run *r);
void run_observers_save(const run *r, hsbd_writer *w);
int run_observers_load(run *r, hsbd_reader *rd);
int run_observers_write_tables(const run *r, hsbd_error *err);
void run_observers_write_summary(const run *r, FILE *f);
void run_observers_expose(const run *r, hsbd_sim_parts *parts);
void run_observers_free(run *r);

/* A warning about the run found while it is built (a time step too large, an output that
 * cannot be made): printed on stderr once the input is accepted, listed in summary.json. */
void run_warn(run *r, const char *format, ...) __attribute__((format(printf, 2, 3)));
/* run_warn's warnings, then the model's warn_start, on stderr (unless quiet_warnings) */
void run_warn_start(const run *r);
/* The summary's "warnings": the model's own (measured ones) first, then run_warn's. */
void run_write_warnings(const run *r, FILE *f, const char (*more)[HSBD_WARNING_LEN], int nmore);

/* The particles now, as a frame (made once per step, on demand). */
const hsbd_frame *run_frame(run *r);

/* A built run enters its first equilibration. */
void run_begin(run *r);
/* At most `steps` more steps of the run (equilibration, production with its operations,
 * replicas), fewer when it ends; the lifecycle's own loop, as hsbd_run runs it. */
int run_advance(run *r, uint64_t steps, hsbd_error *err);

/* The common fields of summary.json (program, version, completion, steps, timings); the
 * model then adds its own. */
void run_write_summary_head(const run *r, FILE *f, const char *stop_reason);
/* The whole of summary.json: the head, the model's and the observers' lines, the
 * parameters. */
void run_write_summary(run *r, FILE *f, const char *stop_reason);

/* The noise key of this run: system.seed mixed with run.replica (src/run/replica.c; the
 * ensembles themselves are src/rundir/). */
uint64_t run_noise_seed(const hsbd_config *cfg);

#endif
