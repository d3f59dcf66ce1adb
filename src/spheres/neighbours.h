/* Neighbour shells and the symmetric neighbour rows (internal to src/spheres; see
 * neighbours.c and docs/spheres.md, "Neighbours without global rebuilds"). */
#ifndef HSBD_SPHERES_NEIGHBOURS_H
#define HSBD_SPHERES_NEIGHBOURS_H

#include "spheres/state.h"

/* Adds j to row i (upper part when j > i); the rows grow when one is full. */
void sph_nb_add(hsbd_spheres *s, int32_t i, int32_t j);
void sph_nb_remove(hsbd_spheres *s, int32_t i, int32_t j);
/* The points of `cells` whose shells overlap the shell of i (point_sigma: their sigma),
 * into s->near; returns their number. */
uint32_t sph_shells_near(hsbd_spheres *s, const hsbd_cells *cells, const double *point_sigma,
                         int32_t i);
/* Moves i's shell to its current position and finds its neighbours (only i's pairs). */
void sph_recentre(hsbd_spheres *s, int32_t i);
/* Places every particle's shell at its position and builds all neighbour lists. */
int sph_rebuild_neighbours(hsbd_spheres *s);

#endif
