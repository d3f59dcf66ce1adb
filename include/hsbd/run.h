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

typedef struct hsbd_run_options {
    int force;    /* replace the files of an earlier run in the run directory */
    int check;    /* verify the hard core after every step (min gap >= -1e-9 sigma) */
    int progress; /* progress line with rate and ETA on stderr */
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

/* ---- Ensembles of replicas (docs/scaling.md) ---------------------------------------------
 * Replica k of a configuration runs it whole (initial state, equilibration, production)
 * with the key of its noise made from system.seed and k; an ensemble's run directory DIR
 * holds each replica's run directory DIR/replica-k and their merged tables: means over the
 * replicas and errors from their scatter, combined in replica order, so the bytes depend
 * only on the set of replicas (not on the processes or the order they ran in). */

/* The replicas of an ensemble started on `ranks` processes: run.replicas, or one per rank
 * when it is 0; 1 means a single run. */
HSBD_API size_t hsbd_ensemble_size(const hsbd_config *cfg, int ranks);
/* What hsbd_ensemble_prepare holds for the ensemble until hsbd_ensemble_finish. */
typedef struct hsbd_ensemble_claim {
    int lock;                /* DIR's lock (one writer per run directory, docs/runs.md), or -1 */
    int aside_lock;          /* DIR.earlier's, while earlier results are set aside, or -1 */
    int set_aside;           /* the earlier results in DIR were set aside as DIR.earlier */
    int created;             /* DIR was made here: the levels of its path made (0: none) */
    char dir[HSBD_PATH_MAX]; /* with set_aside: the directory set aside and made anew (DIR,
                              * or the directory a symbolic link DIR points to) */
} hsbd_ensemble_claim;
/* Checks and claims the ensemble's directory (one process, before any replica runs): a
 * missing one is made, an existing one is refused when it holds anything unless force, or
 * when another process writes there (or in one of its replica-K); with force, an earlier
 * ensemble's or run's files (checked to be nothing else) are set aside as DIR.earlier and
 * a new DIR is made (when DIR is a symbolic link, the directory it points to is set aside
 * and made anew, and the link kept). */
HSBD_API int hsbd_ensemble_prepare(const hsbd_config *cfg, int force, hsbd_ensemble_claim *claim,
                                   hsbd_error *err);
/* After the ensemble (the process that prepared it, whatever prepare returned), with its
 * status: earlier files set aside are removed when it succeeded; when it failed they come
 * back if no replica began, else they stay as DIR.earlier, and err's message says which; a
 * DIR made by prepare goes again if it failed before any replica began. The locks are
 * released. Returns status, or an error when the set-aside files cannot be removed. */
HSBD_API int hsbd_ensemble_finish(const hsbd_config *cfg, int status, hsbd_ensemble_claim *claim,
                                  hsbd_error *err);
/* Runs replicas k = rank, rank + ranks, ... below `replicas`, each into DIR/replica-k. */
HSBD_API int hsbd_ensemble_run(const hsbd_config *cfg, const hsbd_run_options *opt, size_t replicas,
                               int rank, int ranks, hsbd_error *err);
/* Merges DIR/replica-0 .. DIR/replica-(replicas-1) into DIR. */
HSBD_API int hsbd_ensemble_merge(const hsbd_config *cfg, size_t replicas, hsbd_error *err);
/* Merges the completed run directories of replicas of one configuration (any order of the
 * arguments; distinct replica indices, at least two) into out. HSBD_EINPUT naming the
 * directory and the parameter when they are not replicas of the same configuration. With
 * ndirs = 0, out is an ensemble's directory: its replica-K directories (all of them when
 * they give run.replicas) are merged into it, as the ensemble does at its end. */
HSBD_API int hsbd_merge(const char *out, const char *const *dirs, size_t ndirs, int force,
                        hsbd_error *err);

#endif
