/* Run directories, ensembles and merges (docs/runs.md, docs/scaling.md): the policy of the
 * command line, internal to the library and the CLI (not in the public API). */
#ifndef HSBD_RUNDIR_RUNDIR_H
#define HSBD_RUNDIR_RUNDIR_H

#include <stddef.h>

#include "hsbd/config.h"
#include "hsbd/error.h"
#include "hsbd/run.h"

/* ---- one run directory (rundir.c) ------------------------------------------------------ */

/* One writer per run directory: hsbd run, hsbd resume, an ensemble and hsbd merge (into
 * OUT) hold an exclusive advisory lock (flock) on this file in it while they write there
 * (a file, not the directory: NFS locks only files opened for writing); merge holds shared
 * locks on its inputs while it reads them. The system drops a lock when its process ends;
 * the file stays (an otherwise empty directory counts as empty). */
#define RUNDIR_LOCK_FILE ".hsbd.lock"
typedef enum rundir_use {
    RUNDIR_WRITE_NEW, /* a writer of a new or earlier run's directory, made if missing; no
                       * lock file made in a directory of other files (its checks refuse it) */
    RUNDIR_WRITE,     /* a writer continuing in an existing directory (resume, merge DIR) */
    RUNDIR_READ,      /* a reader: a shared lock, no lock file made */
    RUNDIR_CHECK      /* nobody writes there (the caller releases the lock at once) */
} rundir_use;
/* Claims dir for `use`, before the directory's own checks: *fd gets the lock's descriptor,
 * or -1 where no lock is needed or can be had (no directory or lock file yet, a file system
 * without locks). HSBD_EINPUT when another process holds a conflicting lock, or the lock
 * file is a link, a FIFO or a directory. */
int rundir_claim(const char *dir, rundir_use use, int *fd, hsbd_error *err);
void rundir_release(int fd);

/* The directory of a new run: made (with its parents) and proved writable (a probe file
 * written, synced and removed). An existing non-empty one is refused unless force; with
 * force an earlier run's files are removed first, and a directory holding anything else
 * (an ensemble's replicas included) is refused. HSBD_EINPUT naming the directory. */
int rundir_prepare(const char *dir, int force, hsbd_error *err);
/* The same without any clearing: made if missing, proved writable. */
int rundir_create(const char *dir, hsbd_error *err);
/* Makes dir and its missing parents; *made counts the levels made (0: dir was there). 0, or
 * -1 with errno. */
int rundir_make(const char *dir, int *made);
/* Takes back what rundir_make made (`made` levels) with dir's lock file, as far as they are
 * empty; only for a directory whose lock this process holds, or no other process knows. */
void rundir_unmake(const char *dir, int made);

/* dir holds no entry but its lock file (or cannot be read) */
int rundir_is_empty(const char *dir);
/* dir holds a checkpoint (checkpoint.hsbd or checkpoint.prev.hsbd) */
int rundir_holds_checkpoint(const char *dir);
/* dir holds a run's own results: a checkpoint, or a summary.json that is no merge's */
int rundir_holds_run(const char *dir);
/* The entry name of dir is a replica directory: replica-<digits>, a directory (no link). */
int rundir_replica_entry(const char *dir, const char *name);
/* dir holds an ensemble's replica directory */
int rundir_holds_replicas(const char *dir);
/* ---- ensembles of replicas (ensemble.c) ------------------------------------------------ */

/* The replicas of a run started on `ranks` processes: run.replicas, or one per rank when
 * it is 0; 1 means a single run (also run.replica >= 0: one replica run alone). */
size_t rundir_ensemble_size(const hsbd_config *cfg, int ranks);
/* What the process that begins an ensemble holds until its end. */
typedef struct rundir_ensemble {
    int lock; /* the lock of output.dir, or -1 */
    int made; /* levels of output.dir's path made by the begin (0: it was there) */
} rundir_ensemble;
/* Claims output.dir for an ensemble (one process, before any replica runs): a missing
 * directory is made; one that holds anything is refused, with or without force (an
 * ensemble never replaces earlier results). */
int rundir_ensemble_begin(const hsbd_config *cfg, rundir_ensemble *e, hsbd_error *err);
/* Runs replicas k = rank, rank + ranks, ... each into output.dir/replica-k. */
int rundir_ensemble_run(const hsbd_config *cfg, const hsbd_run_options *opt, size_t replicas,
                        int rank, int ranks, hsbd_error *err);
/* After every replica (the process that began it), with the ensemble's status: when it
 * succeeded the replicas are merged into output.dir; when it failed a directory the begin
 * made goes again if no replica began. The lock is released. Returns the final status. */
int rundir_ensemble_end(const hsbd_config *cfg, int status, rundir_ensemble *e, hsbd_error *err);

/* ---- merges (merge.c) ------------------------------------------------------------------ */

/* hsbd merge: the completed run directories of replicas of one configuration (any order,
 * distinct replica indices, at least two) into out, which must be new, empty or (with
 * force) an earlier merge's result. With ndirs = 0, out is an ensemble's directory: its
 * replica-K directories are merged into it. HSBD_EINPUT naming the directory and the
 * parameter when they are not replicas of one configuration; nothing is written then. */
int rundir_merge(const char *out, const char *const *dirs, size_t ndirs, int force,
                 hsbd_error *err);
/* The replicas of the ensemble in dir merged into dir; the caller holds dir's lock. */
int rundir_merge_ensemble(const char *dir, hsbd_error *err);

#endif
