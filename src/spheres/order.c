/* Spatial order of the particles in memory (internal to src/spheres).
 *
 * Every part of a step that is not a stream over the particles (the collisions, the shell
 * updates, the half scan's neighbour reads) jumps to a particle and then to its
 * neighbours. When neighbours in space are far apart in memory each of those reads is a
 * cache miss, and above a few 10^4 particles the step waits on memory. So the engine
 * keeps its per-particle arrays in the Morton (Z-curve) order of the cells, re-sorted
 * whenever the particles could have moved about half a cell since the last sort; the
 * neighbour lists and cells are renumbered, not rebuilt, so the shells stay put. The
 * user never sees this order: label[i] is the user's index of internal particle i, the
 * noise is drawn by label, and views and parameters show the user's order. */
#include <stdlib.h>
#include <string.h>

#include "spheres/neighbours.h"
#include "spheres/order.h"

/* The slab (of `slabs` along `axis`) holding the middle of cell k. */
static int slab_of_cell(const hsbd_cells *c, int slabs, int axis, size_t stride, size_t k) {
    const size_t index = k / stride % (size_t)c->nc[axis];
    return (int)(((double)index + 0.5) * slabs / c->nc[axis]);
}

/* Ranks ordered by the slab of each cell first, the given rank second. Returns 0, or -1
 * when out of memory. */
static int group_by_slab(const hsbd_cells *c, int slabs, int axis, int32_t *rank) {
    size_t start[SPH_MAX_SLABS + 1] = {0};
    const size_t ncells = c->ncells, stride = axis == 0   ? 1
                                              : axis == 1 ? (size_t)c->nc[0]
                                                          : (size_t)c->nc[0] * c->nc[1];
    for (size_t k = 0; k < ncells; ++k)
        start[slab_of_cell(c, slabs, axis, stride, k) + 1]++;
    for (int b = 0; b < slabs; ++b)
        start[b + 1] += start[b];
    int32_t *cell_at = malloc(ncells * sizeof *cell_at); /* the cells in rank order */
    if (!cell_at) return -1;
    for (size_t k = 0; k < ncells; ++k)
        cell_at[rank[k]] = (int32_t)k;
    for (size_t r = 0; r < ncells; ++r) {
        const size_t k = (size_t)cell_at[r];
        rank[k] = (int32_t)start[slab_of_cell(c, slabs, axis, stride, k)]++;
    }
    free(cell_at);
    return 0;
}

/* Rank of each cell along the Z curve through the grid (cells outside the grid of the
 * next power-of-two size are skipped); with the groups' slabs, slab by slab (a stable
 * sort of the curve by the slab of each cell's middle), so that the first pass of the
 * groups sweeps memory slab after slab. */
static int32_t *morton_cell_ranks(const hsbd_cells *c, int dim, int slabs, int axis) {
    int32_t *rank = malloc(c->ncells * sizeof *rank);
    if (!rank) return NULL;
    int bits = 0;
    while ((1 << bits) < c->nc[0] || (1 << bits) < c->nc[1] || (1 << bits) < c->nc[2])
        ++bits;
    const uint64_t codes = (uint64_t)1 << (dim * bits);
    int32_t next = 0;
    for (uint64_t code = 0; code < codes; ++code) {
        int k[3] = {0, 0, 0};
        for (int b = 0; b < bits; ++b)
            for (int a = 0; a < dim; ++a)
                k[a] |= (int)((code >> (dim * b + a)) & 1u) << b;
        if (k[0] >= c->nc[0] || k[1] >= c->nc[1] || k[2] >= c->nc[2]) continue;
        rank[((size_t)k[2] * (size_t)c->nc[1] + (size_t)k[1]) * (size_t)c->nc[0] + (size_t)k[0]] =
            next++;
    }
    if (slabs && group_by_slab(c, slabs, axis, rank)) {
        free(rank);
        return NULL;
    }
    return rank;
}

/* new_to_old: internal particle k after the sort is particle new_to_old[k] before it.
 * Stable counting sort by the Z-curve rank of each particle's cell. */
static int spatial_permutation(hsbd_spheres *s, int32_t *new_to_old) {
    const size_t n = s->n, nc = s->cells.ncells;
    int axis, slabs = sph_slabs(s, &axis);
    if (!s->cell_rank && !(s->cell_rank = morton_cell_ranks(&s->cells, s->dim, slabs, axis)))
        return -1;
    uint32_t *start = calloc(nc + 1, sizeof *start);
    int32_t *rank_of = malloc(n * sizeof *rank_of);
    if (!start || !rank_of) {
        free(start);
        free(rank_of);
        return -1;
    }
    for (size_t i = 0; i < n; ++i) {
        rank_of[i] = s->cell_rank[hsbd_cells_index(&s->cells, s->x + 3 * i)];
        start[rank_of[i] + 1]++;
    }
    for (size_t r = 0; r < nc; ++r)
        start[r + 1] += start[r];
    for (size_t i = 0; i < n; ++i)
        new_to_old[start[rank_of[i]]++] = (int32_t)i;
    free(start);
    free(rank_of);
    return 0;
}

/* The per-particle arrays that outlive a step, in one table. */
typedef struct {
    void *array;
    size_t bytes; /* per particle: 4, 8 or 24 */
} per_particle;

enum { PER_PARTICLE_ARRAYS = 14 }; /* most entries of per_particle_table */

static size_t per_particle_table(hsbd_spheres *s, per_particle *t) {
    size_t k = 0;
    t[k++] = (per_particle){s->x, 3 * sizeof *s->x};
    t[k++] = (per_particle){s->image, 3 * sizeof *s->image};
    t[k++] = (per_particle){s->counter, sizeof *s->counter};
    t[k++] = (per_particle){s->sigma, sizeof *s->sigma};
    t[k++] = (per_particle){s->diffusion, sizeof *s->diffusion};
    t[k++] = (per_particle){s->noise_amp, sizeof *s->noise_amp};
    t[k++] = (per_particle){s->species, sizeof *s->species};
    t[k++] = (per_particle){s->label, sizeof *s->label};
    t[k++] = (per_particle){s->centre, 3 * sizeof *s->centre};
    t[k++] = (per_particle){s->cells.cell_of, sizeof *s->cells.cell_of};
    t[k++] = (per_particle){s->cells.slot_of, sizeof *s->cells.slot_of};
    if (s->drift_mu) t[k++] = (per_particle){s->drift_mu, sizeof *s->drift_mu};
    if (s->nb) {
        t[k++] = (per_particle){s->nb_count, sizeof *s->nb_count};
        t[k++] = (per_particle){s->nb_upper, sizeof *s->nb_upper};
    }
    return k;
}

/* array[k] = array[new_to_old[k]] for elements of `bytes` (4, 8 or 24), through scratch
 * (room for n elements of 24 bytes). */
static void permute_array(void *array, size_t bytes, size_t n, const int32_t *new_to_old,
                          void *scratch) {
    if (bytes == 4) {
        const uint32_t *from = array;
        uint32_t *to = scratch;
        for (size_t k = 0; k < n; ++k)
            to[k] = from[new_to_old[k]];
    } else if (bytes == 8) {
        const uint64_t *from = array;
        uint64_t *to = scratch;
        for (size_t k = 0; k < n; ++k)
            to[k] = from[new_to_old[k]];
    } else { /* three doubles or three int64 */
        const uint64_t *from = array;
        uint64_t *to = scratch;
        for (size_t k = 0; k < n; ++k)
            memcpy(to + 3 * k, from + 3 * (size_t)new_to_old[k], 3 * sizeof *to);
    }
    memcpy(array, scratch, n * bytes);
}

/* Every row, where it is, with the new indices and its neighbours j > i first (i's new
 * index), the rest after them in the reverse of their order; nb_upper[old] the count of
 * the first. tmp: room for a row. */
static void renumber_rows(hsbd_spheres *s, const int32_t *old_to_new, int32_t *tmp) {
    const size_t cap = s->nb_cap;
    for (size_t old = 0; old < s->n; ++old) {
        int32_t *row = s->nb + old * cap;
        const int32_t k = old_to_new[old];
        const uint32_t c = s->nb_count[old];
        memcpy(tmp, row, c * sizeof *row);
        uint32_t up = 0, low = c;
        for (uint32_t q = 0; q < c; ++q) {
            const int32_t j = old_to_new[tmp[q]];
            if (j > k)
                row[up++] = j;
            else
                row[--low] = j;
        }
        s->nb_upper[old] = up;
    }
}

/* Row k takes the row new_to_old[k] was, cycle by cycle of the permutation (moved: a bit
 * per row, zero on entry; tmp: room for a row). Only the entries in use move; the counts
 * move with the other per-particle arrays. */
static void move_rows(hsbd_spheres *s, const int32_t *new_to_old, uint64_t *moved, int32_t *tmp) {
    const size_t cap = s->nb_cap;
    for (size_t start = 0; start < s->n; ++start) {
        if (moved[start / 64] >> (start % 64) & 1 || (size_t)new_to_old[start] == start) continue;
        memcpy(tmp, s->nb + start * cap, s->nb_count[start] * sizeof *tmp);
        size_t at = start;
        for (;;) {
            moved[at / 64] |= (uint64_t)1 << (at % 64);
            const size_t from = (size_t)new_to_old[at];
            if (from == start) {
                memcpy(s->nb + at * cap, tmp, s->nb_count[from] * sizeof *s->nb);
                break;
            }
            memcpy(s->nb + at * cap, s->nb + from * cap, s->nb_count[from] * sizeof *s->nb);
            at = from;
        }
    }
}

/* The cells' point indices renumbered. */
static void renumber_cells(hsbd_spheres *s, const int32_t *old_to_new) {
    for (size_t cell = 0; cell < s->cells.ncells; ++cell)
        for (uint32_t u = 0; u < hsbd_cells_count(&s->cells, (int32_t)cell); ++u) {
            int32_t *id = hsbd_cells_id_slot(&s->cells, (int32_t)cell, u);
            *id = old_to_new[*id];
        }
}

/* Applies new_to_old to every per-particle array, the neighbour lists and the cells
 * (between steps: t_local is 0 and v is redrawn). The shells stay where they are, so the
 * run goes on as if nothing had moved. Everything moves in place, through x_start (which
 * only a step uses) and a few small buffers: a sort that took fresh arrays and freed the
 * old ones cost, at N 10^6, two to three steps' time in page faults and in the slower step
 * after it (docs/spheres.md). Returns 0, or -1 with nothing changed when out of memory. */
static int permute_particles(hsbd_spheres *s, const int32_t *new_to_old) {
    const size_t n = s->n, rows = s->nb ? n : 0;
    int32_t *old_to_new = malloc(n * sizeof *old_to_new);
    int32_t *tmp = malloc((rows ? s->nb_cap : 1) * sizeof *tmp);
    uint64_t *moved = calloc(rows / 64 + 1, sizeof *moved);
    void *own = s->x_start ? NULL : malloc(3 * n * sizeof *s->x);
    void *scratch = s->x_start ? (void *)s->x_start : own;
    if (!old_to_new || !tmp || !moved || !scratch) {
        free(old_to_new), free(tmp), free(moved), free(own);
        return -1;
    }
    for (size_t k = 0; k < n; ++k)
        old_to_new[new_to_old[k]] = (int32_t)k;
    if (rows) {
        renumber_rows(s, old_to_new, tmp);
        move_rows(s, new_to_old, moved, tmp);
        renumber_cells(s, old_to_new);
    }
    per_particle table[PER_PARTICLE_ARRAYS];
    const size_t count = per_particle_table(s, table);
    for (size_t a = 0; a < count; ++a)
        permute_array(table[a].array, table[a].bytes, n, new_to_old, scratch);
    free(old_to_new), free(tmp), free(moved), free(own);
    s->reordered = 0;
    for (size_t k = 0; k < n && !s->reordered; ++k)
        s->reordered = s->label[k] != (int32_t)k;
    s->par.species = s->reordered ? s->user_species : s->species;
    return 0;
}

/* The user's copies of the constant per-particle values, taken while the order is the
 * user's own. */
static void copy_user_constants(hsbd_spheres *s) {
    memcpy(s->user_sigma, s->sigma, s->n * sizeof *s->sigma);
    memcpy(s->user_diffusion, s->diffusion, s->n * sizeof *s->diffusion);
    memcpy(s->user_species, s->species, s->n * sizeof *s->species);
}

int sph_sort_spatially(hsbd_spheres *s) {
    int32_t *new_to_old = malloc(s->n * sizeof *new_to_old);
    if (!new_to_old || spatial_permutation(s, new_to_old)) return free(new_to_old), -1;
    if (!s->reordered) copy_user_constants(s);
    const int rc = permute_particles(s, new_to_old);
    free(new_to_old);
    return rc;
}

int sph_set_order(hsbd_spheres *s, const int32_t *label) {
    if (s->reordered) return -1;
    copy_user_constants(s);
    /* internal particle i becomes the user's particle label[i]: new_to_old is the label */
    return permute_particles(s, label);
}

int sph_restore_user_order(hsbd_spheres *s) {
    if (!s->reordered) return 0;
    int32_t *new_to_old = malloc(s->n * sizeof *new_to_old);
    if (!new_to_old) return -1;
    for (size_t i = 0; i < s->n; ++i)
        new_to_old[s->label[i]] = (int32_t)i;
    const int rc = permute_particles(s, new_to_old);
    free(new_to_old);
    return rc;
}

void sph_fill_user_view(const hsbd_spheres *s) {
    for (size_t i = 0; i < s->n; ++i) {
        const size_t u = (size_t)s->label[i];
        memcpy(s->user_x + 3 * u, s->x + 3 * i, 3 * sizeof *s->x);
        memcpy(s->user_image + 3 * u, s->image + 3 * i, 3 * sizeof *s->image);
    }
}
