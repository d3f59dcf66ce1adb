#include "core/vmath.h"

#include <math.h>

int hsbd_vmath_vectorised(void) {
#if defined(__x86_64__) && defined(__GNUC__)
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
    return 0;
#endif
}

int hsbd_cpu_has_avx2(void) {
#if defined(__x86_64__) && defined(__GNUC__)
    return __builtin_cpu_supports("avx2") != 0;
#else
    return 0;
#endif
}

void hsbd_vmath_box_muller(size_t n, double *restrict u1, double *restrict u2) {
    if (hsbd_vmath_vectorised()) {
        hsbd_vmath_box_muller_avx2(n, u1, u2);
        return;
    }
    const double two_pi = 6.283185307179586476925286766559;
    for (size_t i = 0; i < n; ++i) {
        const double r = sqrt(-2.0 * log(u1[i]));
        const double phase = two_pi * u2[i];
        u1[i] = r * cos(phase);
        u2[i] = r * sin(phase);
    }
}

void hsbd_vmath_scaled_sinpi(size_t n, const double *restrict t, double scale,
                             double *restrict out) {
    if (hsbd_vmath_vectorised()) {
        hsbd_vmath_scaled_sinpi_avx2(n, t, scale, out);
        return;
    }
    const double pi = 3.141592653589793238462643383280;
    for (size_t i = 0; i < n; ++i) {
        /* reduce to [-1, 1) first so that sin sees an exact small argument */
        const double r = t[i] - 2.0 * floor(0.5 * t[i] + 0.5);
        out[i] = scale * sin(pi * r);
    }
}

void hsbd_vmath_log(size_t n, double *x) {
    if (hsbd_vmath_vectorised()) {
        hsbd_vmath_log_avx2(n, x);
        return;
    }
    for (size_t i = 0; i < n; ++i)
        x[i] = log(x[i]);
}
