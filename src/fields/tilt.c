/* Constant force (tilted potential U(x) = -f x). */
#include "hsbd/field.h"

static void tilt_add_force(const hsbd_field_term *t, size_t n, const double *restrict x,
                           double *restrict f) {
    (void)x;
    const double force = t->p[0];
    for (size_t i = 0; i < n; ++i)
        f[i] += force;
}

static double tilt_potential(const hsbd_field_term *t, double x) {
    return -t->p[0] * x;
}

static double tilt_max_curvature(const hsbd_field_term *t) {
    (void)t;
    return 0.0;
}

static const hsbd_field_ops tilt_ops = {.name = "tilt",
                                        .strength = 1,
                                        .position = 0,
                                        .add_force = tilt_add_force,
                                        .potential = tilt_potential,
                                        .max_curvature = tilt_max_curvature};

hsbd_field_term hsbd_field_tilt(double force) {
    hsbd_field_term t = {.ops = &tilt_ops};
    t.p[0] = force;
    return t;
}
