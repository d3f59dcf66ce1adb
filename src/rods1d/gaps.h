/* The reflect rule's passes over a batch of gaps (internal to src/rods1d): which gaps may
 * have touched zero during the step, and which of those a uniform does not clear. Each
 * has a scalar and an AVX2 version, chosen at run time; both evaluate the same IEEE
 * operations in the same order (no FMA), so they give the same lists and the same numbers
 * (tests/unit/test_bcd_step.c checks it).
 *
 * A gap runs from g0 at the step's start to g1 at its free end; its increments have
 * variance 2 d_rel dt (d_rel: the pair's relative diffusion). The minimum m of its Brownian
 * bridge has P(m < x) = exp(-(g0 - x)(g1 - x) / (d_rel dt)) (design note 7). */
#ifndef HSBD_RODS1D_GAPS_H
#define HSBD_RODS1D_GAPS_H

#include <stddef.h>

/* The gap may have touched zero: its crossing probability exp(-g0 g1 / d_rel_dt) is not
 * below 2e-9. */
static inline int bridge_may_cross(double g0, double g1, double d_rel_dt) {
    return !(g1 > 0) | !(g0 * g1 > 20.0 * d_rel_dt); /* no branch: | evaluates both */
}

/* A gap that may cross whose uniform u shows, without a log, that its bridge minimum stays
 * >= 0 (bcd.c's bridge_push_with would return +0.0). The minimum is < 0 when
 * -ln u > g0 g1 / d_rel_dt, and -ln u <= (1 - u) / u, so 4 d_rel_dt (1 - u) < 4 g0 g1 u
 * (times u > 0) rules the crossing out. The relative margin of 1e-12 covers every rounding
 * of this test and of the minimum (a few ulps, with libm's log within one), so the sign of
 * the computed minimum is the one this test implies. */
static inline int bridge_surely_clear(double g0, double g1, double d_rel_dt, double u) {
    const double a = g0 + g1;
    return 4.0 * d_rel_dt * (1.0 - u) * (1.0 + 1e-12) + 1e-12 * a * a * u < 4.0 * g0 * g1 * u;
}

/* The gaps j < m that may cross zero, in order into idx[], and their values at the start
 * and the end into g0[] and g1[] (each with room for m); returns their number. Gap j is
 * z[j + 1] - z[j] at the start and y[j + 1] - y[j] at the free end, with relative diffusion
 * times dt d[j], or d_one for every gap when d is NULL. */
size_t gap_list_may_cross(const double *z, const double *y, const double *d, double d_one, size_t m,
                          unsigned *idx, double *g0, double *g1);
/* The places k < count of the listed gaps (values g0[k], g1[k], relative diffusion times
 * dt d[k] or d_one, uniform u[k]) that bridge_surely_clear does not clear, in order into
 * keep[] (room for count); returns their number. */
size_t gap_list_uncertain(const double *g0, const double *g1, const double *d, double d_one,
                          const double *u, size_t count, unsigned *keep);

/* The versions (the dispatchers above call the AVX2 ones when the CPU has AVX2; on other
 * processors those list nothing and return 0): */
size_t gap_list_may_cross_scalar(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, unsigned *idx, double *g0, double *g1);
size_t gap_list_may_cross_avx2(const double *z, const double *y, const double *d, double d_one,
                               size_t m, unsigned *idx, double *g0, double *g1);
size_t gap_list_uncertain_scalar(const double *g0, const double *g1, const double *d, double d_one,
                                 const double *u, size_t count, unsigned *keep);
size_t gap_list_uncertain_avx2(const double *g0, const double *g1, const double *d, double d_one,
                               const double *u, size_t count, unsigned *keep);

#endif
