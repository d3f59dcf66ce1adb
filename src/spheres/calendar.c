#include "spheres/calendar.h"

#include <stdlib.h>

void sph_calendar_free(sph_calendar *c) {
    free(c->pool);
    free(c->next);
    free(c->head);
    *c = (sph_calendar){0};
}

int sph_calendar_start(sph_calendar *c, double dt) {
    return sph_calendar_start_for(c, dt, c->pushed, 64); /* about the last step's events */
}

int sph_calendar_start_for(sph_calendar *c, double dt, size_t expect, size_t least) {
    size_t want = least; /* a power of two near the expected number of events */
    while (want < expect && want < ((size_t)1 << 24))
        want *= 2;
    if (want > c->head_cap) {
        int32_t *head = realloc(c->head, want * sizeof *head);
        if (!head) return -1;
        c->head = head;
        for (size_t b = c->head_cap; b < want; ++b)
            c->head[b] = -1;
        c->head_cap = want;
    }
    if (c->size) /* a finished run leaves every bucket empty; one cut short does not */
        for (size_t b = 0; b < c->nbuckets; ++b)
            c->head[b] = -1;
    c->nbuckets = want;
    c->inv_width = (double)c->nbuckets / dt;
    c->current = 0;
    c->size = c->pushed = c->pool_used = 0;
    c->free_head = -1;
    return 0;
}

static int32_t take_entry(sph_calendar *c) {
    if (c->free_head >= 0) {
        const int32_t k = c->free_head;
        c->free_head = c->next[k];
        return k;
    }
    if (c->pool_used == c->pool_cap) {
        const size_t cap = c->pool_cap ? 2 * c->pool_cap : 256;
        sph_event *pool = realloc(c->pool, cap * sizeof *pool);
        if (pool) c->pool = pool;
        int32_t *next = pool ? realloc(c->next, cap * sizeof *next) : NULL;
        if (!next) return -1;
        c->next = next;
        c->pool_cap = cap;
    }
    return (int32_t)c->pool_used++;
}

int sph_calendar_push(sph_calendar *c, sph_event e) {
    const int32_t k = take_entry(c);
    if (k < 0) return -1;
    const double q = e.t * c->inv_width;
    size_t b = q >= 0 ? (q < (double)c->nbuckets ? (size_t)q : c->nbuckets - 1) : 0;
    if (b < c->current) b = c->current; /* round-off or NaN: never behind the present */
    c->pool[k] = e;
    c->next[k] = c->head[b];
    c->head[b] = k;
    c->size++;
    c->pushed++;
    return 0;
}

int sph_calendar_pop(sph_calendar *c, sph_event *e) {
    if (!c->size) return 0;
    while (c->head[c->current] < 0)
        c->current++;
    int32_t *link = &c->head[c->current], *best = link;
    for (int32_t k = *link; k >= 0; k = c->next[k]) {
        if (c->pool[k].t < c->pool[*best].t) best = link;
        link = &c->next[k];
    }
    const int32_t k = *best;
    *e = c->pool[k];
    *best = c->next[k];
    c->next[k] = c->free_head;
    c->free_head = k;
    c->size--;
    return 1;
}
