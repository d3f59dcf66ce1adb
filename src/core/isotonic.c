#include "hsbd/isotonic.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

/* A block of pooled elements: weighted sum and total weight (its mean is sum/weight,
 * computed only when the fit is written: the pooling loop compares means by
 * cross-multiplication, which keeps divisions off its dependency chain), its length and
 * first element. Virtual element index j >= n stands for element j - n seen through the
 * ring's periodic shift. Only blocks of two or more elements are stored: an element no
 * stored block covers is a block of its own (a singleton), read from y when needed. */
typedef struct pava_block {
    double sum;    /* sum of w_i y_i (virtual coordinates) */
    double weight; /* sum of w_i > 0 */
    size_t len, start;
} pava_block;

/* The blocks of one chunk of HSBD_PAVA_CHUNK elements: its elements [start, end) (virtual
 * indices), of which the stored blocks in slots [lo, hi) of the block array cover some
 * (chunk c's own pass fills them from slot c K), in order. `pooled`: the last stored
 * block is the result of pooling in the join or the ring's closure, so its fit must be
 * written again. */
typedef struct pava_segment {
    size_t lo, hi, start, end;
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
    size_t *before;  /* blocks in the live segments before live[lh + i]; then the total */
    size_t *item;    /* per stored block: its place among its segment's blocks */
    uint64_t *flag;  /* a bit per element: scratch of the chunks' passes (chunk c: from c K) */
    double *saved;   /* weighted and in place: the input, for the join's singletons */
    const double *y; /* of the solve under way: the singletons' values */
    const double *w;
    size_t nblocks;   /* of the last solve */
    size_t hint;      /* the live segment (from lh) of the last block size asked for */
    size_t hint_slot; /* and the stored block at or before it */
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
    p->item = malloc((nmax + 1) * sizeof *p->item);
    p->flag = malloc((nmax / 64 + 2) * sizeof *p->flag);
    p->saved = malloc((nmax + 1) * sizeof *p->saved);
    if (!p->block || !p->seg || !p->live || !p->before || !p->item || !p->flag || !p->saved) {
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
    free(p->item);
    free(p->flag);
    free(p->saved);
    free(p);
}

void hsbd_pava_set_threads(hsbd_pava *p, int threads) {
    p->threads = threads > 1 ? threads : 1;
}

/* mean(a) >= mean(b), weights positive */
static inline int violates(const pava_block *a, const pava_block *b) {
    return a->sum * b->weight >= b->sum * a->weight;
}

/* b joins a on its right */
static inline void pool(pava_block *a, const pava_block *b) {
    a->sum += b->sum;
    a->weight += b->weight;
    a->len += b->len;
}

/* Element i (< n) as a block of its own. */
static inline pava_block singleton(const double *restrict y, const double *restrict w, size_t i,
                                   int weighted) {
    return (pava_block){weighted ? w[i] * y[i] : y[i], weighted ? w[i] : 1.0, 1, i};
}

/* Block mean; a block of weight exactly 1 (an unweighted singleton) is its own sum, and
 * skipping the division there is bit-identical. */
static inline double block_mean(const pava_block *b) {
    return b->weight == 1.0 ? b->sum : b->sum / b->weight;
}

/* ---- a chunk's own pass ---- */

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

/* Pools `top` with the blocks below it on the stack while they violate: the stored
 * blocks blk[head .. *t) and the singletons between them, down to element `first`. */
static inline pava_block pool_down(pava_block *restrict blk, size_t head, size_t *t, size_t first,
                                   const double *restrict y, const double *restrict w, int weighted,
                                   pava_block top) {
    while (top.start > first) {
        const int stored = *t > head && blk[*t - 1].start + blk[*t - 1].len == top.start;
        pava_block below = stored ? blk[*t - 1] : singleton(y, w, top.start - 1, weighted);
        if (!violates(&below, &top)) break;
        *t -= (size_t)stored;
        pool(&below, &top);
        top = below;
    }
    return top;
}

/* PAVA of the elements [first, first + n) into blk[head ..), returning the end slot: every
 * element pushed as a block, pooled backwards while the last two violate; the operations
 * and their order are those of that plain pass, so are the bits. Most elements do not
 * violate their left neighbour: while the top is the singleton of element r and flag bit
 * r is clear, element r + 1 cannot pool with it and stays a singleton, which is not
 * stored. flag holds the bits of this chunk (bit 0 for element first). */
static inline size_t push_all(pava_block *restrict blk, size_t head, size_t first, size_t n,
                              const double *restrict y, const double *restrict w, int weighted,
                              const uint64_t *restrict flag) {
    size_t t = head, r = 0;
    while (n > 0) {
        r = next_flag(flag, r); /* singletons up to r, none pools with the next */
        if (r == n - 1) break;  /* the last element, a singleton */
        pava_block top = singleton(y, w, first + r, weighted);
        pava_block cur = singleton(y, w, first + r + 1, weighted);
        pool(&top, &cur); /* they violate: flag bit r */
        top = pool_down(blk, head, &t, first, y, w, weighted, top);
        size_t i = r + 2;
        for (; i < n; ++i) { /* the top is a pooled block */
            cur = singleton(y, w, first + i, weighted);
            if (!violates(&top, &cur)) break;
            pool(&top, &cur);
            top = pool_down(blk, head, &t, first, y, w, weighted, top);
        }
        blk[t++] = top;
        if (i == n) break;
        r = i; /* the top is singleton i */
    }
    return t;
}

/* The fit of the elements [first, first + n) of a chunk after its pass: each singleton's
 * own mean, then the stored blocks blk[lo .. hi) over their elements. */
static void write_chunk_fit(const pava_block *restrict blk, size_t lo, size_t hi, size_t first,
                            size_t n, const double *y, const double *restrict w, double *fit) {
    if (w)
        for (size_t i = first; i < first + n; ++i) /* = block_mean of the singleton */
            fit[i] = (w[i] * y[i]) / w[i];
    else if (fit != y)
        memcpy(fit + first, y + first, n * sizeof *fit);
    for (size_t b = lo; b < hi; ++b) {
        const double m = block_mean(&blk[b]);
        for (size_t j = blk[b].start; j < blk[b].start + blk[b].len; ++j)
            fit[j] = m;
    }
}

/* Chunk c's own pass, then the fit of its blocks as they stand, written while they are in
 * cache: the join and the ring's closure change only the blocks they pool, whose fit
 * write_pooled writes again (fit may alias y: the chunk has read its own elements). */
static void push_chunk(hsbd_pava *p, size_t c, size_t n, const double *y, const double *w,
                       double *fit) {
    const size_t first = c * HSBD_PAVA_CHUNK;
    const size_t len = n - first < HSBD_PAVA_CHUNK ? n - first : HSBD_PAVA_CHUNK;
    uint64_t *flag = p->flag + first / 64;
    pava_segment *s = &p->seg[c];
    s->lo = first;
    s->start = first;
    s->end = first + len;
    s->pooled = 0;
    if (w) {
        singleton_violations(len, y + first, w + first, 1, flag);
        s->hi = push_all(p->block, first, first, len, y, w, 1, flag);
    } else {
        singleton_violations(len, y + first, NULL, 0, flag);
        s->hi = push_all(p->block, first, first, len, y, NULL, 0, flag);
    }
    write_chunk_fit(p->block, s->lo, s->hi, first, len, y, w, fit);
}

/* ---- the live blocks as one deque ---- */

/* the singleton of element j (< n) of the solve under way */
static inline pava_block element_block(const hsbd_pava *p, size_t j) {
    return p->w ? singleton(p->y, p->w, j, 1) : singleton(p->y, NULL, j, 0);
}

/* whether the last (first) block of segment s is a stored one */
static inline int last_is_stored(const hsbd_pava *p, const pava_segment *s) {
    return s->hi > s->lo && p->block[s->hi - 1].start + p->block[s->hi - 1].len == s->end;
}

static inline int first_is_stored(const hsbd_pava *p, const pava_segment *s) {
    return s->hi > s->lo && p->block[s->lo].start == s->start;
}

static inline pava_block last_block(const hsbd_pava *p, const pava_segment *s) {
    return last_is_stored(p, s) ? p->block[s->hi - 1] : element_block(p, s->end - 1);
}

static inline pava_block first_block(const hsbd_pava *p, const pava_segment *s) {
    return first_is_stored(p, s) ? p->block[s->lo] : element_block(p, s->start);
}

static inline int deque_empty(const hsbd_pava *p) {
    return p->lh == p->lt;
}

/* removes the last block of the deque, returning it and its segment */
static inline pava_block deque_pop(hsbd_pava *p, size_t *segment) {
    *segment = p->live[p->lt - 1];
    pava_segment *s = &p->seg[*segment];
    const pava_block b = last_block(p, s);
    if (last_is_stored(p, s)) --s->hi;
    s->end -= b.len;
    if (s->start == s->end) --p->lt;
    return b;
}

/* puts the pooled block `b` back as the last one, in `segment`, where its first element's
 * block was popped from */
static inline void deque_push_back(hsbd_pava *p, size_t segment, const pava_block *b) {
    pava_segment *s = &p->seg[segment];
    if (s->start == s->end) p->live[p->lt++] = segment; /* it had emptied */
    p->block[s->hi++] = *b;
    s->end = b->start + b->len;
    s->pooled = 1;
}

/* Pools `cur` (following the last block) backwards while the last block violates it, and
 * leaves the pooled block as the last one. The caller has removed cur from its place and
 * found that it violates the last block (so at least one block pools). Sums are added left
 * block first, as push_all adds them. */
static void pool_backwards(hsbd_pava *p, pava_block cur) {
    size_t segment;
    pava_block last;
    do {
        pava_block below = deque_pop(p, &segment);
        pool(&below, &cur);
        cur = below;
    } while (!deque_empty(p) &&
             (last = last_block(p, &p->seg[p->live[p->lt - 1]]), violates(&last, &cur)));
    deque_push_back(p, segment, &cur);
}

/* removes the first block of segment s, returning it */
static inline pava_block take_first(hsbd_pava *p, pava_segment *s) {
    const pava_block b = first_block(p, s);
    if (first_is_stored(p, s)) ++s->lo;
    s->start += b.len;
    return b;
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
        while (s->start < s->end && !deque_empty(p)) {
            const pava_block last = last_block(p, &p->seg[p->live[p->lt - 1]]);
            const pava_block first = first_block(p, s);
            if (!violates(&last, &first)) break;
            pool_backwards(p, take_first(p, s));
        }
        if (s->start < s->end) p->live[p->lt++] = c;
    }
}

/* The fit of the last stored block of live segment k when pooling made it; its elements
 * past n wrap to the start of the array at mean - shift. */
static void write_pooled(const hsbd_pava *p, size_t k, size_t n, double shift,
                         double *restrict fit) {
    const pava_segment *s = &p->seg[p->live[k]];
    if (!s->pooled || s->hi == s->lo) return;
    const pava_block *b = &p->block[s->hi - 1];
    const double m = block_mean(b);
    size_t j = b->start;
    const size_t end = b->start + b->len;
    for (; j < end && j < n; ++j)
        fit[j] = m;
    for (; j < end; ++j)
        fit[j - n] = m - shift;
}

/* Close the ring: the last block meets the image (+shift) of the first one; pool them and
 * keep pooling backwards. Each pooling removes a block: O(n) in total. */
static void close_ring(hsbd_pava *p, size_t n, double shift) {
    for (;;) {
        pava_segment *h = &p->seg[p->live[p->lh]];
        pava_block first = first_block(p, h);
        if (p->lt - p->lh < 2 && first.len == h->end - h->start) break; /* one block left */
        first.sum += shift * first.weight; /* the image of the first block */
        first.start += n;
        const pava_block last = last_block(p, &p->seg[p->live[p->lt - 1]]);
        if (!violates(&last, &first)) break;
        take_first(p, h);
        if (h->start == h->end) ++p->lh;
        pool_backwards(p, first); /* the last block, still there, violates it */
    }
}

/* the blocks before each live segment, and their number; the place of each stored block
 * among its segment's blocks (for the size queries) */
static void count_blocks(hsbd_pava *p) {
    size_t total = 0;
    for (size_t k = p->lh; k < p->lt; ++k) {
        const pava_segment *s = &p->seg[p->live[k]];
        p->before[k - p->lh] = total;
        size_t pooled_away = 0; /* elements that are not the first of their stored block */
        for (size_t b = s->lo; b < s->hi; ++b) {
            p->item[b] = p->block[b].start - s->start - pooled_away;
            pooled_away += p->block[b].len - 1;
        }
        total += s->end - s->start - pooled_away;
    }
    p->before[p->lt - p->lh] = total;
    p->nblocks = total;
    p->hint = 0;
    p->hint_slot = p->lt > p->lh ? p->seg[p->live[p->lh]].lo : 0;
}

/* Between the chunks' passes and the fit: the join, on a ring the closure, the count. */
static void join_and_close(hsbd_pava *p, size_t nchunks, size_t n, int ring, double shift) {
    join_chunks(p, nchunks);
    if (ring) close_ring(p, n, shift);
    count_blocks(p);
}

/* One solve: the chunks' passes with their fits, the join, on a ring the closure, then the
 * fit of the pooled blocks. On threads the passes are shared out and the rest runs on one
 * thread. (The serial path has no work-sharing construct: called from inside another
 * parallel region, one would bind to that region's team.) The join reads the singletons
 * from y: weighted and in place, from a copy (the fit of a weighted singleton need not
 * give back its sum; an unweighted singleton's fit is its own value). */
static size_t solve(hsbd_pava *p, size_t n, const double *y, const double *w, int ring,
                    double shift, double *fit) {
    if (n == 0) return p->nblocks = 0;
    if (w && fit == y) {
        memcpy(p->saved, y, n * sizeof *y);
        y = p->saved;
    }
    p->y = y;
    p->w = w;
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
    join_and_close(p, nchunks, n, ring, shift);
    for (size_t k = p->lh; k < p->lt; ++k)
        write_pooled(p, k, n, shift, fit);
    p->y = p->w = NULL;
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

/* In segment s, the last stored block whose place is <= q, or s->lo when none is: from
 * `from` when q lies at or after its place (blocks asked for in order), else by
 * bisection. */
static size_t stored_at_or_before(const hsbd_pava *p, const pava_segment *s, size_t q,
                                  size_t from) {
    size_t lo = from >= s->lo && from < s->hi && p->item[from] <= q ? from : s->lo;
    if (lo + 1 < s->hi && p->item[lo + 1] <= q) { /* not from itself: bisect what follows */
        size_t hi = s->hi;
        while (hi - lo > 1) {
            const size_t mid = lo + (hi - lo) / 2;
            if (p->item[mid] <= q)
                lo = mid;
            else
                hi = mid;
        }
    }
    return lo;
}

size_t hsbd_pava_block_size(hsbd_pava *p, size_t k) {
    const size_t i = segment_of_block(p, k);
    const pava_segment *s = &p->seg[p->live[p->lh + i]];
    const size_t q = k - p->before[i];
    const size_t b = stored_at_or_before(p, s, q, i == p->hint ? p->hint_slot : s->lo);
    p->hint = i;
    p->hint_slot = b;
    return b < s->hi && p->item[b] == q ? p->block[b].len : 1;
}
