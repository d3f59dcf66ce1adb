#include "hsbd/rng.h"

#include <Random123/philox.h>
#include <math.h>

#include "core/vmath.h"

enum { RNG_CHUNK = 128 }; /* index pairs handled per inner batch (fits in L1) */

/* Two 53-bit uniforms in (0, 1) per index pair k = k0 .. k0+npairs-1. */
static void philox_uniform_pairs(uint64_t seed, uint32_t stream, uint64_t step, uint64_t k0,
                                 size_t npairs, double *restrict u1, double *restrict u2) {
    const philox4x32_key_t key = {{(uint32_t)seed, (uint32_t)(seed >> 32)}};
    const double scale = 0x1.0p-53;
    size_t j = 0;
#if defined(__x86_64__)
    if (hsbd_cpu_has_avx2()) { /* the same numbers, twelve counters at a time */
        j = npairs / 4 * 4;
        hsbd_philox_uniform_pairs_avx2(seed, stream, step, k0, j, u1, u2);
        if (j < npairs) { /* a tail of one to three pairs: four counters, the rest unused */
            double t1[4], t2[4];
            hsbd_philox_uniform_pairs_avx2(seed, stream, step, k0 + j, 4, t1, t2);
            for (size_t q = 0; j < npairs; ++j, ++q)
                u1[j] = t1[q], u2[j] = t2[q];
        }
    }
#endif
    for (; j < npairs; ++j) {
        const philox4x32_ctr_t ctr = {
            {(uint32_t)(k0 + j), (uint32_t)step, (uint32_t)(step >> 32), stream}};
        const philox4x32_ctr_t r = philox4x32(ctr, key);
        const uint64_t a = (((uint64_t)r.v[0] << 32) | r.v[1]) >> 11;
        const uint64_t b = (((uint64_t)r.v[2] << 32) | r.v[3]) >> 11;
        u1[j] = ((double)a + 0.5) * scale; /* never 0: log(u1) is finite */
        u2[j] = ((double)b + 0.5) * scale;
    }
}

/* The uniform pair of counter k (index pair), as philox_uniform_pairs gives it. */
static void philox_uniform_pair(uint64_t seed, uint32_t stream, uint64_t step, uint64_t k,
                                double *u1, double *u2) {
    philox_uniform_pairs(seed, stream, step, k, 1, u1, u2);
}

/* Calls body(pair_buffers) over the pairs that cover indices first .. first+n-1 and
 * copies the wanted half-pairs to out; shared by the normal and uniform generators. */
typedef void (*pair_transform)(size_t npairs, double *u1, double *u2);

static void fill_indices(uint64_t seed, uint32_t stream, uint64_t step, size_t first, size_t n,
                         double *out, pair_transform transform) {
    double u1[RNG_CHUNK], u2[RNG_CHUNK];
    size_t i = first;
    const size_t end = first + n;
    while (i < end) {
        const uint64_t k0 = i / 2;
        const uint64_t k_end = (end + 1) / 2;
        const size_t npairs = (size_t)(k_end - k0 < RNG_CHUNK ? k_end - k0 : RNG_CHUNK);
        philox_uniform_pairs(seed, stream, step, k0, npairs, u1, u2);
        if (transform) transform(npairs, u1, u2);
        for (size_t j = 0; j < npairs; ++j) {
            const size_t even = (size_t)(2 * (k0 + j));
            if (even >= first && even < end) out[even - first] = u1[j];
            if (even + 1 >= first && even + 1 < end) out[even + 1 - first] = u2[j];
        }
        i = (size_t)(2 * (k0 + npairs));
    }
}

/* Box-Muller: (u1, u2) -> two independent standard normals, in place. */
static void box_muller(size_t npairs, double *u1, double *u2) {
    hsbd_vmath_box_muller(npairs, u1, u2);
}

void hsbd_rng_normals(uint64_t seed, uint32_t stream, uint64_t step, size_t first, size_t n,
                      double *out) {
    fill_indices(seed, stream, step, first, n, out, box_muller);
}

void hsbd_rng_uniforms(uint64_t seed, uint32_t stream, uint64_t step, size_t first, size_t n,
                       double *out) {
    fill_indices(seed, stream, step, first, n, out, NULL);
}

void hsbd_rng_uniforms_at(uint64_t seed, uint32_t stream, uint64_t step, size_t base,
                          const unsigned *offset, size_t n, double *out) {
#if defined(__x86_64__)
    if (hsbd_cpu_has_avx2()) { /* twelve indices at a time, each picks its half of a pair */
        hsbd_philox_uniforms_at_avx2(seed, stream, step, base, offset, n, out);
        return;
    }
#endif
    for (size_t k = 0; k < n; ++k) {
        const size_t index = base + offset[k];
        double u1, u2;
        philox_uniform_pair(seed, stream, step, index / 2, &u1, &u2);
        out[k] = index % 2 ? u2 : u1;
    }
}

void hsbd_rng_bytes_at(uint64_t seed, uint32_t stream, uint64_t step, uint64_t base,
                       const unsigned *block, size_t n, uint8_t *out) {
#if defined(__x86_64__)
    if (hsbd_cpu_has_avx2()) { /* twelve blocks at a time */
        hsbd_philox_bytes_at_avx2(seed, stream, step, base, block, n, out);
        return;
    }
#endif
    const philox4x32_key_t key = {{(uint32_t)seed, (uint32_t)(seed >> 32)}};
    for (size_t k = 0; k < n; ++k) {
        const philox4x32_ctr_t ctr = {
            {(uint32_t)(base + block[k]), (uint32_t)step, (uint32_t)(step >> 32), stream}};
        const philox4x32_ctr_t r = philox4x32(ctr, key);
        uint8_t *b = out + 16 * (size_t)block[k];
        for (int i = 0; i < 16; ++i)
            b[i] = (uint8_t)(r.v[i / 4] >> (8 * (i % 4)));
    }
}

void hsbd_rng_bytes_and_four(uint64_t seed, uint64_t step, uint32_t byte_stream, uint64_t base,
                             const unsigned *block, size_t n, uint8_t *out, uint32_t uniform_stream,
                             uint64_t index, double *four) {
#if defined(__x86_64__)
    if (hsbd_cpu_has_avx2() && n <= 8) {
        hsbd_philox_bytes_and_four_avx2(seed, step, byte_stream, base, block, n, out,
                                        uniform_stream, index, four);
        return;
    }
#endif
    hsbd_rng_bytes_at(seed, byte_stream, step, base, block, n, out);
    hsbd_rng_uniforms(seed, uniform_stream, step, index, 4, four);
}
