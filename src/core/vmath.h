/* Bulk elementary functions for the hot loops (internal).
 *
 * On CPUs with AVX2+FMA these use SLEEF's vectorised functions (log: 1.0 ulp,
 * sinpi/cospi: 0.506 ulp, SLEEF's stated bounds); elsewhere glibc's scalar libm. The
 * choice is made per call from the CPU's features, so one binary runs everywhere. */
#ifndef HSBD_CORE_VMATH_H
#define HSBD_CORE_VMATH_H

#include <stddef.h>
#include <stdint.h>

/* In place: (u1, u2) uniforms in (0,1] -> sqrt(-2 ln u1) * (cos 2 pi u2, sin 2 pi u2). */
void hsbd_vmath_box_muller(size_t n, double *restrict u1, double *restrict u2);

/* out[i] = scale * sin(pi * t[i]). */
void hsbd_vmath_scaled_sinpi(size_t n, const double *restrict t, double scale,
                             double *restrict out);

/* Whether the vectorised (AVX2+FMA) path is in use on this CPU. */
int hsbd_vmath_vectorised(void);

/* The AVX2 kernels (vmath_avx2.c, compiled with -mavx2 -mfma); call only when
 * hsbd_vmath_vectorised() is true. They handle n % 4 tails themselves. */
void hsbd_vmath_box_muller_avx2(size_t n, double *restrict u1, double *restrict u2);
void hsbd_vmath_scaled_sinpi_avx2(size_t n, const double *restrict t, double scale,
                                  double *restrict out);

/* Whether this CPU has AVX2 (the integer kernels below need nothing else). */
int hsbd_cpu_has_avx2(void);
/* src/core/rng.c's uniform pairs for counters k0 .. k0 + npairs - 1, twelve at a time, then
 * a tail of eight or four (philox_avx2.c, -mavx2); npairs a multiple of 4. */
void hsbd_philox_uniform_pairs_avx2(uint64_t seed, uint32_t stream, uint64_t step, uint64_t k0,
                                    size_t npairs, double *restrict u1, double *restrict u2);
/* hsbd_rng_uniforms_at: the uniforms of the indices base + offset[k], k < n, twelve at a
 * time, the tail in one call. */
void hsbd_philox_uniforms_at_avx2(uint64_t seed, uint32_t stream, uint64_t step, uint64_t base,
                                  const unsigned *offset, size_t n, double *restrict out);

/* hsbd_rng_bytes_at: twelve blocks at a time, the tail in one call. */
void hsbd_philox_bytes_at_avx2(uint64_t seed, uint32_t stream, uint64_t step, uint64_t base,
                               const unsigned *block, size_t n, uint8_t *restrict out);

/* hsbd_rng_bytes_at's bytes of n <= 8 blocks (stream byte_stream) and hsbd_rng_uniforms'
 * uniforms of the indices index .. index + 3 (uniform_stream) into four[]: with AVX2 in one
 * call, whose chains of multiplies run side by side where two calls would wait for two
 * (src/core/rng.c; the AVX2 kernel in philox_avx2.c). */
void hsbd_rng_bytes_and_four(uint64_t seed, uint64_t step, uint32_t byte_stream, uint64_t base,
                             const unsigned *block, size_t n, uint8_t *out, uint32_t uniform_stream,
                             uint64_t index, double *four);
void hsbd_philox_bytes_and_four_avx2(uint64_t seed, uint64_t step, uint32_t byte_stream,
                                     uint64_t base, const unsigned *block, size_t n,
                                     uint8_t *restrict out, uint32_t uniform_stream, uint64_t index,
                                     double *restrict four);

/* In place: x[i] -> ln x[i] (SLEEF's faster vector log, 3.5 ulp, with AVX2+FMA; else libm). */
void hsbd_vmath_log(size_t n, double *x);
void hsbd_vmath_log_avx2(size_t n, double *x);

#endif
