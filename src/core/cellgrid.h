/* Cell grid over a periodic box (internal; the EDBD engine and g(r) use it): each point
 * sits in one cell, cells at least `min_size` wide, so every point within min_size of a
 * position lies in the (up to 27, deduplicated when an axis has fewer than 3 cells) cells
 * around it. A cell keeps its points' indices and positions in slots, four to a chunk (the
 * EDBD kernels test four at a time). Every cell's first chunk and its count share one
 * 128-byte record aligned to cache lines: a scan of the cells around a point reads two
 * whole lines per cell, and the three cells along x of each row are contiguous. Slots
 * beyond the fourth sit in per-cell overflow chunks elsewhere (few cells need them). */
#ifndef HSBD_CORE_CELLGRID_H
#define HSBD_CORE_CELLGRID_H

#include <stddef.h>
#include <stdint.h>

enum { HSBD_CELL_CHUNK = 4 };

typedef struct hsbd_cell_chunk {
    double pos[3 * HSBD_CELL_CHUNK]; /* positions given at insertion, slot after slot */
    int32_t id[HSBD_CELL_CHUNK];     /* point indices (stale in empty slots) */
} hsbd_cell_chunk;                   /* a vector load of the last slot reads into `id` */

typedef struct hsbd_cell {
    hsbd_cell_chunk first;
    uint32_t count; /* points in the cell */
    uint32_t unused[3];
} hsbd_cell; /* 128 bytes: two cache lines */

typedef struct hsbd_cells {
    int dim;
    int nc[3]; /* cells per axis (1 for z in 2D) */
    double inv_width[3];
    size_t ncells;
    int few;                    /* some axis has fewer than 3 cells: neighbour cells repeat */
    hsbd_cell *cell;            /* ncells records, 64-byte aligned inside cell_block */
    void *cell_block;           /* zeroed lazily by the system: untouched cells cost no memory */
    hsbd_cell_chunk *more;      /* ncells x more_chunks chunks: the slots beyond the first chunk */
    uint32_t more_chunks;       /* 0, 1, 3, 7...: the slots per cell double when one fills */
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
    return c->cell[k].count;
}
/* Slots a cell holds before the grid must grow. */
static inline uint32_t hsbd_cells_room(const hsbd_cells *c) {
    return HSBD_CELL_CHUNK * (1 + c->more_chunks);
}
/* Chunk q of cell k: slots HSBD_CELL_CHUNK q to HSBD_CELL_CHUNK (q + 1) - 1. */
static inline hsbd_cell_chunk *hsbd_cells_chunk(const hsbd_cells *c, int32_t k, uint32_t q) {
    return q ? c->more + (size_t)k * c->more_chunks + (q - 1) : &c->cell[k].first;
}
/* Where slot u of cell k keeps its point's index and position. */
static inline int32_t *hsbd_cells_id_slot(const hsbd_cells *c, int32_t k, uint32_t u) {
    return hsbd_cells_chunk(c, k, u / HSBD_CELL_CHUNK)->id + u % HSBD_CELL_CHUNK;
}
static inline double *hsbd_cells_position_slot(const hsbd_cells *c, int32_t k, uint32_t u) {
    return hsbd_cells_chunk(c, k, u / HSBD_CELL_CHUNK)->pos + 3 * (u % HSBD_CELL_CHUNK);
}
static inline int32_t hsbd_cells_id(const hsbd_cells *c, int32_t k, uint32_t u) {
    return *hsbd_cells_id_slot(c, k, u);
}
static inline const double *hsbd_cells_position(const hsbd_cells *c, int32_t k, uint32_t u) {
    return hsbd_cells_position_slot(c, k, u);
}

#endif
