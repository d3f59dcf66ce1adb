/* Helpers of the spheres tests: an FNV-1a hash of the positions and image counters a view
 * shows (user order), the smallest gap over all pairs, and a one-size fluid's parameters. */
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

/* Smallest surface gap over all pairs relative to sigma_ij (brute force, minimum image
 * along the periodic axes) and to the walls relative to sigma_i, as hsbd_spheres_min_gap. */
static inline double brute_min_gap(const hsbd_spheres_view *v) {
    double worst = INFINITY;
    for (size_t i = 0; i < v->n; ++i) {
        for (int a = 0; a < v->dimension; ++a)
            if (v->walls[a]) {
                const double x = v->x[3 * i + a], half = 0.5 * v->sigma[i];
                worst = fmin(worst, fmin(x - half, v->box[a] - half - x) / v->sigma[i]);
            }
        for (size_t j = i + 1; j < v->n; ++j) {
            double r2 = 0;
            for (int a = 0; a < v->dimension; ++a) {
                double d = v->x[3 * j + a] - v->x[3 * i + a];
                if (!v->walls[a]) d -= v->box[a] * nearbyint(d / v->box[a]);
                r2 += d * d;
            }
            const double sij = 0.5 * (v->sigma[i] + v->sigma[j]);
            worst = fmin(worst, (sqrt(r2) - sij) / sij);
        }
    }
    return worst;
}

/* n hard spheres (dim 3) or disks (dim 2), sigma = D = kT = 1, at packing fraction phi in
 * a cubic or square periodic box, dt 1e-3. */
static inline hsbd_spheres_params fluid_params(int dim, size_t n, double phi, uint64_t seed) {
    const double pi = 3.14159265358979323846;
    const double side = dim == 3 ? cbrt((double)n * pi / 6 / phi) : sqrt((double)n * pi / 4 / phi);
    return (hsbd_spheres_params){.n = n,
                                 .dimension = dim,
                                 .box = {side, side, side},
                                 .sigma = 1,
                                 .diffusion = 1,
                                 .kT = 1,
                                 .dt = 1e-3,
                                 .seed = seed,
                                 .hard_core = 1};
}

#endif
