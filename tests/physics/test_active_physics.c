/* Active Brownian disks and spheres against exact results, fixed seeds; every check
 * |sim - theory| <= 4 error bars unless said otherwise.
 *   - The rotational step, one step of many independent particles (hard_core = off) at
 *     tau = D_r dt from 0.01 to 30 (3D: substeps above 0.2, uniform above 20): the averages of
 * P_l(e(t).e(t+dt)) for l = 1, 2, 3 against exp(-l (l + 1) tau) in 3D, of cos(l dtheta) against
 *     exp(-l^2 tau) in 2D. The samples are independent (one rotation each), so the error bar
 *     is their standard deviation over sqrt(count). A step that normalised a Gaussian kick
 *     instead (e + sqrt(2 tau) xi_perp, normalised) gives <e.e'> = E[(1 + 4 tau X)^(-1/2)],
 *     X exponential: 0.98114 at tau = 0.01 against exp(-0.02) = 0.98020, 24 error bars
 *     off, and 0.656 against 0.368 at tau = 0.5.
 *   - Ideal ABPs (hard_core = off, periodic box) in 2D and 3D, D 1, v0 5, D_r 3 (k = (d-1) D_r
 *     = 3 and 6), dt 1e-3: the orientation correlation <e(0).e(t)> = exp(-k t) and the MSD
 *     2 d D t + 2 v0^2 / k^2 (k t - 1 + exp(-k t)) at every lag of the log-spaced table,
 *     errors from blocks of time origins (the propulsion uses the orientation at the step's
 *     start: the active part of the MSD is off by k dt^2 / (3 t) relative at lag t, 2e-4
 *     at the shortest lag here, far below the error bars).
 *   - The mechanical pressure of ideal ABPs on hard walls (walls along x, periodic
 *     otherwise; Solon et al., Nat. Phys. 11, 673 (2015)): P = rho_bulk (kT + v0^2 /
 *     (d (d-1) mu D_r)), P from the walls' impulses (contact theorem), rho_bulk the density
 *     in the middle third of the slit, 2D and 3D. The wall step is exact for the step's
 *     constant drift; the allowance adds the pressure change of 4 error bars of rho_bulk.
 *   - A dense active fluid (2D, phi 0.4, Pe 20): its contact statistics (the swim speed
 *     ratio and the collisional pressure) converged in dt: equal within 4 error bars at
 *     dt 8e-4, 4e-4 and 2e-4 (below).
 * HSBD_VALIDATE=long (make validate): the sampled times 10 times longer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "../test_util.h"
#include "hsbd/observe.h"
#include "hsbd/spheres.h"

static const double PI = 3.14159265358979323846;
enum { BLOCKS = 20 };

static double sampled_time(double t) {
    const char *v = getenv("HSBD_VALIDATE");
    return v && !strcmp(v, "long") ? 10 * t : t;
}

/* n ideal active particles of D 1, sigma 1, v0 and D_r, scattered over the box (or between
 * walls along x) */
static hsbd_spheres *ideal_abps(int dim, size_t n, const double box[3], int walls_x, double dt,
                                double v0, double dr, uint64_t seed) {
    double *v0s = malloc(n * sizeof *v0s), *drs = malloc(n * sizeof *drs);
    for (size_t i = 0; i < n; ++i)
        v0s[i] = v0, drs[i] = dr;
    hsbd_spheres_params p = {.n = n,
                             .dimension = dim,
                             .box = {box[0], box[1], box[2]},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = dt,
                             .seed = seed,
                             .hard_core = 0,
                             .walls = {walls_x, 0, 0},
                             .particle_v0 = v0s,
                             .particle_rotational_diffusion = drs};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    free(v0s), free(drs);
    CHECK(s != NULL, "alloc: %s", err.message);
    if (!s) return NULL;
    double *x = malloc(3 * n * sizeof *x);
    for (size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            const double lo = a == 0 && walls_x ? 0.5 : 0,
                         hi = a == 0 && walls_x ? box[0] - 0.5 : box[a];
            x[3 * i + a] =
                a < dim ? lo + (hi - lo) * fmod(0.5 + (double)i * (0.618034 + 0.1 * a), 1.0) : 0;
        }
    CHECK(hsbd_spheres_set_positions(s, x, &err) == HSBD_OK, "positions: %s", err.message);
    free(x);
    return s;
}

/* ---- the rotational step ---- */

static void test_rotation_step(int dim, double tau) {
    const size_t n = 20000;
    const int steps = 10;
    const double box[3] = {100, 100, 100}, dt = 0.01;
    hsbd_spheres *s = ideal_abps(dim, n, box, 0, dt, 0.0, tau / dt, 40 + (uint64_t)(100 * tau));
    if (!s) return;
    double *before = malloc(3 * n * sizeof *before), sum[4] = {0}, sum2[4] = {0};
    for (int k = 0; k < steps; ++k) {
        memcpy(before, hsbd_spheres_get_view(s).orientation, 3 * n * sizeof *before);
        CHECK(hsbd_spheres_step(s) == HSBD_OK, "step %d", k);
        const double *e = hsbd_spheres_get_view(s).orientation;
        for (size_t i = 0; i < n; ++i) {
            const double *a = before + 3 * i, *b = e + 3 * i;
            const double c = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            double f[4];
            if (dim == 3) { /* Legendre P_1, P_2, P_3 */
                f[1] = c, f[2] = 0.5 * (3 * c * c - 1), f[3] = 0.5 * (5 * c * c * c - 3 * c);
            } else { /* cos(l dtheta) by Chebyshev */
                f[1] = c, f[2] = 2 * c * c - 1, f[3] = 4 * c * c * c - 3 * c;
            }
            for (int l = 1; l <= 3; ++l)
                sum[l] += f[l], sum2[l] += f[l] * f[l];
        }
    }
    const double count = (double)n * steps;
    for (int l = 1; l <= 3; ++l) {
        const double mean = sum[l] / count;
        const double err = sqrt(fmax(0, sum2[l] / count - mean * mean) / (count - 1));
        const double exact = exp(-(dim == 3 ? l * (l + 1) : l * l) * tau);
        printf("rotation %dD, tau %g: l = %d: %.5f +- %.5f, exact %.5f (%+.2f)\n", dim, tau, l,
               mean, err, exact, (mean - exact) / err);
        CHECK(fabs(mean - exact) <= 4 * err + 1e-12, "%dD tau %g l %d: %.5f vs %.5f", dim, tau, l,
              mean, exact);
    }
    free(before);
    hsbd_spheres_free(s);
}

/* ---- ideal ABPs: orientation correlation and MSD ---- */

static void test_ideal_laws(int dim) {
    const size_t n = dim == 2 ? 1000 : 800;
    const double box[3] = {60, 60, 60}, dt = 1e-3, v0 = 5, dr = 3, diff = 1;
    const double k = (dim - 1) * dr, t_total = sampled_time(20);
    const uint64_t every = 10, samples = (uint64_t)llround(t_total / dt) / every;
    hsbd_spheres *s = ideal_abps(dim, n, box, 0, dt, v0, dr, 7 + (uint64_t)dim);
    if (!s) return;
    hsbd_error err;
    hsbd_msd *msd = hsbd_msd_alloc((size_t)dim * n, dt * every, samples, 2.0, 8, BLOCKS, &err);
    hsbd_msd *rot = hsbd_msd_alloc((size_t)dim * n, dt * every, samples, 2.0, 8, BLOCKS, &err);
    CHECK(msd && rot, "msd: %s", err.message);
    double *xs = malloc((size_t)dim * n * sizeof *xs), *es = malloc((size_t)dim * n * sizeof *es);
    int failed = 0;
    for (uint64_t step = 1; step <= samples * every; ++step) {
        failed |= hsbd_spheres_step(s) != HSBD_OK;
        if (step % every) continue;
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        for (size_t i = 0; i < n; ++i)
            for (int a = 0; a < dim; ++a) {
                xs[(size_t)dim * i + a] = v.x[3 * i + a] + (double)v.image[3 * i + a] * v.box[a];
                es[(size_t)dim * i + a] = v.orientation[3 * i + a];
            }
        hsbd_msd_sample_values(msd, xs);
        hsbd_msd_sample_values(rot, es);
    }
    int lags = 0, worst_lag = 0;
    double worst_msd = 0, worst_rot = 0;
    for (size_t q = 0; q < hsbd_msd_lags(msd); ++q) {
        double t, m, me, c, ce;
        size_t origins;
        hsbd_msd_result(msd, q, &t, &m, &me, &origins);
        hsbd_msd_result(rot, q, &t, &c, &ce, &origins);
        if (origins < 2 * BLOCKS) continue;
        m *= dim, me *= dim;                        /* per particle */
        c = 1 - 0.5 * dim * c, ce = 0.5 * dim * ce; /* e(0).e(t) = 1 - |de|^2 / 2 */
        const double m_exact =
            2 * dim * diff * t + 2 * v0 * v0 / (k * k) * (k * t - 1 + exp(-k * t));
        const double c_exact = exp(-k * t);
        const double zm = (m - m_exact) / me, zc = (c - c_exact) / ce;
        if (fabs(zm) > fabs(worst_msd)) worst_msd = zm, worst_lag = (int)q;
        if (fabs(zc) > fabs(worst_rot)) worst_rot = zc;
        if (getenv("ACTIVE_VERBOSE"))
            printf("  t %g msd %+.2f rot %+.2f (c %.5f +- %.5f)\n", t, zm, zc, c, ce);
        CHECK(fabs(zm) <= 4, "%dD MSD at t = %g: %.6g +- %.3g, exact %.6g", dim, t, m, me, m_exact);
        CHECK(fabs(zc) <= 4, "%dD <e(0).e(t)> at t = %g: %.6g +- %.3g, exact %.6g", dim, t, c, ce,
              c_exact);
        ++lags;
    }
    printf("ideal ABPs %dD (v0 %g, D_r %g, dt %g, %g time units): %d lags, largest deviations: "
           "MSD %+.2f error bars (lag %d), orientation %+.2f\n",
           dim, v0, dr, dt, t_total, lags, worst_msd, worst_lag, worst_rot);
    CHECK(!failed && lags >= 15, "%dD: %d lags", dim, lags);
    free(xs), free(es);
    hsbd_msd_free(msd), hsbd_msd_free(rot);
    hsbd_spheres_free(s);
}

/* ---- ideal ABPs on hard walls: the mechanical pressure ---- */

static void test_wall_pressure(int dim) {
    const size_t n = 1500;
    const double box[3] = {24, 8, 8}, dt = 0.02, v0 = 5, dr = 3, kt = 1, mu = 1;
    const double t_equil = 20, t_total = sampled_time(150);
    hsbd_spheres *s = ideal_abps(dim, n, box, 1, dt, v0, dr, 30 + (uint64_t)dim);
    if (!s) return;
    int failed = 0;
    for (uint64_t k = 0; k < (uint64_t)llround(t_equil / dt); ++k)
        failed |= hsbd_spheres_step(s) != HSBD_OK;
    const uint64_t every = 10, steps = (uint64_t)llround(t_total / dt);
    hsbd_blocks *b = hsbd_blocks_alloc(3, BLOCKS, steps / every); /* rho_bulk, two walls */
    const double area = dim == 2 ? box[1] : box[1] * box[2], third = box[0] / 3;
    hsbd_spheres_reset_stats(s);
    double last[6] = {0}, now[6];
    for (uint64_t k = 1; k <= steps; ++k) {
        failed |= hsbd_spheres_step(s) != HSBD_OK;
        if (k % every) continue;
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        double *acc = hsbd_blocks_acc(b);
        size_t mid = 0;
        for (size_t i = 0; i < n; ++i)
            mid += v.x[3 * i] >= third && v.x[3 * i] < 2 * third;
        acc[0] += (double)mid / (third * area);
        hsbd_spheres_wall_impulses(s, now);
        acc[1] += (now[0] - last[0]) * kt / (every * dt * area); /* force per area */
        acc[2] += (now[1] - last[1]) * kt / (every * dt * area);
        memcpy(last, now, sizeof last);
        hsbd_blocks_end_sample(b);
    }
    CHECK(!failed, "a step failed");
    double mean[3], err[3];
    hsbd_blocks_result(b, mean, err);
    const double per = kt + v0 * v0 / (dim * (dim - 1) * mu * dr); /* P / rho_bulk */
    for (int side = 0; side < 2; ++side) {
        const double p = mean[1 + side], pe = err[1 + side], exact = mean[0] * per;
        const double allowance = 4 * pe + 4 * err[0] * per;
        printf("ideal ABPs %dD on hard walls (v0 %g, D_r %g, dt %g): rho_bulk %.5f +- %.5f, P at "
               "wall %d %.5f +- %.5f, rho_bulk (kT + v0^2 / (d (d-1) mu D_r)) %.5f (%+.2f error "
               "bars)\n",
               dim, v0, dr, dt, mean[0], err[0], side, p, pe, exact, (p - exact) / pe);
        CHECK(fabs(p - exact) <= allowance, "%dD wall %d: P %.5f, exact %.5f, allowance %.5f", dim,
              side, p, exact, allowance);
    }
    hsbd_blocks_free(b);
    hsbd_spheres_free(s);
}

/* ---- a dense active fluid: contact statistics against dt ----
 * 2D hard ABPs at phi 0.4, Pe 20 (a step's propulsion v0 dt = 0.004 to 0.016 sigma, its
 * noise sqrt(2 D dt) = 0.02 to 0.04 sigma): the swim speed ratio <e.dr/dt> / v0 and the
 * collisional pressure at dt 8e-4, 4e-4 and 2e-4 agree pairwise within 4 error bars
 * (measured over sixteen seeds, docs/active.md: 0.5491 +- 0.0012 and 3.485 +- 0.016 at dt
 * 8e-4 against 0.5517 +- 0.0015 and 3.465 +- 0.021 at 5e-5, differences of 0.5 % and 0.6 %
 * within the seeds' 1 % scatter). The blocks are 1 time unit long: the clusters of an
 * active fluid decorrelate slowly, and shorter blocks understated the scatter between
 * seeds by half. */

typedef struct contact_stats {
    double ratio, ratio_err, pc, pc_err; /* swim_speed_ratio, collisional pressure */
} contact_stats;

/* 2D hard ABPs (phi 0.4, Pe = v0 sigma / D = 20, D_r = 3), N 400, after 0.5 time units from
 * random insertion: <e_i . dr_i/dt> / v0 and the collisional pressure kT <sum sigma n . F>
 * / (d V kT), errors from 5 time blocks */
static contact_stats dense_active(double dt, double t_total) {
    const size_t n = 400;
    const double phi = 0.4, v0 = 20, dr = 3, side = sqrt((double)n * PI / 4 / phi);
    double *v0s = malloc(n * sizeof *v0s), *drs = malloc(n * sizeof *drs);
    for (size_t i = 0; i < n; ++i)
        v0s[i] = v0, drs[i] = dr;
    hsbd_spheres_params p = {.n = n,
                             .dimension = 2,
                             .box = {side, side, 0},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = dt,
                             .seed = 78,
                             .hard_core = 1,
                             .particle_v0 = v0s,
                             .particle_rotational_diffusion = drs};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    free(v0s), free(drs);
    contact_stats out = {NAN, NAN, NAN, NAN};
    CHECK(s && hsbd_spheres_init_random(s, &err) == HSBD_OK, "dense: %s", err.message);
    if (!s) return out;
    int failed = 0;
    for (uint64_t k = 0; k < (uint64_t)llround(0.5 / dt); ++k)
        failed |= hsbd_spheres_step(s) != HSBD_OK;
    hsbd_spheres_reset_stats(s);
    const uint64_t every = (uint64_t)llround(0.02 / dt), steps = (uint64_t)llround(t_total / dt);
    hsbd_blocks *b = hsbd_blocks_alloc(2, 5, steps / every);
    double last[2] = {0, 0};
    for (uint64_t k = 1; k <= steps; ++k) {
        failed |= hsbd_spheres_step(s) != HSBD_OK;
        if (k % every) continue;
        const hsbd_spheres_stats st = hsbd_spheres_get_stats(s);
        double *acc = hsbd_blocks_acc(b);
        acc[0] += st.swim_collisional - last[0], acc[1] += st.virial - last[1];
        last[0] = st.swim_collisional, last[1] = st.virial;
        hsbd_blocks_end_sample(b);
    }
    CHECK(!failed, "dense: a step failed");
    double mean[2], e[2];
    hsbd_blocks_result(b, mean, e);
    const double interval = every * dt, weight = n * v0 * v0 / dr; /* sum_i w_i v0_i, d - 1 = 1 */
    out.ratio = 1 + mean[0] / (interval * weight), out.ratio_err = e[0] / (interval * weight);
    out.pc = mean[1] / (interval * 2 * side * side),
    out.pc_err = e[1] / (interval * 2 * side * side);
    hsbd_blocks_free(b);
    hsbd_spheres_free(s);
    return out;
}

static void test_dense_convergence(void) {
    static const double dts[] = {8e-4, 4e-4, 2e-4};
    contact_stats c[3];
    for (int k = 0; k < 3; ++k) {
        c[k] = dense_active(dts[k], sampled_time(5));
        printf("dense active disks (phi 0.4, Pe 20), dt %g: swim speed ratio %.4f +- %.4f, "
               "collisional pressure %.4f +- %.4f\n",
               dts[k], c[k].ratio, c[k].ratio_err, c[k].pc, c[k].pc_err);
    }
    for (int i = 0; i < 3; ++i)
        for (int j = i + 1; j < 3; ++j) {
            const double er = hypot(c[i].ratio_err, c[j].ratio_err);
            const double ep = hypot(c[i].pc_err, c[j].pc_err);
            CHECK(fabs(c[i].ratio - c[j].ratio) <= 4 * er,
                  "swim speed ratio at dt %g and %g: %.4f and %.4f (4 error bars %.4f)", dts[i],
                  dts[j], c[i].ratio, c[j].ratio, 4 * er);
            CHECK(fabs(c[i].pc - c[j].pc) <= 4 * ep,
                  "collisional pressure at dt %g and %g: %.4f and %.4f (4 error bars %.4f)", dts[i],
                  dts[j], c[i].pc, c[j].pc, 4 * ep);
        }
}

static double cpu_seconds(void) {
    return (double)clock() / CLOCKS_PER_SEC;
}

int main(void) {
    static const double taus[] = {0.01, 0.1, 0.5, 3.0, 30.0};
    for (int dim = 2; dim <= 3; ++dim)
        for (size_t k = 0; k < sizeof taus / sizeof *taus; ++k)
            test_rotation_step(dim, taus[k]);
    for (int dim = 2; dim <= 3; ++dim) {
        double t0 = cpu_seconds();
        test_ideal_laws(dim);
        const double t1 = cpu_seconds();
        test_wall_pressure(dim);
        printf("  (%dD: laws %.1f s, walls %.1f s of CPU time)\n", dim, t1 - t0,
               cpu_seconds() - t1);
    }
    const double t0 = cpu_seconds();
    test_dense_convergence();
    printf("  (dense: %.1f s of CPU time)\n", cpu_seconds() - t0);
    return test_finish("test_active_physics");
}
