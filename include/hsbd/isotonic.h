/* Weighted isotonic regression by pool-adjacent-violators (PAVA), O(n).
 *
 * Finds the non-decreasing fit minimising sum_i w_i (fit_i - y_i)^2. For hard rods in
 * contact-offset coordinates this is one whole Brownian-cluster-dynamics step
 * (fragmentation, Antonov Eqs. 4-5, and all time-ordered mergers, Eqs. 13-19); see
 * docs/algorithms.md. Blocks are pooled while the left mean is >= the right mean, so
 * the fitted blocks have strictly increasing means (Eq. 4) and every block satisfies the
 * prefix condition (Eq. 5). */
#ifndef HSBD_ISOTONIC_H
#define HSBD_ISOTONIC_H

#include "hsbd/export.h"
#include <stddef.h>

typedef struct hsbd_pava hsbd_pava;

HSBD_API hsbd_pava *hsbd_pava_alloc(size_t nmax);
HSBD_API void hsbd_pava_free(hsbd_pava *p);

/* On a line: fit_0 <= ... <= fit_{n-1}. w may be NULL (all weights 1). fit may alias y.
 * Returns the number of blocks. */
HSBD_API size_t hsbd_pava_line(hsbd_pava *p, size_t n, const double *y, const double *w,
                               double *fit);

/* On a ring whose sequence continues periodically as y_{i+n} = y_i + shift (shift > 0):
 * fit_0 <= ... <= fit_{n-1} <= fit_0 + shift. A block may wrap around (its members at
 * the start of the array then sit at block mean - shift). Returns the number of blocks. */
HSBD_API size_t hsbd_pava_ring(hsbd_pava *p, size_t n, const double *y, const double *w,
                               double shift, double *fit);

/* Blocks of the last call, in order: size of block k (0 <= k < number of blocks). */
HSBD_API size_t hsbd_pava_block_size(const hsbd_pava *p, size_t k);

#endif
