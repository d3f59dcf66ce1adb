/* Neighbour shells and the symmetric neighbour rows (internal to src/spheres; see
 * neighbours.c and docs/spheres.md, "Neighbours without global rebuilds"). */
#ifndef HSBD_SPHERES_NEIGHBOURS_H
#define HSBD_SPHERES_NEIGHBOURS_H

#include "spheres/state.h"

/* The functions returning int give 0, or -1 when out of memory: the rows may then miss
 * pairs (the caller fails the step; sph_rebuild_neighbours puts them right). */

/* Room for n rows of cap entries, aligned to 64 bytes: with cap a multiple of 16 every
 * row starts a cache line (a row of 16 fits one line, not two). NULL when out of memory;
 * released with free(). */
int32_t *sph_rows_alloc(size_t n, uint32_t cap);

/* Adds j to row i (upper part when j > i); the rows grow when one is full. */
int sph_nb_add(hsbd_spheres *s, int32_t i, int32_t j);
void sph_nb_remove(hsbd_spheres *s, int32_t i, int32_t j);
/* The points of `cells` whose shells overlap the shell of i (point_sigma: their sigma),
 * into out (grown to fit), their number into *found. */
int sph_shells_near(hsbd_spheres *s, const hsbd_cells *cells, const double *point_sigma, int32_t i,
                    sph_near *out, uint32_t *found);
/* Moves i's shell to x, its position now, and finds its neighbours (only i's pairs). */
int sph_recentre(hsbd_spheres *s, int32_t i, const double x[3]);
/* sph_recentre in three parts, so that the shells of far-apart particles can move on
 * threads (scan.c): i leaves its neighbours' rows and its cell and its shell moves to its
 * position x (then sph_shells_near finds its new neighbours); whether the pairs with
 * near[0 .. found) and i's new cell fit without growing the rows or the cells; those pairs
 * into both rows and i into its cell (rows and cells grow when full). */
void sph_shell_lift(hsbd_spheres *s, int32_t i, const double x[3]);
int sph_shell_fits(const hsbd_spheres *s, int32_t i, const int32_t *near, uint32_t found);
int sph_shell_land(hsbd_spheres *s, int32_t i, const int32_t *near, uint32_t found);
/* From this many particles on the state leaves the caches, and the loops whose loads
 * jump through memory ask for their data ahead (software prefetch). */
enum { SPH_PREFETCH_MIN_N = 8192 };
/* Asks for the lines holding row i's first 16 entries, which the kernels read: one line
 * when the row starts a line, two otherwise (rows of 24 entries, the usual capacity at phi
 * 0.3, are 96 bytes apart, so every second row straddles two lines; asking for the first
 * line alone left the second to miss). A hint only (always inlined, see groups.c). */
static inline __attribute__((always_inline)) void sph_prefetch_row(const hsbd_spheres *s,
                                                                   int32_t i) {
    const int32_t *row = s->nb + (size_t)i * s->nb_cap;
    __builtin_prefetch(row);
    __builtin_prefetch(row + 15);
}
/* Asks for the positions and velocities of i's neighbours ahead of a row prediction that
 * will read them: beyond the caches these loads, whose addresses come from the row, were
 * most of the row kernel's time. A hint only: no result changes (always inlined, see
 * groups.c). */
static inline __attribute__((always_inline)) void sph_prefetch_neighbours(const hsbd_spheres *s,
                                                                          int32_t i) {
    const int32_t *row = s->nb + (size_t)i * s->nb_cap;
    for (uint32_t q = 0; q < s->nb_count[i]; ++q) {
        __builtin_prefetch(s->x + 3 * (size_t)row[q]);
        __builtin_prefetch(s->v + 3 * (size_t)row[q]);
        __builtin_prefetch(s->t_local + row[q]);
        __builtin_prefetch(s->sigma + row[q]);
    }
}
/* Places every particle's shell at its position and builds all neighbour lists. Returns
 * HSBD_OK, or HSBD_ENOMEM with s->nb_stale set (the lists then miss pairs). */
int sph_rebuild_neighbours(hsbd_spheres *s);
/* The cells and neighbour lists of the shells where they are (a checkpoint's). */
int sph_rebuild_rows(hsbd_spheres *s);

#endif
