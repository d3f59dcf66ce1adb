#include "spheres/scan.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "spheres/events.h"
#include "spheres/neighbours.h"
#include "spheres/slab_queue.h"

enum { SCAN_CHUNK = 4096 }; /* pairs per kernel call (at least one whole row) */

int sph_threads(const hsbd_spheres *s) {
    return s->threads > 1 && s->n >= SPH_THREADS_MIN_N ? s->threads : 1;
}

void *sph_grow_zeroed(void *parts, size_t count, size_t want, size_t size) { /* want > count */
    unsigned char *grown = realloc(parts, want * size);
    if (grown) memset(grown + count * size, 0, (want - count) * size);
    return grown;
}

size_t sph_range_start(size_t n, int parts, int k) {
    return n * (size_t)k / (size_t)parts; /* n < 2^31, k <= parts <= 1024: no overflow */
}

/* Whether i's straight path from its start leaves the room between the walls: only if
 * its end point does (the room is convex); after the bridge pushes, rarely. */
static int leaves_walls(const hsbd_spheres *s, size_t i) {
    const double *x = s->x + 3 * i, *v = s->v + 3 * i, half = 0.5 * s->sigma[i];
    int out = 0;
    for (int a = 0; a < s->dim; ++a) {
        const double end = x[a] + v[a] * s->dt;
        out |= s->walls[a] & (end < half || end > s->length[a] - half);
    }
    return out;
}

/* Room for the hit buffers of `threads` threads in *parts (*count of them held). Returns
 * 0, or -1 when out of memory. */
static int reserve_parts(sph_hits **parts, size_t *count, int threads) {
    if ((size_t)threads <= *count) return 0;
    sph_hits *grown = sph_grow_zeroed(*parts, *count, (size_t)threads, sizeof *grown);
    if (!grown) return -1;
    *parts = grown;
    *count = (size_t)threads;
    return 0;
}

/* Room for `more` hits after the h->len held. Returns 0, or -1 when out of memory. */
static int hits_reserve(sph_hits *h, size_t more) {
    if (h->len + more <= h->cap) return 0;
    size_t cap = h->cap ? 2 * h->cap : 4096;
    while (cap < h->len + more)
        cap *= 2;
    int32_t *i = realloc(h->i, cap * sizeof *i);
    if (i) h->i = i;
    int32_t *j = i ? realloc(h->j, cap * sizeof *j) : NULL;
    if (j) h->j = j;
    double *t = j ? realloc(h->t, cap * sizeof *t) : NULL;
    if (!t) return -1;
    h->t = t;
    h->cap = cap;
    return 0;
}

static int hits_add(sph_hits *h, double t, int32_t i, int32_t j) {
    if (hits_reserve(h, 1)) return -1;
    h->i[h->len] = i;
    h->j[h->len] = j;
    h->t[h->len++] = t;
    return 0;
}

/* The flags of particles [i0, i1), and into h their start-of-step events in particle
 * order: the time a path leaves the shell it will have once its shell moved (centred on
 * its start position, sph_move_leaving_shells), and the time it meets a wall. Returns 0,
 * or -1 when out of memory. */
static int flag_range(hsbd_spheres *s, size_t i0, size_t i1, sph_hits *h) {
    const double dt = s->dt, r2 = s->shell * s->shell;
    h->len = 0;
    for (size_t i = i0; i < i1; ++i) {
        double d[3];
        sph_min_image(s, s->x + 3 * i, s->centre + 3 * i, d);
        const double *v = s->v + 3 * i;
        const double e[3] = {d[0] + v[0] * dt, d[1] + v[1] * dt, d[2] + v[2] * dt};
        uint8_t flag = hsbd_dot3(e, e) > r2 ? SPH_LEAVES_SHELL : 0;
        if (s->any_walls && leaves_walls(s, i)) flag |= SPH_LEAVES_WALLS;
        s->start_flag[i] = flag;
        if (flag & SPH_LEAVES_SHELL) {
            double c[3];
            sph_centre_for(s, s->x + 3 * i, c);
            const double exit = sph_shell_exit_from(s, (int32_t)i, 0.0, c);
            if (exit >= 0 && hits_add(h, exit, (int32_t)i, SPH_EVENT_SHELL)) return -1;
        }
        if (flag & SPH_LEAVES_WALLS) {
            int wall = 0;
            const double contact = sph_wall_time(s, (int32_t)i, 0.0, &wall);
            if (contact >= 0 && hits_add(h, contact, (int32_t)i, sph_wall_event(wall))) return -1;
        }
    }
    return 0;
}

int sph_scan_leaving(hsbd_spheres *s, int threads) {
    if (reserve_parts(&s->exit_parts, &s->exit_nparts, threads)) return -1;
    int failed = 0;
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)                 \
    reduction(|                                                                                    \
              : failed)
    for (int k = 0; k < threads; ++k)
        failed |= flag_range(s, sph_range_start(s->n, threads, k),
                             sph_range_start(s->n, threads, k + 1), &s->exit_parts[k]) != 0;
    return failed ? -1 : 0;
}

/* ---- the shells that move at the start of a step ----
 * A shell moved from its centre c to its particle's position (closer than `shell`) edits
 * the rows of the shells within reach of either centre (sigma_ij + 2 shell, less than a
 * cell width w) and its old and new cells, and reads the cells around the new centre:
 * all of it lies within m = shell + 2 w of c along the slab axis. The box is cut into an
 * even number of slabs at least 2 m wide, and every slab moves the shells whose centres
 * it holds, in particle order; then two even slabs touch disjoint rows and cells, and so
 * do two odd ones. Every even slab moves its shells before its odd neighbours: each row
 * and cell sees the same edits in the same order for any number of threads. Threads take
 * the even slabs, then each odd one once its two neighbours are done (slab_queue.h; no
 * barrier between the parities, which with three slabs of a parity on two threads left one
 * idle half the time); one thread takes them in the order 0, 2, 1, 4, 3, ..., which
 * gives the same edits and sweeps the box once (two sweeps cost it 15 % more of the
 * shells' time). OpenMP tasks with dependences would do the same, but with them
 * LeakSanitizer found memory of gcc 12's libgomp still held at exit. */

enum { SHELL_SLABS_MAX = SPH_SLAB_QUEUE_MAX }; /* even */

/* The slabs' number along *axis: even, at least 4 (fewer could not work side by side),
 * or 0 (particle order). */
static int shell_slabs(const hsbd_spheres *s, int *axis) {
    *axis = sph_slab_axis(s);
    if (*axis < 0) return 0;
    const double length = s->box[*axis], cell = length / s->cells.nc[*axis];
    const int n = 2 * (int)floor(length / (2 * 1.01 * 2 * (s->shell + 2 * cell)));
    return n < 4 ? 0 : n < SHELL_SLABS_MAX ? n : SHELL_SLABS_MAX;
}

/* The slab of i's shell centre, or nslabs when i's position is farther than `shell` from
 * it along the axis (not expected: every particle starts a step inside its shell). */
static int shell_slab(const hsbd_spheres *s, int axis, int nslabs, int32_t i) {
    const double c = s->centre[3 * (size_t)i + axis];
    if (fabs(hsbd_wrap_delta(s->x[3 * (size_t)i + axis] - c, s->box[axis])) > s->shell)
        return nslabs;
    const int k = (int)(c * nslabs / s->box[axis]); /* the centre is wrapped into the box */
    return k < nslabs ? k : nslabs - 1;
}

/* The flagged particles into s->leaving slab by slab, in particle order within a slab;
 * slab k's are first[k] .. first[k + 1] - 1, the strays (slab nslabs) last. */
static void sort_leaving(hsbd_spheres *s, int axis, int nslabs, size_t first[]) {
    size_t count[SHELL_SLABS_MAX + 1] = {0};
    for (size_t i = 0; i < s->n; ++i)
        if (s->start_flag[i] & SPH_LEAVES_SHELL) count[shell_slab(s, axis, nslabs, (int32_t)i)]++;
    first[0] = 0;
    for (int k = 0; k <= nslabs; ++k)
        first[k + 1] = first[k] + count[k];
    for (int k = 0; k <= nslabs; ++k)
        count[k] = first[k];
    for (size_t i = 0; i < s->n; ++i)
        if (s->start_flag[i] & SPH_LEAVES_SHELL)
            s->leaving[count[shell_slab(s, axis, nslabs, (int32_t)i)]++] = (int32_t)i;
}

/* Beyond the caches (SPH_PREFETCH_MIN_N) a shell move waits on loads whose addresses
 * come from other loads: its neighbours' rows from its own row, the cells from its
 * position. So the data are asked for in two stages: the own row, count and position of
 * the move SHELL_ROWS_AHEAD places ahead, then, once they are in cache, the neighbours'
 * rows and the cells around the new centre of the move SHELL_NEIGHBOURS_AHEAD ahead.
 * Hints only: no result changes. Always inlined (see groups.c). */
enum { SHELL_ROWS_AHEAD = 8, SHELL_NEIGHBOURS_AHEAD = 3 };

static inline __attribute__((always_inline)) void prefetch_shell_own(const hsbd_spheres *s,
                                                                     int32_t i) {
    sph_prefetch_row(s, i);
    __builtin_prefetch(s->nb_count + i);
    __builtin_prefetch(s->x + 3 * (size_t)i);
    __builtin_prefetch(s->cells.cell_of + i);
}

static inline __attribute__((always_inline)) void prefetch_shell_around(const hsbd_spheres *s,
                                                                        int32_t i) {
    const int32_t *row = s->nb + (size_t)i * s->nb_cap;
    for (uint32_t q = 0; q < s->nb_count[i]; ++q) {
        const int32_t *other = s->nb + (size_t)row[q] * s->nb_cap; /* loses i: written */
        __builtin_prefetch(other, 1);
        __builtin_prefetch(other + 15, 1); /* its first 16 entries, as sph_prefetch_row */
        __builtin_prefetch(s->nb_count + row[q], 1);
    }
    int32_t around[27];
    const hsbd_cells *c = &s->cells;
    const int nc = hsbd_cells_around(c, s->x + 3 * (size_t)i, around);
    for (int k = 0; k < nc; ++k) {
        const char *record = (const char *)(c->cell + around[k]);
        __builtin_prefetch(record); /* both lines of the record: the first chunk and count */
        __builtin_prefetch(record + 64);
    }
}

/* Moves the shells of s->leaving[from .. to) in order; the first is already lifted when
 * `lifted`. Without `may_grow` it stops before a pair or a point that would need a full row
 * or cell to grow, that particle lifted. Returns the position reached (to when done), or
 * -1 when out of memory; *moved counts the shells lifted. */
static long move_shells(hsbd_spheres *s, size_t from, size_t to, int lifted, int may_grow,
                        sph_near *near, uint64_t *moved) {
    const int ahead = s->n >= SPH_PREFETCH_MIN_N;
    for (size_t q = from; q < to; ++q) {
        const int32_t i = s->leaving[q];
        if (ahead && q + SHELL_ROWS_AHEAD < to)
            prefetch_shell_own(s, s->leaving[q + SHELL_ROWS_AHEAD]);
        if (ahead && q + SHELL_NEIGHBOURS_AHEAD < to)
            prefetch_shell_around(s, s->leaving[q + SHELL_NEIGHBOURS_AHEAD]);
        if (!(lifted && q == from)) {
            sph_shell_lift(s, i, s->x + 3 * (size_t)i);
            (*moved)++;
        }
        uint32_t found;
        if (sph_shells_near(s, &s->cells, s->sigma, i, near, &found)) return -1;
        if (!may_grow && !sph_shell_fits(s, i, near->id, found)) return (long)q;
        if (sph_shell_land(s, i, near->id, found)) return -1;
    }
    return (long)to;
}

/* The q-th slab to take: 0, 2, 1, 4, 3, ..., nslabs - 2, nslabs - 3, nslabs - 1. */
static int wave_slab(int q, int nslabs) {
    return q == 0 || q == nslabs - 1 ? q : q % 2 ? q + 1 : q - 1;
}

int sph_move_leaving_shells(hsbd_spheres *s, int threads) {
    int axis;
    const int nslabs = shell_slabs(s, &axis);
    if (!nslabs) { /* one slab: particle order */
        for (size_t i = 0; i < s->n; ++i)
            if ((s->start_flag[i] & SPH_LEAVES_SHELL) && sph_recentre(s, (int32_t)i, s->x + 3 * i))
                return -1;
        return 0;
    }
    if ((size_t)nslabs > s->near_nparts) { /* a buffer of points found for each slab */
        sph_near *parts =
            sph_grow_zeroed(s->near_parts, s->near_nparts, (size_t)nslabs, sizeof *parts);
        if (!parts) return -1;
        s->near_parts = parts;
        s->near_nparts = (size_t)nslabs;
    }
    size_t first[SHELL_SLABS_MAX + 2];
    sort_leaving(s, axis, nslabs, first);
    long reached[SHELL_SLABS_MAX];
    uint64_t moved[SHELL_SLABS_MAX] = {0};
    if (threads == 1) { /* one sweep: 0, 2, 1, 4, 3, ... (an odd slab after both neighbours) */
        for (int q = 0; q < nslabs; ++q) {
            const int k = wave_slab(q, nslabs);
            reached[k] = move_shells(s, first[k], first[k + 1], 0, 0, &s->near_parts[k], &moved[k]);
        }
    } else { /* even slabs first, an odd one after its neighbours: the same edits, in order */
        sph_slab_queue queue;
        sph_slab_queue_start(&queue, nslabs);
#pragma omp parallel num_threads(threads)
        for (int k; (k = sph_slab_queue_take(&queue)) >= 0;) {
            reached[k] = move_shells(s, first[k], first[k + 1], 0, 0, &s->near_parts[k], &moved[k]);
            sph_slab_queue_finish(&queue, k, 0); /* a failure is handled below, as before */
        }
    }
    uint64_t total = 0;
    for (int q = 0; q < nslabs; ++q) { /* the slabs stopped by a full row or cell, in order */
        const int k = wave_slab(q, nslabs);
        if (reached[k] < 0) return -1;
        if ((size_t)reached[k] < first[k + 1] &&
            move_shells(s, (size_t)reached[k], first[k + 1], 1, 1, &s->near, &moved[k]) < 0)
            return -1;
        total += moved[k];
    }
    if (move_shells(s, first[nslabs], first[nslabs + 1], 0, 1, &s->near, &total) < 0) return -1;
    s->stats.shell_updates += total;
    return 0;
}

/* The hits of rows [i0, i1) appended to h in row order. Returns 0, or -1. */
static int scan_rows(const hsbd_spheres *s, const sph_scan_query *q, size_t i0, size_t i1,
                     sph_hits *h) {
    for (size_t a = i0; a < i1;) {
        size_t b = a, pairs = 0;
        while (b < i1 && (b == a || pairs + s->nb_upper[b] <= SCAN_CHUNK))
            pairs += s->nb_upper[b++];
        if (hits_reserve(h, pairs)) return -1;
        h->len += s->half_scan(q, a, b, h->i + h->len, h->j + h->len, h->t + h->len);
        a = b;
    }
    return 0;
}

int sph_scan_pairs(hsbd_spheres *s, int threads) {
    if (reserve_parts(&s->hit_parts, &s->hit_nparts, threads)) return -1;
    const sph_scan_query q = {.x = s->x,
                              .v = s->v,
                              .sigma = s->sigma,
                              .nb = s->nb,
                              .nb_upper = s->nb_upper,
                              .nb_cap = s->nb_cap,
                              .box = {s->box[0], s->box[1], s->box[2]},
                              .tmax = s->dt};
    int failed = 0;
#pragma omp parallel for schedule(static, 1) num_threads(threads) if (threads > 1)                 \
    reduction(|                                                                                    \
              : failed)
    for (int k = 0; k < threads; ++k) {
        sph_hits *h = &s->hit_parts[k];
        h->len = 0;
        failed |= scan_rows(s, &q, sph_range_start(s->n, threads, k),
                            sph_range_start(s->n, threads, k + 1), h) != 0;
    }
    return failed ? -1 : 0;
}
