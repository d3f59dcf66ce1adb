/* Neighbour shells (internal to src/spheres): every particle owns a shell of radius
 * `shell` around a centre fixed at its last update, and i, j are neighbours when their
 * shells overlap, |c_i - c_j| < sigma_ij + 2 shell. The symmetric rows (j > i first), the
 * cell grid of the centres, re-centring one shell, and a full rebuild. */
#include "spheres/neighbours.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include <stdlib.h>
#include <string.h>

/* The next row capacity: about 1.5 times, a multiple of 4 and never a power of two from 32
 * on. Rows 128 or 256 bytes apart ran 25-30 % slower at N = 1e5 than rows of 96 to 192
 * bytes (bench/RESULTS.md); the first overflow came within a few hundred steps. */
static uint32_t nb_next_cap(uint32_t cap) {
    uint32_t next = cap + (cap / 2 + 3) / 4 * 4;
    if ((next & (next - 1)) == 0) next += 4;
    return next;
}

int32_t *sph_rows_alloc(size_t n, uint32_t cap) {
    const size_t line = 64, bytes = n * cap * sizeof(int32_t);
    return aligned_alloc(line, bytes ? (bytes + line - 1) / line * line : line); /* whole lines */
}

static int nb_grow(hsbd_spheres *s) {
    const uint32_t cap = nb_next_cap(s->nb_cap);
    if (cap > s->scan_cap) { /* a row's scan takes the whole row */
        int32_t *sj = realloc(s->scan_j, cap * sizeof *sj);
        if (sj) s->scan_j = sj;
        double *st = realloc(s->scan_t, cap * sizeof *st);
        if (st) s->scan_t = st;
        if (!sj || !st) return -1;
        s->scan_cap = cap;
    }
    int32_t *nb = sph_rows_alloc(s->n, cap);
    if (!nb) return -1;
    for (size_t i = 0; i < s->n; ++i)
        memcpy(nb + i * cap, s->nb + i * s->nb_cap, s->nb_count[i] * sizeof *nb);
    free(s->nb);
    s->nb = nb;
    s->nb_cap = cap;
    return 0;
}

/* Row i holds its neighbours j > i first (nb_upper of them), then the others: the
 * per-step half scan then runs without a branch per entry. */
int sph_nb_add(hsbd_spheres *s, int32_t i, int32_t j) {
    if (s->nb_count[i] == s->nb_cap && nb_grow(s)) return -1;
    int32_t *row = s->nb + (size_t)i * s->nb_cap;
    const uint32_t c = s->nb_count[i]++;
    if (j > i) {
        const uint32_t up = s->nb_upper[i]++;
        row[c] = row[up];
        row[up] = j;
    } else {
        row[c] = j;
    }
    return 0;
}

/* The place of j in the row's first c entries (it is there at most once), or c. */
static uint32_t row_find(const int32_t *row, uint32_t c, int32_t j) {
#if defined(__SSE2__)
    if (c <= 16) { /* a row has room for at least 16 entries: four vector compares */
        const __m128i want = _mm_set1_epi32(j);
        unsigned at = 0;
        for (int q = 0; q < 4; ++q) {
            const __m128i e = _mm_loadu_si128((const __m128i *)(const void *)(row + 4 * q));
            at |= (unsigned)_mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(e, want))) << (4 * q);
        }
        at &= (1u << c) - 1u; /* entries past the count are stale */
        return at ? (uint32_t)__builtin_ctz(at) : c;
    }
#endif
    uint32_t k = c;
    for (uint32_t q = 0; q < c; ++q) /* no early exit: the position is unpredictable */
        k = row[q] == j ? q : k;
    return k;
}

void sph_nb_remove(hsbd_spheres *s, int32_t i, int32_t j) {
    int32_t *row = s->nb + (size_t)i * s->nb_cap;
    const uint32_t c = s->nb_count[i];
    const uint32_t k = row_find(row, c, j);
    if (k == c) return;
    if (j > i) { /* keep the partition: last upper entry fills the hole */
        const uint32_t up = --s->nb_upper[i];
        row[k] = row[up];
        row[up] = row[c - 1];
    } else {
        row[k] = row[c - 1];
    }
    s->nb_count[i] = c - 1;
}

int sph_shells_near(hsbd_spheres *s, const hsbd_cells *cells, const double *point_sigma, int32_t i,
                    sph_near *out, uint32_t *found) {
    const size_t room = 27 * (size_t)hsbd_cells_room(cells) + SPH_NEAR_PAD;
    if (room > out->cap) {
        int32_t *id = realloc(out->id, room * sizeof *id);
        if (!id) return -1;
        out->id = id;
        out->cap = room;
    }
    const double *ci = s->centre + 3 * (size_t)i;
    int32_t around[27];
    const int nc = hsbd_cells_around(cells, ci, around);
    const double base = 0.5 * s->sigma[i] + sph_shell_reach(s); /* + sigma_j / 2 */
    const double *sigma = s->one_sigma ? NULL : point_sigma;    /* one diameter: none to read */
    *found = s->cells_near(cells, around, nc, ci, s->box, sigma,
                           sigma ? base : base + 0.5 * s->sigma_max, out->id);
    return 0;
}

void sph_shell_lift(hsbd_spheres *s, int32_t i, const double x[3]) {
    const int32_t *row = s->nb + (size_t)i * s->nb_cap;
    for (uint32_t k = 0; k < s->nb_count[i]; ++k)
        sph_nb_remove(s, row[k], i);
    s->nb_count[i] = s->nb_upper[i] = 0;
    hsbd_cells_remove(&s->cells, i);
    sph_set_centre(s, i, x);
}

int sph_shell_fits(const hsbd_spheres *s, int32_t i, const int32_t *near, uint32_t found) {
    int fits = found <= s->nb_cap &&
               hsbd_cells_count(&s->cells, hsbd_cells_index(&s->cells, s->centre + 3 * (size_t)i)) <
                   hsbd_cells_room(&s->cells);
    for (uint32_t k = 0; k < found; ++k) /* no early exit: almost every row has room */
        fits &= s->nb_count[near[k]] < s->nb_cap;
    return fits;
}

int sph_shell_land(hsbd_spheres *s, int32_t i, const int32_t *near, uint32_t found) {
    for (uint32_t k = 0; k < found; ++k)
        if (sph_nb_add(s, i, near[k]) || sph_nb_add(s, near[k], i)) return -1;
    return hsbd_cells_insert(&s->cells, i, s->centre + 3 * (size_t)i);
}

/* Adds i's pairs with the points in the cells whose shells overlap i's, |c_i - c_j| <
 * sigma_ij + 2 shell (j > i only), to both rows. */
static int add_upper_neighbours(hsbd_spheres *s, int32_t i) {
    uint32_t found;
    if (sph_shells_near(s, &s->cells, s->sigma, i, &s->near, &found)) return -1;
    for (uint32_t k = 0; k < found; ++k) {
        const int32_t j = s->near.id[k];
        if (j > i && (sph_nb_add(s, i, j) || sph_nb_add(s, j, i))) return -1;
    }
    return 0;
}

int sph_recentre(hsbd_spheres *s, int32_t i, const double x[3]) {
    sph_shell_lift(s, i, x);
    s->stats.shell_updates++;
    uint32_t found;
    if (sph_shells_near(s, &s->cells, s->sigma, i, &s->near, &found)) return -1;
    return sph_shell_land(s, i, s->near.id, found);
}

int sph_rebuild_rows(hsbd_spheres *s) {
    if (!s->par.hard_core) return HSBD_OK;
    hsbd_cells_clear(&s->cells);
    for (size_t i = 0; i < s->n; ++i)
        s->nb_count[i] = s->nb_upper[i] = 0;
    s->nb_stale = 1; /* until every pair is in */
    for (size_t i = 0; i < s->n; ++i)
        if (hsbd_cells_insert(&s->cells, (int32_t)i, s->centre + 3 * i)) return HSBD_ENOMEM;
    for (size_t i = 0; i < s->n; ++i)
        if (add_upper_neighbours(s, (int32_t)i)) return HSBD_ENOMEM;
    s->nb_stale = 0;
    return HSBD_OK;
}

int sph_rebuild_neighbours(hsbd_spheres *s) {
    if (!s->par.hard_core) return HSBD_OK;
    for (size_t i = 0; i < s->n; ++i)
        sph_set_centre(s, (int32_t)i, s->x + 3 * i);
    return sph_rebuild_rows(s);
}
