/* Progress of a run on stderr (hsbd_run_options.progress): on a terminal one line
 * rewritten in place, at most twice a second; in a batch job's log whole lines: one as the
 * run starts, then after 10 s of wall time and at intervals that double up to 10 minutes,
 * and one at its end. Each says the stage, the percentage of the whole run (every
 * equilibration included), the stage's simulated time, the rate and the ETA of the whole
 * run. */
#ifndef HSBD_CORE_PROGRESS_H
#define HSBD_CORE_PROGRESS_H

#include <stdint.h>

#include "hsbd/run.h"

typedef struct hsbd_progress {
    int mode;               /* enum hsbd_progress_mode */
    const char *label;      /* after "hsbd: " on each whole line ("replica 3: "), or "" */
    double particles;       /* particle-steps per step */
    double t_start, t_last; /* wall clock: the start, the last line */
    double interval;        /* whole lines: seconds to the next */
    uint64_t done_start;    /* steps done when this process began */
    int printed;            /* lines printed */
} hsbd_progress;

double hsbd_wall_seconds(void);
void hsbd_progress_start(hsbd_progress *p, int mode, const char *label, double particles,
                         uint64_t done);
/* When an update comes: a poll of the loop, the run's start or its end (whole lines only). */
enum { HSBD_PROGRESS_POLL = 0, HSBD_PROGRESS_START, HSBD_PROGRESS_END };
/* done of total steps of the whole run; the stage's name and simulated time t of t_end. */
void hsbd_progress_update(hsbd_progress *p, const char *stage, uint64_t done, uint64_t total,
                          double t, double t_end, int when);
void hsbd_progress_end(hsbd_progress *p);

#endif
