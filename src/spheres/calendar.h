/* Event calendar of one EDBD step (internal to src/spheres): a bucket queue over [0, dt).
 * Events are never removed when they go stale; each carries the collision counters its
 * particles had when it was predicted and is dropped on popping if they changed. Event
 * times only grow within a step and every event lies in [0, dt], so equal-width buckets
 * over the step with about one event each give O(1) pushes and pops: the earliest event
 * is the earliest of the first non-empty bucket (the bucket index is a non-decreasing
 * function of t). A step ends with the calendar empty. */
#ifndef HSBD_SPHERES_CALENDAR_H
#define HSBD_SPHERES_CALENDAR_H

#include <stddef.h>
#include <stdint.h>

/* j of a shell-exit event; j = SPH_EVENT_WALL - w: i meets wall w = 2 axis + side */
enum { SPH_EVENT_SHELL = -1, SPH_EVENT_WALL = -2 };

typedef struct sph_event {
    double t;
    int32_t i, j;    /* particles; j = SPH_EVENT_SHELL: i leaves its neighbour shell */
    uint32_t ci, cj; /* collision counters at prediction */
} sph_event;

typedef struct sph_calendar {
    sph_event *pool; /* events in use and free ones */
    int32_t *next;   /* per pool entry: next in its bucket or in the free list, -1 ends */
    size_t pool_cap, pool_used;
    int32_t free_head;
    int32_t *head; /* first event of each bucket, -1 empty */
    size_t nbuckets, head_cap, current;
    double inv_width;    /* buckets per unit time */
    size_t size, pushed; /* events held; pushed in this step */
} sph_calendar;

void sph_calendar_free(sph_calendar *c);
/* Starts a step of length dt on an empty calendar, with buckets for about as many events
 * as the last step pushed. Returns 0, or -1 when out of memory. */
int sph_calendar_start(sph_calendar *c, double dt);
/* The same for about `expect` events (at least `least` buckets, a power of two). */
int sph_calendar_start_for(sph_calendar *c, double dt, size_t expect, size_t least);
/* Returns 0, or -1 when out of memory. */
int sph_calendar_push(sph_calendar *c, sph_event e);
/* Removes the earliest event into *e; 0 when empty. */
int sph_calendar_pop(sph_calendar *c, sph_event *e);

/* An event `ahead` buckets after the present one (about as many events later), or NULL:
 * what is likely to come, for prefetching. */
static inline const sph_event *sph_calendar_peek(const sph_calendar *c, size_t ahead) {
    const size_t b = c->current + ahead;
    return b < c->nbuckets && c->head[b] >= 0 ? &c->pool[c->head[b]] : NULL;
}

#endif
