/* The observers' accumulators (include/hsbd/observe.h, src/observe/) on inputs whose
 * answers are known by hand:
 *
 * 1. Block averages: the sample -> time block map for totals that do not divide evenly
 *    (block k holds samples ceil(k T / nb) .. ceil((k + 1) T / nb) - 1), the means and the
 *    standard error of the block means of a fixed sequence, a run stopped inside a block,
 *    blocks without samples (NaN rows, left out of the error), spatial blocks, and the
 *    shape rescaling (each block's row scaled to the common total). Errors are checked
 *    where the blocks are equal, or where the mean over the samples equals the mean of the
 *    block means (and the mean of the rescaled rows), so the expected value does not
 *    depend on which of the two the deviations are taken from.
 * 2. MSD: ballistic items x_i(t) = x_i(0) + v_i t give msd(t) = <v^2> t^2 and
 *    F_s(k, t) = <cos(k v t)> at every lag from every origin; a walk whose increments are
 *    the rows of a Hadamard matrix (orthogonal over the items) gives msd = l s^2 exactly
 *    at every lag l and origin, so D_L = s^2 / (2 dt); x = k^2 / 2 gives per-origin values
 *    (l (2 o + l) / 2)^2 whose block error is worked out from the origins in time order;
 *    members, restarts (no lag spans a restart) and the origins per lag.
 * 3. g(r): square (2D) and simple cubic (3D) lattices of spacing a in a periodic box: a
 *    bin's pair count, recovered as g x shell volume x (N - 1) / V (the reference counts
 *    the N (N - 1) / 2 distinct pairs), is the lattice's coordination number of the shell
 *    (4, 4, 4, 8 at a, a sqrt 2, 2a, a sqrt 5 in 2D; 6, 12, 8, 6, 24 at a sqrt s, s = 1..5,
 *    in 3D), zero in every other bin; a checkerboard of two species splits them by the
 *    parity of the lattice vector; the contact weight and the quadratic contact fit.
 * 4. Clusters: rods placed with gaps exactly zero or positive, stepped once in a field that
 *    keeps every touching pair together and every open gap open (D = 1e-200: the noise,
 *    ~1e-102, is far below any rounding), give the hand-counted clusters, one of them
 *    across the ring's end, and rods pressed against both walls; the mean cluster size is
 *    the number mean N / clusters of each sample.
 * 5. Profiles and contacts: rods at known positions (density = counts / (bin width x
 *    periods x samples), pairs with gaps in the contact window, the four-window
 *    extrapolation's weights 0.85, 0.45, 0.05, -0.35 of a least-squares line), and contact
 *    impulses of hand-made free end points y (the impulse across a contact is the sum of
 *    (y_k - z_k) / mu_k over the cluster's rods to its left, over kT dt).
 *
 * Exactness: the positions, velocities and time steps are chosen dyadic where it matters
 * (sums and squares then carry no rounding at all) and away from bin edges, so every
 * count is exact and every expected value is a few correctly rounded operations away
 * from the library's (which sums in another order). Values are compared to 1e-12 relative
 * (absolute below 1): ~1e4 ulps above that rounding, far below the changes of >= 1e-3 a
 * wrong count, normalisation or block assignment makes. Where a value goes through a
 * solve (the contact fit) the tolerance says why it is wider. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/field.h"
#include "hsbd/observe.h"
#include "hsbd/rods.h"
#include "hsbd/spheres.h"

static const double PI = 3.14159265358979323846;

/* a few correctly rounded operations apart (see the header) */
#define CHECK_NEAR(a, b) CHECK_CLOSE((a), (b), 1e-12 * (1.0 + fabs((double)(b))))

/* ---------------------------------------------------------------- block averages ---- */

static void test_block_of(void) {
    /* block k holds samples ceil(k T / nb) .. ceil((k + 1) T / nb) - 1 */
    static const size_t t10[10] = {0, 0, 0, 0, 1, 1, 1, 2, 2, 2}; /* T 10, 3 blocks: 4 3 3 */
    static const size_t t7[7] = {0, 0, 0, 1, 1, 2, 2};            /* T 7, 3 blocks: 3 2 2 */
    static const size_t t5[5] = {0, 0, 1, 2, 3};                  /* T 5, 4 blocks: 2 1 1 1 */
    static const size_t t6[6] = {0, 0, 1, 1, 2, 2};               /* T 6, 3 blocks: 2 2 2 */
    for (uint64_t s = 0; s < 10; ++s)
        CHECK(hsbd_blocks_block_of(s, 3, 10) == t10[s], "T 10: sample %d in block %zu, not %zu",
              (int)s, hsbd_blocks_block_of(s, 3, 10), t10[s]);
    for (uint64_t s = 0; s < 7; ++s)
        CHECK(hsbd_blocks_block_of(s, 3, 7) == t7[s], "T 7: sample %d in block %zu, not %zu",
              (int)s, hsbd_blocks_block_of(s, 3, 7), t7[s]);
    for (uint64_t s = 0; s < 5; ++s)
        CHECK(hsbd_blocks_block_of(s, 4, 5) == t5[s], "T 5: sample %d in block %zu, not %zu",
              (int)s, hsbd_blocks_block_of(s, 4, 5), t5[s]);
    for (uint64_t s = 0; s < 6; ++s)
        CHECK(hsbd_blocks_block_of(s, 3, 6) == t6[s], "T 6: sample %d in block %zu, not %zu",
              (int)s, hsbd_blocks_block_of(s, 3, 6), t6[s]);
    CHECK(hsbd_blocks_block_of(12, 3, 10) == 2, "a sample beyond the total goes to the last block");
    CHECK(hsbd_blocks_block_of(0, 3, 0) == 0, "a zero total: block 0");
}

/* 10 samples of two values in 3 time blocks of 4, 3 and 3 samples. Value 0 has block means
 * 2, 1, 3; its mean over the samples (8 + 3 + 9) / 10 = 2 is also the mean of the block
 * means, so the error is sqrt((0 + 1 + 1) / (3 x 2)) however it is centred. Value 1 has
 * block means 4, 4, 4 (error 0). Had the blocks been 3, 3, 4 samples, value 0's would be
 * 2, 1, 2.75. */
static void test_time_blocks(void) {
    static const double v0[10] = {1, 3, 2, 2, 0, 1, 2, 3, 5, 1};
    static const double v1[10] = {4, 4, 4, 4, 4, 2, 6, 8, 0, 4};
    static const size_t block[10] = {0, 0, 0, 0, 1, 1, 1, 2, 2, 2};
    hsbd_blocks *b = hsbd_blocks_alloc(2, 3, 10);
    CHECK(b != NULL, "hsbd_blocks_alloc");
    if (!b) return;
    CHECK(hsbd_blocks_count(b) == 3, "blocks: %zu", hsbd_blocks_count(b));
    double mean[2], err[2], rows[6];
    for (size_t s = 0; s < 10; ++s) {
        CHECK(hsbd_blocks_current(b) == block[s], "sample %zu: current block %zu, not %zu", s,
              hsbd_blocks_current(b), block[s]);
        double *acc = hsbd_blocks_acc(b);
        acc[0] += v0[s];
        acc[1] += v1[s];
        hsbd_blocks_end_sample(b);
        CHECK(hsbd_blocks_samples(b) == s + 1, "samples %d after %zu", (int)hsbd_blocks_samples(b),
              s + 1);
        if (s != 4) continue;
        /* stopped after 5 samples: block 0 full ({1, 3, 2, 2} and {4, 4, 4, 4}), block 1
         * holds one sample (0 and 4) and counts with its own weight, block 2 none */
        const size_t used = hsbd_blocks_result(b, mean, err);
        CHECK(used == 2, "partial run: %zu blocks used", used);
        CHECK_NEAR(mean[0], 8.0 / 5.0);
        CHECK_NEAR(mean[1], 4.0);
        CHECK_NEAR(err[1], 0.0); /* block means 4 and 4 (0 if the open block were dropped) */
        CHECK(hsbd_blocks_block_means(b, 0, rows) == 3, "block_means returns nblocks");
        CHECK_NEAR(rows[0], 2.0);
        CHECK_NEAR(rows[1], 4.0);
        CHECK_NEAR(rows[2], 0.0);
        CHECK_NEAR(rows[3], 4.0);
        CHECK(isnan(rows[4]) && isnan(rows[5]), "a block without samples: NaN row (%g, %g)",
              rows[4], rows[5]);
    }
    CHECK(hsbd_blocks_current(b) == 2, "after the run: the last block");
    const size_t used = hsbd_blocks_result(b, mean, err);
    CHECK(used == 3, "full run: %zu blocks used", used);
    CHECK_NEAR(mean[0], 2.0);
    CHECK_NEAR(err[0], sqrt(2.0 / 6.0));
    CHECK_NEAR(mean[1], 4.0);
    CHECK_NEAR(err[1], 0.0);
    /* block means, and rescaled to the mean total per sample (20 + 40) / 10 = 6: the rows'
     * totals are 6, 5, 7 */
    static const double plain[6] = {2, 4, 1, 4, 3, 4};
    const double shaped[6] = {2, 4, 1.2, 4.8, 18.0 / 7.0, 24.0 / 7.0};
    CHECK(hsbd_blocks_block_means(b, 0, rows) == 3, "block_means returns nblocks");
    for (int k = 0; k < 6; ++k)
        CHECK_NEAR(rows[k], plain[k]);
    hsbd_blocks_block_means(b, 1, rows);
    for (int k = 0; k < 6; ++k)
        CHECK_NEAR(rows[k], shaped[k]);
    double smean[2], serr[2];
    CHECK(hsbd_blocks_result_shape(b, smean, serr) == 3, "result_shape returns the blocks used");
    CHECK_NEAR(smean[0], 2.0);
    CHECK_NEAR(smean[1], 4.0);
    hsbd_blocks_free(b);
}

/* The shape error of an interrupted run counts the block being filled, as the plain error
 * does: samples (1,3), (1,3) close block 0, (3,1) is in the open block 1; rescaled to the
 * total 4 the rows are (1,3) and (3,1), the mean (5/3, 7/3), so the error is
 * sqrt(((1 - 5/3)^2 + (3 - 5/3)^2) / 2) = sqrt(10)/3 for both values. */
static void test_shape_open_block(void) {
    hsbd_blocks *b = hsbd_blocks_alloc(2, 2, 4);
    CHECK(b != NULL, "hsbd_blocks_alloc");
    if (!b) return;
    static const double s[3][2] = {{1, 3}, {1, 3}, {3, 1}};
    for (int k = 0; k < 3; ++k) {
        hsbd_blocks_acc(b)[0] += s[k][0], hsbd_blocks_acc(b)[1] += s[k][1];
        hsbd_blocks_end_sample(b);
    }
    double mean[2], err[2];
    CHECK(hsbd_blocks_result_shape(b, mean, err) == 2, "two blocks used");
    CHECK_NEAR(err[0], sqrt(10.0) / 3);
    CHECK_NEAR(err[1], sqrt(10.0) / 3);
    hsbd_blocks_free(b);
}

/* Blocks without samples: no samples at all (NaN mean and error, 0 blocks used), one block
 * (a mean, NaN error), two of four blocks (the empty ones left out of the error). */
static void test_empty_blocks(void) {
    hsbd_blocks *b = hsbd_blocks_alloc(1, 4, 8); /* blocks of 2 samples */
    CHECK(b != NULL, "hsbd_blocks_alloc");
    if (!b) return;
    double mean, err, rows[4];
    CHECK(hsbd_blocks_result(b, &mean, &err) == 0, "no samples: no block used");
    CHECK(isnan(mean) && isnan(err), "no samples: mean %g, error %g (NaN)", mean, err);
    CHECK(hsbd_blocks_result_shape(b, &mean, &err) == 0, "no samples: shape uses no block");
    CHECK(isnan(mean) && isnan(err), "no samples, shape: mean %g, error %g (NaN)", mean, err);
    hsbd_blocks_block_means(b, 0, rows);
    CHECK(isnan(rows[0]) && isnan(rows[1]) && isnan(rows[2]) && isnan(rows[3]),
          "no samples: NaN rows");
    static const double v[4] = {1, 3, 5, 7};
    for (int s = 0; s < 2; ++s) {
        hsbd_blocks_acc(b)[0] += v[s];
        hsbd_blocks_end_sample(b);
    }
    CHECK(hsbd_blocks_result(b, &mean, &err) == 1, "one block used");
    CHECK_NEAR(mean, 2.0);
    CHECK(isnan(err), "one block: error %g (NaN)", err);
    CHECK(hsbd_blocks_result_shape(b, &mean, &err) == 1, "shape: one block used");
    CHECK_NEAR(mean, 2.0);
    CHECK(isnan(err), "shape, one block: error %g (NaN)", err);
    for (int s = 2; s < 4; ++s) {
        hsbd_blocks_acc(b)[0] += v[s];
        hsbd_blocks_end_sample(b);
    }
    /* block means 2 and 6 of 2 samples each: mean 4, error sqrt((4 + 4) / (2 x 1)) */
    CHECK(hsbd_blocks_result(b, &mean, &err) == 2, "two blocks used");
    CHECK_NEAR(mean, 4.0);
    CHECK_NEAR(err, 2.0);
    hsbd_blocks_block_means(b, 0, rows);
    CHECK_NEAR(rows[0], 2.0);
    CHECK_NEAR(rows[1], 6.0);
    CHECK(isnan(rows[2]) && isnan(rows[3]), "empty blocks: NaN rows (%g, %g)", rows[2], rows[3]);
    hsbd_blocks_block_means(b, 1, rows); /* one value: each row rescaled to the mean, 4 */
    CHECK_NEAR(rows[0], 4.0);
    CHECK_NEAR(rows[1], 4.0);
    CHECK(isnan(rows[2]) && isnan(rows[3]), "shape: empty blocks stay NaN");
    hsbd_blocks_free(b);
}

/* Spatial blocks: three parts of a system, each adding (1/4, 3/4), (3/2, 1/2), (3/4, 9/4)
 * in each of two samples. Means over the parts (5/6, 7/6); the block means' deviations
 * (-7, 8, -1) / 12 and (-5, -8, 13) / 12 give errors sqrt(114 / 144 / 6) = sqrt(19) / 12
 * and sqrt(258 / 144 / 6) = sqrt(43) / 12. The rows' totals are 1, 2, 3 (mean 2): rescaled
 * to 2 they are (1/2, 3/2), (3/2, 1/2), (1/2, 3/2), whose mean is again (5/6, 7/6), and
 * whose error is sqrt((1/9 + 4/9 + 1/9) / 6) = 1/3. Rows of one shape and different
 * totals: shape error 0, plain error not. */
static void test_spatial_blocks(void) {
    static const double part[3][2] = {{0.25, 0.75}, {1.5, 0.5}, {0.75, 2.25}};
    static const double same_shape[3][2] = {{0.25, 0.75}, {0.5, 1.5}, {0.75, 2.25}};
    hsbd_blocks *b = hsbd_blocks_alloc_spatial(2, 3), *c = hsbd_blocks_alloc_spatial(2, 3);
    CHECK(b != NULL && c != NULL, "hsbd_blocks_alloc_spatial");
    if (!b || !c) {
        hsbd_blocks_free(b);
        hsbd_blocks_free(c);
        return;
    }
    for (int s = 0; s < 2; ++s) {
        for (size_t k = 0; k < 3; ++k)
            for (int j = 0; j < 2; ++j) {
                hsbd_blocks_acc_block(b, k)[j] += part[k][j];
                hsbd_blocks_acc_block(c, k)[j] += same_shape[k][j];
            }
        hsbd_blocks_end_sample(b);
        hsbd_blocks_end_sample(c);
        CHECK(hsbd_blocks_current(b) == 0, "spatial: current block 0");
    }
    CHECK(hsbd_blocks_samples(b) == 2 && hsbd_blocks_count(b) == 3, "spatial: 2 samples, 3 blocks");
    double mean[2], err[2], rows[6];
    CHECK(hsbd_blocks_result(b, mean, err) == 3, "spatial: 3 blocks used");
    CHECK_NEAR(mean[0], 5.0 / 6.0);
    CHECK_NEAR(mean[1], 7.0 / 6.0);
    CHECK_NEAR(err[0], sqrt(19.0) / 12.0);
    CHECK_NEAR(err[1], sqrt(43.0) / 12.0);
    CHECK(hsbd_blocks_result_shape(b, mean, err) == 3, "spatial shape: 3 blocks used");
    CHECK_NEAR(mean[0], 5.0 / 6.0);
    CHECK_NEAR(mean[1], 7.0 / 6.0);
    CHECK_NEAR(err[0], 1.0 / 3.0);
    CHECK_NEAR(err[1], 1.0 / 3.0);
    hsbd_blocks_block_means(b, 0, rows);
    for (int k = 0; k < 6; ++k)
        CHECK_NEAR(rows[k], part[k / 2][k % 2]);
    static const double rescaled[6] = {0.5, 1.5, 1.5, 0.5, 0.5, 1.5};
    hsbd_blocks_block_means(b, 1, rows);
    for (int k = 0; k < 6; ++k)
        CHECK_NEAR(rows[k], rescaled[k]);
    /* one shape, totals 1, 2, 3: value 0's block means 1/4, 1/2, 3/4 scatter (error
     * sqrt((1/16 + 1/16) / 6)), their shape does not */
    hsbd_blocks_result(c, mean, err);
    CHECK_NEAR(mean[0], 0.5);
    CHECK_NEAR(err[0], sqrt(1.0 / 48.0));
    hsbd_blocks_result_shape(c, mean, err);
    CHECK_NEAR(mean[0], 0.5);
    CHECK_NEAR(mean[1], 1.5);
    CHECK_NEAR(err[0], 0.0);
    CHECK_NEAR(err[1], 0.0);
    hsbd_blocks_free(b);
    hsbd_blocks_free(c);
}

/* ---------------------------------------------------------------------------- MSD ---- */

/* Ballistic items, every sample an origin (lags up to 20 samples: the snapshots of all
 * origins within reach fit in the 64 slots msd.c allows, one origin per sample), so lag l
 * has T - l origins. Lags: round(10^(j / 10)) up to 20, duplicates removed. */
static void test_msd_ballistic(void) {
    enum { N = 4, T = 30 };
    const double v[N] = {0.25, -1.5, 2, 0.75}, x0[N] = {1, -2, 0.5, 3}, dt = 0.5, k = 0.7;
    static const uint64_t lags[] = {1, 2, 3, 4, 5, 6, 8, 10, 13, 16, 20};
    const size_t nlags = sizeof lags / sizeof lags[0];
    const double v2 = (0.0625 + 2.25 + 4 + 0.5625) / 4; /* <v^2> = 1.71875 */
    hsbd_error err;
    hsbd_msd *m = hsbd_msd_alloc(N, dt, T, 10.0, 10, 4, &err);
    CHECK(m != NULL, "hsbd_msd_alloc");
    if (!m) return;
    CHECK(hsbd_msd_set_wavenumber(m, k, &err) == HSBD_OK, "set_wavenumber");
    for (int s = 0; s < T; ++s) {
        double x[N];
        for (int i = 0; i < N; ++i)
            x[i] = x0[i] + v[i] * (s * dt);
        hsbd_msd_sample_values(m, x);
    }
    CHECK(hsbd_msd_set_wavenumber(m, k, &err) == HSBD_EINPUT, "set_wavenumber after sampling");
    CHECK(hsbd_msd_lags(m) == nlags, "%zu lags, not %zu", hsbd_msd_lags(m), nlags);
    for (size_t q = 0; q < nlags && q < hsbd_msd_lags(m); ++q) {
        double t, msd, e, fs, fe;
        size_t origins;
        hsbd_msd_result(m, q, &t, &msd, &e, &origins);
        const double lag_t = (double)lags[q] * dt;
        CHECK(t == lag_t, "lag %zu: t = %g, not %g", q, t, lag_t);
        CHECK(origins == T - lags[q], "lag %d: %zu origins, not %d", (int)lags[q], origins,
              (int)(T - lags[q]));
        CHECK_NEAR(msd, v2 * lag_t * lag_t);
        CHECK_NEAR(e, 0.0); /* every origin gives the same value */
        double cs = 0;
        for (int i = 0; i < N; ++i)
            cs += cos(k * v[i] * lag_t);
        hsbd_msd_fs(m, q, &fs, &fe);
        CHECK_NEAR(fs, cs / N);
        CHECK_NEAR(fe, 0.0);
    }
    hsbd_msd_free(m);
}

/* Lags up to 100 samples: 64 snapshots cannot hold an origin per sample, so origins come
 * every ceil(100 / 63) = 2 samples (msd.c: at most 64 live snapshots); lag l then has the
 * even origins o <= 149 - l: floor((149 - l) / 2) + 1 of them. */
static void test_msd_sparse_origins(void) {
    enum { N = 2, T = 150 };
    const double v[N] = {1, -0.5}, dt = 0.125;
    static const uint64_t lags[] = {1, 2, 3, 4, 6, 10, 16, 25, 40, 63, 100};
    const size_t nlags = sizeof lags / sizeof lags[0];
    hsbd_error err;
    hsbd_msd *m = hsbd_msd_alloc(N, dt, T, 12.5, 5, 4, &err);
    CHECK(m != NULL, "hsbd_msd_alloc");
    if (!m) return;
    for (int s = 0; s < T; ++s) {
        const double x[N] = {v[0] * s * dt, 3 + v[1] * s * dt};
        hsbd_msd_sample_values(m, x);
    }
    CHECK(hsbd_msd_lags(m) == nlags, "%zu lags, not %zu", hsbd_msd_lags(m), nlags);
    for (size_t q = 0; q < nlags && q < hsbd_msd_lags(m); ++q) {
        double t, msd, e;
        size_t origins;
        hsbd_msd_result(m, q, &t, &msd, &e, &origins);
        const size_t want = (size_t)((T - 1 - lags[q]) / 2 + 1);
        CHECK(origins == want, "lag %d: %zu origins, not %zu", (int)lags[q], origins, want);
        CHECK_NEAR(t, (double)lags[q] * dt);
        CHECK_NEAR(msd, 0.625 * t * t);
    }
    hsbd_msd_free(m);
}

/* +1 or -1: row r, column i of the Sylvester-Hadamard matrix, (-1)^popcount(r & i) */
static double hadamard(unsigned r, unsigned i) {
    unsigned bits = r & i, parity = 0;
    for (; bits; bits >>= 1)
        parity ^= bits & 1u;
    return parity ? -1.0 : 1.0;
}

/* A walk of 32 items whose step from sample k to k + 1 is s H[k + 1][i]: the rows are
 * orthogonal, so the squared displacement summed over the items over any l consecutive
 * steps is n l s^2 exactly: msd = l s^2 at every lag and origin, a diffusion coefficient
 * s^2 / (2 dt) = 0.5 per coordinate, whatever the dimension the items are taken to be
 * coordinates of. Lags up to T - 1 = 31 (the max_lag asked is longer); the last (one
 * origin) has no error. D_L: the largest lag with two origins (18) and the first lag of at
 * least a tenth of it (2). */
static void test_msd_diffusive(void) {
    enum { N = 32, T = 32 };
    const double s = 0.5, dt = 0.25;
    static const uint64_t lags[] = {1, 2, 3, 6, 10, 18, 31};
    const size_t nlags = sizeof lags / sizeof lags[0];
    hsbd_error err;
    hsbd_msd *m = hsbd_msd_alloc(N, dt, T, 100.0, 4, 4, &err);
    CHECK(m != NULL, "hsbd_msd_alloc");
    if (!m) return;
    double x[N];
    for (int i = 0; i < N; ++i)
        x[i] = 0.75 * i;
    for (unsigned k = 0; k < T; ++k) {
        hsbd_msd_sample_values(m, x);
        for (unsigned i = 0; i < N; ++i)
            x[i] += s * hadamard(k + 1, i);
    }
    CHECK(hsbd_msd_lags(m) == nlags, "%zu lags, not %zu", hsbd_msd_lags(m), nlags);
    for (size_t q = 0; q < nlags && q < hsbd_msd_lags(m); ++q) {
        double t, msd, e;
        size_t origins;
        hsbd_msd_result(m, q, &t, &msd, &e, &origins);
        CHECK(origins == T - lags[q], "lag %d: %zu origins", (int)lags[q], origins);
        CHECK_NEAR(msd, (double)lags[q] * s * s);
        if (origins >= 2)
            CHECK_NEAR(e, 0.0);
        else
            CHECK(isnan(e), "one origin: error %g (NaN)", e);
    }
    double dl, dle, t0, t1;
    hsbd_msd_long_time_lags(m, &t0, &t1);
    CHECK(t0 == 2 * dt && t1 == 18 * dt, "D_L lags %g, %g (not 0.5, 4.5)", t0, t1);
    hsbd_msd_long_time_diffusion(m, 1, &dl, &dle);
    CHECK_NEAR(dl, s * s / (2 * dt));
    CHECK_NEAR(dle, 0.0);
    hsbd_msd_long_time_diffusion(m, 2, &dl, &dle);
    CHECK_NEAR(dl, s * s / (2 * dt));
    hsbd_msd_free(m);
}

/* One item at x_k = k^2 / 2: from origin o, lag l, the squared displacement is
 * (l (2 o + l) / 2)^2. 13 samples, lags {1, 2, 3, 4, 5, 6, 8, 10, 12} with 13 - l
 * origins; the error is that of 4 blocks of consecutive origins (as many blocks as
 * origins below 4), checked where the blocks are equal: 12 origins (lag 1), 8 (lag 5), 3
 * (lag 10, three blocks of one); one origin (lag 12): NaN. */
static void test_msd_origin_blocks(void) {
    enum { T = 13 };
    static const uint64_t lags[] = {1, 2, 3, 4, 5, 6, 8, 10, 12};
    const size_t nlags = sizeof lags / sizeof lags[0];
    hsbd_error err;
    hsbd_msd *m = hsbd_msd_alloc(1, 1.0, T, 12.0, 10, 4, &err);
    CHECK(m != NULL, "hsbd_msd_alloc");
    if (!m) return;
    for (int k = 0; k < T; ++k) {
        const double x = 0.5 * k * k;
        hsbd_msd_sample_values(m, &x);
    }
    CHECK(hsbd_msd_lags(m) == nlags, "%zu lags, not %zu", hsbd_msd_lags(m), nlags);
    for (size_t q = 0; q < nlags && q < hsbd_msd_lags(m); ++q) {
        const double l = (double)lags[q];
        const size_t c = T - (size_t)lags[q];
        double val[T], sum = 0;
        for (size_t o = 0; o < c; ++o) {
            const double d = 0.5 * l * (2.0 * (double)o + l);
            val[o] = d * d;
            sum += val[o];
        }
        double t, msd, e;
        size_t origins;
        hsbd_msd_result(m, q, &t, &msd, &e, &origins);
        CHECK(origins == c, "lag %g: %zu origins, not %zu", l, origins, c);
        CHECK_NEAR(msd, sum / (double)c);
        const size_t nb = c < 4 ? c : 4;
        if (nb < 2) {
            CHECK(isnan(e), "lag %g, one origin: error %g (NaN)", l, e);
            continue;
        }
        if (c % nb) continue; /* unequal blocks: not pinned here */
        const size_t per = c / nb;
        double var = 0;
        for (size_t b = 0; b < nb; ++b) {
            double bs = 0;
            for (size_t o = b * per; o < (b + 1) * per; ++o)
                bs += val[o];
            const double d = bs / (double)per - sum / (double)c;
            var += d * d;
        }
        CHECK_CLOSE(e, sqrt(var / ((double)nb * (double)(nb - 1))), 1e-12 * msd);
    }
    hsbd_msd_free(m);
}

/* Members 1, 3, 4 of six items: the others jump by +-1000 every sample and must not enter.
 * msd = (0.25 + 1.5625 + 4) / 3 t^2 = 1.9375 t^2, F_s over the members only. */
static void test_msd_members(void) {
    enum { N = 6, T = 8 };
    const double v[N] = {9, 0.5, 9, -1.25, 2, 9}, k = 1.3;
    const size_t members[3] = {1, 3, 4};
    hsbd_error err;
    hsbd_msd *m = hsbd_msd_alloc(N, 1.0, T, 4.0, 10, 4, &err);
    CHECK(m != NULL, "hsbd_msd_alloc");
    if (!m) return;
    CHECK(hsbd_msd_set_members(m, 0, members, &err) == HSBD_EINPUT, "no members refused");
    CHECK(hsbd_msd_set_members(m, N + 1, members, &err) == HSBD_EINPUT, "N + 1 members refused");
    CHECK(hsbd_msd_set_members(m, 3, members, &err) == HSBD_OK, "set_members");
    CHECK(hsbd_msd_set_wavenumber(m, k, &err) == HSBD_OK, "set_wavenumber");
    for (int s = 0; s < T; ++s) {
        double x[N];
        for (int i = 0; i < N; ++i)
            x[i] = v[i] == 9 ? (s % 2 ? 1000.0 : -1000.0) : v[i] * s;
        hsbd_msd_sample_values(m, x);
    }
    CHECK(hsbd_msd_set_members(m, 2, members, &err) == HSBD_EINPUT,
          "set_members after sampling refused");
    CHECK(hsbd_msd_lags(m) == 4, "%zu lags, not 4", hsbd_msd_lags(m));
    for (size_t q = 0; q < 4 && q < hsbd_msd_lags(m); ++q) {
        double t, msd, e, fs, fe;
        size_t origins;
        hsbd_msd_result(m, q, &t, &msd, &e, &origins);
        CHECK(t == (double)(q + 1), "lag %zu: t = %g", q, t);
        CHECK(origins == T - (q + 1), "lag %zu: %zu origins", q, origins);
        CHECK_NEAR(msd, 1.9375 * t * t);
        hsbd_msd_fs(m, q, &fs, &fe);
        CHECK_NEAR(fs, (cos(k * 0.5 * t) + cos(k * -1.25 * t) + cos(k * 2 * t)) / 3);
    }
    hsbd_msd_free(m);
}

/* Two replicas: 7 samples with velocities (1, -1/2), a restart, 5 samples with (2, 1)
 * a thousand lengths away. Lag l gets 7 - l origins of <v^2> = 0.625 and max(0, 5 - l) of
 * 2.5; a lag across the restart would add ~1e6. */
static void test_msd_restart(void) {
    enum { TA = 7, TB = 5 };
    hsbd_error err;
    hsbd_msd *m = hsbd_msd_alloc(2, 1.0, TA + TB, 6.0, 10, 4, &err);
    CHECK(m != NULL, "hsbd_msd_alloc");
    if (!m) return;
    for (int s = 0; s < TA; ++s) {
        const double x[2] = {1.0 * s, 2 - 0.5 * s};
        hsbd_msd_sample_values(m, x);
    }
    hsbd_msd_restart(m);
    for (int s = 0; s < TB; ++s) {
        const double x[2] = {1000 + 2.0 * s, -1000 + 1.0 * s};
        hsbd_msd_sample_values(m, x);
    }
    CHECK(hsbd_msd_lags(m) == 6, "%zu lags, not 6", hsbd_msd_lags(m));
    for (size_t q = 0; q < 6 && q < hsbd_msd_lags(m); ++q) {
        const int l = (int)q + 1, a = TA - l, b = TB - l > 0 ? TB - l : 0;
        double t, msd, e;
        size_t origins;
        hsbd_msd_result(m, q, &t, &msd, &e, &origins);
        CHECK(origins == (size_t)(a + b), "lag %d: %zu origins, not %d", l, origins, a + b);
        CHECK_NEAR(msd, (a * 0.625 + b * 2.5) / (a + b) * l * l);
    }
    hsbd_msd_free(m);
}

/* From a rods view: the unwrapped position is z + offset + unwrap. Two rods moving by 1
 * per sample on a ring of length 4, the view's z folded back and unwrap advanced by 4
 * every other sample: msd = l^2. */
static void test_msd_view(void) {
    enum { T = 6 };
    hsbd_error err;
    hsbd_msd *m = hsbd_msd_alloc(2, 1.0, T, 3.0, 10, 2, &err);
    CHECK(m != NULL, "hsbd_msd_alloc");
    if (!m) return;
    const double offset[2] = {0, 1};
    for (int s = 0; s < T; ++s) {
        const double unwrap = 4.0 * (s / 2), z[2] = {0.5 + s - unwrap, 0.5 + s - unwrap};
        const hsbd_rods_view v = {.n = 2,
                                  .length = 4,
                                  .sigma = 1,
                                  .free_length = 2,
                                  .periodic = 1,
                                  .z = z,
                                  .offset = offset,
                                  .unwrap = unwrap};
        hsbd_msd_sample(m, &v);
    }
    for (size_t q = 0; q < hsbd_msd_lags(m); ++q) {
        double t, msd, e;
        size_t origins;
        hsbd_msd_result(m, q, &t, &msd, &e, &origins);
        CHECK_NEAR(msd, t * t);
        CHECK(origins == T - (size_t)t, "lag %g: %zu origins", t, origins);
    }
    hsbd_msd_free(m);
}

/* ---------------------------------------------------------------------------- g(r) ---- */

enum { LATTICE_MAX = 216 };

typedef struct lattice {
    size_t n;
    double x[3 * LATTICE_MAX], sigma[LATTICE_MAX];
    int species[LATTICE_MAX];
    hsbd_spheres_view view;
} lattice;

/* m^dim sites (i + 1/2) a; species (i + j + k) mod 2 when two species */
static void lattice_build(lattice *lt, int dim, int m, double a, double sigma, int two) {
    memset(lt, 0, sizeof *lt);
    size_t n = 0;
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j)
            for (int k = 0; k < (dim == 3 ? m : 1); ++k) {
                lt->x[3 * n] = (i + 0.5) * a;
                lt->x[3 * n + 1] = (j + 0.5) * a;
                lt->x[3 * n + 2] = dim == 3 ? (k + 0.5) * a : 0.0;
                lt->sigma[n] = sigma;
                lt->species[n] = two ? (i + j + k) % 2 : 0;
                ++n;
            }
    lt->n = n;
    lt->view = (hsbd_spheres_view){.n = n,
                                   .dimension = dim,
                                   .box = {m * a, m * a, dim == 3 ? m * a : 0.0},
                                   .x = lt->x,
                                   .sigma = lt->sigma,
                                   .species = lt->species,
                                   .nspecies = two ? 2 : 1};
}

static double shell(int dim, double r0, double r1) {
    return dim == 3 ? 4.0 / 3.0 * PI * (r1 * r1 * r1 - r0 * r0 * r0) : PI * (r1 * r1 - r0 * r0);
}

enum { GR_BINS = 34 }; /* r_max 3 in bins of 0.09: ceil(33.3) bins up to 3.06 */
static const double GR_A = 1.25, GR_W = 0.09, GR_RMAX = 3.0, GR_FIT = 0.1;

/* Each pair within r_max = 3.06 is joined by one lattice vector (p, q, r) a with |p|, |q|,
 * |r| <= 2 (the boxes are 6a = 7.5 and 8a = 10 long, so a component of 3 would already be
 * 3.75 > r_max, and no pair has two images within r_max). The bin of a sqrt(s):
 * 1.25 sqrt(s) / 0.09 = 13.9, 19.6, 24.1, 27.8, 31.1 for s = 1, 2, 3, 4, 5, each at least
 * 0.06 bins from an edge (a sqrt 6 = 3.062 > 3.06 is out). */
static size_t shell_bin(int s) {
    return (size_t)floor(GR_A * sqrt((double)s) / GR_W);
}

/* g of one species -> neighbours per particle in each bin: g x shell x (N - 1) / V */
static void check_coordination(const char *name, const hsbd_gr *g, size_t pair, int dim,
                               double pairs_over_v, const double *want) {
    double r[GR_BINS], gr[GR_BINS], err[GR_BINS];
    hsbd_gr_result(g, pair, r, gr, err);
    for (size_t k = 0; k < GR_BINS; ++k) {
        CHECK_NEAR(r[k], (k + 0.5) * GR_W);
        const double count = gr[k] * shell(dim, k * GR_W, (k + 1) * GR_W) * pairs_over_v;
        CHECK(fabs(count - want[k]) <= 1e-12 * (1 + want[k]),
              "%s: bin %zu (r = %g): %.17g neighbours, not %g", name, k, r[k], count, want[k]);
        CHECK(err[k] == 0, "%s: bin %zu: error %g of identical samples", name, k, err[k]);
    }
}

/* Simple cubic, 6^3 sites, spacing a = 1.25 = sigma (nearest neighbours touch): 6, 12, 8,
 * 6, 24 neighbours at a sqrt(s), s = 1..5 (the representations of s as a sum of three
 * squares). Two identical samples in two blocks: error 0. Contact: the 3N touching pairs
 * sit at gap 0, in the first of ten gap bins of width 0.01, nothing else below a gap of
 * 0.1 (the next shell's gap is 0.52); the reference of that bin is sigma x P / V x the
 * shell between sigma and sigma + 0.01 (P = N (N - 1) / 2 pairs, each counted with weight
 * sigma), and the contact value is the intercept of the quadratic fitted through
 * (0.005, y0), (0.015, 0), ..., (0.095, 0). Contact weight: P 4 pi sigma^3 / (3 V N) =
 * 2 pi sigma^3 (N - 1) / (3 V). */
static void test_gr_cubic(void) {
    static lattice lt;
    lattice_build(&lt, 3, 6, GR_A, GR_A, 0);
    const double n = (double)lt.n, volume = 7.5 * 7.5 * 7.5;
    hsbd_error err;
    hsbd_gr *g = hsbd_gr_alloc(&lt.view, GR_RMAX, GR_W, GR_FIT, 2, 2, &err);
    CHECK(g != NULL, "hsbd_gr_alloc: %s", g ? "" : err.message);
    if (!g) return;
    CHECK(hsbd_gr_bins(g) == GR_BINS, "%zu bins, not %d", hsbd_gr_bins(g), GR_BINS);
    CHECK(hsbd_gr_pairs(g) == 1 && hsbd_gr_profile_axis(g) == -1, "one pair, no profile axis");
    for (int s = 0; s < 2; ++s)
        CHECK(hsbd_gr_sample(g, &lt.view) == HSBD_OK, "hsbd_gr_sample");
    double want[GR_BINS] = {0};
    static const double r3[6] = {0, 6, 12, 8, 6, 24};
    for (int s = 1; s <= 5; ++s)
        want[shell_bin(s)] += r3[s];
    check_coordination("simple cubic", g, 0, 3, (n - 1) / volume, want);
    /* the contact fit: gap bin 0 holds 3N pairs of weight sigma against a reference of
     * sigma P / V times the shell between sigma and sigma + h; the other nine bins nothing.
     * The intercept of a least-squares quadratic through ten equally spaced points weighs
     * the first one by 663/880, whatever the spacing (worked out in rational arithmetic
     * from the normal equations). The library solves those equations in floating point:
     * their condition number is 2e6 at this spacing, so 1e-9 relative. */
    const double sigma = GR_A, h = GR_FIT / 10, pairs = n * (n - 1) / 2;
    const double y0 = 3 * n * sigma / (sigma * pairs / volume * shell(3, sigma, sigma + h));
    double contact, contact_err;
    hsbd_gr_contact(g, 0, &contact, &contact_err);
    CHECK_CLOSE(contact, y0 * 663.0 / 880.0, 1e-9 * y0);
    CHECK_NEAR(hsbd_gr_contact_weight(g, 0),
               2 * PI * sigma * sigma * sigma * (n - 1) / (3 * volume));
    hsbd_gr_free(g);
}

/* Square lattice, 8^2 sites, spacing 1.25, disks of diameter 1: 4, 4, 4, 8 neighbours at
 * a, a sqrt 2, 2a, a sqrt 5. A checkerboard of two species (32 each): vector (p, q) joins
 * the same species when p + q is even, so A-B pairs hold the 4 at a and the 8 at a sqrt 5
 * (per A particle: count = g_AB x shell x N_A N_B / V, over N_A), A-A and B-B the 4 at
 * a sqrt 2 and the 4 at 2a (per particle: 2 count / N_A, count = g_AA x shell x
 * N_A (N_A - 1) / (2 V)). */
static void test_gr_square(void) {
    static lattice lt;
    const double volume = 10.0 * 10.0;
    hsbd_error err;
    /* one species */
    lattice_build(&lt, 2, 8, GR_A, 1.0, 0);
    hsbd_gr *g = hsbd_gr_alloc(&lt.view, GR_RMAX, GR_W, GR_FIT, 2, 2, &err);
    CHECK(g != NULL, "hsbd_gr_alloc: %s", g ? "" : err.message);
    if (!g) return;
    for (int s = 0; s < 2; ++s)
        CHECK(hsbd_gr_sample(g, &lt.view) == HSBD_OK, "hsbd_gr_sample");
    double want[GR_BINS] = {0};
    want[shell_bin(1)] = 4, want[shell_bin(2)] = 4, want[shell_bin(4)] = 4, want[shell_bin(5)] = 8;
    check_coordination("square", g, 0, 2, (64.0 - 1) / volume, want);
    CHECK_NEAR(hsbd_gr_contact_weight(g, 0), PI * 1.0 * (64.0 - 1) / (2 * volume));
    hsbd_gr_free(g);
    /* two species */
    lattice_build(&lt, 2, 8, GR_A, 1.0, 1);
    g = hsbd_gr_alloc(&lt.view, GR_RMAX, GR_W, GR_FIT, 2, 2, &err);
    CHECK(g != NULL, "hsbd_gr_alloc (two species): %s", g ? "" : err.message);
    if (!g) return;
    CHECK(hsbd_gr_pairs(g) == 3, "%zu species pairs, not 3", hsbd_gr_pairs(g));
    size_t a = 9, b = 9;
    hsbd_gr_pair_species(g, 1, &a, &b);
    CHECK(a == 0 && b == 1, "pair 1 is (%zu, %zu), not (0, 1)", a, b);
    hsbd_gr_pair_species(g, 2, &a, &b);
    CHECK(a == 1 && b == 1, "pair 2 is (%zu, %zu), not (1, 1)", a, b);
    for (int s = 0; s < 2; ++s)
        CHECK(hsbd_gr_sample(g, &lt.view) == HSBD_OK, "hsbd_gr_sample");
    double same[GR_BINS] = {0}, other[GR_BINS] = {0};
    same[shell_bin(2)] = 4, same[shell_bin(4)] = 4;
    other[shell_bin(1)] = 4, other[shell_bin(5)] = 8;
    const double na = 32;
    /* same species: 2 count / N_A = g shell (N_A - 1) / V */
    check_coordination("A-A", g, 0, 2, (na - 1) / volume, same);
    check_coordination("B-B", g, 2, 2, (na - 1) / volume, same);
    /* A-B: count / N_A = g shell N_B / V */
    check_coordination("A-B", g, 1, 2, na / volume, other);
    hsbd_gr_free(g);
}

/* ------------------------------------------------------------------------ clusters ---- */

/* Rods stepped once from the positions x: D = kT = 1e-200 (mobility 1, noise amplitude
 * sqrt(2e-200 dt) ~ 1e-102, far below the rounding of any position), sticky contacts, and
 * the field of par: the end points y = z + F dt. Returns the step's statistics. */
static int step_from(hsbd_rods *rods, const double *x, hsbd_rods_step_stats *st) {
    hsbd_error err;
    if (hsbd_rods_set_positions(rods, x, &err) != HSBD_OK) return -1;
    hsbd_rods_step(rods, st);
    return 0;
}

/* A ring of length 20 with 11 rods of length 1 in a harmonic trap about 0 (nearest image,
 * F = -d): within 10 of 0 the force decreases along the line, so every touching pair is
 * pressed together (unless it straddles 10, none does), and the open gaps (>= 0.5) close
 * by at most 1e-2 in the step (dt 1e-3). Configuration A: {19.5, 0.5, 1.5} touching across
 * the end of the ring (gap 0.5 + 20 - 19.5 - 1 = 0), {4, 5}, 8, 11.5, {14, 15, 16, 17}:
 * clusters of 3, 2, 1, 1, 4. Configuration B: {0.5, 1.5} and nine single rods: 2 and nine
 * 1s. Samples A, A, B, B in two time blocks: mean cluster size N / clusters = 11/5, then
 * 11/10: mean 1.65, error 0.55. Size fractions over all samples' 30 clusters: 22 of size 1,
 * 4 of size 2, 2 of 3, 2 of 4. Merges per step from the statistics passed in: fragments -
 * clusters at the end, 2, 0, 2, 3: block means 1 and 2.5, mean 1.75, error 0.75. */
static void test_clusters_ring(void) {
    enum { N = 11 };
    hsbd_rods_params par = {.n = N,
                            .length = 20,
                            .sigma = 1,
                            .diffusion = 1e-200,
                            .kT = 1e-200,
                            .dt = 1e-3,
                            .seed = 5,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY};
    hsbd_field_add(&par.field, hsbd_field_harmonic(1.0, 0.0, 20.0));
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_clusters *c = hsbd_clusters_alloc(N, 2, 4);
    CHECK(rods != NULL && c != NULL, "alloc");
    if (!rods || !c) {
        hsbd_rods_free(rods);
        hsbd_clusters_free(c);
        return;
    }
    static const double xa[N] = {19.5, 0.5, 1.5, 4, 5, 8, 11.5, 14, 15, 16, 17};
    static const double xb[N] = {0.5, 1.5, 3, 5, 7, 9.25, 11, 13, 15, 17, 19};
    const double *config[4] = {xa, xa, xb, xb};
    static const size_t clusters[4] = {5, 5, 10, 10};
    static const size_t fragments[4] = {7, 5, 12, 13};
    for (int s = 0; s < 4; ++s) {
        hsbd_rods_step_stats real;
        CHECK(step_from(rods, config[s], &real) == 0, "set_positions");
        CHECK(hsbd_rods_cluster_count(rods) == clusters[s], "sample %d: %zu clusters, not %zu", s,
              hsbd_rods_cluster_count(rods), clusters[s]);
        const hsbd_rods_step_stats st = {
            .clusters_start = clusters[s], .fragments = fragments[s], .clusters_end = clusters[s]};
        hsbd_clusters_sample(c, rods, &st);
    }
    static const double fraction[N + 1] = {0, 22, 4, 2, 2, 0, 0, 0, 0, 0, 0, 0};
    for (size_t s = 1; s <= N; ++s)
        CHECK_NEAR(hsbd_clusters_size_fraction(c, s), fraction[s] / 30);
    CHECK(hsbd_clusters_max_size(c) == 4, "largest cluster %zu, not 4", hsbd_clusters_max_size(c));
    double mean, mean_err, merges, merges_err;
    hsbd_clusters_means(c, &mean, &mean_err, &merges, &merges_err);
    CHECK_NEAR(mean, 1.65);
    CHECK_NEAR(mean_err, 0.55);
    CHECK_NEAR(merges, 1.75);
    CHECK_NEAR(merges_err, 0.75);
    hsbd_clusters_free(c);
    hsbd_rods_free(rods);
}

/* Between walls at 0 and 10: F = -4 + x (a tilt and an inverted trap) drives the three
 * rods touching the left wall {0.5, 1.5, 2.5} into it and apart from each other, and the
 * two touching the right wall {8.5, 9.5} into it and apart: each wall holds its rods
 * together, one cluster of 3 and one of 2; 4.5 and 6.5 stay single. 4 clusters of 7 rods. */
static void test_clusters_walls(void) {
    enum { N = 7 };
    hsbd_rods_params par = {.n = N,
                            .length = 10,
                            .sigma = 1,
                            .diffusion = 1e-200,
                            .kT = 1e-200,
                            .dt = 1e-3,
                            .seed = 5,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY,
                            .boundary = HSBD_RODS_WALLS};
    hsbd_field_add(&par.field, hsbd_field_tilt(-4.0));
    hsbd_field_add(&par.field, hsbd_field_harmonic(-1.0, 0.0, 0.0));
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_clusters *c = hsbd_clusters_alloc(N, 1, 1);
    CHECK(rods != NULL && c != NULL, "alloc");
    if (!rods || !c) {
        hsbd_rods_free(rods);
        hsbd_clusters_free(c);
        return;
    }
    static const double x[N] = {0.5, 1.5, 2.5, 4.5, 6.5, 8.5, 9.5};
    hsbd_rods_step_stats st;
    CHECK(step_from(rods, x, &st) == 0, "set_positions");
    CHECK(hsbd_rods_cluster_count(rods) == 4, "%zu clusters, not 4", hsbd_rods_cluster_count(rods));
    hsbd_clusters_sample(c, rods, &st);
    CHECK_NEAR(hsbd_clusters_size_fraction(c, 1), 0.5);
    CHECK_NEAR(hsbd_clusters_size_fraction(c, 2), 0.25);
    CHECK_NEAR(hsbd_clusters_size_fraction(c, 3), 0.25);
    CHECK_NEAR(hsbd_clusters_size_fraction(c, 4), 0.0);
    CHECK(hsbd_clusters_max_size(c) == 3, "largest cluster %zu, not 3", hsbd_clusters_max_size(c));
    double mean, mean_err, merges, merges_err;
    hsbd_clusters_means(c, &mean, &mean_err, &merges, &merges_err);
    CHECK_NEAR(mean, 7.0 / 4.0);
    CHECK(isnan(mean_err), "one block: error %g (NaN)", mean_err);
    hsbd_clusters_free(c);
    hsbd_rods_free(rods);
}

/* --------------------------------------------------------- profiles and contacts ---- */

/* 8 rods of length 0.4 on a ring of 10, profile folded into period 5 (2 periods) in bins
 * of 0.5, contact window 0.2 (sub-windows of 0.05), one time block per sample.
 * Configuration 1: 0.3, 0.7, 1.22, 2.25, 3.6, 5.35, 6.8, 9.1 (gaps right of each: 0,
 * 0.12, 0.63, 0.95, 1.35, 1.05, 1.9, 0.8); folded bins 0, 1, 2, 4, 7, 0, 3, 8.
 * Configuration 2: 0.15, 0.55, 0.98, 2.9, 4.4, 6.2, 7.7, 9.63 (gaps 0, 0.03, 1.52, 1.1,
 * 1.4, 1.1, 1.53, and 0.12 across the ring's end); bins 0, 1, 1, 5, 8, 2, 5, 9.
 * Density = counts / (0.5 x 2) per sample; window pairs (gap <= 0.2) at the left rod's
 * bin, over 0.5 x 0.2 x 2; the extrapolation adds c_k / h for each open gap in sub-window
 * k (gap 0 is left out), c = the intercept weights of the least-squares line through the
 * four sub-window centres (k + 1/2) h: c_k = 1/4 - 2 (x_k - 2h) / (5h) = 0.85, 0.45, 0.05,
 * -0.35. */
static void test_profile(void) {
    enum { N = 8, BINS = 10 };
    hsbd_rods_params par = {
        .n = N, .length = 10, .sigma = 0.4, .diffusion = 1, .kT = 1, .dt = 0.01, .hard_core = 1};
    static const double x1[N] = {0.3, 0.7, 1.22, 2.25, 3.6, 5.35, 6.8, 9.1};
    static const double x2[N] = {0.15, 0.55, 0.98, 2.9, 4.4, 6.2, 7.7, 9.63};
    static const double count1[BINS] = {2, 1, 1, 1, 1, 0, 0, 1, 1, 0};
    static const double count2[BINS] = {1, 2, 1, 0, 0, 2, 0, 0, 1, 1};
    static const double window1[BINS] = {1, 1, 0, 0, 0, 0, 0, 0, 0, 0};
    static const double window2[BINS] = {1, 1, 0, 0, 0, 0, 0, 0, 0, 1};
    double c[4];
    for (int k = 0; k < 4; ++k)
        c[k] = 0.25 - 2 * ((k + 0.5) - 2) / 5;
    const double h = 0.05;
    double extrap1[BINS] = {0}, extrap2[BINS] = {0};
    extrap1[1] = c[2] / h;                        /* gap 0.12 right of 0.7 */
    extrap2[1] = c[0] / h, extrap2[9] = c[2] / h; /* 0.03 right of 0.55, 0.12 right of 9.63 */
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_profile *p = hsbd_profile_alloc(5.0, 0.5, 0.2, 2, 2, &err);
    CHECK(rods != NULL && p != NULL, "alloc");
    if (!rods || !p) {
        hsbd_rods_free(rods);
        hsbd_profile_free(p);
        return;
    }
    CHECK(hsbd_profile_bins(p) == BINS && hsbd_profile_blocks(p) == 2, "10 bins, 2 blocks");
    const double *config[2] = {x1, x2};
    for (int s = 0; s < 2; ++s) {
        CHECK(hsbd_rods_set_positions(rods, config[s], &err) == HSBD_OK, "set_positions");
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        CHECK(hsbd_profile_sample(p, &v) == HSBD_OK, "hsbd_profile_sample");
    }
    double x[BINS], val[BINS], e[BINS], blocks[2 * BINS];
    hsbd_profile_density(p, x, val, e);
    double total = 0;
    for (int k = 0; k < BINS; ++k) {
        CHECK_NEAR(x[k], (k + 0.5) * 0.5);
        CHECK_NEAR(val[k], (count1[k] + count2[k]) / 2);
        CHECK_NEAR(e[k], fabs(count1[k] - count2[k]) / 2);
        total += val[k];
    }
    CHECK_NEAR(total / BINS, 0.8); /* its mean over a period is N / L */
    hsbd_profile_density_blocks(p, blocks);
    for (int k = 0; k < BINS; ++k) {
        CHECK_NEAR(blocks[k], count1[k]);
        CHECK_NEAR(blocks[BINS + k], count2[k]);
    }
    hsbd_profile_contact_window(p, x, val, e);
    for (int k = 0; k < BINS; ++k) {
        CHECK_NEAR(val[k], 5 * (window1[k] + window2[k]) / 2);
        CHECK_NEAR(e[k], 5 * fabs(window1[k] - window2[k]) / 2);
    }
    hsbd_profile_contact_extrapolated(p, x, val, e);
    for (int k = 0; k < BINS; ++k) {
        CHECK_NEAR(val[k], (extrap1[k] + extrap2[k]) / 2);
        CHECK_NEAR(e[k], fabs(extrap1[k] - extrap2[k]) / 2);
    }
    hsbd_profile_contact_extrapolated_blocks(p, blocks);
    for (int k = 0; k < BINS; ++k) {
        CHECK_NEAR(blocks[k], extrap1[k]);
        CHECK_NEAR(blocks[BINS + k], extrap2[k]);
    }
    /* no step yet: no free end points, no impulses */
    hsbd_profile_contact(p, x, val, e);
    for (int k = 0; k < BINS; ++k)
        CHECK(val[k] == 0, "bin %d: contact impulses %g without a step", k, val[k]);
    CHECK(fabs(hsbd_profile_min_gap(p)) <= 1e-12, "smallest gap %g, not 0",
          hsbd_profile_min_gap(p));
    CHECK(hsbd_profile_nonfinite(p) == 0, "no non-finite positions");
    hsbd_profile_free(p);
    hsbd_rods_free(rods);
}

/* The same ring in two segments [0, 5) and [5, 10) (spatial blocks, one period each), one
 * sample of configuration 1: segment 0 holds 5 rods (bins 0, 1, 2, 4, 7), segment 1 holds 3
 * (bins 0, 3, 8). The density is the segments' mean over 0.5 x 1: counts of the whole ring
 * as above; each segment's row rescaled to the mean total of 4 rods: counts x 4/5 and
 * x 4/3, over 0.5. */
static void test_profile_segments(void) {
    enum { N = 8, BINS = 10 };
    hsbd_rods_params par = {
        .n = N, .length = 10, .sigma = 0.4, .diffusion = 1, .kT = 1, .dt = 0.01, .hard_core = 1};
    static const double x1[N] = {0.3, 0.7, 1.22, 2.25, 3.6, 5.35, 6.8, 9.1};
    static const double seg0[BINS] = {1, 1, 1, 0, 1, 0, 0, 1, 0, 0};
    static const double seg1[BINS] = {1, 0, 0, 1, 0, 0, 0, 0, 1, 0};
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_profile *p = hsbd_profile_alloc_spatial(5.0, 0.5, 0.2, 2, &err);
    CHECK(rods != NULL && p != NULL, "alloc");
    if (!rods || !p) {
        hsbd_rods_free(rods);
        hsbd_profile_free(p);
        return;
    }
    CHECK(hsbd_rods_set_positions(rods, x1, &err) == HSBD_OK, "set_positions");
    const hsbd_rods_view v = hsbd_rods_get_view(rods);
    CHECK(hsbd_profile_sample(p, &v) == HSBD_OK, "hsbd_profile_sample");
    double x[BINS], val[BINS], e[BINS], blocks[2 * BINS];
    hsbd_profile_density(p, x, val, e);
    for (int k = 0; k < BINS; ++k)
        CHECK_NEAR(val[k], seg0[k] + seg1[k]);
    hsbd_profile_density_blocks(p, blocks);
    for (int k = 0; k < BINS; ++k) {
        CHECK_NEAR(blocks[k], seg0[k] * 0.8 / 0.5);
        CHECK_NEAR(blocks[BINS + k], seg1[k] * 4.0 / 3.0 / 0.5);
    }
    hsbd_profile_free(p);
    hsbd_rods_free(rods);
}

/* A hand-made view of 4 rods of length 1 on a ring of 10 (free length 6), species 0, 1, 1,
 * 0 with mobilities 1 and 1/2, kT 2, dt 0.01: z = 1, 1, 3, 7, so rods 3, 0, 1 touch (3 to 0
 * across the end: 1 + 6 - 7 = 0) and rod 2 is alone. Free end points y - z = 0.01, -0.02,
 * 0.005, 0.03: across contact (3, 0) the impulse is 0.03 / 1, across (0, 1) 0.03 + 0.01 / 1;
 * over kT dt = 0.02: 1.5 and 2. Per length of line (over L = 10): species pair (0, 0) 0.15,
 * (0, 1) 0.2. The second sample doubles every y - z. The profile (period 10, bins of 1)
 * puts them at the left rods' centres z + offset = 1 (rod 0) and 10 = 0 (rod 3). */
static void test_contacts_ring(void) {
    const double z[4] = {1, 1, 3, 7}, offset[4] = {0, 1, 2, 3}, dy[4] = {0.01, -0.02, 0.005, 0.03};
    const int species[4] = {0, 1, 1, 0};
    const double sp_sigma[2] = {1, 1}, sp_mobility[2] = {1, 0.5};
    hsbd_error err;
    hsbd_contacts *c = hsbd_contacts_alloc(4, 2, 2, 2, &err);
    hsbd_profile *p = hsbd_profile_alloc(10.0, 1.0, 0.5, 2, 2, &err);
    CHECK(c != NULL && p != NULL, "alloc");
    if (!c || !p) {
        hsbd_contacts_free(c);
        hsbd_profile_free(p);
        return;
    }
    for (int s = 0; s < 2; ++s) {
        double y[4];
        for (int i = 0; i < 4; ++i)
            y[i] = z[i] + (s + 1) * dy[i];
        const hsbd_rods_view v = {.n = 4,
                                  .length = 10,
                                  .sigma = 1,
                                  .free_length = 6,
                                  .periodic = 1,
                                  .z = z,
                                  .offset = offset,
                                  .nspecies = 2,
                                  .species = species,
                                  .species_sigma = sp_sigma,
                                  .species_mobility = sp_mobility,
                                  .y = y,
                                  .mobility = 1,
                                  .kT = 2,
                                  .dt = 0.01,
                                  .hard_core = 1};
        double out[5];
        hsbd_contact_impulses(&v, out);
        const double want[5] = {2.0 * (s + 1), 0, 0, 1.5 * (s + 1), 0};
        for (int i = 0; i < 5; ++i)
            CHECK_NEAR(out[i], want[i]);
        hsbd_contacts_sample(c, &v);
        CHECK(hsbd_profile_sample(p, &v) == HSBD_OK, "hsbd_profile_sample");
    }
    /* samples 1 and 2 in blocks of their own: means 1.5 x, errors 0.5 x the first's */
    double val, e;
    hsbd_contacts_pair(c, 0, 0, &val, &e);
    CHECK_NEAR(val, 0.225);
    CHECK_NEAR(e, 0.075);
    hsbd_contacts_pair(c, 0, 1, &val, &e);
    CHECK_NEAR(val, 0.3);
    CHECK_NEAR(e, 0.1);
    hsbd_contacts_pair(c, 1, 0, &val, &e);
    CHECK_NEAR(val, 0.0);
    hsbd_contacts_pair(c, 1, 1, &val, &e);
    CHECK_NEAR(val, 0.0);
    double x[10], rho2[10], err2[10], win[10], winerr[10];
    hsbd_profile_contact(p, x, rho2, err2);
    hsbd_profile_contact_window(p, x, win, winerr);
    for (int k = 0; k < 10; ++k) {
        const double want = k == 0 ? 1.5 * 1.5 : k == 1 ? 1.5 * 2 : 0;
        CHECK_NEAR(rho2[k], want);
        CHECK_NEAR(err2[k], want / 3); /* 0.5 x the first sample's, which is want / 1.5 */
        /* the two touching pairs at bins 0 and 1, over bin 1 x window 0.5 x 1 period */
        CHECK_NEAR(win[k], k < 2 ? 2.0 : 0.0);
        CHECK_NEAR(winerr[k], 0.0);
    }
    hsbd_contacts_free(c);
    hsbd_profile_free(p);
}

/* Between walls at 0 and 3, two rods of length 1 (free length 1): rod 0 at the left wall
 * (z 0) with y - z = -0.2, rod 1 at the right wall (z 1) with y - z = 0.3, the gap
 * between them 1. Mobility 1, kT 1, dt 0.1: the left wall passed 0.2 / 0.1 = 2, the right
 * wall 3, the rods nothing to each other. */
static void test_contacts_walls(void) {
    const double z[2] = {0, 1}, offset[2] = {0.5, 1.5}, y[2] = {-0.2, 1.3};
    const hsbd_rods_view v = {.n = 2,
                              .length = 3,
                              .sigma = 1,
                              .free_length = 1,
                              .periodic = 0,
                              .z = z,
                              .offset = offset,
                              .y = y,
                              .mobility = 1,
                              .kT = 1,
                              .dt = 0.1,
                              .hard_core = 1};
    double out[3];
    hsbd_contact_impulses(&v, out);
    CHECK_NEAR(out[0], 0.0);
    CHECK_NEAR(out[1], 3.0);
    CHECK_NEAR(out[2], 2.0);
    hsbd_error err;
    hsbd_contacts *c = hsbd_contacts_alloc(2, 1, 1, 1, &err);
    CHECK(c != NULL, "alloc");
    if (!c) return;
    hsbd_contacts_sample(c, &v);
    double val, e;
    hsbd_contacts_wall(c, 0, &val, &e);
    CHECK_NEAR(val, 2.0);
    CHECK(isnan(e), "one block: error %g (NaN)", e);
    hsbd_contacts_wall(c, 1, &val, &e);
    CHECK_NEAR(val, 3.0);
    hsbd_contacts_pair(c, 0, 0, &val, &e);
    CHECK_NEAR(val, 0.0);
    hsbd_contacts_free(c);
    double walls[2];
    hsbd_wall_impulses(&v, walls);
    CHECK_NEAR(walls[0], 2.0);
    CHECK_NEAR(walls[1], 3.0);
}

/* The walls' impulses alone (log.tsv's) equal the walls' entries of all the impulses:
 * three rods of length 1 between walls at 0 and 5 (free length 2), rod 0 at the left wall,
 * rods 1 and 2 touching each other and the right wall (y - z = -0.1, 0.05, 0.2; dt 0.1,
 * kT 1, mobility 1: the left wall 1, the right wall 2.5); then all three touching both
 * walls (free length 0), where the chain closes on itself. */
static void test_wall_impulses(void) {
    const double offset[3] = {0.5, 1.5, 2.5};
    const double zs[2][3] = {{0, 2, 2}, {0, 0, 0}}, free_length[2] = {2, 0};
    for (int c = 0; c < 2; ++c) {
        const double *z = zs[c];
        const double y[3] = {z[0] - 0.1, z[1] + 0.05, z[2] + 0.2};
        const hsbd_rods_view v = {.n = 3,
                                  .length = 3 + free_length[c],
                                  .sigma = 1,
                                  .free_length = free_length[c],
                                  .z = z,
                                  .offset = offset,
                                  .y = y,
                                  .mobility = 1,
                                  .kT = 1,
                                  .dt = 0.1,
                                  .hard_core = 1};
        double all[4], walls[2];
        hsbd_contact_impulses(&v, all);
        hsbd_wall_impulses(&v, walls);
        CHECK_NEAR(walls[0], all[3]);
        CHECK_NEAR(walls[1], all[2]);
        if (c == 0) CHECK_NEAR(walls[0], 1.0);
        if (c == 0) CHECK_NEAR(walls[1], 2.5);
    }
}

int main(void) {
    test_wall_impulses();
    test_shape_open_block();
    test_block_of();
    test_time_blocks();
    test_empty_blocks();
    test_spatial_blocks();
    test_msd_ballistic();
    test_msd_sparse_origins();
    test_msd_diffusive();
    test_msd_origin_blocks();
    test_msd_members();
    test_msd_restart();
    test_msd_view();
    test_gr_cubic();
    test_gr_square();
    test_clusters_ring();
    test_clusters_walls();
    test_profile();
    test_profile_segments();
    test_contacts_ring();
    test_contacts_walls();
    return test_finish("test_observers");
}
