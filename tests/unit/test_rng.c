/* Philox streams: reproducible per (seed, stream, step, index) whatever the batching, equal
 * to Random123's philox4x32 bit for bit (uniforms, listed uniforms, random bytes),
 * distinct across seeds/streams/steps, and with the moments of N(0,1) and U(0,1) within
 * 5 standard errors over 2^21 draws (fixed seeds). The vectorised Box-Muller agrees
 * with glibc's scalar functions to 1e-13. */
#include <Random123/philox.h>
#include <math.h>
#include <string.h>

#include "../test_util.h"
#include "core/vmath.h"
#include "hsbd/rng.h"

static const double PI = 3.141592653589793238462643383280;

enum { NDRAW = 1 << 21 };

static void test_batching_invariance(void) {
    double all[1000], part[1000];
    hsbd_rng_normals(42, HSBD_STREAM_NOISE, 7, 0, 1000, all);
    int bad = 0;
    for (size_t first = 0; first < 300; first += 37) {
        const size_t n = 1 + first % 401;
        hsbd_rng_normals(42, HSBD_STREAM_NOISE, 7, first, n, part);
        for (size_t i = 0; i < n; ++i)
            bad += memcmp(&part[i], &all[first + i], sizeof(double)) != 0;
    }
    CHECK(bad == 0, "%d normals depend on how the range was requested", bad);
    double a, b, c, d;
    hsbd_rng_normals(42, HSBD_STREAM_NOISE, 7, 5, 1, &a);
    hsbd_rng_normals(43, HSBD_STREAM_NOISE, 7, 5, 1, &b);
    hsbd_rng_normals(42, HSBD_STREAM_NOISE, 8, 5, 1, &c);
    hsbd_rng_normals(42, HSBD_STREAM_INIT, 7, 5, 1, &d);
    CHECK(a != b && a != c && a != d, "seed, step and stream must all change the draw");
    CHECK(all[5] == a, "same (seed, stream, step, index) must give the same draw");
}

/* hsbd_rng_uniforms (twelve counters at a time with AVX2, then a tail of eight or four)
 * against Random123's philox4x32 called here, bit for bit, across the 2^32 wrap of the
 * index pair and a 64-bit step: 139 uniforms are 70 pairs (five runs of twelve counters,
 * a tail of eight, two alone), 131 are 66 (a tail of four). */
static void test_uniforms_match_random123(void) {
    const uint64_t seed = 0x0123456789abcdefull, step = 0x100000003ull;
    const uint32_t stream = 5;
    const size_t first = 2 * (size_t)0xfffffff0u + 1, lengths[2] = {139, 131};
    for (int l = 0; l < 2; ++l) {
        const size_t n = lengths[l];
        double u[139];
        hsbd_rng_uniforms(seed, stream, step, first, n, u);
        const philox4x32_key_t key = {{(uint32_t)seed, (uint32_t)(seed >> 32)}};
        for (size_t k = 0; k < n; ++k) {
            const uint64_t index = first + k, pair = index / 2;
            const philox4x32_ctr_t ctr = {
                {(uint32_t)pair, (uint32_t)step, (uint32_t)(step >> 32), stream}};
            const philox4x32_ctr_t r = philox4x32(ctr, key);
            const uint64_t bits = index % 2 ? (((uint64_t)r.v[2] << 32) | r.v[3]) >> 11
                                            : (((uint64_t)r.v[0] << 32) | r.v[1]) >> 11;
            const double want = ((double)bits + 0.5) * 0x1.0p-53;
            CHECK(memcmp(&u[k], &want, sizeof want) == 0,
                  "n %zu, index %zu: %.17g, Random123 %.17g", n, index, u[k], want);
        }
    }
}

/* uniforms of listed indices (the reflect rule's gaps that may cross) equal those of the
 * index ranges bit for bit: any order, repeats, odd and even indices, a count that is
 * not a multiple of twelve, a base index past 2^32 pairs */
static void test_uniforms_at_listed_indices(void) {
    const uint64_t seed = 77, step = 12345;
    const size_t bases[2] = {1000, (size_t)1 << 34};
    /* groups of twelve and a tail of three groups, the last one padded; tails of two
     * groups and of one; no tail */
    const size_t counts[5] = {203, 5, 1, 8, 24};
    for (int b = 0; b < 2; ++b)
        for (int c = 0; c < 5; ++c) {
            unsigned offset[203];
            for (size_t k = 0; k < 203; ++k)
                offset[k] = (unsigned)((k * 7919u + 13u * (k % 3)) % 500u);
            offset[5] = offset[4]; /* a repeat */
            double got[203], range[500];
            hsbd_rng_uniforms_at(seed, HSBD_STREAM_CONTACT, step, bases[b], offset, counts[c], got);
            hsbd_rng_uniforms(seed, HSBD_STREAM_CONTACT, step, bases[b], 500, range);
            int bad = 0;
            for (size_t k = 0; k < counts[c]; ++k)
                bad += memcmp(&got[k], &range[offset[k]], sizeof got[k]) != 0;
            CHECK(bad == 0, "%d of %zu listed uniforms differ from the range's (base %zu)", bad,
                  counts[c], bases[b]);
        }
}

/* random bytes of listed blocks (the reflect rule's gaps) against Random123's philox4x32 called
 * here, byte for byte (word w of a counter gives bytes 4w .. 4w + 3, least significant
 * first): counts of whole runs of twelve counters and tails of one to eleven, blocks in any
 * order, a base across the 2^32 wrap of the counter's first word and a 64-bit step; the
 * bytes of blocks not listed stay as they were */
static void test_bytes_at_match_random123(void) {
    const uint64_t seed = 0x0fedcba987654321ull, step = 0x200000007ull;
    const uint64_t bases[2] = {3, 0xfffffff0ull};
    const philox4x32_key_t key = {{(uint32_t)seed, (uint32_t)(seed >> 32)}};
    for (int b = 0; b < 2; ++b)
        for (size_t n = 0; n <= 30; ++n) {
            unsigned block[30];
            uint8_t out[16 * 64];
            memset(out, 0xa5, sizeof out);
            for (size_t k = 0; k < n; ++k)
                block[k] = (unsigned)((k * 37 + 11) % 64); /* distinct, out of order */
            hsbd_rng_bytes_at(seed, HSBD_STREAM_CONTACT, step, bases[b], block, n, out);
            int bad = 0;
            for (unsigned blk = 0; blk < 64; ++blk) {
                int listed = 0;
                for (size_t k = 0; k < n; ++k)
                    listed |= block[k] == blk;
                const philox4x32_ctr_t ctr = {{(uint32_t)(bases[b] + blk), (uint32_t)step,
                                               (uint32_t)(step >> 32), HSBD_STREAM_CONTACT}};
                const philox4x32_ctr_t r = philox4x32(ctr, key);
                for (int i = 0; i < 16; ++i) {
                    const uint8_t want = listed ? (uint8_t)(r.v[i / 4] >> (8 * (i % 4))) : 0xa5;
                    bad += out[16 * blk + (unsigned)i] != want;
                }
            }
            CHECK(bad == 0, "base %llu, %zu blocks: %d bytes differ from Random123's",
                  (unsigned long long)bases[b], n, bad);
        }
}

/* bytes and four uniforms in one call (the reflect rule's short batches) are those of the two
 * calls apart: one to eight blocks, even and odd first indices */
static void test_bytes_and_four(void) {
    const unsigned block[8] = {5, 0, 7, 2, 9, 1, 3, 11};
    int bad = 0;
    for (size_t n = 1; n <= 8; ++n)
        for (uint64_t index = 1022; index <= 1025; ++index) {
            uint8_t got[16 * 12], want[16 * 12];
            double four[4], want_four[4];
            memset(got, 0, sizeof got), memset(want, 0, sizeof want);
            hsbd_rng_bytes_and_four(9, 44, HSBD_STREAM_CONTACT, 100, block, n, got,
                                    HSBD_STREAM_CONTACT_DEPTH, index, four);
            hsbd_rng_bytes_at(9, HSBD_STREAM_CONTACT, 44, 100, block, n, want);
            hsbd_rng_uniforms(9, HSBD_STREAM_CONTACT_DEPTH, 44, index, 4, want_four);
            bad += memcmp(got, want, sizeof got) != 0 || memcmp(four, want_four, sizeof four) != 0;
        }
    CHECK(bad == 0, "%d of 32 calls differ from the two calls apart", bad);
}

static void test_normal_moments(void) {
    static double g[NDRAW];
    hsbd_rng_normals(123456789, HSBD_STREAM_NOISE, 1, 0, NDRAW, g);
    double m1 = 0, m2 = 0, m3 = 0, m4 = 0;
    for (size_t i = 0; i < NDRAW; ++i) {
        const double x = g[i], x2 = x * x;
        m1 += x, m2 += x2, m3 += x2 * x, m4 += x2 * x2;
    }
    const double n = NDRAW;
    m1 /= n, m2 /= n, m3 /= n, m4 /= n;
    /* standard errors of the sample moments of N(0,1): sqrt(Var(x^k)/n) */
    CHECK(fabs(m1) < 5 * sqrt(1 / n), "mean %.3g", m1);
    CHECK(fabs(m2 - 1) < 5 * sqrt(2 / n), "variance %.6f", m2);
    CHECK(fabs(m3) < 5 * sqrt(15 / n), "third moment %.3g", m3);
    CHECK(fabs(m4 - 3) < 5 * sqrt(96 / n), "fourth moment %.5f", m4);
    /* neighbours (the two halves of one Box-Muller pair) uncorrelated */
    double c = 0;
    for (size_t i = 0; i + 1 < NDRAW; i += 2)
        c += g[i] * g[i + 1];
    c /= n / 2;
    CHECK(fabs(c) < 5 * sqrt(2 / n), "pair correlation %.3g", c);
}

static void test_uniform_moments(void) {
    static double u[NDRAW];
    hsbd_rng_uniforms(99, HSBD_STREAM_INIT, 3, 0, NDRAW, u);
    double m1 = 0, m2 = 0, lo = 1, hi = 0;
    for (size_t i = 0; i < NDRAW; ++i) {
        m1 += u[i], m2 += u[i] * u[i];
        lo = fmin(lo, u[i]), hi = fmax(hi, u[i]);
    }
    const double n = NDRAW;
    m1 /= n, m2 /= n;
    CHECK(lo > 0 && hi < 1, "uniforms must lie in (0,1): [%g, %g]", lo, hi);
    CHECK(fabs(m1 - 0.5) < 5 * sqrt(1.0 / 12 / n), "mean %.6f", m1);
    CHECK(fabs(m2 - 1.0 / 3) < 5 * sqrt(4.0 / 45 / n), "second moment %.6f", m2);
}

static void test_vector_math_matches_libm(void) {
    enum { M = 1001 };
    double u1[M], u2[M], a[M], b[M], t[M], s[M];
    for (int i = 0; i < M; ++i) {
        u1[i] = a[i] = (i + 0.5) / M;
        u2[i] = b[i] = fmod(0.618033988749 * i, 1.0);
        t[i] = -40.0 + 0.08 * i;
    }
    hsbd_vmath_box_muller(M, a, b);
    hsbd_vmath_scaled_sinpi(M, t, 3.0, s);
    double worst = 0, worst_sin = 0;
    for (int i = 0; i < M; ++i) {
        const double r = sqrt(-2 * log(u1[i]));
        worst = fmax(worst, fabs(a[i] - r * cos(2 * PI * u2[i])));
        worst = fmax(worst, fabs(b[i] - r * sin(2 * PI * u2[i])));
        worst_sin = fmax(worst_sin, fabs(s[i] - 3.0 * sin(PI * (t[i] - 2 * floor(t[i] / 2)))));
    }
    CHECK(worst < 1e-13, "Box-Muller differs from libm by %.3g (vectorised: %d)", worst,
          hsbd_vmath_vectorised());
    CHECK(worst_sin < 1e-13, "sinpi differs from libm by %.3g", worst_sin);
    /* the bulk logarithm (the reflect rule's candidates), every length's tail, down to 2^-60 */
    double x[M], lx[M], worst_log = 0;
    for (int i = 0; i < M; ++i)
        x[i] = lx[i] = ldexp((i % 97 + 0.5) / 97, -(i % 61));
    for (size_t n = 0; n <= 9; ++n)
        hsbd_vmath_log(n, lx + 100 * n);
    hsbd_vmath_log(M - 1000, lx + 1000);
    for (int i = 0; i < M; ++i) {
        const int done = i >= 1000 || i % 100 < i / 100;
        worst_log =
            fmax(worst_log, fabs(lx[i] - (done ? log(x[i]) : x[i])) / fmax(1, fabs(log(x[i]))));
    }
    CHECK(worst_log < 1e-15, "log differs from libm by %.3g (relative)", worst_log);
}

int main(void) {
    test_batching_invariance();
    test_uniforms_match_random123();
    test_uniforms_at_listed_indices();
    test_bytes_at_match_random123();
    test_bytes_and_four();
    test_normal_moments();
    test_uniform_moments();
    test_vector_math_matches_libm();
    return test_finish("test_rng");
}
