#include "spheres/slab_queue.h"

#include <sched.h>

void sph_slab_queue_start(sph_slab_queue *q, int nslabs) {
    q->nslabs = nslabs;
    atomic_init(&q->next, 0);
    atomic_init(&q->failed, 0);
    for (int k = 0; k < nslabs; ++k)
        atomic_init(&q->done[k], 0);
}

/* Whether slab k has finished. */
static int slab_done(sph_slab_queue *q, int k) {
    return atomic_load_explicit(&q->done[k], memory_order_acquire) != 0;
}

int sph_slab_queue_take(sph_slab_queue *q) {
    const int place = atomic_fetch_add_explicit(&q->next, 1, memory_order_relaxed);
    const int half = q->nslabs / 2;
    if (place >= q->nslabs) return -1;
    const int k = place < half ? 2 * place : 2 * (place - half) + 1;
    if (k % 2) { /* its even neighbours were handed out before it: they will finish */
        const int left = k - 1, right = k + 1 < q->nslabs ? k + 1 : 0;
        for (unsigned spins = 0; !slab_done(q, left) || !slab_done(q, right); ++spins) {
            if (atomic_load_explicit(&q->failed, memory_order_relaxed)) return -1;
            if (spins >= 64) sched_yield(); /* the neighbour's thread may wait for a core */
        }
    }
    return atomic_load_explicit(&q->failed, memory_order_relaxed) ? -1 : k;
}

void sph_slab_queue_finish(sph_slab_queue *q, int k, int failed) {
    if (failed) atomic_store_explicit(&q->failed, 1, memory_order_relaxed);
    atomic_store_explicit(&q->done[k], 1, memory_order_release);
}
