/* The reflect rule's first pass over a batch of gaps (internal to src/rods1d): which gaps
 * may have touched zero during the step. A scalar and an AVX2 version, chosen at run time;
 * both evaluate the same IEEE operations (no FMA), so they list the same gaps
 * (tests/unit/test_bcd_step.c checks it). */
#ifndef HSBD_RODS1D_GAPS_H
#define HSBD_RODS1D_GAPS_H

#include <stddef.h>

/* A gap from g0 to its free end g1 (relative diffusion times dt: d_rel_dt) may have touched
 * zero: its crossing probability exp(-g0 g1 / d_rel_dt) is not below 2e-9. */
static inline int bridge_may_cross(double g0, double g1, double d_rel_dt) {
    return !(g1 > 0) | !(g0 * g1 > 20.0 * d_rel_dt); /* no branch: | evaluates both */
}

/* The gaps j < m that may cross zero, in order into idx[] (room for m); returns their
 * number. Gap j runs from z[j + 1] - z[j] at the step's start to y[j + 1] - y[j] at its free
 * end, with relative diffusion times dt d[j], or d_one for every gap when d is NULL. */
size_t gap_list_may_cross(const double *z, const double *y, const double *d, double d_one, size_t m,
                          unsigned *idx);
/* The two versions (gap_list_may_cross calls the AVX2 one when the CPU has it; the AVX2
 * one returns 0 elsewhere, for the test): */
size_t gap_list_may_cross_scalar(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, unsigned *idx);
size_t gap_list_may_cross_avx2(const double *z, const double *y, const double *d, double d_one,
                               size_t m, unsigned *idx);

#endif
