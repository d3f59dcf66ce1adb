#include "hsbd/isotonic.h"

#include <stdlib.h>

/* A block of pooled elements: weighted sum and total weight (its mean is sum/weight,
 * computed only when the fit is written: the pooling loop compares means by
 * cross-multiplication, which keeps divisions off its dependency chain). */
typedef struct pava_block {
    double sum;    /* sum of w_i y_i (virtual coordinates) */
    double weight; /* sum of w_i > 0 */
    size_t len;
} pava_block;

/* Blocks form a deque [head, tail) in one array. The head block starts at virtual
 * index head_start; the others follow contiguously. Virtual index j >= n stands for
 * element j - n seen through the ring's periodic shift. */
struct hsbd_pava {
    size_t nmax, head, tail, head_start;
    pava_block *block;
};

hsbd_pava *hsbd_pava_alloc(size_t nmax) {
    hsbd_pava *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    p->nmax = nmax;
    p->block = malloc((nmax + 1) * sizeof *p->block);
    if (!p->block) {
        free(p);
        return NULL;
    }
    return p;
}

void hsbd_pava_free(hsbd_pava *p) {
    if (!p) return;
    free(p->block);
    free(p);
}

/* mean(a) >= mean(b), weights positive */
static inline int violates(const pava_block *a, const pava_block *b) {
    return a->sum * b->weight >= b->sum * a->weight;
}

static inline void pool(pava_block *a, const pava_block *b) {
    a->sum += b->sum;
    a->weight += b->weight;
    a->len += b->len;
}

/* Push every element as a block and pool backwards while the last two violate. The top
 * block stays in registers and is stored only when a new block starts, so the common
 * no-pooling path carries no store-to-load dependency from one element to the next.
 * `weighted` is a compile-time constant at each call site, so both variants inline. */
static inline size_t push_all(pava_block *restrict blk, size_t head, size_t n,
                              const double *restrict y, const double *restrict w, int weighted) {
    if (n == 0) return head;
    size_t t = head; /* blocks below the top: blk[head .. t) */
    pava_block top = {weighted ? w[0] * y[0] : y[0], weighted ? w[0] : 1.0, 1};
    for (size_t i = 1; i < n; ++i) {
        const double wi = weighted ? w[i] : 1.0;
        const pava_block cur = {wi * y[i], wi, 1};
        if (!violates(&top, &cur)) {
            blk[t++] = top;
            top = cur;
            continue;
        }
        pool(&top, &cur);
        while (t > head && violates(&blk[t - 1], &top)) {
            pava_block below = blk[--t];
            pool(&below, &top);
            top = below;
        }
    }
    blk[t++] = top;
    return t;
}

/* Block mean; a block of weight exactly 1 (an unweighted singleton) is its own sum, and
 * skipping the division there is bit-identical and saves most divisions of a step. */
static inline double block_mean(const pava_block *b) {
    return b->weight == 1.0 ? b->sum : b->sum / b->weight;
}

static void write_fit(const hsbd_pava *p, size_t n, double shift, double *restrict fit) {
    size_t j = p->head_start;
    const size_t last = p->tail - 1;
    /* all blocks but the last end inside [0, n): a tight loop */
    for (size_t b = p->head; b < last; ++b) {
        const double m = block_mean(&p->block[b]);
        const size_t end = j + p->block[b].len;
        do
            fit[j] = m;
        while (++j < end);
    }
    /* the last block may wrap around to the start of the array */
    const double m = block_mean(&p->block[last]);
    const size_t end = j + p->block[last].len;
    for (; j < end && j < n; ++j)
        fit[j] = m;
    for (; j < end; ++j)
        fit[j - n] = m - shift;
}

static void run_push(hsbd_pava *p, size_t n, const double *y, const double *w) {
    p->head = p->head_start = 0;
    p->tail = w ? push_all(p->block, 0, n, y, w, 1) : push_all(p->block, 0, n, y, NULL, 0);
}

size_t hsbd_pava_line(hsbd_pava *p, size_t n, const double *y, const double *w, double *fit) {
    run_push(p, n, y, w);
    write_fit(p, n, 0.0, fit);
    return p->tail - p->head;
}

size_t hsbd_pava_ring(hsbd_pava *p, size_t n, const double *y, const double *w, double shift,
                      double *fit) {
    run_push(p, n, y, w);
    pava_block *blk = p->block;
    /* Close the ring: the last block meets the image (+shift) of the first one; pool them
     * and keep pooling backwards. Each pooling removes a block: O(n) in total. */
    while (p->tail - p->head >= 2) {
        pava_block first = blk[p->head];
        first.sum += shift * first.weight; /* the image of the first block */
        if (!violates(&blk[p->tail - 1], &first)) break;
        p->head_start += first.len;
        ++p->head;
        pava_block cur = first;
        size_t t = p->tail;
        while (t > p->head && violates(&blk[t - 1], &cur)) {
            pool(&blk[t - 1], &cur);
            cur = blk[--t];
        }
        blk[t++] = cur;
        p->tail = t;
    }
    write_fit(p, n, shift, fit);
    return p->tail - p->head;
}

size_t hsbd_pava_block_size(const hsbd_pava *p, size_t k) {
    return p->block[p->head + k].len;
}
