#include "core/progress.h"

#include <stdio.h>
#include <time.h>

enum { FIRST_LINE = 10, LONGEST_INTERVAL = 600 }; /* seconds */

double hsbd_wall_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void hsbd_progress_start(hsbd_progress *p, int mode, const char *label, double particles,
                         uint64_t done) {
    *p = (hsbd_progress){.mode = mode,
                         .label = label ? label : "",
                         .particles = particles,
                         .t_start = hsbd_wall_seconds(),
                         .interval = FIRST_LINE,
                         .done_start = done};
    p->t_last = p->t_start;
}

/* h:mm:ss */
static void clock_text(char *buf, size_t len, double seconds) {
    const long s = (long)(seconds + 0.5);
    snprintf(buf, len, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
}

void hsbd_progress_update(hsbd_progress *p, const char *stage, uint64_t done, uint64_t total,
                          double t, double t_end, int when) {
    const int lines = p->mode == HSBD_PROGRESS_LINES;
    if (p->mode == HSBD_PROGRESS_NONE || (when != HSBD_PROGRESS_POLL && !lines)) return;
    const double now = hsbd_wall_seconds();
    const double percent = 100.0 * (double)done / (double)(total ? total : 1);
    if (when == HSBD_PROGRESS_START) {
        fprintf(stderr, "hsbd: %s%s %5.1f%%  t = %.6g of %.6g  %llu steps to go\n", p->label, stage,
                percent, t, t_end, (unsigned long long)(total - done));
        return;
    }
    if (when == HSBD_PROGRESS_POLL && now - p->t_last < (lines ? p->interval : 0.5)) return;
    if (lines && when == HSBD_PROGRESS_POLL)
        p->interval = p->interval * 2 < LONGEST_INTERVAL ? p->interval * 2 : LONGEST_INTERVAL;
    p->t_last = now;
    const double elapsed = now - p->t_start;
    const double rate = elapsed > 0 ? (double)(done - p->done_start) / elapsed : 0;
    char eta[32], after[32];
    clock_text(eta, sizeof eta, rate > 0 ? (double)(total - done) / rate : 0);
    clock_text(after, sizeof after, elapsed);
    if (lines)
        fprintf(stderr,
                "hsbd: %s%s %5.1f%%  t = %.6g of %.6g  %.3g M particle-steps/s  ETA %s  "
                "(after %s)\n",
                p->label, stage, percent, t, t_end, rate * p->particles / 1e6, eta, after);
    else
        fprintf(stderr, "\r%s %5.1f%%  t = %.4g of %.4g  %.3g M particle-steps/s  ETA %s   ", stage,
                percent, t, t_end, rate * p->particles / 1e6, eta);
    fflush(stderr);
    p->printed += 1;
}

void hsbd_progress_end(hsbd_progress *p) {
    if (p->mode == HSBD_PROGRESS_TERMINAL && p->printed) fprintf(stderr, "\r%*s\r", 79, "");
}
