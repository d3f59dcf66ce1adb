/* Active Brownian particles (internal to src/spheres; docs/active.md): each particle's
 * orientation e_i (a unit vector, kept in the user's order), its propulsion v0_i e_i added
 * to the step's velocity like any other drift of the particle, and the exact rotational
 * step of e_i at the end of a step. */
#ifndef HSBD_SPHERES_ACTIVE_H
#define HSBD_SPHERES_ACTIVE_H

#include "spheres/state.h"

/* A 3D rotation is drawn in substeps of at most this D_r dt (exact below it to within a
 * probability below 1e-20; active.c). */
#define SPH_ROTATION_TAU_MAX 0.2

/* The parameters' v0 and D_r: both arrays or none, finite, >= 0, v0 = 0 where D = 0
 * (diffusion[i] the particle's D). HSBD_EINPUT naming the particle, else HSBD_OK. */
int sph_active_check(const hsbd_spheres_params *p, const double *diffusion, hsbd_error *err);
/* The active state from s->par (after the particles' D are set): the copies, the weights,
 * the step's buffers, random orientations. Returns 0, or -1 when out of memory. */
int sph_active_alloc(hsbd_spheres *s);
void sph_active_free(hsbd_spheres *s);
/* Uniformly random orientations from the seed's stream (by the user's index). */
void sph_random_orientations(hsbd_spheres *s);

/* The propulsion velocity v0 e of internal particle i (zero for a passive one): each
 * particle's own drift, as a pair rule for relative drifts needs it. Such a rule is
 * wanted whenever s->v0_max > 0, and its pushes belong after sph_keep_free_velocities
 * (the swim sum counts every displacement the pairs cause). */
static inline void sph_propulsion(const hsbd_spheres *s, int32_t i, double g[3]) {
    const size_t u = (size_t)s->label[i];
    const double v0 = s->active && s->propel ? s->v0[u] : 0.0;
    for (int a = 0; a < 3; ++a)
        g[a] = v0 * s->orient[3 * u + a];
}

/* v_i += v0_i e_i for every particle (internal order), the orientation at the step's
 * start: the propulsion enters the step as each particle's own drift. */
void sph_add_propulsion(hsbd_spheres *s);
/* Before the events: the velocities the events start from (for the swim sum). */
void sph_keep_free_velocities(hsbd_spheres *s);
/* After the events, before the final move: sum_i w_i e_i . (the displacement the
 * collisions gave i) of the step into stats.swim_collisional. */
void sph_add_swim_collisional(hsbd_spheres *s);
/* e_i(t) -> e_i(t + dt) with the step's counter s->step (before it advances). */
void sph_rotate(hsbd_spheres *s);

#endif
