/* Counter-based random streams (Philox4x32-10, Random123).
 *
 * Key = the 64-bit seed; counter = (index / 2, step low, step high, stream). One Philox
 * call yields two 53-bit uniforms and hence, by Box-Muller, the normals of the index pair
 * (2k, 2k+1). The number an index receives at a step therefore depends only on
 * (seed, stream, step, index): not on processing order, threads, ranks or restarts. */
#ifndef HSBD_RNG_H
#define HSBD_RNG_H

#include "hsbd/export.h"
#include <stddef.h>
#include <stdint.h>

enum hsbd_stream {
    HSBD_STREAM_NOISE = 1,    /* Brownian displacements, one normal per rod per step */
    HSBD_STREAM_INIT = 2,     /* initial configurations */
    HSBD_STREAM_CONTACT = 3,  /* Brownian-bridge minima: rods' gaps (contact_rule = reflect,
                                 random bytes), spheres' walls (uniforms) */
    HSBD_STREAM_COMPRESS = 4, /* Brownian steps that compress dense initial states (spheres) */
    HSBD_STREAM_COMPRESS_CONTACT = 5, /* their bridge minima at walls (spheres) */
    HSBD_STREAM_CONTACT_DEPTH = 6,    /* rods, reflect rule: the low digits of the bridge minima */
    /* active particles (spheres): the rotational noise (normals), the acceptance of a 3D
     * rotation (uniforms), the initial orientations */
    HSBD_STREAM_ROTATION = 8,
    HSBD_STREAM_ROTATION_ACCEPT = 9,
    HSBD_STREAM_ORIENTATION_INIT = 10
};

/* Standard normals for indices first .. first+n-1 at counter `step` of `stream`. */
HSBD_API void hsbd_rng_normals(uint64_t seed, uint32_t stream, uint64_t step, size_t first,
                               size_t n, double *out);

/* Uniforms in the open interval (0, 1) for indices first .. first+n-1. */
HSBD_API void hsbd_rng_uniforms(uint64_t seed, uint32_t stream, uint64_t step, size_t first,
                                size_t n, double *out);

/* Uniforms of the indices base + offset[k], k < n (any order, repeats allowed), each the
 * number hsbd_rng_uniforms gives that index. */
HSBD_API void hsbd_rng_uniforms_at(uint64_t seed, uint32_t stream, uint64_t step, size_t base,
                                   const unsigned *offset, size_t n, double *out);

/* Random bytes, sixteen per Philox counter: the bytes of block b are those of the four
 * output words of counter b, each word least significant byte first. For k < n, the 16
 * bytes of block base + block[k] go to out[16 block[k]] .. out[16 block[k] + 15] (out
 * covers blocks base, base + 1, ...; only the listed ones are written). */
HSBD_API void hsbd_rng_bytes_at(uint64_t seed, uint32_t stream, uint64_t step, uint64_t base,
                                const unsigned *block, size_t n, uint8_t *out);

#endif
