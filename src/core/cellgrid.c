#include "core/cellgrid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(hsbd_cell) == 128, "a cell record fills two cache lines");

enum { CELL_ALIGN = 64 };

int hsbd_cells_init(hsbd_cells *c, int dim, const double box[3], double min_size, size_t npoints) {
    memset(c, 0, sizeof *c);
    c->dim = dim;
    c->ncells = 1;
    c->npoints = npoints;
    for (int a = 0; a < 3; ++a) {
        int n = 1;
        if (a < dim) {
            const double q = floor(box[a] / min_size);
            n = q < 1 ? 1 : q > 1024 ? 1024 : (int)q;
        }
        c->nc[a] = n;
        if (a < dim && n < 3) c->few = 1;
        c->inv_width[a] = a < dim ? n / box[a] : 0.0;
        c->ncells *= (size_t)n;
    }
    /* calloc, aligned by hand: aligned_alloc would have to zero every page at once */
    c->cell_block = calloc(c->ncells * sizeof *c->cell + CELL_ALIGN, 1);
    c->cell_of = malloc(npoints * sizeof *c->cell_of);
    c->slot_of = malloc(npoints * sizeof *c->slot_of);
    if (!c->cell_block || !c->cell_of || !c->slot_of) return -1;
    const uintptr_t at = (uintptr_t)c->cell_block;
    c->cell = (hsbd_cell *)((char *)c->cell_block + (CELL_ALIGN - at % CELL_ALIGN) % CELL_ALIGN);
    hsbd_cells_clear(c);
    return 0;
}

int hsbd_cells_reserve_points(hsbd_cells *c, size_t npoints) {
    if (npoints <= c->npoints) return 0;
    int32_t *cell_of = realloc(c->cell_of, npoints * sizeof *cell_of);
    if (cell_of) c->cell_of = cell_of;
    int32_t *slot_of = cell_of ? realloc(c->slot_of, npoints * sizeof *slot_of) : NULL;
    if (!slot_of) return -1;
    c->slot_of = slot_of;
    for (size_t i = c->npoints; i < npoints; ++i)
        c->cell_of[i] = -1;
    c->npoints = npoints;
    return 0;
}

void hsbd_cells_free(hsbd_cells *c) {
    free(c->cell_block);
    free(c->more);
    free(c->cell_of);
    free(c->slot_of);
    memset(c, 0, sizeof *c);
}

void hsbd_cells_clear(hsbd_cells *c) {
    for (size_t k = 0; k < c->ncells; ++k)
        if (c->cell[k].count) c->cell[k].count = 0; /* a clear grid's pages stay untouched */
    for (size_t i = 0; i < c->npoints; ++i)
        c->cell_of[i] = -1;
}

static int axis_cell(const hsbd_cells *c, int a, double x) {
    const double q = x * c->inv_width[a];
    int k = (int)q; /* truncation: floor for the wrapped (non-negative) positions */
    if ((unsigned)k < (unsigned)c->nc[a] && q >= 0) return k; /* inside: no division */
    if (q < 0) k = (int)floor(q);
    k %= c->nc[a];
    return k < 0 ? k + c->nc[a] : k;
}

int32_t hsbd_cells_index(const hsbd_cells *c, const double x[3]) {
    const int kx = axis_cell(c, 0, x[0]), ky = axis_cell(c, 1, x[1]);
    const int kz = c->dim == 3 ? axis_cell(c, 2, x[2]) : 0;
    return (int32_t)((kz * c->nc[1] + ky) * c->nc[0] + kx);
}

/* Twice the slots per cell (overflow chunks 1, 3, 7, ...), every cell's copied over. */
static int grow(hsbd_cells *c) {
    const uint32_t chunks = 2 * c->more_chunks + 1;
    hsbd_cell_chunk *more = calloc(c->ncells * chunks, sizeof *more);
    if (!more) return -1;
    for (size_t k = 0; k < c->ncells; ++k) {
        const uint32_t used = c->cell[k].count > HSBD_CELL_CHUNK
                                  ? (c->cell[k].count - 1) / HSBD_CELL_CHUNK /* beyond the first */
                                  : 0;
        if (used) memcpy(more + k * chunks, c->more + k * c->more_chunks, used * sizeof *more);
    }
    free(c->more);
    c->more = more;
    c->more_chunks = chunks;
    return 0;
}

int hsbd_cells_insert(hsbd_cells *c, int32_t i, const double x[3]) {
    const int32_t k = hsbd_cells_index(c, x);
    if (c->cell[k].count == hsbd_cells_room(c) && grow(c)) return -1;
    const uint32_t u = c->cell[k].count++;
    *hsbd_cells_id_slot(c, k, u) = i;
    memcpy(hsbd_cells_position_slot(c, k, u), x, 3 * sizeof *x);
    c->cell_of[i] = k;
    c->slot_of[i] = (int32_t)u;
    return 0;
}

void hsbd_cells_remove(hsbd_cells *c, int32_t i) {
    const int32_t k = c->cell_of[i];
    if (k < 0) return;
    const uint32_t u = (uint32_t)c->slot_of[i], last = --c->cell[k].count;
    if (u != last) { /* the last point fills the hole */
        const int32_t moved = hsbd_cells_id(c, k, last);
        *hsbd_cells_id_slot(c, k, u) = moved;
        memcpy(hsbd_cells_position_slot(c, k, u), hsbd_cells_position(c, k, last),
               3 * sizeof(double));
        c->slot_of[moved] = (int32_t)u;
    }
    c->cell_of[i] = -1;
}

/* k + d (d = -1, 0, 1) on a periodic axis of n cells */
static inline int axis_step(int k, int d, int n) {
    k += d;
    return k < 0 ? k + n : k >= n ? k - n : k;
}

int hsbd_cells_around(const hsbd_cells *c, const double x[3], int32_t out[27]) {
    const int kx = axis_cell(c, 0, x[0]), ky = axis_cell(c, 1, x[1]);
    const int kz = c->dim == 3 ? axis_cell(c, 2, x[2]) : 0, zr = c->dim == 3 ? 1 : 0;
    int along_x[3], along_y[3]; /* the index offsets of the three columns and rows */
    for (int d = -1; d <= 1; ++d) {
        along_x[d + 1] = axis_step(kx, d, c->nc[0]);
        along_y[d + 1] = axis_step(ky, d, c->nc[1]) * c->nc[0];
    }
    int count = 0;
    for (int dz = -zr; dz <= zr; ++dz) {
        const int plane = axis_step(kz, dz, c->nc[2]) * c->nc[1] * c->nc[0];
        for (int b = 0; b < 3; ++b)
            for (int a = 0; a < 3; ++a) {
                const int32_t k = (int32_t)(plane + along_y[b] + along_x[a]);
                int seen = 0;
                for (int q = 0; c->few && q < count && !seen; ++q)
                    seen = out[q] == k;
                if (!seen) out[count++] = k;
            }
    }
    return count;
}
