#include "hsbd/isotonic.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* A block of pooled elements: weighted sum and total weight (its mean is sum/weight,
 * computed only when the fit is written: the pooling loop compares means by
 * cross-multiplication, which keeps divisions off its dependency chain). */
typedef struct pava_block {
    double sum;    /* sum of w_i y_i (virtual coordinates) */
    double weight; /* sum of w_i > 0 */
    size_t len;
} pava_block;

/* The blocks of one chunk of HSBD_PAVA_CHUNK elements: slots [lo, hi) of the block array
 * (chunk c's own pass fills them from slot c K), the first starting at virtual element
 * index `start`. Virtual index j >= n stands for element j - n seen through the ring's
 * periodic shift. `pooled`: the last block is the result of pooling in the join or the
 * ring's closure, so its fit must be written again. */
typedef struct pava_segment {
    size_t lo, hi, start;
    int pooled;
} pava_segment;

/* The fitted blocks are the blocks of the live segments, in order: a deque of segment
 * indices live[lh .. lt) whose blocks are the solution read left to right. */
struct hsbd_pava {
    size_t nmax, lh, lt;
    int threads;
    pava_block *block;
    pava_segment *seg;
    size_t *live;
    size_t *before;      /* blocks in the live segments before live[lh + i]; then the total */
    uint64_t *flag;      /* a bit per element: scratch of push_all (chunk c: from c K) */
    size_t *pooled_slot; /* per element: the pooled blocks' slots of push_all */
    size_t nblocks;      /* of the last solve */
    size_t hint;         /* the live segment (from lh) of the last block size asked for */
};

static size_t chunks_of(size_t n) {
    return n == 0 ? 1 : (n + HSBD_PAVA_CHUNK - 1) / HSBD_PAVA_CHUNK;
}

hsbd_pava *hsbd_pava_alloc(size_t nmax) {
    hsbd_pava *p = calloc(1, sizeof *p);
    if (!p) return NULL;
    const size_t nchunks = chunks_of(nmax);
    p->nmax = nmax;
    p->threads = 1;
    p->block = malloc((nmax + 1) * sizeof *p->block);
    p->seg = malloc(nchunks * sizeof *p->seg);
    p->live = malloc(nchunks * sizeof *p->live);
    p->before = malloc((nchunks + 1) * sizeof *p->before);
    p->flag = malloc((nmax / 64 + 2) * sizeof *p->flag);
    p->pooled_slot = malloc((nmax + 1) * sizeof *p->pooled_slot);
    if (!p->block || !p->seg || !p->live || !p->before || !p->flag || !p->pooled_slot) {
        hsbd_pava_free(p);
        return NULL;
    }
    return p;
}

void hsbd_pava_free(hsbd_pava *p) {
    if (!p) return;
    free(p->block);
    free(p->seg);
    free(p->live);
    free(p->before);
    free(p->flag);
    free(p->pooled_slot);
    free(p);
}

void hsbd_pava_set_threads(hsbd_pava *p, int threads) {
    p->threads = threads > 1 ? threads : 1;
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

/* Element i as a block of its own. */
static inline pava_block singleton(const double *restrict y, const double *restrict w, size_t i,
                                   int weighted) {
    return (pava_block){weighted ? w[i] * y[i] : y[i], weighted ? w[i] : 1.0, 1};
}

/* Bit i of flag[] set where singletons i and i + 1 violate (the comparison `violates`
 * makes, with the same products), for i < n - 1; bit n - 1 set stops the scans of push_all
 * at the end. Two elements per SSE2 comparison where the compiler targets it. */
static void singleton_violations(size_t n, const double *restrict y, const double *restrict w,
                                 int weighted, uint64_t *restrict flag) {
    for (size_t word = 0; word * 64 < n; ++word) {
        const size_t lo = word * 64, hi = lo + 64 < n ? lo + 64 : n; /* pairs (i, i+1), i < hi */
        uint64_t bits = 0;
        size_t i = lo;
#if defined(__SSE2__)
        /* the pairs (i, i + 1) and (i + 1, i + 2), y[i + 2] up to y[last] */
        const size_t last = hi < n ? hi : n - 1;
        for (; i + 2 <= last; i += 2) {
            __m128d left = _mm_loadu_pd(y + i), right = _mm_loadu_pd(y + i + 1);
            if (weighted) {
                const __m128d wl = _mm_loadu_pd(w + i), wr = _mm_loadu_pd(w + i + 1);
                left = _mm_mul_pd(_mm_mul_pd(wl, left), wr);
                right = _mm_mul_pd(_mm_mul_pd(wr, right), wl);
            }
            bits |= (uint64_t)_mm_movemask_pd(_mm_cmpge_pd(left, right)) << (i - lo);
        }
#endif
        for (; i < hi && i + 1 < n; ++i) {
            const int v = weighted ? (w[i] * y[i]) * w[i + 1] >= (w[i + 1] * y[i + 1]) * w[i]
                                   : y[i] >= y[i + 1];
            bits |= (uint64_t)v << (i - lo);
        }
        if (hi == n) bits |= (uint64_t)1 << (n - 1 - lo); /* the stop */
        flag[word] = bits;
    }
}

/* The first set bit at or after r (there is one: bit n - 1). */
static inline size_t next_flag(const uint64_t *flag, size_t r) {
    size_t word = r / 64;
    uint64_t bits = flag[word] >> (r % 64);
    if (bits) return r + (size_t)__builtin_ctzll(bits);
    while (!flag[++word]) {
    }
    return word * 64 + (size_t)__builtin_ctzll(flag[word]);
}

/* Pools `top` (just joined by an element) with the blocks below it while they violate;
 * a pooled block that leaves the stack leaves the list of pooled slots too. */
static inline pava_block pool_down(pava_block *restrict blk, size_t head, size_t *t,
                                   const size_t *restrict pooled, size_t *npooled, pava_block top) {
    while (*t > head && violates(&blk[*t - 1], &top)) {
        pava_block below = blk[--*t];
        if (*npooled && pooled[*npooled - 1] == *t) --*npooled;
        pool(&below, &top);
        top = below;
    }
    return top;
}

/* PAVA of y[0 .. n) into blk[head ..), returning the end slot: every element pushed as a
 * block, pooled backwards while the last two violate; the operations and their order are
 * those of that plain pass, so are the bits. Most elements do not violate their left
 * neighbour, so runs of singletons are copied without comparing blocks: while the top is
 * the singleton of element r and flag[r] is clear, element r + 1 cannot pool with it. The
 * slots of the pooled blocks on the stack go to pooled[] (increasing), their count to
 * *npooled: the fit of every other block is its element's own mean. */
static inline size_t push_all(pava_block *restrict blk, size_t head, size_t n,
                              const double *restrict y, const double *restrict w, int weighted,
                              const uint64_t *restrict flag, size_t *restrict pooled,
                              size_t *npooled) {
    if (n == 0) return head;
    size_t t = head, r = 0, np = 0;
    for (;;) {
        const size_t v = next_flag(flag, r); /* up to v, no singleton pools with the next */
        for (; r < v; ++r)
            blk[t++] = singleton(y, w, r, weighted);
        if (r == n - 1) { /* the last element, a singleton */
            blk[t++] = singleton(y, w, r, weighted);
            break;
        }
        pava_block top = singleton(y, w, r, weighted), cur = singleton(y, w, r + 1, weighted);
        pool(&top, &cur); /* they violate: flag[r] */
        top = pool_down(blk, head, &t, pooled, &np, top);
        size_t i = r + 2;
        for (; i < n; ++i) { /* the top is a pooled block */
            cur = singleton(y, w, i, weighted);
            if (!violates(&top, &cur)) break;
            pool(&top, &cur);
            top = pool_down(blk, head, &t, pooled, &np, top);
        }
        pooled[np++] = t;
        blk[t++] = top;
        if (i == n) break;
        r = i; /* the top is singleton i */
    }
    *npooled = np;
    return t;
}

/* Block mean; a block of weight exactly 1 (an unweighted singleton) is its own sum, and
 * skipping the division there is bit-identical and saves most divisions of a step. */
static inline double block_mean(const pava_block *b) {
    return b->weight == 1.0 ? b->sum : b->sum / b->weight;
}

/* ---- the live blocks as one deque ---- */

static inline int deque_empty(const hsbd_pava *p) {
    return p->lh == p->lt;
}

/* slot of the last block */
static inline size_t deque_top(const hsbd_pava *p) {
    return p->seg[p->live[p->lt - 1]].hi - 1;
}

/* removes the last block, returning its slot and segment */
static inline size_t deque_pop(hsbd_pava *p, size_t *segment) {
    *segment = p->live[p->lt - 1];
    pava_segment *s = &p->seg[*segment];
    const size_t slot = --s->hi;
    if (s->lo == s->hi) --p->lt;
    return slot;
}

/* puts `b` back as the last block in the slot just popped from `segment` */
static inline void deque_push_back(hsbd_pava *p, size_t segment, size_t slot, const pava_block *b) {
    pava_segment *s = &p->seg[segment];
    if (s->lo == s->hi) p->live[p->lt++] = segment; /* it had emptied */
    p->block[slot] = *b;
    s->hi = slot + 1;
    s->pooled = 1;
}

/* Pools `cur` (following the last block) backwards while the last block violates it, and
 * leaves the pooled block as the last one. The caller has removed cur from its place and
 * found that it violates the last block (so at least one block pools). Sums are added left
 * block first, as push_all adds them. */
static void pool_backwards(hsbd_pava *p, pava_block cur) {
    size_t segment, slot;
    do {
        slot = deque_pop(p, &segment);
        pava_block below = p->block[slot];
        pool(&below, &cur);
        cur = below;
    } while (!deque_empty(p) && violates(&p->block[deque_top(p)], &cur));
    deque_push_back(p, segment, slot, &cur);
}

/* Joins the chunks' solutions left to right: each chunk's blocks are pushed onto the
 * blocks to their left with pooling, which is PAVA on the concatenated chunk solutions
 * (pooling adjacent violators in any order reaches the unique solution). Once one of a
 * chunk's blocks stays unpooled, the rest of the chunk is increasing (its own pass
 * compared them with these very values) and stays as it is: the join costs the chunk
 * count plus the blocks pooled at seams. */
static void join_chunks(hsbd_pava *p, size_t nchunks) {
    p->lh = 0;
    p->lt = 1;
    p->live[0] = 0;
    for (size_t c = 1; c < nchunks; ++c) {
        pava_segment *s = &p->seg[c];
        while (s->lo < s->hi && !deque_empty(p) &&
               violates(&p->block[deque_top(p)], &p->block[s->lo])) {
            const pava_block first = p->block[s->lo++];
            s->start += first.len;
            pool_backwards(p, first);
        }
        if (s->lo < s->hi) p->live[p->lt++] = c;
    }
}

/* The fit of a chunk's blocks as they stand after its pass (elements y[0 .. n) in slots
 * from `head`): each singleton's own mean, then the pooled blocks' means over their
 * elements (a pooled block of length m shifts the elements of the later slots by m - 1). */
static void write_chunk_fit(const pava_block *restrict blk, size_t head, size_t n, const double *y,
                            const double *restrict w, const size_t *restrict pooled, size_t npooled,
                            double *fit) {
    if (w)
        for (size_t i = 0; i < n; ++i) /* = block_mean of the singleton, to the bit */
            fit[i] = (w[i] * y[i]) / w[i];
    else if (fit != y)
        memcpy(fit, y, n * sizeof *fit);
    size_t shift = 0;
    for (size_t k = 0; k < npooled; ++k) {
        const pava_block *b = &blk[pooled[k]];
        const double m = block_mean(b);
        const size_t start = pooled[k] - head + shift;
        for (size_t j = start; j < start + b->len; ++j)
            fit[j] = m;
        shift += b->len - 1;
    }
}

/* Chunk c's own pass, then the fit of its blocks as they stand, written while they are
 * in cache: the join and the ring's closure change only the blocks they pool, whose fit
 * write_pooled writes again (fit may alias y: the chunk has read its own elements). */
static void push_chunk(hsbd_pava *p, size_t c, size_t n, const double *y, const double *w,
                       double *fit) {
    const size_t first = c * HSBD_PAVA_CHUNK;
    const size_t len = n - first < HSBD_PAVA_CHUNK ? n - first : HSBD_PAVA_CHUNK;
    const double *yc = y + first, *wc = w ? w + first : NULL;
    uint64_t *flag = p->flag + first / 64;
    size_t *pooled = p->pooled_slot + first, npooled = 0;
    pava_segment *s = &p->seg[c];
    s->lo = s->start = first;
    s->pooled = 0;
    if (w) {
        singleton_violations(len, yc, wc, 1, flag);
        s->hi = push_all(p->block, first, len, yc, wc, 1, flag, pooled, &npooled);
    } else {
        singleton_violations(len, yc, NULL, 0, flag);
        s->hi = push_all(p->block, first, len, yc, NULL, 0, flag, pooled, &npooled);
    }
    write_chunk_fit(p->block, first, len, yc, wc, pooled, npooled, fit + first);
}

/* The fit of the last block of live segment k when pooling made it: its elements end
 * where the next live segment's begin (the last segment's where the first one's begin,
 * one period on); one reaching past n wraps to the start of the array at mean - shift. */
static void write_pooled(const hsbd_pava *p, size_t k, size_t n, double shift,
                         double *restrict fit) {
    const pava_segment *s = &p->seg[p->live[k]];
    if (!s->pooled) return;
    const size_t end =
        k + 1 < p->lt ? p->seg[p->live[k + 1]].start : p->seg[p->live[p->lh]].start + n;
    const pava_block *top = &p->block[s->hi - 1];
    const double m = block_mean(top);
    size_t j = end - top->len;
    for (; j < end && j < n; ++j)
        fit[j] = m;
    for (; j < end; ++j)
        fit[j - n] = m - shift;
}

/* Close the ring: the last block meets the image (+shift) of the first one; pool them and
 * keep pooling backwards. Each pooling removes a block: O(n) in total. */
static void close_ring(hsbd_pava *p, double shift) {
    for (;;) {
        pava_segment *h = &p->seg[p->live[p->lh]];
        if (p->lt - p->lh < 2 && h->hi - h->lo < 2) break; /* one block left */
        pava_block first = p->block[h->lo];
        first.sum += shift * first.weight; /* the image of the first block */
        if (!violates(&p->block[deque_top(p)], &first)) break;
        h->start += first.len;
        if (++h->lo == h->hi) ++p->lh;
        pool_backwards(p, first); /* the last block, still there, violates it */
    }
}

/* the blocks before each live segment, and their number */
static void count_blocks(hsbd_pava *p) {
    size_t total = 0;
    for (size_t k = p->lh; k < p->lt; ++k) {
        p->before[k - p->lh] = total;
        total += p->seg[p->live[k]].hi - p->seg[p->live[k]].lo;
    }
    p->before[p->lt - p->lh] = total;
    p->nblocks = total;
    p->hint = 0;
}

/* Between the chunks' passes and the fit: the join, on a ring the closure, the count. */
static void join_and_close(hsbd_pava *p, size_t nchunks, int ring, double shift) {
    join_chunks(p, nchunks);
    if (ring) close_ring(p, shift);
    count_blocks(p);
}

/* One solve: the chunks' passes with their fits, the join, on a ring the closure, then the
 * fit of the pooled blocks. On threads the passes are shared out and the rest runs on one
 * thread. (The serial path has no work-sharing construct: called from inside another
 * parallel region, one would bind to that region's team.) */
static size_t solve(hsbd_pava *p, size_t n, const double *y, const double *w, int ring,
                    double shift, double *fit) {
    if (n == 0) return p->nblocks = 0;
    const size_t nchunks = chunks_of(n);
    const int threads = nchunks > 1 ? p->threads : 1;
    if (threads > 1) {
#pragma omp parallel for schedule(static) num_threads(threads)
        for (long c = 0; c < (long)nchunks; ++c)
            push_chunk(p, (size_t)c, n, y, w, fit);
    } else {
        for (size_t c = 0; c < nchunks; ++c)
            push_chunk(p, c, n, y, w, fit);
    }
    join_and_close(p, nchunks, ring, shift);
    for (size_t k = p->lh; k < p->lt; ++k)
        write_pooled(p, k, n, shift, fit);
    return p->nblocks;
}

size_t hsbd_pava_line(hsbd_pava *p, size_t n, const double *y, const double *w, double *fit) {
    return solve(p, n, y, w, 0, 0.0, fit);
}

size_t hsbd_pava_ring(hsbd_pava *p, size_t n, const double *y, const double *w, double shift,
                      double *fit) {
    return solve(p, n, y, w, 1, shift, fit);
}

/* The live segment i holding block k (before[i] <= k < before[i + 1]): the last one
 * asked for or the next (blocks asked for in order), else by bisection. */
static size_t segment_of_block(const hsbd_pava *p, size_t k) {
    const size_t nlive = p->lt - p->lh, *before = p->before;
    size_t i = p->hint < nlive ? p->hint : 0;
    if (before[i] <= k && k < before[i + 1]) return i;
    if (i + 1 < nlive && before[i + 1] <= k && k < before[i + 2]) return i + 1;
    size_t lo = 0, hi = nlive;
    while (hi - lo > 1) {
        const size_t mid = lo + (hi - lo) / 2;
        if (before[mid] <= k)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

size_t hsbd_pava_block_size(hsbd_pava *p, size_t k) {
    const size_t i = segment_of_block(p, k);
    p->hint = i;
    return p->block[p->seg[p->live[p->lh + i]].lo + (k - p->before[i])].len;
}
