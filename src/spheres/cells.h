/* Cell grid over a periodic box (internal to src/spheres): each point sits in one cell,
 * cells at least `min_size` wide, so every point within min_size of a position lies in
 * the (up to 27, deduplicated when an axis has fewer than 3 cells) cells around it. */
#ifndef HSBD_SPHERES_CELLS_H
#define HSBD_SPHERES_CELLS_H

#include <stddef.h>
#include <stdint.h>

typedef struct sph_cells {
    int dim;
    int nc[3]; /* cells per axis (1 for z in 2D) */
    double inv_width[3];
    size_t ncells;
    int few;              /* some axis has fewer than 3 cells: neighbour cells repeat */
    int32_t *head;        /* first point of each cell, -1 empty */
    int32_t *next, *prev; /* doubly linked points (O(1) removal) */
    int32_t *cell_of;     /* cell of each point, -1 when not inserted */
} sph_cells;

/* Returns 0, or -1 when out of memory. */
int sph_cells_init(sph_cells *c, int dim, const double box[3], double min_size, size_t npoints);
void sph_cells_free(sph_cells *c);
void sph_cells_clear(sph_cells *c);
/* Cell index of a position wrapped into the box. */
int32_t sph_cells_index(const sph_cells *c, const double x[3]);
void sph_cells_insert(sph_cells *c, int32_t i, const double x[3]);
void sph_cells_remove(sph_cells *c, int32_t i);
/* Distinct cells around the cell of x (itself included); returns their number. */
int sph_cells_around(const sph_cells *c, const double x[3], int32_t out[27]);

#endif
