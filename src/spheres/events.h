/* The pieces of event processing both schedulers use, the global calendar (global.c) and
 * the groups (groups.c): internal to src/spheres. */
#ifndef HSBD_SPHERES_EVENTS_H
#define HSBD_SPHERES_EVENTS_H

#include "spheres/state.h"

/* Event (i, j) at time t into s->calendar, with the particles' collision counters.
 * Returns 0, or -1 when out of memory. */
int sph_push_event(hsbd_spheres *s, double t, int32_t i, int32_t j);
/* The time (>= t) at which i, at local time t, leaves its shell before dt; -1 if never. */
double sph_shell_exit_time(const hsbd_spheres *s, int32_t i, double t);
/* The same for a shell centred at c instead of i's own. */
double sph_shell_exit_from(const hsbd_spheres *s, int32_t i, double t, const double c[3]);
/* i (at time t, on the segment it began at t_local) against its row: the neighbours it
 * reaches before dt into s->scan_j, their contact times into s->scan_t; returns their
 * number. Each pair's time comes from the two segments alone, from the later start
 * (sph_row_query), so that every prediction of a collision, whoever makes it and when,
 * gives the same bits; a time before t (round-off) is raised to t. */
uint32_t sph_row_hits(hsbd_spheres *s, int32_t i, double t);
/* Moves e's particles to e->t and applies the collision rule; returns 1 and the event's
 * virial term when they approach, 0 (nothing changed but the positions) otherwise. */
int sph_collide_pair(hsbd_spheres *s, const sph_event *e, double *virial);

/* The first wall that i (at local time t, on its current segment) meets moving
 * outwards inside [t, dt): its time (>= t), the wall 2 axis + side into *wall; -1 if none. */
double sph_wall_time(const hsbd_spheres *s, int32_t i, double t, int *wall);
/* Moves i to e->t at wall sph_event_wall(e->j) and reflects its normal velocity (the
 * wall has infinite mass); logs the impulse for `group` (-1: the global calendar).
 * Returns 1, 0 when i already moves away (nothing changed but its position), or -1
 * when out of memory. */
int sph_collide_wall(hsbd_spheres *s, const sph_event *e, int32_t group);

/* Appends a wall event to the step's log. Returns 0, or -1 when out of memory. */
int sph_log_wall_hit(hsbd_spheres *s, sph_wall_hit hit);

/* An event predicted before one of its particles collided again: counted, to be dropped. */
static inline int sph_event_stale(hsbd_spheres *s, const sph_event *e) {
    const int stale = s->counter[e->i] != e->ci || (e->j >= 0 && s->counter[e->j] != e->cj);
    s->stats.stale_events += (uint64_t)stale;
    return stale;
}

#endif
