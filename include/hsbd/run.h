/* The run driver: configuration -> state -> steps -> observers -> result files. */
#ifndef HSBD_RUN_H
#define HSBD_RUN_H

#include "hsbd/export.h"
#include <signal.h>

#include "hsbd/config.h"
#include "hsbd/error.h"

/* Where a configuration came from, kept in checkpoints so that `hsbd resume` can build
 * the same configuration again: the file's name and text and the overrides in order. */
typedef struct hsbd_run_source {
    const char *name; /* the configuration file as given; NULL: the defaults only */
    const char *text; /* its contents */
    size_t text_len;
    const char *const *sets; /* "section.key=value" in the order applied after the file */
    size_t nsets;
} hsbd_run_source;

/* hsbd_run_options.progress: how a run reports its progress on stderr (each report: the
 * stage, percentage and ETA of the whole run, simulated time, rate) */
enum hsbd_progress_mode {
    HSBD_PROGRESS_NONE = 0,
    HSBD_PROGRESS_TERMINAL = 1, /* one line rewritten in place, twice a second */
    HSBD_PROGRESS_LINES = 2     /* whole lines for a batch job's log: after 10 s, then at
                                   intervals doubling up to 10 minutes */
};

typedef struct hsbd_run_options {
    int force;    /* replace the files of an earlier run in the run directory */
    int check;    /* verify the hard core after every step (min gap >= -1e-9 sigma) */
    int progress; /* enum hsbd_progress_mode */
    /* set asynchronously (by a signal handler, to the signal's number) to stop: a
     * checkpoint and the results so far are written */
    const volatile sig_atomic_t *stop;
    /* the configuration's source (NULL: checkpoints are written but cannot be resumed) */
    const hsbd_run_source *source;
    /* the scheme's warnings (time step too large, Eq. 33 of the sticky rule) go to
     * summary.json only, not to stderr: an ensemble's replicas after the first */
    int quiet_warnings;
} hsbd_run_options;

/* Runs a finalized configuration (rods or spheres, system.model) into cfg->output.dir.
 * HSBD_EINPUT for bad input (nothing is written then), HSBD_EINTERRUPT when stopped
 * (valid partial results and "completed": false in summary.json, and a checkpoint to
 * continue from). */
HSBD_API int hsbd_run(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err);
/* The same, by model (kept for callers that name it). */
HSBD_API int hsbd_run_rods(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err);
HSBD_API int hsbd_run_spheres(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err);

/* Continues the run in dir from its newest valid checkpoint (the previous one when the
 * newest is damaged): the configuration is built again from its source, the state and
 * every accumulator loaded, the stream files cut back to the checkpoint, and the run goes
 * on as if never stopped (byte-identical results). sets: overrides, of which only
 * run.t_total may be given (a longer time extends the run, also a completed one).
 * HSBD_EINPUT for a missing, damaged or incompatible checkpoint, a changed input file, or
 * a completed run without a longer run.t_total. */
HSBD_API int hsbd_resume(const char *dir, const char *const *sets, size_t nsets,
                         const hsbd_run_options *opt, hsbd_error *err);

#endif
