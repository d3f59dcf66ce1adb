/* Event calendar of one EDBD step (internal to src/spheres): a binary min-heap on time.
 * Events are never removed when they go stale; each carries the collision counters its
 * particles had when it was predicted and is dropped on popping if they changed. Only a
 * few percent of particles collide per step, so the heap stays small. */
#ifndef HSBD_SPHERES_CALENDAR_H
#define HSBD_SPHERES_CALENDAR_H

#include <stddef.h>
#include <stdint.h>

enum { SPH_EVENT_SHELL = -1 }; /* j of a shell-exit event */

typedef struct sph_event {
    double t;
    int32_t i, j;    /* particles; j = SPH_EVENT_SHELL: i leaves its neighbour shell */
    uint32_t ci, cj; /* collision counters at prediction */
} sph_event;

typedef struct sph_calendar {
    sph_event *heap;
    size_t size, cap;
} sph_calendar;

void sph_calendar_free(sph_calendar *c);
static inline void sph_calendar_clear(sph_calendar *c) {
    c->size = 0;
}
/* Returns 0, or -1 when out of memory. */
int sph_calendar_push(sph_calendar *c, sph_event e);
/* Removes the earliest event into *e; 0 when empty. */
int sph_calendar_pop(sph_calendar *c, sph_event *e);

#endif
