/* Harmonic trap U(x) = (k/2) (x - center)^2, nearest image on a ring. */
#include <math.h>

#include "hsbd/field.h"

enum { HARM_K, HARM_CENTER, HARM_PERIOD };

/* x - center, reduced to the nearest image when the line is a ring */
static double displacement(const hsbd_field_term *t, double x) {
    const double d = x - t->p[HARM_CENTER], period = t->p[HARM_PERIOD];
    return period > 0 ? d - period * floor(d / period + 0.5) : d;
}

/* f = -dU/dx = -k d (kT/length) */
static void harmonic_add_force(const hsbd_field_term *t, size_t n, const double *restrict x,
                               double *restrict f) {
    const double k = t->p[HARM_K];
    for (size_t i = 0; i < n; ++i)
        f[i] -= k * displacement(t, x[i]);
}

static double harmonic_potential(const hsbd_field_term *t, double x) {
    const double d = displacement(t, x);
    return 0.5 * t->p[HARM_K] * d * d;
}

static double harmonic_max_curvature(const hsbd_field_term *t) {
    return fabs(t->p[HARM_K]);
}

static const hsbd_field_ops harmonic_ops = {.name = "harmonic",
                                            .strength = HARM_K + 1,
                                            .position = HARM_CENTER + 1,
                                            .add_force = harmonic_add_force,
                                            .potential = harmonic_potential,
                                            .max_curvature = harmonic_max_curvature};

hsbd_field_term hsbd_field_harmonic(double stiffness, double center, double period) {
    hsbd_field_term t = {.ops = &harmonic_ops};
    t.p[HARM_K] = stiffness;
    t.p[HARM_CENTER] = center;
    t.p[HARM_PERIOD] = period;
    return t;
}
