#include "core/progress.h"

#include <stdio.h>
#include <time.h>

double hsbd_wall_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void hsbd_progress_start(hsbd_progress *p, int enabled, const char *label, double particles) {
    p->enabled = enabled;
    p->label = label;
    p->particles = particles;
    p->t_start = p->t_last = hsbd_wall_seconds();
}

void hsbd_progress_update(hsbd_progress *p, uint64_t done, uint64_t total) {
    if (!p->enabled) return;
    const double now = hsbd_wall_seconds();
    if (now - p->t_last < 0.5) return;
    p->t_last = now;
    const double elapsed = now - p->t_start;
    const double rate = elapsed > 0 ? (double)done / elapsed : 0;
    const double eta = rate > 0 ? (double)(total - done) / rate : 0;
    const long e = (long)(eta + 0.5);
    fprintf(stderr, "\r%s %5.1f%%  %.3g M particle-steps/s  ETA %ld:%02ld:%02ld   ", p->label,
            100.0 * (double)done / (double)(total ? total : 1), rate * p->particles / 1e6, e / 3600,
            e / 60 % 60, e % 60);
    fflush(stderr);
}

void hsbd_progress_end(hsbd_progress *p) {
    if (p->enabled && p->t_last > p->t_start) fprintf(stderr, "\r%*s\r", 72, "");
}
