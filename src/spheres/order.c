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

/* The per-particle arrays that outlive a step, in one table: the permutation moves them
 * all or, when memory runs out, none. */
typedef struct {
    void **array;
    size_t bytes; /* per particle */
    size_t pad;   /* extra bytes at the end (vector loads past the last particle) */
} per_particle;

enum { PER_PARTICLE_ARRAYS = 12 }; /* most entries of per_particle_table */

static size_t per_particle_table(hsbd_spheres *s, per_particle *t) {
    size_t k = 0;
    t[k++] = (per_particle){(void **)&s->x, 3 * sizeof *s->x, sizeof *s->x};
    t[k++] = (per_particle){(void **)&s->image, 3 * sizeof *s->image, 0};
    t[k++] = (per_particle){(void **)&s->counter, sizeof *s->counter, 0};
    t[k++] = (per_particle){(void **)&s->sigma, sizeof *s->sigma, 0};
    t[k++] = (per_particle){(void **)&s->diffusion, sizeof *s->diffusion, 0};
    t[k++] = (per_particle){(void **)&s->noise_amp, sizeof *s->noise_amp, 0};
    t[k++] = (per_particle){(void **)&s->species, sizeof *s->species, 0};
    t[k++] = (per_particle){(void **)&s->label, sizeof *s->label, 0};
    t[k++] = (per_particle){(void **)&s->centre, 3 * sizeof *s->centre, 0};
    t[k++] = (per_particle){(void **)&s->cells.cell_of, sizeof *s->cells.cell_of, 0};
    t[k++] = (per_particle){(void **)&s->cells.slot_of, sizeof *s->cells.slot_of, 0};
    if (s->drift_mu) t[k++] = (per_particle){(void **)&s->drift_mu, sizeof *s->drift_mu, 0};
    return k;
}

/* The neighbour rows in the new order with the new indices, each row again holding its
 * neighbours j > i first; the cells' point indices renumbered. */
static int permute_neighbours(hsbd_spheres *s, const int32_t *new_to_old,
                              const int32_t *old_to_new) {
    const size_t n = s->n, cap = s->nb_cap;
    int32_t *nb = sph_rows_alloc(n, cap);
    uint32_t *count = malloc(n * sizeof *count), *upper = malloc(n * sizeof *upper);
    if (!nb || !count || !upper) {
        free(nb);
        free(count);
        free(upper);
        return -1;
    }
    for (size_t k = 0; k < n; ++k) {
        const size_t old = (size_t)new_to_old[k];
        const int32_t *from = s->nb + old * cap;
        int32_t *row = nb + k * cap;
        const uint32_t c = s->nb_count[old];
        uint32_t up = 0, low = c;
        for (uint32_t q = 0; q < c; ++q) {
            const int32_t j = old_to_new[from[q]];
            if (j > (int32_t)k)
                row[up++] = j;
            else
                row[--low] = j;
        }
        count[k] = c;
        upper[k] = up;
    }
    free(s->nb);
    free(s->nb_count);
    free(s->nb_upper);
    s->nb = nb;
    s->nb_count = count;
    s->nb_upper = upper;
    for (size_t cell = 0; cell < s->cells.ncells; ++cell)
        for (uint32_t u = 0; u < hsbd_cells_count(&s->cells, (int32_t)cell); ++u) {
            int32_t *id = hsbd_cells_id_slot(&s->cells, (int32_t)cell, u);
            *id = old_to_new[*id];
        }
    return 0;
}

/* Applies new_to_old to every per-particle array, the neighbour lists and the cells
 * (between steps: t_local is 0 and v is redrawn). The shells stay where they are, so the
 * run goes on as if nothing had moved. Returns 0, or -1 with nothing changed when out of
 * memory. */
static int permute_particles(hsbd_spheres *s, const int32_t *new_to_old) {
    per_particle table[PER_PARTICLE_ARRAYS];
    const size_t count = per_particle_table(s, table), n = s->n;
    void *fresh[PER_PARTICLE_ARRAYS];
    size_t ready = 0;
    while (ready < count && (fresh[ready] = calloc(1, n * table[ready].bytes + table[ready].pad)))
        ++ready;
    int32_t *old_to_new = ready == count ? malloc(n * sizeof *old_to_new) : NULL;
    if (old_to_new)
        for (size_t k = 0; k < n; ++k)
            old_to_new[new_to_old[k]] = (int32_t)k;
    if (!old_to_new || permute_neighbours(s, new_to_old, old_to_new)) {
        free(old_to_new);
        while (ready-- > 0)
            free(fresh[ready]);
        return -1;
    }
    free(old_to_new);
    for (size_t a = 0; a < count; ++a) {
        const size_t b = table[a].bytes;
        const char *old = *table[a].array;
        char *out = fresh[a];
        for (size_t k = 0; k < n; ++k)
            memcpy(out + k * b, old + (size_t)new_to_old[k] * b, b);
        free(*table[a].array);
        *table[a].array = fresh[a];
    }
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
