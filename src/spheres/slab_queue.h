/* Slabs handed to threads (internal to src/spheres): an even number of slabs around a
 * periodic axis, taken even ones first, then odd ones, and an odd slab only once both of
 * its even neighbours are done. Two slabs that run at once are then never neighbours, and
 * every odd slab starts after its neighbours, as with a barrier between the two parities;
 * but a thread that finds no even slab left goes on to an odd one whose neighbours are
 * done instead of waiting for the last even slab. With three slabs of a parity and two
 * threads, the barrier left one thread idle for half of the parity's time. */
#ifndef HSBD_SPHERES_SLAB_QUEUE_H
#define HSBD_SPHERES_SLAB_QUEUE_H

#include <stdatomic.h>

enum { SPH_SLAB_QUEUE_MAX = 64 };

typedef struct sph_slab_queue {
    int nslabs;
    atomic_int next;                       /* the next place in the order: evens, then odds */
    atomic_int failed;                     /* set: no slab is handed out any more */
    atomic_uchar done[SPH_SLAB_QUEUE_MAX]; /* slab k finished (release; read with acquire) */
} sph_slab_queue;

/* Ready for nslabs slabs (even, 4 .. SPH_SLAB_QUEUE_MAX), none done. Not on threads. */
void sph_slab_queue_start(sph_slab_queue *q, int nslabs);
/* The next slab for the calling thread, after its even neighbours are done when it is
 * odd; -1 when none is left or a slab failed. */
int sph_slab_queue_take(sph_slab_queue *q);
/* Slab k is done; `failed` stops the handing out. */
void sph_slab_queue_finish(sph_slab_queue *q, int k, int failed);

#endif
