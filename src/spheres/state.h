/* The EDBD object, shared by the files of src/spheres (internal): its data and the
 * small inline helpers on one particle's path. Only data: the functions that act on it
 * live in the files above (docs/spheres.md, "Files"). */
#ifndef HSBD_SPHERES_STATE_H
#define HSBD_SPHERES_STATE_H

#include <math.h>

#include "core/cellgrid.h"
#include "core/periodic.h"
#include "hsbd/spheres.h"
#include "spheres/calendar.h"
#include "spheres/kernels.h"

/* The state of the group scheduler (groups.c), allocated by it on first use. */
typedef struct sph_groups sph_groups;

/* Hits of the start-of-step half scan, one buffer per thread (scan.c). */
typedef struct sph_hits {
    int32_t *i, *j;
    double *t;
    size_t len, cap;
} sph_hits;

/* The points found around one particle (neighbours.c), grown to fit. */
typedef struct sph_near {
    int32_t *id;
    size_t cap;
} sph_near;

/* A sum that does not depend on the order of its terms: each term is rounded to a multiple
 * of a quantum and the multiples add exactly in 128-bit integers, in which addition is
 * associative. The global calendar and the event groups meet the same events in other
 * orders; with these sums a step's virial and wall impulses come out bit for bit the same.
 * The quantum is 2^-64 of a power of two near the quantity's natural unit (the Brownian
 * time sigma_max^2 / D_max for the virial, sigma_max / D_max for the wall impulses / kT),
 * so a term of 10^-3 units keeps about 54 bits whatever the user's units, and the
 * rounding of any term (at most half a quantum) is far below the sum's own last bit.
 * Terms beyond 2^56 units (none in any sensible system) saturate; a NaN term counts 0. */
__extension__ typedef __int128 sph_exact_sum;
typedef struct sph_exact_scale {
    double to_quanta, from_quanta; /* 2^(64 - e) and 2^(e - 64), 2^e near the unit */
} sph_exact_scale;
static inline sph_exact_scale sph_exact_scale_for(double unit) {
    const int e = isnormal(unit) ? ilogb(unit) : 0;
    return (sph_exact_scale){ldexp(1.0, 64 - e), ldexp(1.0, e - 64)};
}
static inline sph_exact_sum sph_exact_term(sph_exact_scale scale, double v) {
    double q = v * scale.to_quanta; /* exact: a power of two */
    if (fabs(q) < 0x1p52) { /* to the nearest integer, ties to even, without library calls */
        const double shift = copysign(0x1p52, q);
        return (int64_t)((q + shift) - shift);
    }
    if (fabs(q) < 0x1p63) return (int64_t)q; /* from 2^52 on a double is an integer */
    if (!(fabs(q) <= 0x1p120)) q = isnan(q) ? 0.0 : copysign(0x1p120, q);
    return (sph_exact_sum)q;
}
static inline double sph_exact_value(sph_exact_scale scale, sph_exact_sum sum) {
    return (double)sum * scale.from_quanta;
}

/* A particle's share of a pair's change by the exact pair rule in a step (reflect.c): the
 * engine's particle i and its displacement d. The changes of a step, one buffer per
 * thread, with the pairs changed and their share of the virial. */
typedef struct sph_pair_end {
    int32_t i;
    double d[3];
} sph_pair_end;
typedef struct sph_pushes {
    sph_pair_end *p;
    size_t len, cap;
    uint64_t pairs;
    sph_exact_sum virial;
    int32_t *near; /* a row's pairs within the screen */
    uint32_t near_cap;
} sph_pushes;

/* A wall event of a step: particle, wall 2 axis + side, displacement / D, the group
 * that ran it (-1: the global calendar). */

typedef struct sph_wall_hit {
    int32_t particle, wall, group;
    double impulse;
} sph_wall_hit;

struct hsbd_spheres {
    hsbd_spheres_params par;
    int dim;
    size_t n;
    double box[3], inv_box[3];
    /* per particle (x, v, centre, image: 3 per particle; z = 0 in 2D) */
    double *x;       /* position at the particle's local time t_local (wrapped at step ends) */
    double *x_start; /* x at the start of the step: put back when the step fails */
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
    int one_sigma; /* every particle has diameter sigma_max */
    /* neighbours: pairs whose shells overlap, |c_i - c_j| < sigma_ij + 2 shell */
    uint32_t nb_cap;
    uint32_t *nb_count, *nb_upper; /* entries of each row; those with j > i (first) */
    int32_t *nb;                   /* n x nb_cap */
    int nb_stale;                  /* the rows miss pairs (out of memory): rebuild them */
    hsbd_cells cells;              /* of the shell centres, cells >= sigma_max + 2 shell wide */
    sph_calendar calendar;
    sph_predict_row_fn predict_row; /* scalar or AVX2 (the same results) */
    sph_cells_near_fn cells_near;   /* scalar or AVX2 */
    sph_half_scan_fn half_scan;     /* scalar or AVX2 */
    int32_t *scan_j;                /* hits of one row's scan */
    double *scan_t;
    size_t scan_cap;     /* >= nb_cap */
    int threads;         /* for the loops over all particles (scan.h) */
    uint8_t *start_flag; /* per particle: its path leaves its shell or the walls (scan.h) */
    sph_hits *hit_parts; /* the half scan's hits, one part per thread */
    size_t hit_nparts;
    sph_hits *exit_parts; /* the start's shell exits and wall contacts, one part per thread */
    size_t exit_nparts;
    sph_near near;        /* points found around one particle */
    sph_near *near_parts; /* one per thread: the shells moved at the start of a step */
    size_t near_nparts;
    int32_t *leaving;       /* n: the particles whose shells move, slab by slab (scan.c) */
    double *normals;        /* dim x n draws of a step */
    uint32_t noise_stream;  /* HSBD_STREAM_NOISE; the compression uses its own */
    uint32_t bridge_stream; /* HSBD_STREAM_CONTACT (wall bridges); the compression's own */
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
    sph_groups *groups; /* local event processing (groups.c); NULL until first used */
    /* walls (edbd.c, docs/spheres.md "Walls"): along an axis with walls[a] the planes are
     * at 0 and length[a], and box[a] is a period no pair reaches across (2 length + 3
     * (sigma_max + 2 shell)), so minimum images, cells and wrapping never act there */
    int walls[3], any_walls;
    double length[3];
    sph_exact_sum *wall_step; /* 6 nspecies: this step's wall impulses / kT (see wall_sum) */
    double *wall_sum;         /* 6 nspecies: since the last reset (hsbd_spheres_wall_impulses) */
    sph_wall_hit *wall_log;   /* this step's wall events (a re-run group drops its own) */
    size_t wall_log_len, wall_log_cap;
    double *drift_mu;          /* N: D_i coupling_i / kT (field drift per unit force), or NULL */
    double *field_x, *field_f; /* N: coordinates along the field axis, forces */
    double *field_fp;          /* N: Heun's forces at the predictor's end points, or NULL */
    /* active particles (active.c), in the user's order; all NULL when none is active */
    int active;          /* the parameters gave v0 and D_r */
    int propel;          /* 0 while the compression runs: no propulsion, no rotation */
    double v0_max;       /* the largest v0: > 0, pairs of active particles have relative
                          * drifts (what a pair rule for relative drifts needs to know) */
    double *orient;      /* 3 N unit vectors (z = 0 in 2D) */
    double *v0, *rot_d;  /* N each: propulsion speed, rotational diffusion coefficient */
    double *swim_weight; /* N: v0 kT / ((d - 1) D D_r), 0 where D_r = 0 */
    double *rot_normals, *rot_uniforms; /* a step's rotational draws: 3 N (2D: N), N */
    double *v_free; /* 3 N, internal order: the velocities before any event (hard core) */
    /* the exact pair rule (reflect.c, docs/spheres.md "Pair collisions under a relative
     * drift"): on when the rule is exact and two drifts can differ; the skin widens the
     * neighbour rows so that every pair the rule can change is in them */
    int pair_exact;
    double pair_skin;
    double *drift;          /* 3 N: each particle's drift velocity in this step (when pair_exact) */
    sph_pushes *push_parts; /* one per thread */
    sph_exact_sum *push_sum; /* 3 N: a step's changes per particle (zero between steps) */
    size_t push_nparts;
    sph_exact_sum step_virial; /* this step's virial so far (stats.virial at its end) */
    sph_exact_sum push_virial; /* this step's pair rule's share of it */
    sph_exact_scale virial_scale, wall_scale, swim_scale; /* the quanta of those sums */
    hsbd_spheres_stats stats;
};

/* ---- small vector helpers (3 components; z = 0 in 2D) ---- */

/* minimum-image a - b */
static inline void sph_min_image(const hsbd_spheres *s, const double *a, const double *b,
                                 double *r) {
    for (int k = 0; k < 3; ++k)
        r[k] = hsbd_wrap_delta(a[k] - b[k], s->box[k]);
}

/* How far beyond sigma_ij two shell centres may be for i and j to be neighbours: the two
 * shells, plus the exact pair rule's skin (0 without it). */
static inline double sph_shell_reach(const hsbd_spheres *s) {
    return 2 * s->shell + s->pair_skin;
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

/* The shell centre that sph_set_centre puts at position x: x wrapped into the box. */
static inline void sph_centre_for(const hsbd_spheres *s, const double x[3], double c[3]) {
    for (int a = 0; a < 3; ++a)
        c[a] = x[a] - s->box[a] * floor(x[a] * s->inv_box[a]);
}

/* Puts i's shell centre at position x (i's position now), wrapped into the box. */
static inline void sph_set_centre(hsbd_spheres *s, int32_t i, const double x[3]) {
    sph_centre_for(s, x, s->centre + 3 * (size_t)i);
}

/* The axis that slabs cut (the groups' first pass, the shells moved at the start of a
 * step): the longest periodic one; of equal ones the last, the slowest along the Z curve
 * (order.c). -1 when every axis has walls. */
static inline int sph_slab_axis(const hsbd_spheres *s) {
    int axis = -1;
    for (int a = 0; a < s->dim; ++a)
        if (!s->walls[a] && (axis < 0 || s->box[a] >= s->box[axis])) axis = a;
    return axis;
}

/* The slabs of the groups' first pass on threads (groups.c, docs/spheres.md "Threads"):
 * an even number, 4 to SPH_MAX_SLABS, of equal slabs along the periodic axis *axis, or 0
 * when there is no first pass (walls, no hard core, a small box). Fixed for a system: the
 * spatial order (order.c) keeps each slab's particles together in memory. */
enum { SPH_MAX_SLABS = 64 };
static inline int sph_slabs(const hsbd_spheres *s, int *axis) {
    *axis = sph_slab_axis(s);
    if (*axis < 0 || s->any_walls || !s->par.hard_core) return 0;
    /* a neighbour pair's reach at the start of a step, sigma_max + 4 shell (+ the pair
     * rule's skin); slabs three reaches wide cut few groups, one reach is the least */
    const double reach = 1.01 * (s->sigma_max + 4 * s->shell + s->pair_skin);
    const double length = s->box[*axis];
    int n = 2 * (int)floor(length / (2 * 3 * reach));
    if (n < 4) n = 2 * (int)floor(length / (2 * reach));
    return n < 4 ? 0 : n < SPH_MAX_SLABS ? n : SPH_MAX_SLABS;
}

/* Events of particle i with wall w (2 axis + side) have j = sph_wall_event(w). */
static inline int32_t sph_wall_event(int w) {
    return SPH_EVENT_WALL - w;
}
static inline int sph_event_wall(int32_t j) {
    return SPH_EVENT_WALL - j;
}

#endif
