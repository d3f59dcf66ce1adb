/* Spatial order of the particles in memory (internal to src/spheres; see order.c). */
#ifndef HSBD_SPHERES_ORDER_H
#define HSBD_SPHERES_ORDER_H

#include "spheres/state.h"

/* Puts the particles in the Z-curve order of their cells, the neighbour lists and cells
 * renumbered (between steps). Returns 0, or -1 when out of memory (the order is then kept). */
int sph_sort_spatially(hsbd_spheres *s);
/* From the user's order to the internal order `label` (internal particle i is the user's
 * label[i]), a checkpoint's. Returns 0, or -1 when out of memory or already reordered. */
int sph_set_order(hsbd_spheres *s, const int32_t *label);
/* Back to the user's order (before anything writes per-particle values by user index).
 * Returns 0, or -1 when out of memory. */
int sph_restore_user_order(hsbd_spheres *s);
/* Writes the positions and image counters in user order into user_x and user_image. */
void sph_fill_user_view(const hsbd_spheres *s);

#endif
