#include "spheres/calendar.h"

#include <stdlib.h>

void sph_calendar_free(sph_calendar *c) {
    free(c->heap);
    c->heap = NULL;
    c->size = c->cap = 0;
}

int sph_calendar_push(sph_calendar *c, sph_event e) {
    if (c->size == c->cap) {
        const size_t cap = c->cap ? 2 * c->cap : 256;
        sph_event *h = realloc(c->heap, cap * sizeof *h);
        if (!h) return -1;
        c->heap = h;
        c->cap = cap;
    }
    size_t k = c->size++;
    while (k > 0) { /* sift up */
        const size_t parent = (k - 1) / 2;
        if (!(e.t < c->heap[parent].t)) break;
        c->heap[k] = c->heap[parent];
        k = parent;
    }
    c->heap[k] = e;
    return 0;
}

int sph_calendar_pop(sph_calendar *c, sph_event *e) {
    if (!c->size) return 0;
    *e = c->heap[0];
    const sph_event last = c->heap[--c->size];
    size_t k = 0;
    for (;;) { /* sift down */
        size_t child = 2 * k + 1;
        if (child >= c->size) break;
        if (child + 1 < c->size && c->heap[child + 1].t < c->heap[child].t) ++child;
        if (!(c->heap[child].t < last.t)) break;
        c->heap[k] = c->heap[child];
        k = child;
    }
    if (c->size) c->heap[k] = last;
    return 1;
}
