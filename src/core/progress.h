/* A one-line progress report (rate, ETA) for terminals; silent otherwise. */
#ifndef HSBD_CORE_PROGRESS_H
#define HSBD_CORE_PROGRESS_H

#include <stdint.h>

typedef struct hsbd_progress {
    int enabled;
    const char *label;
    double t_start, t_last;
    double particles; /* particle-steps per step */
} hsbd_progress;

double hsbd_wall_seconds(void);
void hsbd_progress_start(hsbd_progress *p, int enabled, const char *label, double particles);
/* Prints at most twice a second. */
void hsbd_progress_update(hsbd_progress *p, uint64_t done, uint64_t total);
void hsbd_progress_end(hsbd_progress *p);

#endif
