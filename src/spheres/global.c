/* The global calendar (internal to src/spheres): every event of the step in one
 * time-ordered calendar for the whole box; after a collision both partners' rows are
 * tested again, after a shell exit the particle's shell is re-centred, after a wall
 * contact the particle's row and walls are tested again. */
#include "spheres/global.h"

#include "spheres/events.h"
#include "spheres/neighbours.h"

/* Beyond the caches (from SPH_PREFETCH_MIN_N) the events, in time order, jump across
 * the box: the rows of the particles of an event GLOBAL_PREFETCH_ROWS buckets ahead
 * (about as many events) are asked for, and the neighbours of those of an event
 * GLOBAL_PREFETCH_NEIGHBOURS ahead (N 32768: about 12 % less time per step). Hints only:
 * no result changes. */
enum { GLOBAL_PREFETCH_ROWS = 8, GLOBAL_PREFETCH_NEIGHBOURS = 3 };

/* Collisions of i (at time t) with its neighbours inside [t, dt): into the calendar. */
static int predict_row(hsbd_spheres *s, int32_t i, double t) {
    const uint32_t hits = sph_row_hits(s, i, t);
    for (uint32_t k = 0; k < hits; ++k)
        if (sph_push_event(s, s->scan_t[k], i, s->scan_j[k])) return -1;
    return 0;
}

/* When i (at local time t) would leave its shell before dt: schedule that. */
static int predict_shell_exit(hsbd_spheres *s, int32_t i, double t) {
    const double exit = sph_shell_exit_time(s, i, t);
    return exit >= 0 ? sph_push_event(s, exit, i, SPH_EVENT_SHELL) : 0;
}

/* When i (at local time t) would meet a wall before dt: schedule that. */
static int predict_wall(hsbd_spheres *s, int32_t i, double t) {
    int wall = 0;
    const double when = s->any_walls ? sph_wall_time(s, i, t, &wall) : -1;
    return when >= 0 ? sph_push_event(s, when, i, sph_wall_event(wall)) : 0;
}

static int predict_particle(hsbd_spheres *s, int32_t i, double t) {
    return predict_row(s, i, t) || predict_shell_exit(s, i, t) || predict_wall(s, i, t) ? -1 : 0;
}

static int process_collision(hsbd_spheres *s, const sph_event *e) {
    const int32_t i = e->i, j = e->j;
    __builtin_prefetch(s->centre + 3 * (size_t)i); /* for the shell-exit tests at the end */
    __builtin_prefetch(s->centre + 3 * (size_t)j);
    double virial;
    if (!sph_collide_pair(s, e, &virial)) return 0;
    s->step_virial += sph_exact_term(s->virial_scale, virial);
    s->stats.collisions++;
    return predict_particle(s, i, e->t) || predict_particle(s, j, e->t) ? -1 : 0;
}

static inline __attribute__((always_inline)) void prefetch_ahead(const hsbd_spheres *s) {
    const sph_event *far = sph_calendar_peek(&s->calendar, GLOBAL_PREFETCH_ROWS);
    if (far)
        for (int e = 0; e < 1 + (far->j >= 0); ++e) {
            const int32_t p = e ? far->j : far->i;
            sph_prefetch_row(s, p);
            __builtin_prefetch(s->nb_count + p);
        }
    const sph_event *next = sph_calendar_peek(&s->calendar, GLOBAL_PREFETCH_NEIGHBOURS);
    if (next)
        for (int e = 0; e < 1 + (next->j >= 0); ++e)
            sph_prefetch_neighbours(s, e ? next->j : next->i);
}

int sph_global_run(hsbd_spheres *s) {
    sph_event e;
    while (sph_calendar_pop(&s->calendar, &e)) {
        if (s->n >= SPH_PREFETCH_MIN_N) prefetch_ahead(s);
        if (sph_event_stale(s, &e)) continue;
        if (e.j == SPH_EVENT_SHELL) {
            /* the same path (its wall event stands), kept as it began: see sph_row_hits */
            double x[3];
            sph_position_at(s, e.i, e.t, x);
            if (sph_recentre(s, e.i, x) || predict_row(s, e.i, e.t) ||
                predict_shell_exit(s, e.i, e.t))
                return -1;
        } else if (e.j <= SPH_EVENT_WALL) {
            const int rc = sph_collide_wall(s, &e, -1);
            if (rc < 0 || (rc && predict_particle(s, e.i, e.t))) return -1;
        } else if (process_collision(s, &e)) {
            return -1;
        }
    }
    return 0;
}
