/* Neighbour shells and the symmetric neighbour rows (internal to src/spheres; see
 * neighbours.c and docs/spheres.md, "Neighbours without global rebuilds"). */
#ifndef HSBD_SPHERES_NEIGHBOURS_H
#define HSBD_SPHERES_NEIGHBOURS_H

#include "spheres/state.h"

/* The functions returning int give 0, or -1 when out of memory: the rows may then miss
 * pairs (the caller fails the step; sph_rebuild_neighbours puts them right). */

/* Adds j to row i (upper part when j > i); the rows grow when one is full. */
int sph_nb_add(hsbd_spheres *s, int32_t i, int32_t j);
void sph_nb_remove(hsbd_spheres *s, int32_t i, int32_t j);
/* The points of `cells` whose shells overlap the shell of i (point_sigma: their sigma),
 * into s->near, their number into *found. */
int sph_shells_near(hsbd_spheres *s, const hsbd_cells *cells, const double *point_sigma, int32_t i,
                    uint32_t *found);
/* Moves i's shell to its current position and finds its neighbours (only i's pairs). */
int sph_recentre(hsbd_spheres *s, int32_t i);
/* Places every particle's shell at its position and builds all neighbour lists. Returns
 * HSBD_OK, or HSBD_ENOMEM with s->nb_stale set (the lists then miss pairs). */
int sph_rebuild_neighbours(hsbd_spheres *s);
/* The cells and neighbour lists of the shells where they are (a checkpoint's). */
int sph_rebuild_rows(hsbd_spheres *s);

#endif
