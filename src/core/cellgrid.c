#include "core/cellgrid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { CELLS_FIRST_CAP = 4 };

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
    c->cap = CELLS_FIRST_CAP;
    c->count = calloc(c->ncells, sizeof *c->count);
    c->id = calloc(c->ncells * c->cap, sizeof *c->id); /* empty slots are read (cellgrid.h) */
    c->pos = calloc(3 * c->ncells * c->cap + 1, sizeof *c->pos); /* + 1: see cellgrid.h */
    c->cell_of = malloc(npoints * sizeof *c->cell_of);
    c->slot_of = malloc(npoints * sizeof *c->slot_of);
    if (!c->count || !c->id || !c->pos || !c->cell_of || !c->slot_of) return -1;
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
    free(c->count);
    free(c->id);
    free(c->pos);
    free(c->cell_of);
    free(c->slot_of);
    memset(c, 0, sizeof *c);
}

void hsbd_cells_clear(hsbd_cells *c) {
    memset(c->count, 0, c->ncells * sizeof *c->count);
    for (size_t i = 0; i < c->npoints; ++i)
        c->cell_of[i] = -1;
}

static int axis_cell(const hsbd_cells *c, int a, double x) {
    const double q = x * c->inv_width[a];
    int k = (int)q; /* truncation: floor for the wrapped (non-negative) positions */
    if (q < 0) k = (int)floor(q);
    k %= c->nc[a];
    return k < 0 ? k + c->nc[a] : k;
}

int32_t hsbd_cells_index(const hsbd_cells *c, const double x[3]) {
    const int kx = axis_cell(c, 0, x[0]), ky = axis_cell(c, 1, x[1]);
    const int kz = c->dim == 3 ? axis_cell(c, 2, x[2]) : 0;
    return (int32_t)((kz * c->nc[1] + ky) * c->nc[0] + kx);
}

/* Twice the slots per cell, every cell copied over. */
static int grow(hsbd_cells *c) {
    const uint32_t cap = 2 * c->cap;
    int32_t *id = calloc(c->ncells * cap, sizeof *id);
    double *pos = calloc(3 * c->ncells * cap + 1, sizeof *pos);
    if (!id || !pos) {
        free(id);
        free(pos);
        return -1;
    }
    for (size_t k = 0; k < c->ncells; ++k) {
        memcpy(id + k * cap, c->id + k * c->cap, c->count[k] * sizeof *id);
        memcpy(pos + 3 * k * cap, c->pos + 3 * k * c->cap, 3 * c->count[k] * sizeof *pos);
    }
    free(c->id);
    free(c->pos);
    c->id = id;
    c->pos = pos;
    c->cap = cap;
    return 0;
}

int hsbd_cells_insert(hsbd_cells *c, int32_t i, const double x[3]) {
    const int32_t k = hsbd_cells_index(c, x);
    if (c->count[k] == c->cap && grow(c)) return -1;
    const uint32_t u = c->count[k]++;
    const size_t slot = (size_t)k * c->cap + u;
    c->id[slot] = i;
    memcpy(c->pos + 3 * slot, x, 3 * sizeof *x);
    c->cell_of[i] = k;
    c->slot_of[i] = (int32_t)u;
    return 0;
}

void hsbd_cells_remove(hsbd_cells *c, int32_t i) {
    const int32_t k = c->cell_of[i];
    if (k < 0) return;
    const size_t base = (size_t)k * c->cap, slot = base + (uint32_t)c->slot_of[i];
    const size_t last = base + --c->count[k];
    if (slot != last) { /* the last point fills the hole */
        const int32_t moved = c->id[last];
        c->id[slot] = moved;
        memcpy(c->pos + 3 * slot, c->pos + 3 * last, 3 * sizeof *c->pos);
        c->slot_of[moved] = c->slot_of[i];
    }
    c->cell_of[i] = -1;
}

/* k + d (d = -1, 0, 1) on a periodic axis of n cells */
static inline int axis_step(int k, int d, int n) {
    k += d;
    return k < 0 ? k + n : k >= n ? k - n : k;
}

int hsbd_cells_around(const hsbd_cells *c, const double x[3], int32_t out[27]) {
    int kc[3] = {axis_cell(c, 0, x[0]), axis_cell(c, 1, x[1]), 0};
    if (c->dim == 3) kc[2] = axis_cell(c, 2, x[2]);
    int count = 0;
    const int zr = c->dim == 3 ? 1 : 0;
    for (int dz = -zr; dz <= zr; ++dz) {
        const int kz = axis_step(kc[2], dz, c->nc[2]);
        for (int dy = -1; dy <= 1; ++dy) {
            const int ky = axis_step(kc[1], dy, c->nc[1]);
            for (int dx = -1; dx <= 1; ++dx) {
                const int kx = axis_step(kc[0], dx, c->nc[0]);
                const int32_t k = (int32_t)((kz * c->nc[1] + ky) * c->nc[0] + kx);
                int seen = 0;
                for (int q = 0; q < count && c->few && !seen; ++q)
                    seen = out[q] == k;
                if (!seen) out[count++] = k;
            }
        }
    }
    return count;
}
