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
 *   - Finite sizes, several contacts: a tracer (D 1, sigma 1) pressed by a force 5 kT /
 *     sigma onto a floor of six immobile touching spheres (2D, periodic along the floor,
 *     walls below and at height 5), dt 2.5e-3 (Pe_step 0.25): the fractions of time within
 *     0.1 of the floor and within 0.1 of two floor spheres at once (the grooves) against
 *     Boltzmann's e^(-5 y) over the room left (exact at equilibrium; quadrature), within 4
 *     error bars of 20 time blocks; the mirror rule's contact layer lies more than 4 below
 *     (asserted; measured -5 %, the exact rule +0.2 +- 0.3 %).
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

/* ---- a tracer pressed onto a floor of immobile spheres: Boltzmann's contact layer ---- */

enum { FLOOR_SPHERES = 6, FLOOR_BLOCKS = 20 };
static const double FLOOR_HEIGHT = 5, FLOOR_LAYER = 0.1; /* walls 0 and 5; contact layer h */

/* The tracer's gaps to its nearest and second-nearest floor sphere (centres (k + 1/2, 1/2),
 * period 6 along x; the floor spheres touch, so these two are the neighbours around x). */
static void floor_gaps(double x, double y, double *first, double *second) {
    const double u = x - floor(x) - 0.5, u1 = fabs(u), u2 = 1 - u1; /* offsets along x */
    *first = sqrt(u1 * u1 + (y - 0.5) * (y - 0.5)) - 1;
    *second = sqrt(u2 * u2 + (y - 0.5) * (y - 0.5)) - 1;
}

/* Boltzmann's probabilities of the tracer (force -f along y) within FLOOR_LAYER of the floor
 * and within it of two floor spheres at once (the groove): over one period in x (midpoint
 * rule, 20000 points) with the y integrals of e^(-f y) in closed form. */
static void floor_boltzmann(double f, double *layer, double *groove) {
    double z = 0, in_layer = 0, in_groove = 0;
    const int m = 20000;
    const double reach = 1 + FLOOR_LAYER, top = FLOOR_HEIGHT - 0.5;
    for (int k = 0; k < m; ++k) {
        const double u1 = fabs((k + 0.5) / m - 0.5), u2 = 1 - u1;
        const double bottom = 0.5 + sqrt(1 - u1 * u1); /* resting on the nearest sphere */
        const double y1 = 0.5 + sqrt(reach * reach - u1 * u1);
        const double y2 = fmax(bottom, 0.5 + sqrt(fmax(0.0, reach * reach - u2 * u2)));
        z += (exp(-f * bottom) - exp(-f * top)) / f;
        in_layer += (exp(-f * bottom) - exp(-f * y1)) / f;
        in_groove += (exp(-f * bottom) - exp(-f * y2)) / f;
    }
    *layer = in_layer / z, *groove = in_groove / z;
}

/* The fractions of time the tracer spends in the layer and the groove, with errors from
 * FLOOR_BLOCKS time blocks, after 5 time units from a start above the floor. */
static void floor_run(double f, double dt, double t_total, int rule, double out[4]) {
    static const int species[FLOOR_SPHERES + 1] = {0, 1, 1, 1, 1, 1, 1};
    static const double sigma[2] = {1, 1}, diffusion[2] = {1, 0}, coupling[2] = {1, 0};
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(-f));
    const hsbd_spheres_params p = {.n = FLOOR_SPHERES + 1,
                                   .dimension = 2,
                                   .box = {FLOOR_SPHERES, FLOOR_HEIGHT, 1},
                                   .kT = 1,
                                   .dt = dt,
                                   .seed = 611,
                                   .hard_core = 1,
                                   .nspecies = 2,
                                   .species = species,
                                   .species_sigma = sigma,
                                   .species_diffusion = diffusion,
                                   .walls = {0, 1, 0},
                                   .field = &gravity,
                                   .field_axis = 1,
                                   .species_coupling = coupling,
                                   .pair_rule = rule};
    double x[3 * (FLOOR_SPHERES + 1)] = {3.25, 2.5, 0};
    for (int k = 0; k < FLOOR_SPHERES; ++k)
        x[3 * (k + 1)] = k + 0.5, x[3 * (k + 1) + 1] = 0.5;
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s && hsbd_spheres_set_positions(s, x, &err) == HSBD_OK, "floor: %s", err.message);
    for (int k = 0; s && k < (int)lround(5 / dt); ++k)
        hsbd_spheres_step(s);
    const long per_block = lround(t_total / dt / FLOOR_BLOCKS);
    double sums[4] = {0};
    int failed = 0;
    for (int b = 0; s && b < FLOOR_BLOCKS; ++b) {
        long layer = 0, groove = 0;
        for (long k = 0; k < per_block; ++k) {
            failed |= hsbd_spheres_step(s) != HSBD_OK;
            const hsbd_spheres_view v = hsbd_spheres_get_view(s);
            double first, second;
            floor_gaps(v.x[0], v.x[1], &first, &second);
            layer += first < FLOOR_LAYER, groove += second < FLOOR_LAYER;
        }
        const double fl = (double)layer / per_block, fg = (double)groove / per_block;
        sums[0] += fl, sums[1] += fl * fl, sums[2] += fg, sums[3] += fg * fg;
    }
    CHECK(!failed, "floor: a step failed");
    hsbd_spheres_free(s);
    for (int q = 0; q < 2; ++q) {
        const double mean = sums[2 * q] / FLOOR_BLOCKS;
        out[2 * q] = mean;
        out[2 * q + 1] =
            sqrt(fmax(0, sums[2 * q + 1] / FLOOR_BLOCKS - mean * mean) / (FLOOR_BLOCKS - 1));
    }
}

static void test_floor(void) {
    const double f = 5, dt = 2.5e-3, t_total = samples(800);
    double layer, groove;
    floor_boltzmann(f, &layer, &groove);
    for (int rule = HSBD_PAIR_EXACT; rule <= HSBD_PAIR_MIRROR; ++rule) {
        double got[4];
        floor_run(f, dt, t_total, rule, got);
        const double z_layer = (got[0] - layer) / got[1], z_groove = (got[2] - groove) / got[3];
        printf("tracer on a floor of immobile spheres, force %g, dt %g, %g time units (%s): "
               "in the contact layer %.5f +- %.5f (Boltzmann %.5f, %+.2f error bars), in a "
               "groove %.5f +- %.5f (%.5f, %+.2f)\n",
               f, dt, t_total, rule == HSBD_PAIR_EXACT ? "exact" : "mirror", got[0], got[1], layer,
               z_layer, got[2], got[3], groove, z_groove);
        if (rule == HSBD_PAIR_EXACT) {
            CHECK(fabs(z_layer) < 4, "floor: contact layer %g +- %g, Boltzmann %g", got[0], got[1],
                  layer);
            CHECK(fabs(z_groove) < 4, "floor: groove %g +- %g, Boltzmann %g", got[2], got[3],
                  groove);
        } else {
            CHECK(z_layer < -4, "floor: the mirror rule's contact layer %g +- %g matches", got[0],
                  got[1]);
        }
    }
}

int main(void) {
    test_tracer_and_obstacle();
    test_mobile_pair();
    test_floor();
    return test_finish("test_pair_drift_physics");
}
