/* AVX2 + FMA kernels on SLEEF (compiled with -mavx2 -mfma; see CMakeLists.txt). */
#include "core/vmath.h"

#if defined(__AVX2__)
#include <immintrin.h>
#include <math.h>
#include <sleef.h>

void hsbd_vmath_box_muller_avx2(size_t n, double *restrict u1, double *restrict u2) {
    const __m256d minus_two = _mm256_set1_pd(-2.0);
    const __m256d two = _mm256_set1_pd(2.0);
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const __m256d a = _mm256_loadu_pd(u1 + i);
        const __m256d b = _mm256_loadu_pd(u2 + i);
        const __m256d r = _mm256_sqrt_pd(_mm256_mul_pd(minus_two, Sleef_logd4_u10avx2(a)));
        const Sleef___m256d_2 sc = Sleef_sincospid4_u05avx2(_mm256_mul_pd(two, b));
        _mm256_storeu_pd(u1 + i, _mm256_mul_pd(r, sc.y)); /* .y = cos(pi x) */
        _mm256_storeu_pd(u2 + i, _mm256_mul_pd(r, sc.x)); /* .x = sin(pi x) */
    }
    if (i < n) { /* tail: pad to a full vector so both paths use the same functions */
        double a[4] = {1, 1, 1, 1}, b[4] = {0, 0, 0, 0};
        for (size_t j = i; j < n; ++j) {
            a[j - i] = u1[j];
            b[j - i] = u2[j];
        }
        hsbd_vmath_box_muller_avx2(4, a, b);
        for (size_t j = i; j < n; ++j) {
            u1[j] = a[j - i];
            u2[j] = b[j - i];
        }
    }
}

void hsbd_vmath_scaled_sinpi_avx2(size_t n, const double *restrict t, double scale,
                                  double *restrict out) {
    const __m256d s = _mm256_set1_pd(scale);
    size_t i = 0;
    for (; i + 4 <= n; i += 4) {
        const __m256d x = _mm256_loadu_pd(t + i);
        _mm256_storeu_pd(out + i, _mm256_mul_pd(s, Sleef_sinpid4_u05avx2(x)));
    }
    if (i < n) {
        double x[4] = {0, 0, 0, 0}, y[4];
        for (size_t j = i; j < n; ++j)
            x[j - i] = t[j];
        hsbd_vmath_scaled_sinpi_avx2(4, x, scale, y);
        for (size_t j = i; j < n; ++j)
            out[j] = y[j - i];
    }
}

void hsbd_vmath_log_avx2(size_t n, double *x) {
    size_t i = 0;
    for (; i + 4 <= n; i += 4)
        _mm256_storeu_pd(x + i, Sleef_logd4_u35avx2(_mm256_loadu_pd(x + i)));
    if (i < n) { /* the tail through a padded vector: one function for every element */
        double pad[4] = {1, 1, 1, 1};
        for (size_t j = i; j < n; ++j)
            pad[j - i] = x[j];
        _mm256_storeu_pd(pad, Sleef_logd4_u35avx2(_mm256_loadu_pd(pad)));
        for (size_t j = i; j < n; ++j)
            x[j] = pad[j - i];
    }
}
#else
/* Built without AVX2 support in the compiler: never selected at run time. */
void hsbd_vmath_box_muller_avx2(size_t n, double *restrict u1, double *restrict u2) {
    (void)n, (void)u1, (void)u2;
}
void hsbd_vmath_scaled_sinpi_avx2(size_t n, const double *restrict t, double scale,
                                  double *restrict out) {
    (void)n, (void)t, (void)scale, (void)out;
}
void hsbd_vmath_log_avx2(size_t n, double *x) {
    (void)n, (void)x;
}
#endif
