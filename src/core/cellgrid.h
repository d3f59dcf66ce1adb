/* Cell grid over a periodic box (internal; the EDBD engine and g(r) use it): each point
 * sits in one cell, cells at least `min_size` wide, so every point within min_size of a
 * position lies in the (up to 27, deduplicated when an axis has fewer than 3 cells) cells
 * around it. A cell keeps its points' indices and positions in contiguous slots, so a scan
 * of the cells around a point streams through memory instead of chasing a linked list. */
#ifndef HSBD_CORE_CELLGRID_H
#define HSBD_CORE_CELLGRID_H

#include <stddef.h>
#include <stdint.h>

typedef struct hsbd_cells {
    int dim;
    int nc[3]; /* cells per axis (1 for z in 2D) */
    double inv_width[3];
    size_t ncells;
    int few; /* some axis has fewer than 3 cells: neighbour cells repeat */
    uint32_t
        cap; /* slots per cell: 4, doubled when one fills (the EDBD kernels read 4 at a time) */
    uint32_t *count; /* points per cell */
    int32_t *id;     /* ncells x cap point indices */
    double *pos;     /* ncells x cap x 3 positions given at insertion, + 1 padding (vector loads) */
    int32_t *cell_of, *slot_of; /* per point; cell -1 when not inserted */
    size_t npoints;
} hsbd_cells;

/* Returns 0, or -1 when out of memory. */
int hsbd_cells_init(hsbd_cells *c, int dim, const double box[3], double min_size, size_t npoints);
/* Room for point indices up to npoints - 1. Returns 0, or -1 when out of memory. */
int hsbd_cells_reserve_points(hsbd_cells *c, size_t npoints);
void hsbd_cells_free(hsbd_cells *c);
void hsbd_cells_clear(hsbd_cells *c);
/* Cell index of a position wrapped into the box. */
int32_t hsbd_cells_index(const hsbd_cells *c, const double x[3]);
/* Returns 0, or -1 when out of memory (the point is then not inserted). */
int hsbd_cells_insert(hsbd_cells *c, int32_t i, const double x[3]);
void hsbd_cells_remove(hsbd_cells *c, int32_t i);
/* Distinct cells around the cell of x (itself included); returns their number. */
int hsbd_cells_around(const hsbd_cells *c, const double x[3], int32_t out[27]);

static inline uint32_t hsbd_cells_count(const hsbd_cells *c, int32_t k) {
    return c->count[k];
}
static inline const int32_t *hsbd_cells_ids(const hsbd_cells *c, int32_t k) {
    return c->id + (size_t)k * c->cap;
}
static inline const double *hsbd_cells_positions(const hsbd_cells *c, int32_t k) {
    return c->pos + 3 * (size_t)k * c->cap;
}

#endif
