/* Cosine potential, Antonov Eq. (21): U(x) = (U0/2) cos(2 pi (x - s) / lambda), s a shift. */
#include <math.h>

#include "core/vmath.h"
#include "hsbd/field.h"

enum { COS_U0, COS_LAMBDA, COS_SHIFT };
enum { COS_CHUNK = 256 };

/* f = -dU/dx = (pi U0 / lambda) sin(2 pi (x - s) / lambda) = (pi U0 / lambda) sinpi(2 (x - s)
 * / lambda); s = 0 gives the same bits as without the shift */
static void cosine_add_force(const hsbd_field_term *t, size_t n, const double *restrict x,
                             double *restrict f) {
    const double pi = 3.141592653589793238462643383280;
    const double u0 = t->p[COS_U0], lambda = t->p[COS_LAMBDA];
    const double amplitude = pi * u0 / lambda, two_over_lambda = 2.0 / lambda;
    const double shift = t->p[COS_SHIFT];
    double arg[COS_CHUNK], s[COS_CHUNK];
    for (size_t i0 = 0; i0 < n; i0 += COS_CHUNK) {
        const size_t m = n - i0 < COS_CHUNK ? n - i0 : COS_CHUNK;
        for (size_t j = 0; j < m; ++j)
            arg[j] = two_over_lambda * (x[i0 + j] - shift);
        hsbd_vmath_scaled_sinpi(m, arg, amplitude, s);
        for (size_t j = 0; j < m; ++j)
            f[i0 + j] += s[j];
    }
}

static double cosine_potential(const hsbd_field_term *t, double x) {
    const double two_pi = 6.283185307179586476925286766559;
    const double lambda = t->p[COS_LAMBDA];
    const double d = x - t->p[COS_SHIFT], r = d - lambda * floor(d / lambda);
    return 0.5 * t->p[COS_U0] * cos(two_pi * r / lambda);
}

/* U'' = -(2 pi^2 U0 / lambda^2) cos(...) */
static double cosine_max_curvature(const hsbd_field_term *t) {
    const double pi = 3.141592653589793, lambda = t->p[COS_LAMBDA];
    return 2 * pi * pi * fabs(t->p[COS_U0]) / (lambda * lambda);
}

static const hsbd_field_ops cosine_ops = {.name = "cosine",
                                          .strength = COS_U0 + 1,
                                          .position = COS_SHIFT + 1,
                                          .add_force = cosine_add_force,
                                          .potential = cosine_potential,
                                          .max_curvature = cosine_max_curvature};

hsbd_field_term hsbd_field_cosine(double amplitude_u0, double wavelength) {
    hsbd_field_term t = {.ops = &cosine_ops};
    t.p[COS_U0] = amplitude_u0;
    t.p[COS_LAMBDA] = wavelength;
    return t;
}
