/* The run driver: configuration -> state -> steps -> observers -> result files. */
#ifndef HSBD_RUN_H
#define HSBD_RUN_H

#include <signal.h>

#include "hsbd/config.h"
#include "hsbd/error.h"

typedef struct hsbd_run_options {
    int force;    /* overwrite files in an existing run directory */
    int check;    /* verify the hard core after every step (min gap >= -1e-9 sigma) */
    int progress; /* progress line with rate and ETA on stderr */
    /* set asynchronously (signal handler) to stop; results so far are written */
    const volatile sig_atomic_t *stop;
} hsbd_run_options;

/* Runs a finalized configuration (rods or spheres, system.model) into cfg->output.dir.
 * HSBD_EINPUT for bad input (nothing is written then), HSBD_EINTERRUPT when stopped
 * (valid partial results and "completed": false in summary.json, and a checkpoint to
 * continue from). */
int hsbd_run(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err);
/* The same, by model (kept for callers that name it). */
int hsbd_run_rods(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err);
int hsbd_run_spheres(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err);

#endif
