/* Pair collisions under a relative drift (docs/spheres.md, "Pair collisions under a relative
 * drift"; docs/theory.md) against exact results, fixed seeds.
 *   - Flat-contact limit (diameters 10^4 against steps of about 1): a pair started with a gap
 *     x0 = 1, relative diffusion D_i + D_j = 1 and relative drift c = -1 (towards contact)
 *     along the line of centres ends, after t = 1, distributed as Scala Eq. 9 corrected
 *     (hsbd_reflected_drift_density): mean and mean square within 4 of their sampling
 *     errors, the Kolmogorov-Smirnov distance sqrt(N) D_N below 1.95 (a false alarm once in a
 *     thousand). A tracer (D 1) against an immobile obstacle (D 0, which never moves) in 2D
 *     in one step dt = 1 and in ten of dt = 0.1; a mobile pair (D 0.8 and 0.2, couplings
 *     +1 and -1 in a force 1, so drifts 0.8 and -0.2 whose forces cancel) in 3D: its
 *     Brownian centre of mass (D_j r_i + D_i r_j) / (D_i + D_j) does not move on average
 *     and spreads as a free particle of D_i D_j / (D_i + D_j) (mean within 4 errors, variance
 *     within 4 errors of its sampling error). The mirror rule, run on the same pairs, gives
 *     the mean 1.13 of |Y| and fails the same checks by far (asserted).
 * HSBD_VALIDATE=long (make validate): ten times the samples. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/field.h"
#include "hsbd/spheres.h"
#include "hsbd/theory.h"

static size_t samples(size_t n) {
    const char *v = getenv("HSBD_VALIDATE");
    return v && !strcmp(v, "long") ? 10 * n : n;
}

static int compare_doubles(const void *a, const void *b) {
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* sqrt(N) times the largest distance between the sorted sample's CDF and Eq. 9's (the
 * density integrated by the trapezoidal rule on a fine grid as the sample is swept). */
static double ks_statistic(double *gap, size_t n, double x0, double c, double diffusion, double t) {
    qsort(gap, n, sizeof *gap, compare_doubles);
    const double h = 1e-4;
    double x = 0, cdf = 0, worst = 0;
    double f = hsbd_reflected_drift_density(0, x0, c, diffusion, t);
    for (size_t k = 0; k < n; ++k) {
        while (x + h <= gap[k]) {
            const double f1 = hsbd_reflected_drift_density(x + h, x0, c, diffusion, t);
            cdf += 0.5 * h * (f + f1);
            f = f1;
            x += h;
        }
        const double at = cdf + (gap[k] - x) * f; /* the last partial interval */
        const double lo = fabs(at - (double)k / (double)n), hi = fabs(at - (double)(k + 1) / n);
        worst = fmax(worst, fmax(lo, hi));
    }
    return sqrt((double)n) * worst;
}

typedef struct pair_case {
    const char *name;
    int dimension;
    double diffusion[2], coupling[2]; /* particle 0 (below along x) and 1 */
    double force;                     /* a tilt along x */
    double dt;
    int steps, rule;
    size_t trials;
    uint64_t seed;
} pair_case;

typedef struct pair_result {
    double mean, mean_err, square, square_err, ks;
    double centre_mean[3], centre_err[3], centre_var[3], centre_var_err[3];
    int obstacle_moved;
    uint64_t pushes, collisions;
} pair_result;

enum { SIGMA = 10000 }; /* the flat limit: steps of about 1 */

/* Runs pairs from gap 1 for steps x dt: each run holds a square (cubic) lattice of pairs
 * 3 diameters apart, which never meet each other, with its own seed; trials pairs in all.
 * Collects the end gaps and the displacements of the pairs' centres. */
static pair_result run_pair(const pair_case *pc) {
    pair_result out = {0};
    const int side = pc->dimension == 2 ? 16 : 8; /* pairs per row */
    const size_t per_run = pc->dimension == 2 ? 256 : 512, n = 2 * per_run;
    const double sigma = SIGMA, x0 = 1, cell = 3 * sigma, box = side * cell;
    int *species = malloc(n * sizeof *species);
    double *start = calloc(3 * n, sizeof *start), *gap = malloc(pc->trials * sizeof *gap);
    const double sp_sigma[2] = {sigma, sigma};
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_tilt(pc->force));
    hsbd_spheres_params p = {.n = n,
                             .dimension = pc->dimension,
                             .box = {box, box, box},
                             .kT = 1,
                             .dt = pc->dt,
                             .hard_core = 1,
                             .shell = 50,
                             .nspecies = 2,
                             .species = species,
                             .species_sigma = sp_sigma,
                             .species_diffusion = pc->diffusion,
                             .field = &field,
                             .field_axis = 0,
                             .species_coupling = pc->coupling,
                             .pair_rule = pc->rule};
    for (size_t k = 0; k < per_run && species && start; ++k) { /* pair k: particles 2k, 2k+1 */
        const size_t c[3] = {k % (size_t)side, k / (size_t)side % (size_t)side,
                             k / ((size_t)side * (size_t)side)};
        for (int a = 0; a < 3; ++a) {
            const double centre = a < pc->dimension ? (c[a] + 0.5) * cell : 0;
            start[6 * k + a] = start[6 * k + 3 + a] = centre;
        }
        start[6 * k] -= 0.5 * (sigma + x0);
        start[6 * k + 3] += 0.5 * (sigma + x0);
        species[2 * k] = 0, species[2 * k + 1] = 1;
    }
    const double di = pc->diffusion[0], dj = pc->diffusion[1];
    double c1[3] = {0}, c2[3] = {0}, c4[3] = {0};
    size_t got = 0;
    for (uint64_t run = 0; got < pc->trials && species && start && gap; ++run) {
        p.seed = pc->seed + 1000 * run;
        hsbd_error err;
        hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
        CHECK(s != NULL, "%s: alloc: %s", pc->name, err.message);
        if (!s) break;
        CHECK(hsbd_spheres_set_positions(s, start, &err) == HSBD_OK, "positions: %s", err.message);
        for (int q = 0; q < pc->steps; ++q)
            CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        for (size_t k = 0; k < per_run && got < pc->trials; ++k, ++got) {
            const double *xi = v.x + 6 * k, *xj = xi + 3, *si = start + 6 * k, *sj = si + 3;
            double r2 = 0;
            for (int a = 0; a < 3; ++a) {
                const double d = xj[a] - xi[a];
                r2 += d * d;
                /* the centre with weights 1/D: (D_j x_i + D_i x_j) / (D_i + D_j) */
                const double moved = (dj * (xi[a] - si[a]) + di * (xj[a] - sj[a])) / (di + dj);
                c1[a] += moved, c2[a] += moved * moved, c4[a] += pow(moved, 4);
            }
            gap[got] = sqrt(r2) - sigma;
            if (di == 0) out.obstacle_moved |= xi[0] != si[0] || xi[1] != si[1] || xi[2] != si[2];
        }
        const hsbd_spheres_stats st = hsbd_spheres_get_stats(s);
        out.pushes += st.pair_corrections;
        out.collisions += st.collisions;
        hsbd_spheres_free(s);
    }
    CHECK(got == pc->trials, "%s: %zu pairs of %zu", pc->name, got, pc->trials);
    const double m = (double)got;
    double m1 = 0, m2 = 0, m4 = 0;
    for (size_t k = 0; k < got; ++k)
        m1 += gap[k], m2 += gap[k] * gap[k], m4 += pow(gap[k], 4);
    m1 /= m, m2 /= m, m4 /= m;
    out.mean = m1, out.mean_err = sqrt((m2 - m1 * m1) / m);
    out.square = m2, out.square_err = sqrt((m4 - m2 * m2) / m);
    out.ks = got ? ks_statistic(gap, got, x0, -1.0, 1.0, pc->dt * pc->steps) : INFINITY;
    for (int a = 0; a < 3; ++a) {
        const double mean = c1[a] / m, var = c2[a] / m - mean * mean;
        out.centre_mean[a] = mean, out.centre_err[a] = sqrt(var / m);
        out.centre_var[a] = var, out.centre_var_err[a] = sqrt((c4[a] / m - var * var) / m);
    }
    free(species), free(start), free(gap);
    return out;
}

/* Eq. 9's checks on a case; returns whether all of them passed (expect = 1: asserted). */
static int check_against_eq9(const pair_case *pc, const pair_result *r, int expect) {
    const double t = pc->dt * pc->steps;
    const double t1 = hsbd_reflected_drift_moment(1, 1.0, -1.0, 1.0, t);
    const double t2 = hsbd_reflected_drift_moment(2, 1.0, -1.0, 1.0, t);
    const double z1 = (r->mean - t1) / r->mean_err, z2 = (r->square - t2) / r->square_err;
    const double pair_steps = (double)pc->trials * pc->steps;
    printf("%s (%s, dt %g x %d, %zu pairs): mean gap %.5f +- %.5f (Eq. 9 %.5f, %+.2f error "
           "bars), mean square %.5f +- %.5f (%.5f, %+.2f), KS sqrt(N) D %.3f; %.3f pushes and "
           "%.3f collisions per pair-step\n",
           pc->name, pc->rule == HSBD_PAIR_EXACT ? "exact" : "mirror", pc->dt, pc->steps,
           pc->trials, r->mean, r->mean_err, t1, z1, r->square, r->square_err, t2, z2, r->ks,
           (double)r->pushes / pair_steps, (double)r->collisions / pair_steps);
    const int ok = fabs(z1) < 4 && fabs(z2) < 4 && r->ks < 1.95;
    if (expect) {
        CHECK(fabs(z1) < 4, "%s: mean gap %.5f vs %.5f +- %.5f", pc->name, r->mean, t1,
              r->mean_err);
        CHECK(fabs(z2) < 4, "%s: mean square %.5f vs %.5f +- %.5f", pc->name, r->square, t2,
              r->square_err);
        CHECK(r->ks < 1.95, "%s: KS statistic %.3f", pc->name, r->ks);
    }
    return ok;
}

static void test_tracer_and_obstacle(void) {
    CHECK(fabs(hsbd_reflected_drift_moment(1, 1, -1, 1, 1) - 0.8504) < 1e-4, "Eq. 9 mean");
    /* tracer D 1 with drift -1 (coupling 1 in the force -1) towards an obstacle at lower
     * x: the obstacle is particle 0 here (D 0), the tracer particle 1 */
    pair_case pc = {.name = "tracer against an immobile obstacle, 2D",
                    .dimension = 2,
                    .diffusion = {0, 1},
                    .coupling = {0, 1},
                    .force = -1,
                    .dt = 1,
                    .steps = 1,
                    .rule = HSBD_PAIR_EXACT,
                    .trials = samples(100000),
                    .seed = 501};
    pair_result r = run_pair(&pc);
    check_against_eq9(&pc, &r, 1);
    CHECK(!r.obstacle_moved, "the obstacle moved");
    CHECK(r.pushes > 0, "no pushes");
    pc.dt = 0.1, pc.steps = 10, pc.trials = samples(30000), pc.seed = 502;
    r = run_pair(&pc);
    check_against_eq9(&pc, &r, 1);
    CHECK(!r.obstacle_moved, "the obstacle moved");
    /* the mirror rule on the same pairs: Eq. 9 fails, the mean is E|Y| = 1.128 */
    pc.dt = 1, pc.steps = 1, pc.trials = samples(100000), pc.seed = 501;
    pc.rule = HSBD_PAIR_MIRROR;
    r = run_pair(&pc);
    CHECK(!check_against_eq9(&pc, &r, 0), "the mirror rule passes Eq. 9");
    CHECK(fabs(r.mean - 1.1284) < 4 * r.mean_err, "mirror mean %.5f +- %.5f, E|Y| 1.1284", r.mean,
          r.mean_err);
    CHECK(r.pushes == 0, "pushes under the mirror rule");
}

static void test_mobile_pair(void) {
    /* D 0.8 and 0.2 (relative diffusion 1), couplings +1 and -1 in the force +1: drifts
     * +0.8 and -0.2, relative drift -1, forces that cancel */
    pair_case pc = {.name = "mobile pair, D 0.8 and 0.2, forces +-1, 3D",
                    .dimension = 3,
                    .diffusion = {0.8, 0.2},
                    .coupling = {1, -1},
                    .force = 1,
                    .dt = 1,
                    .steps = 1,
                    .rule = HSBD_PAIR_EXACT,
                    .trials = samples(100000),
                    .seed = 503};
    const double d_centre = 0.8 * 0.2 / 1.0; /* D_i D_j / (D_i + D_j) */
    for (int rule = HSBD_PAIR_EXACT; rule <= HSBD_PAIR_MIRROR; ++rule) {
        pc.rule = rule;
        const pair_result r = run_pair(&pc);
        const int eq9 = check_against_eq9(&pc, &r, rule == HSBD_PAIR_EXACT);
        if (rule == HSBD_PAIR_MIRROR) CHECK(!eq9, "the mirror rule passes Eq. 9");
        for (int a = 0; a < 3; ++a) {
            const double var = 2 * d_centre * pc.dt; /* per axis, a free particle */
            printf("  centre of mass along %c: mean %+.5f +- %.5f (%+.2f error bars), variance "
                   "%.5f +- %.5f (free %.5f, %+.2f)\n",
                   'x' + a, r.centre_mean[a], r.centre_err[a], r.centre_mean[a] / r.centre_err[a],
                   r.centre_var[a], r.centre_var_err[a], var,
                   (r.centre_var[a] - var) / r.centre_var_err[a]);
            CHECK(fabs(r.centre_mean[a]) < 4 * r.centre_err[a], "centre moved along %d: %g +- %g",
                  a, r.centre_mean[a], r.centre_err[a]);
            CHECK(fabs(r.centre_var[a] - var) < 4 * r.centre_var_err[a],
                  "centre's variance along %d: %g +- %g, free %g", a, r.centre_var[a],
                  r.centre_var_err[a], var);
        }
    }
}

int main(void) {
    test_tracer_and_obstacle();
    test_mobile_pair();
    return test_finish("test_pair_drift_physics");
}
