/* The reflect rule's passes over a batch of gaps (internal to src/rods1d): which gaps may
 * have touched zero during the step, which of those the top byte of their uniform leaves
 * as candidates for a crossing, the candidates' pushes and the rods' shares of them. A
 * scalar and an AVX2 version of each, chosen at run time; both evaluate the same IEEE
 * operations in the same order (no FMA), so they give the same bits
 * (tests/unit/test_bcd_step.c checks it). */
#ifndef HSBD_RODS1D_GAPS_H
#define HSBD_RODS1D_GAPS_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* gaps per block: one Philox counter gives a random byte to each (hsbd_rng_bytes_at) */
enum { GAP_BLOCK = 16 };

/* A gap from g0 to its free end g1 (relative diffusion times dt: d_rel_dt) may have touched
 * zero: its crossing probability exp(-g0 g1 / d_rel_dt) is not below 2e-9. */
static inline int bridge_may_cross(double g0, double g1, double d_rel_dt) {
    return !(g1 > 0) | !(g0 * g1 > 20.0 * d_rel_dt); /* no branch: | evaluates both */
}

/* Whether a gap that may cross, given its product g0 g1, is a candidate for a crossing
 * with its random byte b, the top eight bits of its uniform U = (b + V) / 256. It crosses
 * when U < p = 2^-E, E = g0 g1 log2(e) / D_rel dt (the bridge minimum's law), which needs
 * b / 256 < p, i.e. log2 b < 8 - E. A float's bits read as a whole number are
 * 2^23 (127 + k + f) for b = 2^k (1 + f), and k + f <= k + log2(1 + f) = log2 b (within
 * 0.086): so b is no candidate when E + k + f >= 8, and the candidates,
 * E 2^23 + bits < 135 2^23 (with a margin of 2^-16 in E for the rounding here and in the
 * bridge minimum's formula), are at most 6 % (2^0.086) more bytes than can cross. b = 0
 * (bits 0) is a candidate unless E >= 135. */
static inline int bridge_byte_candidate(double g0g1, double d_rel_dt, unsigned b) {
    const double e = g0g1 * (0x1p23 * 1.4426950408889634 / d_rel_dt); /* 2^23 E */
    const float fb = (float)b;
    uint32_t bits;
    memcpy(&bits, &fb, sizeof bits);
    return e + (double)bits < 0x1p23 * (135.0 + 0x1p-16);
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
 * gap_blocks_may_cross, with its products g0g1): the gaps whose random byte bytes[j] makes
 * them a candidate (bridge_byte_candidate), in order into idx[] (room for m rounded up to a
 * whole block); returns their number. */
size_t gap_candidates(const double *g0g1, const double *d, double d_one, size_t m,
                      const uint16_t *mask, const unsigned *blocks, size_t nblocks,
                      const uint8_t *bytes, unsigned *idx);

/* Both at once for all gaps j < m, given the bytes of every block: the candidates of
 * gap_blocks_may_cross then gap_candidates, in order into idx[] (room for m rounded up to a
 * whole block); returns their number, and in *listed the number of blocks that hold a gap
 * that may cross. */
size_t gap_candidates_all(const double *z, const double *y, const double *d, double d_one, size_t m,
                          const uint8_t *bytes, unsigned *idx, size_t *listed);

/* The pushes -m > 0 of `count` gaps (0 where the bridge minimum m >= 0), in place of their
 * ln U: m = (a - sqrt(s - 4 D_rel dt ln U)) / 2 from their sums a = g0 + g1, squared
 * differences s = (g1 - g0)^2 and D_rel dt (d[k], or d_one when d is NULL). */
void gap_pushes(size_t count, const double *sum, const double *sq, const double *d, double d_one,
                double *ln_u);

/* to[0 .. n) = from[0 .. n), or 0 when from is NULL: with AVX2 in vectors, where memset and
 * memcpy become `rep` string instructions whose start costs more than a batch of 80 */
void gap_copy(size_t n, const double *from, double *to);

/* out[i] = y[i] + push[i - 1] / 2 - push[i] / 2, i < n (in this order): rods of one species
 * between two gaps take half of each gap's push */
void gap_half_pushes(size_t n, const double *y, const double *push, double *out);
/* The same for rods 1 .. m - 1 of a batch of gaps 0 .. m - 1 whose pushes are 0 but at the
 * `count` gaps idx[] (in order): y, then their halves; the same numbers when few. */
void gap_half_pushes_at(size_t m, const double *y, const double *push, const unsigned *idx,
                        size_t count, double *out);

/* The two versions of each (the plain names call the AVX2 ones when the CPU has it; built
 * without AVX2, those fall back to the scalar ones, for the test): */
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
size_t gap_candidates_all_scalar(const double *z, const double *y, const double *d, double d_one,
                                 size_t m, const uint8_t *bytes, unsigned *idx, size_t *listed);
size_t gap_candidates_all_avx2(const double *z, const double *y, const double *d, double d_one,
                               size_t m, const uint8_t *bytes, unsigned *idx, size_t *listed);
void gap_pushes_scalar(size_t count, const double *sum, const double *sq, const double *d,
                       double d_one, double *ln_u);
void gap_pushes_avx2(size_t count, const double *sum, const double *sq, const double *d,
                     double d_one, double *ln_u);
void gap_half_pushes_scalar(size_t n, const double *y, const double *push, double *out);
void gap_half_pushes_avx2(size_t n, const double *y, const double *push, double *out);
void gap_copy_avx2(size_t n, const double *from, double *to);

#endif
