/* Weighted isotonic regression by pool-adjacent-violators (PAVA), O(n).
 *
 * Finds the non-decreasing fit minimising sum_i w_i (fit_i - y_i)^2. For hard rods in
 * contact-offset coordinates this is one whole Brownian-cluster-dynamics step
 * (fragmentation, Antonov Eqs. 4-5, and all time-ordered mergers, Eqs. 13-19); see
 * docs/algorithms.md. Blocks are pooled while the left mean is >= the right mean, so
 * the fitted blocks have strictly increasing means (Eq. 4) and every block satisfies the
 * prefix condition (Eq. 5).
 *
 * Sequences longer than HSBD_PAVA_CHUNK elements are solved in chunks of that many: PAVA
 * on each chunk (on threads, see hsbd_pava_set_threads), then a join left to right that
 * pools each chunk's blocks onto the blocks before it (PAVA of the concatenated chunk
 * solutions: the same unique solution). The chunks do not depend on the number of
 * threads, so neither do the bits; they differ from one pass over the whole sequence only
 * in the rounding of blocks that span a seam. Up to HSBD_PAVA_CHUNK elements the solve is
 * the one pass. */
#ifndef HSBD_ISOTONIC_H
#define HSBD_ISOTONIC_H

#include "hsbd/export.h"
#include <stddef.h>

typedef struct hsbd_pava hsbd_pava;

#define HSBD_PAVA_CHUNK 4096 /* elements per chunk of a long sequence */

HSBD_API hsbd_pava *hsbd_pava_alloc(size_t nmax);
HSBD_API void hsbd_pava_free(hsbd_pava *p);

/* Threads that share out the chunks' passes and the fit of sequences longer than one
 * chunk (default 1; OpenMP builds). The results do not depend on it. */
HSBD_API void hsbd_pava_set_threads(hsbd_pava *p, int threads);

/* On a line: fit_0 <= ... <= fit_{n-1}. w may be NULL (all weights 1). fit may alias y.
 * Returns the number of blocks. */
HSBD_API size_t hsbd_pava_line(hsbd_pava *p, size_t n, const double *y, const double *w,
                               double *fit);

/* On a ring whose sequence continues periodically as y_{i+n} = y_i + shift (shift > 0):
 * fit_0 <= ... <= fit_{n-1} <= fit_0 + shift. A block may wrap around (its members at
 * the start of the array then sit at block mean - shift). Returns the number of blocks. */
HSBD_API size_t hsbd_pava_ring(hsbd_pava *p, size_t n, const double *y, const double *w,
                               double shift, double *fit);

/* Blocks of the last call, in order: size of block k (0 <= k < number of blocks). O(1)
 * when the blocks are asked for in order (a bisection over the few blocks of more than one
 * element when one is passed), O(log n) otherwise (it keeps where the last one was, hence
 * the non-const object). */
HSBD_API size_t hsbd_pava_block_size(hsbd_pava *p, size_t k);

#endif
