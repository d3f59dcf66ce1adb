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
/* Moves i's shell to its current position: out of its neighbours' rows (its own row
 * emptied), into the cell of its new centre. */
int sph_shell_move(hsbd_spheres *s, int32_t i);
/* Edits of many rows queued, then applied on threads (the same rows for any number of
 * threads). sph_queue_begin starts a queue. sph_queue_shell_move moves i's shell as
 * sph_shell_move does, but queues the removal of i from its neighbours' rows, except
 * from those of the neighbours m with moving[m] & bit (whose rows the caller empties by
 * moving them too). sph_queue_pair queues the pair (i, j) for both rows. sph_queue_apply
 * applies the queue on `threads` threads. */
int sph_queue_begin(hsbd_spheres *s);
int sph_queue_shell_move(hsbd_spheres *s, int32_t i, const uint8_t *moving, uint8_t bit);
int sph_queue_pair(hsbd_spheres *s, int32_t i, int32_t j);
int sph_queue_apply(hsbd_spheres *s, int threads);
/* sph_shell_move, then i's pairs with the shells that overlap its new one. */
int sph_recentre(hsbd_spheres *s, int32_t i);
/* Places every particle's shell at its position and builds all neighbour lists. Returns
 * HSBD_OK, or HSBD_ENOMEM with s->nb_stale set (the lists then miss pairs). */
int sph_rebuild_neighbours(hsbd_spheres *s);
/* The cells and neighbour lists of the shells where they are (a checkpoint's). */
int sph_rebuild_rows(hsbd_spheres *s);

#endif
