/* Quick statistical tests of the rods engine against exact results.
 *
 * Every comparison uses a fixed seed and passes when |simulation - exact| < 4 standard
 * errors, the errors measured by block averages in the same run (20 blocks, each much
 * longer than the relaxation time of the observable). Set HSBD_VALIDATE=long for ten
 * times longer runs (make validate). The deviations are printed in units of the error. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/observe.h"
#include "hsbd/rods.h"
#include "hsbd/theory.h"

static double run_scale(void) {
    const char *v = getenv("HSBD_VALIDATE");
    return v && !strcmp(v, "long") ? 10.0 : 1.0;
}

static int within(const char *what, double sim, double err, double exact) {
    const double dev = (sim - exact) / err;
    printf("  %-44s sim %.6g +- %.2g, exact %.6g: %+.2f sigma\n", what, sim, err, exact, dev);
    return isfinite(dev) && fabs(dev) < 4.0;
}

/* U0 = 0 ring (exact equilibrium start, no equilibration): uniform density, and the
 * contact density with window Delta' against the exact canonical gap law of N uniform
 * spacings: P(gap <= D') = 1 - (1 - D'/(L - N sigma))^(N-1). The window is 50 times the
 * rms relative step sqrt(4 D dt); the O(sqrt(dt)) excess at contact that remains was
 * measured at +0.73 +- 0.23 % in a 100 times longer run (docs/validation.md), a third of
 * this test's error bar. */
static void test_tonks_ring(void) {
    enum { NBINS = 20 };
    const size_t n = 20, nblocks = 20;
    const double L = 40, sigma = 0.5, dt = 1e-4, window = 1.0;
    const uint64_t every = 10, steps = (uint64_t)(2.0e6 * run_scale());
    hsbd_rods_params par = {.n = n,
                            .length = L,
                            .sigma = sigma,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = dt,
                            .seed = 31,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY};
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_rods_init_equilibrium(rods);
    /* the same samples binned twice: 20 bins for uniformity, one bin for the mean */
    hsbd_profile *prof = hsbd_profile_alloc(1.0, 1.0 / NBINS, window, nblocks, steps / every, &err);
    hsbd_profile *whole = hsbd_profile_alloc(1.0, 1.0, window, nblocks, steps / every, &err);
    for (uint64_t k = 1; k <= steps; ++k) {
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        if (k % every) continue;
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        hsbd_profile_sample(prof, &v);
        hsbd_profile_sample(whole, &v);
    }
    double x[NBINS], rho[NBINS], rho_err[NBINS];
    hsbd_profile_density(prof, x, rho, rho_err);
    double chi2 = 0;
    for (size_t k = 0; k < NBINS; ++k)
        chi2 += pow((rho[k] - (double)n / L) / rho_err[k], 2);
    /* chi^2/dof of NBINS block-error-normalised deviations: mean 1, sd ~ sqrt(2/NBINS)
     * (somewhat more with 20 blocks: the errors are themselves estimated) */
    printf("  density chi^2/dof = %.3f over %d bins\n", chi2 / NBINS, NBINS);
    CHECK(fabs(chi2 / NBINS - 1) < 4 * sqrt(2.0 / NBINS), "density not uniform: chi2/dof %.3f",
          chi2 / NBINS);
    double x1, c1, e1, d1, de1;
    hsbd_profile_density(whole, &x1, &d1, &de1);
    CHECK(fabs(d1 - (double)n / L) < 1e-12, "density normalisation: mean %.15g != N/L", d1);
    hsbd_profile_contact_window(whole, &x1, &c1, &e1);
    const double lf = L - (double)n * sigma;
    const double exact = (double)n / L * (1 - pow(1 - window / lf, (double)n - 1)) / window;
    CHECK(within("Tonks ring contact density (window 1.0)", c1, e1, exact), "contact density");
    /* contact theorem: mean contact impulse per time / kT = rho2 at contact, exactly
     * (N/L)(N-1)/(L - N sigma) on the ring */
    hsbd_profile_contact(whole, &x1, &c1, &e1);
    CHECK(within("Tonks ring contact density (contact theorem)", c1, e1,
                 hsbd_tonks_ring_contact((double)n, L, sigma)),
          "contact theorem estimator");
    CHECK(hsbd_profile_min_gap(whole) >= 0, "negative gap %.3g", hsbd_profile_min_gap(whole));
    hsbd_profile_free(prof);
    hsbd_profile_free(whole);
    hsbd_rods_free(rods);
}

/* Short-time MSD of dilute hard rods against 2 D t with its exact first collision
 * correction (docs/validation.md): MSD = 2 D t [1 - (4 / (3 sqrt(2 pi))) rho_g sqrt(4 D t)],
 * rho_g = (N-1)/(L - N sigma) the gap density at contact; next order ~ (rho_g sqrt(4 D t))^2
 * < 1e-5 here. Measured in the validation run: 0.99865 +- 0.0011 vs 0.99861 at t = 0.01. */
static void test_short_time_msd(void) {
    const size_t n = 200, nblocks = 20;
    const double L = 20000, sigma = 1.0, dt = 1e-4;
    const uint64_t steps = (uint64_t)(4.0e5 * run_scale());
    hsbd_rods_params par = {.n = n,
                            .length = L,
                            .sigma = sigma,
                            .diffusion = 1.7,
                            .kT = 1,
                            .dt = dt,
                            .seed = 5,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY};
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_rods_init_equilibrium(rods);
    hsbd_msd *msd = hsbd_msd_alloc(n, dt, steps, 0.01, 5, nblocks, &err);
    for (uint64_t k = 0; k < steps; ++k) {
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        hsbd_msd_sample(msd, &v);
    }
    const double pi = 3.141592653589793, rho_gap = ((double)n - 1) / (L - (double)n * sigma);
    int bad = 0;
    for (size_t k = 0; k < hsbd_msd_lags(msd); ++k) {
        double t, m, e;
        size_t origins;
        hsbd_msd_result(msd, k, &t, &m, &e, &origins);
        const double theory = 1 - 4 / (3 * sqrt(2 * pi)) * rho_gap * sqrt(4 * par.diffusion * t);
        char what[64];
        snprintf(what, sizeof what, "MSD(t = %.4g) / (2 D t)", t);
        bad += !within(what, m / (2 * par.diffusion * t), e / (2 * par.diffusion * t), theory);
    }
    CHECK(bad == 0, "%d lags off the short-time law", bad);
    hsbd_msd_free(msd);
    hsbd_rods_free(rods);
}

/* Constant force f: the mean velocity is mu f, with and without the hard core (with it,
 * every cluster feels the same force per rod, so clusters also move at mu f). The error
 * of the mean displacement is measured from blocks of time. */
static void test_drift(int hard_core) {
    const size_t n = 100, nblocks = 20;
    const double L = 200, dt = 1e-3, f = 1.5, D = 0.8, kT = 2.0;
    const uint64_t steps = (uint64_t)(2.0e4 * run_scale());
    hsbd_rods_params par = {.n = n,
                            .length = L,
                            .sigma = 1.0,
                            .diffusion = D,
                            .kT = kT,
                            .dt = dt,
                            .seed = 77,
                            .hard_core = hard_core,
                            .contact_rule = HSBD_CONTACT_STICKY};
    hsbd_field_add(&par.field, hsbd_field_tilt(f));
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_rods_init_equilibrium(rods);
    hsbd_blocks *vel = hsbd_blocks_alloc(1, nblocks, steps);
    double prev = 0;
    for (size_t i = 0; i < n; ++i) {
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        prev += v.z[i] + v.offset[i] + v.unwrap;
    }
    for (uint64_t k = 0; k < steps; ++k) {
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        double sum = 0;
        for (size_t i = 0; i < n; ++i)
            sum += v.z[i] + v.offset[i] + v.unwrap;
        hsbd_blocks_acc(vel)[0] += (sum - prev) / ((double)n * dt);
        hsbd_blocks_end_sample(vel);
        prev = sum;
    }
    double m, e;
    hsbd_blocks_result(vel, &m, &e);
    CHECK(within(hard_core ? "drift velocity / (mu f), hard core" : "drift velocity / (mu f), free",
                 m / (D / kT * f), e / (D / kT * f), 1.0),
          "drift");
    hsbd_blocks_free(vel);
    hsbd_rods_free(rods);
}

/* contact_rule = reflect is exact for an isolated pair at any dt: two rods on a ring
 * have a uniform gap on [0, L - 2 sigma] even with a step whose rms relative move
 * (0.45) is a quarter of the free length; the sticky rule piles up ~90 % extra
 * probability at contact there. 10 bins, errors from 20 time blocks. */
static void test_reflect_two_rods(void) {
    enum { NB = 10 };
    const double L = 3.0, sigma = 0.5, lf = L - 2 * sigma, dt = 0.05;
    const uint64_t steps = (uint64_t)(4e5 * run_scale());
    const int rules[] = {HSBD_CONTACT_STICKY, HSBD_CONTACT_REFLECT};
    for (size_t r = 0; r < 2; ++r) {
        const int rule = rules[r];
        hsbd_rods_params par = {.n = 2,
                                .length = L,
                                .sigma = sigma,
                                .diffusion = 1,
                                .kT = 1,
                                .dt = dt,
                                .seed = 3,
                                .hard_core = 1,
                                .contact_rule = rule};
        hsbd_error err;
        hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
        hsbd_rods_init_equilibrium(rods);
        hsbd_blocks *hist = hsbd_blocks_alloc(NB, 20, steps);
        for (uint64_t k = 0; k < steps; ++k) {
            CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
            const hsbd_rods_view v = hsbd_rods_get_view(rods);
            int b = (int)((v.z[1] - v.z[0]) / lf * NB);
            hsbd_blocks_acc(hist)[b < 0 ? 0 : b >= NB ? NB - 1 : b] += 1.0;
            hsbd_blocks_end_sample(hist);
        }
        double m[NB], e[NB];
        hsbd_blocks_result(hist, m, e);
        if (rule == HSBD_CONTACT_REFLECT) {
            int bad = 0;
            for (int b = 0; b < NB; ++b) {
                char what[64];
                snprintf(what, sizeof what, "reflect: gap probability in bin %d", b);
                bad += !within(what, m[b], e[b], 1.0 / NB);
            }
            CHECK(bad == 0, "%d gap bins off the uniform law", bad);
        } else {
            printf("  sticky: gap probability at contact %.4f (uniform %.4f)\n", m[0], 1.0 / NB);
            CHECK(m[0] > 1.5 / NB, "the sticky rule should pile up at contact here");
        }
        hsbd_blocks_free(hist);
        hsbd_rods_free(rods);
    }
}

/* The reflect rule's pushes follow the law of the minimum m of the Brownian bridge of each
 * gap from g0 to its free end g1 (relative diffusion D_rel dt = d): P(m < a) =
 * exp(-(g0 - a)(g1 - a) / d) for a <= min(g0, g1). So a gap crosses with probability
 * p = exp(-g0 g1 / d) (1 when g0 g1 <= 0), and for a crossing gap pushed by h = -m the
 * probability transform w = exp(-(g0 + h)(g1 + h) / d) / p = P(m < -h | m < 0) is uniform
 * on (0, 1). Checked on every gap of every step, the positions reset before each step so
 * that the start gaps run over closed ones, ones that cross often, rarely (most gaps near
 * 0.1, where crossings with p < 1/100 come from: there the low digits of the uniform decide)
 * and (beyond the listing's bound, p < 2e-9) never: a ring of one species (2100 rods: two
 * whole batches of gaps, a short one and the ring's last gap apart) and a mixture of two
 * species between walls (the wall gaps with the rod's own D). Against the exact law, over
 * all crossings and over the rare ones (p < 1/100): the number of crossings (against the
 * sum of p), the mean and mean square of w (1/2, 1/3) and the fraction of w in each fifth
 * of (0, 1) (1/5). Each is a sum per step of terms of mean zero under the exact law
 * (crossing - p; w - 1/2 per crossing; ...), divided by the mean count it is relative to;
 * its error comes from 20 block averages over the steps (the steps are independent). Fixed
 * seeds; within 4 standard errors. */
enum { BRIDGE_BINS = 5, BRIDGE_VALUES = 3 + BRIDGE_BINS };
static void test_reflect_bridge_law(int walls) {
    enum { N = 2100, NG = 12 };
    const double start_gaps[NG] = {0.0, 0.002, 0.01, 0.03, 0.06, 0.09,
                                   0.1, 0.11,  0.12, 0.13, 0.2,  1.0};
    const double sp_sigma[2] = {0.5, 0.3}, sp_d[2] = {1.0, 3.0}, dt = 1e-3;
    const uint64_t steps = (uint64_t)(600 * run_scale());
    int species[N];
    double x[N], gap[N + 1];
    double occupied = 0, pos = 0;
    for (size_t i = 0; i <= N; ++i)
        gap[i] = start_gaps[(i * 5 + i / NG) % NG]; /* gap i right of rod i; N: left wall */
    if (walls) pos = gap[N];
    for (size_t i = 0; i < N; ++i) {
        species[i] = walls ? (int)(i % 3 == 0) : 0;
        const double sg = walls ? sp_sigma[species[i]] : 0.5;
        x[i] = pos + sg / 2;
        pos += sg + gap[i];
        occupied += sg;
    }
    hsbd_rods_params par = {.n = N,
                            .length = pos,
                            .sigma = 0.5,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = dt,
                            .seed = walls ? 17 : 16,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_REFLECT,
                            .boundary = walls ? HSBD_RODS_WALLS : HSBD_RODS_PERIODIC};
    if (walls) {
        par.nspecies = 2;
        par.species = species;
        par.species_sigma = sp_sigma;
        par.species_diffusion = sp_d;
    }
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    CHECK(rods != NULL, "%s", err.message);
    if (!rods) return;
    const double lf = pos - occupied;
    /* per step, for all gaps (set 0) and the rare ones (set 1): BRIDGE_VALUES sums of terms
     * of mean zero, then the crossings and the sum of p */
    enum { PER_SET = BRIDGE_VALUES + 2 };
    hsbd_blocks *blocks = hsbd_blocks_alloc(2 * PER_SET, 20, steps);
    static double z0[N];
    for (uint64_t s = 0; s < steps; ++s) {
        CHECK(hsbd_rods_set_positions(rods, x, &err) == HSBD_OK, "%s", err.message);
        hsbd_rods_view v = hsbd_rods_get_view(rods);
        memcpy(z0, v.z, sizeof z0);
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        v = hsbd_rods_get_view(rods);
        double *acc = hsbd_blocks_acc(blocks);
        for (size_t k = 0; k <= N; ++k) { /* gap k right of rod k; N: left wall (walls only) */
            double g0, g1, mu_sum;
            if (k + 1 < N) {
                g0 = z0[k + 1] - z0[k], g1 = v.y[k + 1] - v.y[k];
                mu_sum = v.species ? v.species_mobility[v.species[k]] +
                                         v.species_mobility[v.species[k + 1]]
                                   : 2 * v.mobility;
            } else if (k + 1 == N && !walls) {
                g0 = z0[0] + lf - z0[k], g1 = v.y[0] + lf - v.y[k], mu_sum = 2 * v.mobility;
            } else if (k + 1 == N) {
                g0 = lf - z0[k], g1 = lf - v.y[k], mu_sum = v.species_mobility[v.species[k]];
            } else if (walls) {
                g0 = z0[0], g1 = v.y[0], mu_sum = v.species_mobility[v.species[0]];
            } else {
                continue;
            }
            const double d = mu_sum * v.kT * dt, h = v.push[k];
            const double p = g0 * g1 <= 0 ? 1.0 : exp(-g0 * g1 / d);
            for (int rare = 0; rare <= (p < 0.01); ++rare) { /* all, then the rare ones */
                double *a = acc + rare * PER_SET;
                a[0] += (h > 0) - p;
                a[BRIDGE_VALUES + 1] += p;
                if (!(h > 0)) continue;
                const double w = exp(-(g0 + h) * (g1 + h) / d) / p;
                a[1] += w - 0.5;
                a[2] += w * w - 1.0 / 3;
                const int bin = (int)(w * BRIDGE_BINS);
                for (int b = 0; b < BRIDGE_BINS; ++b)
                    a[3 + b] += (b == (bin < BRIDGE_BINS ? bin : BRIDGE_BINS - 1)) - 0.2;
                a[BRIDGE_VALUES] += 1;
            }
        }
        hsbd_blocks_end_sample(blocks);
    }
    double mean[2 * PER_SET], se[2 * PER_SET];
    hsbd_blocks_result(blocks, mean, se);
    int bad = 0;
    for (int rare = 0; rare <= 1; ++rare) {
        const double *m = mean + rare * PER_SET, *e = se + rare * PER_SET;
        const double crossings = m[BRIDGE_VALUES], expected = m[BRIDGE_VALUES + 1];
        const char *set = walls ? (rare ? "walls, mixture, p < 1/100:" : "walls, mixture:")
                                : (rare ? "ring, p < 1/100:" : "ring:");
        char what[80];
        printf("  reflect, %s %.1f crossings per step\n", set, crossings);
        snprintf(what, sizeof what, "%s crossings / expected", set);
        bad += !within(what, 1 + m[0] / expected, e[0] / expected, 1.0);
        snprintf(what, sizeof what, "%s mean of w", set);
        bad += !within(what, 0.5 + m[1] / crossings, e[1] / crossings, 0.5);
        snprintf(what, sizeof what, "%s mean of w^2", set);
        bad += !within(what, 1.0 / 3 + m[2] / crossings, e[2] / crossings, 1.0 / 3);
        for (int b = 0; b < BRIDGE_BINS; ++b) {
            snprintf(what, sizeof what, "%s w in [%.1f, %.1f)", set, 0.2 * b, 0.2 * (b + 1));
            bad += !within(what, 0.2 + m[3 + b] / crossings, e[3 + b] / crossings, 0.2);
        }
    }
    CHECK(bad == 0, "reflect, %s: %d values off the bridge minimum's law", walls ? "walls" : "ring",
          bad);
    hsbd_blocks_free(blocks);
    hsbd_rods_free(rods);
}

int main(void) {
    printf("run scale %.2g\n", run_scale());
    test_reflect_two_rods();
    test_reflect_bridge_law(0);
    test_reflect_bridge_law(1);
    test_tonks_ring();
    test_short_time_msd();
    test_drift(0);
    test_drift(1);
    return test_finish("test_rods_physics");
}
