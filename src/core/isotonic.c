#include "hsbd/isotonic.h"

#include <stdlib.h>

/* Blocks live in plain arrays used as a deque: [head, tail). A block covers the
 * "virtual" indices start .. start+len-1; index j >= n stands for element j - n seen
 * through the ring's periodic shift. */
struct hsbd_pava {
    size_t nmax;
    size_t head, tail;
    size_t *start;
    size_t *len;
    double *weight; /* sum of member weights */
    double *mean;   /* weighted mean of member values (virtual coordinates) */
};

hsbd_pava *hsbd_pava_alloc(size_t nmax) {
    hsbd_pava *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    const size_t cap = nmax + 1;
    p->nmax = nmax;
    p->start = malloc(cap * sizeof *p->start);
    p->len = malloc(cap * sizeof *p->len);
    p->weight = malloc(cap * sizeof *p->weight);
    p->mean = malloc(cap * sizeof *p->mean);
    if (!p->start || !p->len || !p->weight || !p->mean) {
        hsbd_pava_free(p);
        return NULL;
    }
    return p;
}

void hsbd_pava_free(hsbd_pava *p) {
    if (!p) return;
    free(p->start);
    free(p->len);
    free(p->weight);
    free(p->mean);
    free(p);
}

/* Pool block b into block a (a directly left of b); value_shift is added to b's mean. */
static inline void pool_into(hsbd_pava *p, size_t a, size_t b, double value_shift) {
    const double wa = p->weight[a], wb = p->weight[b];
    const double w = wa + wb;
    p->mean[a] = (wa * p->mean[a] + wb * (p->mean[b] + value_shift)) / w;
    p->weight[a] = w;
    p->len[a] += p->len[b];
}

/* Push element i as a block onto the tail and pool backwards while violated. */
static void pava_push_all(hsbd_pava *p, size_t n, const double *y, const double *w) {
    size_t t = p->tail;
    for (size_t i = 0; i < n; ++i) {
        p->start[t] = i;
        p->len[t] = 1;
        p->weight[t] = w ? w[i] : 1.0;
        p->mean[t] = y[i];
        ++t;
        while (t - p->head >= 2 && p->mean[t - 2] >= p->mean[t - 1]) {
            pool_into(p, t - 2, t - 1, 0.0);
            --t;
        }
    }
    p->tail = t;
}

static void write_fit(const hsbd_pava *p, size_t n, double shift, double *fit) {
    for (size_t b = p->head; b < p->tail; ++b) {
        const size_t s = p->start[b], e = s + p->len[b];
        const double m = p->mean[b];
        for (size_t j = s; j < e && j < n; ++j) fit[j] = m;
        for (size_t j = (s > n ? s : n); j < e; ++j) fit[j - n] = m - shift;
    }
}

size_t hsbd_pava_line(hsbd_pava *p, size_t n, const double *y, const double *w, double *fit) {
    p->head = p->tail = 0;
    pava_push_all(p, n, y, w);
    write_fit(p, n, 0.0, fit);
    return p->tail - p->head;
}

size_t hsbd_pava_ring(hsbd_pava *p, size_t n, const double *y, const double *w, double shift,
                      double *fit) {
    p->head = p->tail = 0;
    pava_push_all(p, n, y, w);
    /* Close the ring: the last block meets the image (+shift) of the first one. Each
     * pooling removes a block, so this loop is O(n) in total. */
    while (p->tail - p->head >= 2) {
        const size_t first = p->head, last = p->tail - 1;
        if (p->mean[last] < p->mean[first] + shift) break;
        p->start[first] += n; /* the first block re-enters at the end, as its image */
        pool_into(p, last, first, shift);
        ++p->head;
        size_t t = p->tail;
        while (t - p->head >= 2 && p->mean[t - 2] >= p->mean[t - 1]) {
            pool_into(p, t - 2, t - 1, 0.0);
            --t;
        }
        p->tail = t;
    }
    write_fit(p, n, shift, fit);
    return p->tail - p->head;
}

size_t hsbd_pava_block_size(const hsbd_pava *p, size_t k) {
    return p->len[p->head + k];
}
