/* PAVA on small hand-checked cases, weights, and ring versus line; sequences longer than a
 * chunk (solved chunk by chunk, joined at the seams, on threads) against one serial pass
 * over the whole sequence. */
#include <stdint.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/isotonic.h"

static void test_known_cases(void) {
    hsbd_pava *p = hsbd_pava_alloc(8);
    double fit[8];
    const double y1[] = {1, 3, 2, 4};
    CHECK(hsbd_pava_line(p, 4, y1, NULL, fit) == 3, "blocks");
    CHECK(fit[0] == 1 && fit[1] == 2.5 && fit[2] == 2.5 && fit[3] == 4, "fit %g %g %g %g", fit[0],
          fit[1], fit[2], fit[3]);
    const double y2[] = {5, 4, 3, 2, 1};
    CHECK(hsbd_pava_line(p, 5, y2, NULL, fit) == 1 && fit[0] == 3 && fit[4] == 3, "all pooled");
    const double y3[] = {0, 3}, w3[] = {3, 1};
    CHECK(hsbd_pava_line(p, 2, y3, w3, fit) == 2 && fit[1] == 3, "ordered input untouched");
    const double y4[] = {3, 0};
    CHECK(hsbd_pava_line(p, 2, y4, w3, fit) == 1, "one block");
    CHECK_CLOSE(fit[0], 9.0 / 4.0, 1e-15); /* weighted mean (3*3 + 1*0)/4 */
    CHECK(hsbd_pava_block_size(p, 0) == 2, "block size");
    hsbd_pava_free(p);
}

static void test_ring(void) {
    hsbd_pava *p = hsbd_pava_alloc(8);
    double fit[8];
    /* far from the wrap, the ring is the line */
    const double y[] = {0.1, 0.5, 0.3, 0.9};
    CHECK(hsbd_pava_ring(p, 4, y, NULL, 10.0, fit) == 3, "ring = line");
    CHECK(fit[1] == 0.4 && fit[2] == 0.4, "pooled pair");
    /* last element's image violates the first: they pool across the wrap */
    const double yw[] = {0.0, 0.5, 1.2}; /* shift 1: image of y0 sits at 1.0 < 1.2 */
    const size_t nb = hsbd_pava_ring(p, 3, yw, NULL, 1.0, fit);
    CHECK(nb == 2, "wrapping block: %zu blocks", nb);
    CHECK_CLOSE(fit[2], 1.1, 1e-15);
    CHECK_CLOSE(fit[0], 0.1, 1e-15); /* = block mean - shift */
    CHECK(fit[0] <= fit[1] && fit[1] <= fit[2] && fit[2] <= fit[0] + 1.0, "ring order");
    /* a single element never pools with its own image */
    const double y1[] = {0.7};
    CHECK(hsbd_pava_ring(p, 1, y1, NULL, 0.5, fit) == 1 && fit[0] == 0.7, "n = 1");
    hsbd_pava_free(p);
}

/* ---- the reference: one pass over the whole sequence ---- */

typedef struct ref_block {
    double sum, weight;
    size_t len;
} ref_block;

static int ref_violates(const ref_block *a, const ref_block *b) {
    return a->sum * b->weight >= b->sum * a->weight;
}

static void ref_pool(ref_block *a, const ref_block *b) { /* left block first */
    a->sum += b->sum;
    a->weight += b->weight;
    a->len += b->len;
}

/* Elements pushed left to right and pooled backwards while the last two blocks violate; on
 * a ring the first block's image (+shift) is then pooled into the last while they violate.
 * blk holds n + 1 blocks; returns the block count, the blocks in blk[*head ..), the first
 * starting at element *start. The operations and their order are those of a single pass,
 * so the bits are too. */
static size_t ref_pava(size_t n, const double *y, const double *w, int ring, double shift,
                       ref_block *blk, size_t *head, size_t *start) {
    size_t h = 0, t = 0;
    for (size_t i = 0; i < n; ++i) {
        ref_block cur = {w ? w[i] * y[i] : y[i], w ? w[i] : 1.0, 1};
        while (t > h && ref_violates(&blk[t - 1], &cur)) {
            ref_block below = blk[--t];
            ref_pool(&below, &cur);
            cur = below;
        }
        blk[t++] = cur;
    }
    size_t s = 0;
    while (ring && t - h >= 2) {
        ref_block cur = blk[h];
        cur.sum += shift * cur.weight;
        if (!ref_violates(&blk[t - 1], &cur)) break;
        s += cur.len;
        ++h;
        while (t > h && ref_violates(&blk[t - 1], &cur)) {
            ref_block below = blk[--t];
            ref_pool(&below, &cur);
            cur = below;
        }
        blk[t++] = cur;
    }
    *head = h;
    *start = s;
    return t - h;
}

static double ref_mean(const ref_block *b) {
    return b->weight == 1.0 ? b->sum : b->sum / b->weight;
}

/* splitmix64 as a uniform in [0, 1) */
static double uniform(uint64_t *state) {
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return (double)((z ^ (z >> 31)) >> 11) * 0x1p-53;
}

enum { SHAPE_NOISY, SHAPE_ROUGH, SHAPE_SAWTOOTH, SHAPE_WRAP, SHAPE_TIES, SHAPES };

/* End points of a step-like sequence on [0, shift): an increasing line with noise that
 * pools a few neighbours (or, rough, blocks of tens to hundreds); a sawtooth whose long
 * falling teeth are blocks across several chunks (a whole chunk swallowed at a seam); or
 * noise with the last elements far right and the first far left, so that a ring pools
 * across the wrap; or values on a coarse grid, so that equal neighbours (which pool) are
 * common and runs of them long. */
static void make_sequence(int shape, size_t n, double shift, uint64_t *rng, double *y) {
    for (size_t i = 0; i < n; ++i) {
        const double base = shift * ((double)i + 0.5) / (double)n;
        const double amplitude = shape == SHAPE_ROUGH ? 300.0 : 3.0;
        const double noise = amplitude * shift / (double)n * (uniform(rng) - 0.5);
        y[i] = base + noise;
        if (shape == SHAPE_SAWTOOTH) {
            const size_t tooth = 5 * HSBD_PAVA_CHUNK / 2 + 77;
            y[i] -= 2.0 * shift * (double)(i % tooth) / (double)n;
        }
    }
    if (shape == SHAPE_TIES)
        for (size_t i = 0; i < n; ++i)
            y[i] = floor(y[i] / (20.0 * shift / (double)n)) * (20.0 * shift / (double)n);
    if (shape == SHAPE_WRAP)
        for (size_t i = 0; i < n / 50; ++i) {
            y[n - 1 - i] += 0.02 * shift;
            y[i] -= 0.02 * shift;
        }
}

/* The chunked solve against the reference: the same blocks, fits equal to rounding (and
 * to the bit up to one chunk), and the same bits on 1 to 4 threads and in place. */
static void compare_with_reference(size_t n, int ring, int weighted, int shape, uint64_t seed) {
    const double shift = 0.5 * (double)n;
    uint64_t rng = seed;
    double *y = malloc(n * sizeof *y), *w = malloc(n * sizeof *w), *fit = malloc(n * sizeof *fit);
    double *fit1 = malloc(n * sizeof *fit1), *ref = malloc(n * sizeof *ref);
    ref_block *blk = malloc((n + 1) * sizeof *blk);
    hsbd_pava *p = hsbd_pava_alloc(n);
    if (!y || !w || !fit || !fit1 || !ref || !blk || !p) {
        CHECK(0, "out of memory");
        return;
    }
    make_sequence(shape, n, shift, &rng, y);
    for (size_t i = 0; i < n; ++i)
        w[i] = 0.5 + 2.0 * uniform(&rng);
    const double *wt = weighted ? w : NULL;
    size_t head, start;
    const size_t nref = ref_pava(n, y, wt, ring, shift, blk, &head, &start);
    for (size_t b = head, j = start; b < head + nref; ++b)
        for (size_t k = 0; k < blk[b].len; ++k, ++j)
            ref[j % n] = ref_mean(&blk[b]) - (j >= n ? shift : 0.0);
    const char *what = ring ? "ring" : "line";
    /* With ties a seam's rounding may decide whether two equal means pool: across chunks
     * the blocks (not the fit) may then differ from the one pass. */
    const int same_blocks = shape != SHAPE_TIES || n <= HSBD_PAVA_CHUNK;
    size_t nb1 = 0;
    for (int threads = 1; threads <= 4; ++threads) {
        hsbd_pava_set_threads(p, threads);
        const size_t nb =
            ring ? hsbd_pava_ring(p, n, y, wt, shift, fit) : hsbd_pava_line(p, n, y, wt, fit);
        if (threads == 1 && same_blocks) {
            CHECK(nb == nref, "%s n %zu shape %d: %zu blocks, one pass %zu", what, n, shape, nb,
                  nref);
            size_t same_sizes = 1;
            for (size_t k = 0; k < nb && k < nref; ++k)
                same_sizes &= hsbd_pava_block_size(p, k) == blk[head + k].len;
            CHECK(same_sizes, "%s n %zu shape %d: block sizes differ", what, n, shape);
            /* backwards and by strides: the lookups that do not follow the last one */
            for (size_t k = nb < nref ? nb : nref; k-- > 0;)
                same_sizes &= hsbd_pava_block_size(p, k) == blk[head + k].len;
            for (size_t k = 0, m = nb < nref ? nb : nref; m && k < 3 * m; k += 997)
                same_sizes &= hsbd_pava_block_size(p, k % m) == blk[head + k % m].len;
            CHECK(same_sizes, "%s n %zu shape %d: block sizes out of order differ", what, n, shape);
        }
        if (threads == 1) {
            nb1 = nb;
            double worst = 0;
            for (size_t i = 0; i < n; ++i)
                worst = fmax(worst, fabs(fit[i] - ref[i]));
            CHECK(worst <= 1e-12 * shift, "%s n %zu shape %d: fit off by %g", what, n, shape,
                  worst);
            if (n <= HSBD_PAVA_CHUNK)
                CHECK(memcmp(fit, ref, n * sizeof *fit) == 0,
                      "%s n %zu shape %d: one chunk is not the one pass to the bit", what, n,
                      shape);
            memcpy(fit1, fit, n * sizeof *fit);
            /* in place (fit aliasing y) */
            double *yy = malloc(n * sizeof *yy);
            if (!yy) continue;
            memcpy(yy, y, n * sizeof *yy);
            if (ring)
                hsbd_pava_ring(p, n, yy, wt, shift, yy);
            else
                hsbd_pava_line(p, n, yy, wt, yy);
            CHECK(memcmp(yy, fit1, n * sizeof *yy) == 0, "%s n %zu: in place differs", what, n);
            free(yy);
        } else {
            CHECK(nb == nb1 && memcmp(fit, fit1, n * sizeof *fit) == 0,
                  "%s n %zu shape %d: %d threads differ from one", what, n, shape, threads);
        }
    }
    free(y);
    free(w);
    free(fit);
    free(fit1);
    free(ref);
    free(blk);
    hsbd_pava_free(p);
}

static void test_chunks_against_one_pass(void) {
    const size_t K = HSBD_PAVA_CHUNK;
    const size_t sizes[] = {1000, K, K + 1, 2 * K + 17, 5 * K + 3, 20 * K};
    uint64_t seed = 1;
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; ++s)
        for (int ring = 0; ring <= 1; ++ring)
            for (int weighted = 0; weighted <= 1; ++weighted)
                for (int shape = 0; shape < SHAPES; ++shape)
                    compare_with_reference(sizes[s], ring, weighted, shape, seed++);
}

int main(void) {
    test_known_cases();
    test_ring();
    test_chunks_against_one_pass();
    return test_finish("test_isotonic");
}
