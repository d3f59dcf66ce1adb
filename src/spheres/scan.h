/* The start of a step on threads (internal to src/spheres): which straight paths leave
 * their shells or the room between the walls, the shells moved for those that leave
 * them, and the half scan of every neighbour pair. The flags and the half scan are split
 * into contiguous ranges of particles, one per thread, and the hits come back range by
 * range, in the order one thread finds them; the shells move slab by slab in an order
 * fixed by the box. So a run does not depend on the number of threads (docs/spheres.md,
 * "Threads"). */
#ifndef HSBD_SPHERES_SCAN_H
#define HSBD_SPHERES_SCAN_H

#include "spheres/state.h"

/* Bits of s->start_flag[i]: i's straight end point leaves its shell, leaves the walls. */
enum { SPH_LEAVES_SHELL = 1, SPH_LEAVES_WALLS = 2 };

/* The threads a loop over the particles uses: run.threads from N = SPH_THREADS_MIN_N on
 * (a parallel region costs a few microseconds), else one. */
enum { SPH_THREADS_MIN_N = 2048 };
int sph_threads(const hsbd_spheres *s);
/* parts, an array of `count` elements of `size` bytes, grown to `want` > count elements,
 * the new ones zeroed. Returns it, or NULL when out of memory (the old array then stays). */
void *sph_grow_zeroed(void *parts, size_t count, size_t want, size_t size);
/* The first particle of range k of `parts` (nearly) equal ranges of [0, n). */
size_t sph_range_start(size_t n, int parts, int k);

/* Sets s->start_flag for every particle from its start position, velocity and shell, and
 * puts into s->exit_parts[0 .. threads), part k for the k-th range of particles in their
 * order, the start-of-step events of the flagged: the time a path leaves the shell it has
 * once sph_move_leaving_shells moved it, the time it meets a wall. Returns 0, or -1 when
 * out of memory. */
int sph_scan_leaving(hsbd_spheres *s, int threads);
/* Moves the shells of the particles flagged SPH_LEAVES_SHELL to their positions, with
 * their new pairs (shell_updates counts them), slab by slab on threads: the rows and cells
 * end the same for any number of threads. Returns 0, or -1 when out of memory. */
int sph_move_leaving_shells(hsbd_spheres *s, int threads);
/* The half scan of all rows into s->hit_parts[0 .. threads), part k holding the hits of
 * the k-th range of rows in row order. Returns 0, or -1 when out of memory. */
int sph_scan_pairs(hsbd_spheres *s, int threads);

#endif
