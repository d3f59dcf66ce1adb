/* Helpers of the spheres tests that compare states: an FNV-1a hash of the positions and
 * image counters a view shows (user order), and the smallest gap over all pairs. */
#ifndef HSBD_TEST_SPHERE_CHECKS_H
#define HSBD_TEST_SPHERE_CHECKS_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "hsbd/spheres.h"

static const uint64_t FNV_BASIS = 0xcbf29ce484222325ull;

static inline uint64_t fnv1a(uint64_t h, const void *data, size_t bytes) {
    const unsigned char *p = data;
    for (size_t k = 0; k < bytes; ++k)
        h = (h ^ p[k]) * 0x100000001b3ull;
    return h;
}

/* The positions and image counters of s in the user's order. */
static inline uint64_t positions_hash(const hsbd_spheres *s) {
    const hsbd_spheres_view v = hsbd_spheres_get_view(s);
    const uint64_t h = fnv1a(FNV_BASIS, v.x, 3 * v.n * sizeof *v.x);
    return fnv1a(h, v.image, 3 * v.n * sizeof *v.image);
}

/* Smallest surface gap over all pairs relative to sigma_ij (brute force, minimum image). */
static inline double brute_min_gap(const hsbd_spheres_view *v) {
    double worst = INFINITY;
    for (size_t i = 0; i < v->n; ++i)
        for (size_t j = i + 1; j < v->n; ++j) {
            double r2 = 0;
            for (int a = 0; a < v->dimension; ++a) {
                double d = v->x[3 * j + a] - v->x[3 * i + a];
                d -= v->box[a] * nearbyint(d / v->box[a]);
                r2 += d * d;
            }
            const double sij = 0.5 * (v->sigma[i] + v->sigma[j]);
            worst = fmin(worst, (sqrt(r2) - sij) / sij);
        }
    return worst;
}

#endif
