/* Local processing of a step's events (internal to src/spheres): the pairs predicted to
 * touch at the start of a step join the particles into groups, and each group runs its
 * events in time order on its own, one group after another in memory order, so that the
 * data a group touches stays in cache. Exact: a new path segment is tested against every
 * neighbour outside the group, including the logged earlier segments of particles whose
 * groups already ran; a hit joins the two groups (re-run from the step's start when the
 * other one already moved). See docs/spheres.md, "Events group by group". */
#ifndef HSBD_SPHERES_GROUPS_H
#define HSBD_SPHERES_GROUPS_H

#include "spheres/state.h"

/* Whether this step should run group by group (the parameters, N, recent re-runs). */
int sph_groups_wanted(hsbd_spheres *s);
/* A new step. Returns 0, or -1 when out of memory. */
int sph_groups_begin(hsbd_spheres *s);
/* A start-of-step event: a pair predicted to touch, or a shell exit (j = SPH_EVENT_SHELL).
 * Returns 0, or -1 when out of memory. */
int sph_groups_add_hit(hsbd_spheres *s, double t, int32_t i, int32_t j);
/* Runs every group; returns 0, 1 when it left the step to the global calendar (its
 * events pushed there: the groups were too large), or -1 when out of memory (the step
 * is then cut short: the caller puts the particles back and calls sph_groups_abandon). */
int sph_groups_run(hsbd_spheres *s);
/* Forgets the shells moved inside a step that failed (the neighbour lists are rebuilt). */
void sph_groups_abandon(hsbd_spheres *s);
/* AUTO: the steps left on the global calendar (part of a checkpoint), and setting it */
unsigned sph_groups_pause(const hsbd_spheres *s);
int sph_groups_set_pause(hsbd_spheres *s, unsigned pause);
/* Frees the groups' state (NULL allowed). */
void sph_groups_free(sph_groups *g);

#endif
