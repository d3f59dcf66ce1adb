/* The reflect rule's passes over a batch of gaps (internal to src/rods1d): which gaps may
 * have touched zero during the step, and which of those the top byte of their uniform
 * leaves as candidates for a crossing. A scalar and an AVX2 version of each, chosen at run
 * time; both evaluate the same IEEE operations (no FMA), so they give the same lists
 * (tests/unit/test_bcd_step.c checks it). */
#ifndef HSBD_RODS1D_GAPS_H
#define HSBD_RODS1D_GAPS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

/* gaps per block: one Philox counter gives a random byte to each (hsbd_rng_bytes_at) */
enum { GAP_BLOCK = 16 };

/* A gap from g0 to its free end g1 (relative diffusion times dt: d_rel_dt) may have touched
 * zero: its crossing probability exp(-g0 g1 / d_rel_dt) is not below 2e-9. */
static inline int bridge_may_cross(double g0, double g1, double d_rel_dt) {
    return !(g1 > 0) | !(g0 * g1 > 20.0 * d_rel_dt); /* no branch: | evaluates both */
}

/* 256 times an upper bound of the crossing probability p = exp(-g0 g1 / d_rel_dt) = 2^-e of
 * a gap, given its product g0 g1: with e = t + r, t the whole number nearest to e and
 * |r| <= 1/2, 2^-r <= 1.0607 - 0.7071 r (above the chord of the convex 2^-r over
 * [-1/2, 1/2], by 5e-5 at its ends), so 256 2^-t (1.0607 - 0.7071 r) >= 256 p, at most 6 %
 * above it; the margin covers the rounding here and in the bridge minimum's formula. e is
 * taken in [0, 60] (256 and more for p = 1: g0 g1 <= 0, or NaN), and t made by adding 2^52,
 * which rounds to the nearest whole number. A gap whose random byte b has b >= this bound has
 * a uniform U = (b + V) / 256 >= p whatever its low digits V: it does not cross. */
static inline double bridge_byte_bound(double g0g1, double d_rel_dt) {
    const double e0 = g0g1 * (1.4426950408889634 / d_rel_dt);       /* log2(e) / D_rel dt */
    const double e1 = e0 > 0 ? e0 : 0.0, e = e1 < 60.0 ? e1 : 60.0; /* as maxpd, minpd */
    const double t = (e + 0x1p52) - 0x1p52;
    return ldexp(256.0, -(int)t) * (1.0607 - 0.7071 * (e - t));
}

/* The blocks of GAP_BLOCK gaps among gaps j < m that hold a gap that may cross: bit i of
 * mask[b] is gap GAP_BLOCK b + i (mask has room for ceil(m / GAP_BLOCK)), and the blocks with
 * a bit set are listed in order in blocks[]; returns their number. Gap j runs from
 * z[j + 1] - z[j] at the step's start to y[j + 1] - y[j] at its free end, with relative
 * diffusion times dt d[j], or d_one for every gap when d is NULL; the products of the two,
 * g0 g1, go to g0g1[j]. */
size_t gap_blocks_may_cross(const double *z, const double *y, const double *d, double d_one,
                            size_t m, uint16_t *mask, unsigned *blocks, double *g0g1);

/* The candidates among the gaps that may cross of the listed blocks (from
 * gap_blocks_may_cross, with its products g0g1): the gaps whose random byte bytes[j] is below
 * bridge_byte_bound, in order into idx[] (room for m rounded up to a whole block); returns
 * their number. */
size_t gap_candidates(const double *g0g1, const double *d, double d_one, size_t m,
                      const uint16_t *mask, const unsigned *blocks, size_t nblocks,
                      const uint8_t *bytes, unsigned *idx);

/* The two versions of each (the plain names call the AVX2 ones when the CPU has it; the
 * AVX2 ones return 0 elsewhere, for the test): */
size_t gap_blocks_may_cross_scalar(const double *z, const double *y, const double *d, double d_one,
                                   size_t m, uint16_t *mask, unsigned *blocks, double *g0g1);
size_t gap_blocks_may_cross_avx2(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, uint16_t *mask, unsigned *blocks, double *g0g1);
size_t gap_candidates_scalar(const double *g0g1, const double *d, double d_one, size_t m,
                             const uint16_t *mask, const unsigned *blocks, size_t nblocks,
                             const uint8_t *bytes, unsigned *idx);
size_t gap_candidates_avx2(const double *g0g1, const double *d, double d_one, size_t m,
                           const uint16_t *mask, const unsigned *blocks, size_t nblocks,
                           const uint8_t *bytes, unsigned *idx);

#endif
