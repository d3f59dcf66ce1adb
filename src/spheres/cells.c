#include "spheres/cells.h"

#include <math.h>
#include <stdlib.h>

int sph_cells_init(sph_cells *c, int dim, const double box[3], double min_size, size_t npoints) {
    c->dim = dim;
    c->ncells = 1;
    c->few = 0;
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
    c->head = malloc(c->ncells * sizeof *c->head);
    c->next = malloc(npoints * sizeof *c->next);
    c->prev = malloc(npoints * sizeof *c->prev);
    c->cell_of = malloc(npoints * sizeof *c->cell_of);
    if (!c->head || !c->next || !c->prev || !c->cell_of) return -1;
    for (size_t i = 0; i < npoints; ++i)
        c->cell_of[i] = -1;
    sph_cells_clear(c);
    return 0;
}

void sph_cells_free(sph_cells *c) {
    free(c->head);
    free(c->next);
    free(c->prev);
    free(c->cell_of);
}

void sph_cells_clear(sph_cells *c) {
    for (size_t k = 0; k < c->ncells; ++k)
        c->head[k] = -1;
}

static int axis_cell(const sph_cells *c, int a, double x) {
    const double q = x * c->inv_width[a];
    int k = (int)q; /* truncation: floor for the wrapped (non-negative) positions */
    if (q < 0) k = (int)floor(q);
    k %= c->nc[a];
    return k < 0 ? k + c->nc[a] : k;
}

int32_t sph_cells_index(const sph_cells *c, const double x[3]) {
    const int kx = axis_cell(c, 0, x[0]), ky = axis_cell(c, 1, x[1]);
    const int kz = c->dim == 3 ? axis_cell(c, 2, x[2]) : 0;
    return (int32_t)((kz * c->nc[1] + ky) * c->nc[0] + kx);
}

void sph_cells_insert(sph_cells *c, int32_t i, const double x[3]) {
    const int32_t k = sph_cells_index(c, x);
    c->cell_of[i] = k;
    c->prev[i] = -1;
    c->next[i] = c->head[k];
    if (c->head[k] >= 0) c->prev[c->head[k]] = i;
    c->head[k] = i;
}

void sph_cells_remove(sph_cells *c, int32_t i) {
    const int32_t k = c->cell_of[i];
    if (k < 0) return;
    if (c->prev[i] >= 0)
        c->next[c->prev[i]] = c->next[i];
    else
        c->head[k] = c->next[i];
    if (c->next[i] >= 0) c->prev[c->next[i]] = c->prev[i];
    c->cell_of[i] = -1;
}

int sph_cells_around(const sph_cells *c, const double x[3], int32_t out[27]) {
    int kc[3] = {axis_cell(c, 0, x[0]), axis_cell(c, 1, x[1]), 0};
    if (c->dim == 3) kc[2] = axis_cell(c, 2, x[2]);
    int count = 0;
    const int zr = c->dim == 3 ? 1 : 0;
    for (int dz = -zr; dz <= zr; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                const int kx = (kc[0] + dx + c->nc[0]) % c->nc[0];
                const int ky = (kc[1] + dy + c->nc[1]) % c->nc[1];
                const int kz = (kc[2] + dz + c->nc[2]) % c->nc[2];
                const int32_t k = (int32_t)((kz * c->nc[1] + ky) * c->nc[0] + kx);
                int seen = 0;
                for (int q = 0; q < count && c->few && !seen; ++q)
                    seen = out[q] == k;
                if (!seen) out[count++] = k;
            }
    return count;
}
