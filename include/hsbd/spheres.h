/* Event-driven Brownian dynamics (EDBD) of hard disks (2D) and spheres (3D) in a periodic
 * rectangular box, one species, a mixture, or one size per particle (Scala 2012;
 * docs/spheres.md).
 *
 * A step of length dt draws Gaussian displacements dr_i (variance 2 D_i dt per component,
 * Scala Eq. 2 as corrected in docs/theory.md) plus the common drift, turns them into
 * fictive velocities v_i = dr_i / dt, and runs event-driven elastic collisions inside
 * [0, dt) with masses 1/D_i (the Brownian collision matrix, Scala Sec. III): positions
 * at t + dt follow the last event. Only neighbours can collide: each particle owns a
 * shell (radius `shell` about a centre fixed at its last update) and pairs whose shells
 * overlap are neighbours; a particle that would leave its shell is re-centred, so the
 * hard core is exact without any global rebuild. See docs/spheres.md. */
#ifndef HSBD_SPHERES_H
#define HSBD_SPHERES_H

#include "hsbd/export.h"
#include <stddef.h>
#include <stdint.h>

#include "hsbd/error.h"
#include "hsbd/field.h"

typedef enum hsbd_spheres_event_order {
    HSBD_EVENTS_AUTO = 0,
    HSBD_EVENTS_GLOBAL = 1,
    HSBD_EVENTS_GROUPS = 2
} hsbd_spheres_event_order;

/* From this many particles on, AUTO runs the events group by group (bench/RESULTS.md:
 * below it the state, about 450 bytes per particle, fits in or near the caches and the
 * global calendar is as fast or faster). */
#define HSBD_SPHERES_GROUPS_MIN_N 131072
/* From this many particles on when the box is long enough for the groups' first pass to
 * run on threads (periodic along its longest axis, no walls), on any number of threads:
 * on several the groups run mostly in parallel, the global calendar serially; on one they
 * cost about 5 % more than the global calendar below HSBD_SPHERES_GROUPS_MIN_N. AUTO never
 * follows the thread count itself, so a run takes the same event order on any number of
 * threads and its results do not depend on them even where the two orders differ in the
 * last bits (shells far below the default: docs/spheres.md). */
#define HSBD_SPHERES_GROUPS_MIN_N_THREADS 65536

/* How a pair collides when the two particles' drifts differ (a field with per-particle
 * couplings or a force that varies in space, immobile obstacles in a field; docs/spheres.md,
 * "Pair collisions under a relative drift"). */
typedef enum hsbd_pair_rule {
    /* A pair whose drifts differ keeps the mirror rule's events, but its free end gap Y
     * first becomes sign(Y) X, X the gap at which the law of the pair's normal gap reflected
     * with its relative drift (Scala Eq. 9, in the pair's Brownian centre-of-mass frame) has
     * the quantile that the mirror's law of |Y| has at |Y|; the change is shared in
     * proportion to D_i and D_j. Eq. 9 exactly for a pair alone in the flat-contact limit;
     * a pair without relative drift is not touched (the same bits as HSBD_PAIR_MIRROR). */
    HSBD_PAIR_EXACT = 0,
    /* Elastic collisions of the fictive velocities, drifts included (Scala Sec. III): the
     * image method, exact in the flat-contact limit only without relative drift. */
    HSBD_PAIR_MIRROR = 1
} hsbd_pair_rule;

typedef struct hsbd_spheres_params {
    size_t n;         /* number of particles N */
    int dimension;    /* 2 (disks) or 3 (spheres) */
    double box[3];    /* periodic box lengths (box[2] unused in 2D) */
    double sigma;     /* diameter when nspecies = 0 */
    double diffusion; /* D when nspecies = 0 (length^2 / time) */
    double kT;        /* thermal energy; mobility mu = D / kT */
    double dt;        /* time step */
    uint64_t seed;
    int hard_core;   /* 1: hard spheres (EDBD); 0: free particles (the free-particle bound) */
    double drift[3]; /* common drift velocity (length / time), the same for all particles */
    double shell;    /* neighbour shell radius (half the skin); 0: chosen from dt and D */
    /* Mixtures (nspecies >= 1 with the arrays set): species[i] < nspecies of particle i;
     * diameters species_sigma (> 0) and species_diffusion (>= 0; 0: immobile obstacle).
     * nspecies = N with species[i] = i gives one size per particle. Copied at alloc. */
    size_t nspecies;
    const int *species;
    const double *species_sigma, *species_diffusion;
    /* Optional per-particle values (N each, copied at alloc) that replace the species'
     * (or sigma / diffusion) ones: continuous polydispersity, Stokes-Einstein D. */
    const double *particle_sigma, *particle_diffusion;
    /* 1: keep the particles in the user's order in memory. By default (0) the engine
     * sorts them along a Z curve through space every so often, which it never shows:
     * views, outputs and the noise of each particle follow the user's order. The two
     * runs agree to round-off (tests/unit/test_spheres.c). */
    int keep_order;
    /* How a step's events run (docs/spheres.md): through one time-ordered calendar for
     * the whole box, or group by group (the particles predicted to meet in the step, each
     * group in time order on its own), which keeps large systems in cache. The two give
     * bit-identical trajectories, collisions and virial (tests/unit/test_spheres.c; but
     * see docs/spheres.md for shells far below the default); AUTO (0) takes groups from
     * HSBD_SPHERES_GROUPS_MIN_N particles on (from HSBD_SPHERES_GROUPS_MIN_N_THREADS in a
     * box without walls, on any number of threads), unless they grow too large to gain. */
    hsbd_spheres_event_order event_order;
    size_t groups_min_n; /* AUTO: groups from this N on; 0: the defaults above */
    /* Hard walls (docs/spheres.md, "Walls"): walls[a] = 1 puts planes at 0 and box[a]
     * along axis a (else periodic); centres stay in [sigma_i/2, box[a] - sigma_i/2]. A wall
     * is a body of infinite mass 1/D: a contact reflects the normal velocity. Walls act
     * with hard_core = 0 too. The step is exact for an isolated particle at a wall with
     * any drift (the Skorokhod reflection, docs/theory.md). */
    int walls[3];
    /* External field along axis field_axis (NULL: none; the caller keeps it alive): the
     * drift v_i = (D_i / kT) coupling_i F with F at the start-of-step position x_i (Euler)
     * or the mean of that and F at a free predictor's end point (Heun), field_step (enum
     * hsbd_field_step of hsbd/field.h; 0: Euler). coupling_i from particle_coupling (N
     * values) or species_coupling (nspecies values) or 1. Particles with D_i = 0 do not
     * move. */
    const hsbd_field *field;
    int field_axis;
    const double *species_coupling, *particle_coupling;
    int field_step;
    int pair_rule; /* enum hsbd_pair_rule (0: exact) */
    /* threads for the step's loops over all particles (noise, the start-of-step scan, the
     * final move) and for the first pass of the event groups (slabs of the box; the global
     * calendar runs on one); <= 1: one. The results do not depend on it (docs/spheres.md,
     * "Threads") */
    int threads;
    /* Active Brownian particles (docs/active.md): per particle, in the user's order (N values
     * each, copied at alloc; NULL: no particle is active), the propulsion speed v0_i >= 0
     * (length / time) along the particle's orientation e_i, a unit vector, and the
     * rotational diffusion coefficient D_r,i >= 0 (1 / time) of e_i; both arrays or none.
     * A step adds the drift v0_i e_i (e_i at the step's start) to the particle's velocity,
     * then turns e_i by an exactly distributed rotation (2D: a Gaussian angle of variance
     * 2 D_r dt; 3D: Brownian motion on the sphere, <e(0).e(t)> = exp(-2 D_r t) at any dt).
     * Orientations start uniformly random (the seed's stream); particles with D_i = 0
     * cannot be active. */
    const double *particle_v0, *particle_rotational_diffusion;
} hsbd_spheres_params;

/* Collision statistics accumulated since the last reset. */
typedef struct hsbd_spheres_stats {
    uint64_t steps, collisions, shell_updates, stale_events;
    /* groups that met another group already moved, and ran again from the step's start */
    uint64_t group_reruns;
    /* sum over collisions and the pair rule's changes of sigma_ij n . (impulse on j) / kT,
     * in units of length^2: its mean per unit time gives the collisional virial */
    double virial;
    uint64_t wall_collisions; /* wall events in the calendar (not the bridge pushes) */
    uint64_t wall_pushes;     /* steps of a particle that its bridge pushed off a wall */
    /* pairs whose free end gap the exact pair rule changed (HSBD_PAIR_EXACT) */
    uint64_t pair_corrections;
    /* active particles with D_r > 0: the sum over steps and particles of w_i e_i . (the
     * displacement collisions, the exact pair rule and wall events gave i in the step; not
     * the walls' bridge pushes, which come before), w_i = v0_i kT / ((d - 1) D_i D_r,i)
     * (energy x time / length): its mean per unit time over d V is the collisional part of
     * the swim pressure, P_swim = (1 / d V) sum_i w_i (v0_i + <e_i . v_i,collisions>)
     * (docs/active.md) */
    double swim_collisional;
} hsbd_spheres_stats;

/* Read-only view of the state for observers. Unwrapped position of particle i along axis
 * a: x[3 i + a] + image[3 i + a] * box[a]; wrapped x in [0, box). */
typedef struct hsbd_spheres_view {
    size_t n;
    int dimension;
    double box[3];        /* box lengths (between the walls along a walls axis) */
    int walls[3];         /* 1: hard walls at 0 and box[a] (x in [sigma_i/2, box[a] - sigma_i/2]) */
    const double *x;      /* 3 N, wrapped into the box (z = 0 in 2D) */
    const int64_t *image; /* 3 N image counters */
    const double *sigma;  /* N diameters */
    const double *diffusion;
    const int *species; /* N species indices (all 0 for one species) */
    size_t nspecies;
    double kT, dt, time;
    uint64_t step;
    int hard_core;
    /* active particles (NULL when none are): N orientations (3 each, unit vectors, z = 0
     * in 2D), propulsion speeds and rotational diffusion coefficients, in the user's order */
    const double *orientation, *v0, *rotational_diffusion;
} hsbd_spheres_view;

typedef struct hsbd_spheres hsbd_spheres;

/* Errors: every function that allocates returns HSBD_ENOMEM (and sets err, where it has
 * one) when memory runs out; the object then stays valid to free. After a failed
 * initialisation (init_*, set_positions) the positions are unspecified: initialise again
 * before stepping. */

/* Checks the parameters (N >= 1, dimension 2 or 3, sigma > 0, D >= 0 with some D > 0,
 * kT > 0, dt > 0, every box length >= 2 (sigma_max + 2 shell)); NULL on error with
 * HSBD_EINPUT and a message naming the parameter. */
HSBD_API hsbd_spheres *hsbd_spheres_alloc(const hsbd_spheres_params *params, hsbd_error *err);
HSBD_API void hsbd_spheres_free(hsbd_spheres *s);

/* Initial states. Random sequential insertion (uniform trial positions, overlaps refused)
 * with the seed's initial-state stream; HSBD_EINPUT when it stalls (too dense for RSI). */
HSBD_API int hsbd_spheres_init_random(hsbd_spheres *s, hsbd_error *err);
/* A lattice (square / simple cubic cells filled with 1 (2D: triangular via 2-site
 * cell) or more sites) with spacing large enough for the largest diameter, species
 * shuffled over the sites; HSBD_EINPUT when the box cannot hold N such sites. */
HSBD_API int hsbd_spheres_init_lattice(hsbd_spheres *s, hsbd_error *err);
/* Positions (3 N values; z ignored in 2D), any values (wrapped into the box). Refuses
 * overlaps (gap < -1e-9 sigma_ij, naming the pair) and non-finite values. */
HSBD_API int hsbd_spheres_set_positions(hsbd_spheres *s, const double *x, hsbd_error *err);

/* Dense initial states: random insertion at reduced diameters, then Brownian steps in
 * which every particle grows into a fraction of its smallest gap until all have their
 * final diameters (docs/spheres.md). HSBD_EINPUT when growth stalls (a packing near
 * jamming); the positions are then overlapping and need another init. The compression's
 * noise has its own stream; the clock and statistics start from zero afterwards. */
HSBD_API int hsbd_spheres_init_compress(hsbd_spheres *s, hsbd_error *err);

/* Continuous polydispersity: sigma_i = mean[i] (1 + width xi_i), xi of zero mean and unit
 * variance, Gaussian (truncated beyond about 3 widths, rescaled to keep unit variance) or
 * uniform, from the seed's initial-state stream. width in [0, 0.3]. */
typedef enum { HSBD_SIZES_GAUSSIAN = 0, HSBD_SIZES_UNIFORM = 1 } hsbd_size_distribution;
HSBD_API int hsbd_spheres_draw_diameters(uint64_t seed, size_t n, const double *mean, double width,
                                         hsbd_size_distribution dist, double *sigma,
                                         hsbd_error *err);

/* Packing fraction of n diameters in a periodic box of dimension 2 or 3 (area pi s^2/4 or
 * volume pi s^3/6 per particle over the box). */
HSBD_API double hsbd_spheres_packing_fraction(int dimension, const double box[3], size_t n,
                                              const double *sigma);

/* Active particles: their orientations (3 N values, user order; z ignored in 2D), each
 * normalised; HSBD_EINPUT for a non-finite or zero vector (naming the particle) or a system
 * without active particles. */
HSBD_API int hsbd_spheres_set_orientations(hsbd_spheres *s, const double *e, hsbd_error *err);

/* One EDBD step of length dt. Returns HSBD_OK, or HSBD_ENOMEM when an allocation failed
 * inside the step. A step is exact or fails as a whole: after an error the object holds
 * the state at the start of the failed step (positions, image counters, clock, statistics;
 * views show it), and it can be freed, read, or stepped again (the same step: its noise
 * follows the step number; the shells are rebuilt first, so the retried step agrees with
 * an uninterrupted run to round-off, not bit for bit). */
HSBD_API int hsbd_spheres_step(hsbd_spheres *s);
HSBD_API void hsbd_spheres_set_dt(hsbd_spheres *s, double dt);
/* Threads for the following steps (as the parameter `threads`; the results do not depend
 * on it). */
HSBD_API void hsbd_spheres_set_threads(hsbd_spheres *s, int threads);

HSBD_API hsbd_spheres_view hsbd_spheres_get_view(const hsbd_spheres *s);
HSBD_API const hsbd_spheres_params *hsbd_spheres_get_params(const hsbd_spheres *s);
HSBD_API hsbd_spheres_stats hsbd_spheres_get_stats(const hsbd_spheres *s);
/* Wall impulses since the last reset_stats: out[(6 k + 2 a + side)] (species k, axis a,
 * side 0 at 0, 1 at box[a]) = the sum over the wall's contacts with particles of species
 * k of the displacement the wall caused over D_i: impulse / kT (time / length). Its mean
 * per unit time and wall area is the contact density (contact theorem). out has
 * 6 nspecies values. */
HSBD_API void hsbd_spheres_wall_impulses(const hsbd_spheres *s, double *out);
HSBD_API void hsbd_spheres_reset_stats(hsbd_spheres *s);
HSBD_API double hsbd_spheres_shell(const hsbd_spheres *s);

/* Smallest surface gap over all pairs within reach, relative to sigma_ij, and of every
 * particle to the walls, relative to sigma_i (negative: overlap), and whether every coordinate is
 * finite. Uses the neighbour lists: O(N) (when memory ran out even for rebuilding them after a
 * failed step, the pairs still listed). */
HSBD_API double hsbd_spheres_min_gap(const hsbd_spheres *s, int *all_finite);

/* The Brownian collision rule on the normal components (Scala Sec. III; elastic with
 * masses 1/D_i): u = (v_j - v_i).n < 0 becomes -u, the change shared in proportion to
 * D_i and D_j. Exposed for tests. */
HSBD_API void hsbd_spheres_collide(double di, double dj, const double n[3], double vi[3],
                                   double vj[3]);

/* Time in [0, tmax] at which two spheres at separation r (j minus i) with relative
 * velocity v reach the distance s, or -1 when they do not (exposed for tests). */
HSBD_API double hsbd_spheres_contact_time(const double r[3], const double v[3], double s,
                                          double tmax);

#endif
