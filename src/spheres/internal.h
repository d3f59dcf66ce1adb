/* The EDBD object, shared by the files of src/spheres. */
#ifndef HSBD_SPHERES_INTERNAL_H
#define HSBD_SPHERES_INTERNAL_H

#include "hsbd/spheres.h"
#include "spheres/calendar.h"
#include "core/cellgrid.h"
#include "spheres/groups.h"
#include "spheres/kernels.h"

struct hsbd_spheres {
    hsbd_spheres_params par;
    int dim;
    size_t n;
    double box[3], inv_box[3];
    /* per particle (x, v, centre, image: 3 per particle; z = 0 in 2D) */
    double *x;       /* position at the particle's local time t_local (wrapped at step ends) */
    double *v;       /* fictive velocity of the current step */
    double *t_local; /* time within the step of x */
    double *centre;  /* neighbour-shell centre (wrapped) */
    int64_t *image;
    uint32_t *counter;                     /* collisions so far: invalidates older events */
    double *sigma, *diffusion, *noise_amp; /* sqrt(2 D_i / dt) */
    int *species;
    double *sp_sigma, *sp_diffusion;
    size_t nspecies;
    double sigma_max, shell;
    /* neighbours: pairs whose shells overlap, |c_i - c_j| < sigma_ij + 2 shell */
    uint32_t nb_cap;
    uint32_t *nb_count, *nb_upper; /* entries of each row; those with j > i (first) */
    int32_t *nb;                   /* n x nb_cap */
    hsbd_cells cells;              /* of the shell centres, cells >= sigma_max + 2 shell wide */
    sph_calendar calendar;
    sph_predict_row_fn predict_row; /* scalar or AVX2 (the same results) */
    sph_cells_near_fn cells_near;   /* scalar or AVX2 */
    sph_half_scan_fn half_scan;     /* scalar or AVX2 */
    int32_t *scan_i, *scan_j;       /* hits of a scan: a chunk of rows, or one row (no i) */
    double *scan_t;
    size_t scan_cap; /* >= nb_cap */
    int32_t *near;   /* points found around one particle */
    size_t near_cap;
    double *normals;       /* dim x n draws of a step */
    uint32_t noise_stream; /* HSBD_STREAM_NOISE; the compression uses its own */
    double dt, time;
    uint64_t step;
    /* spatial order (order.c): internal particle i is the user's particle label[i] */
    int32_t *label;
    int reordered;     /* label is not the identity: views show the user_ copies */
    int sort_enabled;  /* 0 while the compression runs (it indexes by user order) */
    double sort_clock; /* D_max t since the last sort (length^2) */
    double diffusion_max;
    int32_t *cell_rank; /* of each cell along the Z curve; NULL until the first sort */
    double *user_x, *user_sigma, *user_diffusion; /* the view's arrays in user order */
    int64_t *user_image;
    int *user_species;
    sph_groups groups; /* local event processing (groups.c) */
    int oom;           /* an allocation failed inside a step (the step is then not exact) */
    hsbd_spheres_stats stats;
};

/* ---- small vector helpers (3 components; z = 0 in 2D) ---- */

/* minimum-image a - b */
static inline void sph_min_image(const hsbd_spheres *s, const double *a, const double *b,
                                 double *r) {
    for (int k = 0; k < 3; ++k)
        r[k] = hsbd_wrap_delta(a[k] - b[k], s->box[k]);
}

static inline double sph_contact_distance(const hsbd_spheres *s, int32_t i, int32_t j) {
    return 0.5 * (s->sigma[i] + s->sigma[j]);
}

/* Position of i at time t of the step (on its current straight segment). */
static inline void sph_position_at(const hsbd_spheres *s, int32_t i, double t, double *out) {
    const double *x = s->x + 3 * (size_t)i, *v = s->v + 3 * (size_t)i;
    const double h = t - s->t_local[i];
    for (int a = 0; a < 3; ++a)
        out[a] = x[a] + v[a] * h;
}

/* Moves i along its segment to time t. */
static inline void sph_advance(hsbd_spheres *s, int32_t i, double t) {
    double *x = s->x + 3 * (size_t)i;
    const double *v = s->v + 3 * (size_t)i;
    const double h = t - s->t_local[i];
    for (int a = 0; a < 3; ++a)
        x[a] += v[a] * h;
    s->t_local[i] = t;
}

/* Puts i's shell centre at its position, wrapped into the box. */
static inline void sph_set_centre(hsbd_spheres *s, int32_t i) {
    const double *x = s->x + 3 * (size_t)i;
    double *c = s->centre + 3 * (size_t)i;
    for (int a = 0; a < 3; ++a)
        c[a] = x[a] - s->box[a] * floor(x[a] * s->inv_box[a]);
}

/* The cached per-particle quantities that follow from dt and D: the noise amplitudes. */
void sph_set_noise_amplitudes(hsbd_spheres *s);

/* Places every particle's shell at its position and builds all neighbour lists. */
int sph_rebuild_neighbours(hsbd_spheres *s);

/* ---- shared by the global calendar (edbd.c) and the groups (groups.c) ---- */

void sph_push_event(hsbd_spheres *s, double t, int32_t i, int32_t j);
/* The time (>= t) at which i, at local time t, leaves its shell before dt; -1 if never. */
double sph_shell_exit_time(const hsbd_spheres *s, int32_t i, double t);
/* Moves e's particles to e->t and applies the collision rule; returns 1 and the event's
 * virial term when they approach, 0 (nothing changed but the positions) otherwise. */
int sph_collide_pair(hsbd_spheres *s, const sph_event *e, double *virial);
/* An event predicted before one of its particles collided again: counted, to be dropped. */
static inline int sph_event_stale(hsbd_spheres *s, const sph_event *e) {
    const int stale = s->counter[e->i] != e->ci || (e->j >= 0 && s->counter[e->j] != e->cj);
    s->stats.stale_events += (uint64_t)stale;
    return stale;
}

/* i (at time t) against its row: the neighbours it reaches inside [t, dt) into
 * s->scan_j, their contact times after t into s->scan_t; returns their number. */
uint32_t sph_row_hits(hsbd_spheres *s, int32_t i, double t);
void sph_nb_add(hsbd_spheres *s, int32_t i, int32_t j);
void sph_nb_remove(hsbd_spheres *s, int32_t i, int32_t j);
/* The points of `cells` whose shells overlap the shell of i (point_sigma: their sigma),
 * into s->near; returns their number. */
uint32_t sph_shells_near(hsbd_spheres *s, const hsbd_cells *cells, const double *point_sigma,
                         int32_t i);
/* The global calendar: runs every event in s->calendar in time order. */
void sph_run_events(hsbd_spheres *s);

/* Groups (groups.c): a new step (0, or -1 when out of memory: use the global calendar);
 * a start-of-step event; run them all. sph_groups_run returns 0, or 1 when it left the
 * step to the global calendar (its events pushed there: the groups were too large). */
int sph_groups_begin(hsbd_spheres *s);
/* Whether this step should run group by group (the parameters, N, recent re-runs). */
int sph_groups_wanted(hsbd_spheres *s);
void sph_groups_add_hit(hsbd_spheres *s, double t, int32_t i, int32_t j);
int sph_groups_run(hsbd_spheres *s);

/* Puts the particles in the Z-curve order of their cells, the neighbour lists and cells
 * renumbered (between steps). Returns 0, or -1 when out of memory (the order is then kept). */
int sph_sort_spatially(hsbd_spheres *s);
/* Back to the user's order (before anything writes per-particle values by user index).
 * Returns 0, or -1 when out of memory. */
int sph_restore_user_order(hsbd_spheres *s);
/* Writes the positions and image counters in user order into user_x and user_image. */
void sph_fill_user_view(const hsbd_spheres *s);

#endif
