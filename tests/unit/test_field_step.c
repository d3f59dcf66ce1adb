/* Heun's field step (field_step = HSBD_FIELD_STEP_HEUN) against its formula: the force is
 * the mean of F at the step's start and at the end point of a free Euler predictor with
 * the step's own noise (docs/algorithms.md, "The time step in a field").
 * - rods, a mixture with the sticky rule on a ring and between walls: the library step
 *   equals the literal oracle fed with Heun's total forces (per-rod mobilities, mergers,
 *   walls);
 * - rods with a pair force: the predictor moves with the field and the pair force, the
 *   pair force itself stays at the step's start;
 * - a driven field: the predictor's force is the field at t + dt;
 * - a constant force (tilt, gravity): the same bits as Euler (rods on a ring and between
 *   walls, spheres between walls with collisions);
 * - spheres: one free particle in a harmonic field along z.
 * Deterministic: exact bits or 1e-12. */
#include <math.h>
#include <string.h>

#include "../test_util.h"
#include "bcd_oracle.h"
#include "hsbd/field.h"
#include "hsbd/pair.h"
#include "hsbd/rng.h"
#include "hsbd/rods.h"
#include "hsbd/spheres.h"

enum { N_MIX = 12 };

/* Heun's total force on m rods at x (Eq. 11 with the field's mean): (F(x) + F(x_p)) / 2 plus
 * the Brownian force sqrt(2 D / dt) / mu g, x_p = x + mu F(x) dt + sqrt(2 D dt) g. */
static void heun_total_forces(const hsbd_field *start, const hsbd_field *end, size_t m,
                              const double *x, const double *mob, const double *g, double kT,
                              double dt, double *force) {
    double xp[N_MIX], fp[N_MIX];
    hsbd_field_force(start, m, x, force);
    for (size_t i = 0; i < m; ++i)
        xp[i] = x[i] + mob[i] * dt * force[i] + sqrt(2 * mob[i] * kT * dt) * g[i];
    hsbd_field_force(end, m, xp, fp);
    for (size_t i = 0; i < m; ++i)
        force[i] = 0.5 * (force[i] + fp[i]) + sqrt(2 * mob[i] * kT / dt) / mob[i] * g[i];
}

/* A binary mixture (lengths 0.3 and 0.7, D 1 and 2.5), sticky rule, on a ring or between
 * walls: the library's Heun step against the oracle fed with heun_total_forces. */
static void test_mixture_heun_vs_oracle(int boundary) {
    const int species[N_MIX] = {0, 1, 1, 0, 0, 1, 0, 1, 1, 1, 0, 0};
    const double sp_sigma[2] = {0.3, 0.7}, sp_d[2] = {1.0, 2.5};
    hsbd_rods_params par = {.n = N_MIX,
                            .length = 7.0,
                            .sigma = 0.3,
                            .diffusion = 1.0,
                            .kT = 0.8,
                            .dt = 1e-2,
                            .seed = 77,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_STICKY,
                            .boundary = boundary,
                            .nspecies = 2,
                            .species = species,
                            .species_sigma = sp_sigma,
                            .species_diffusion = sp_d,
                            .field_step = HSBD_FIELD_STEP_HEUN};
    hsbd_field_add(&par.field, hsbd_field_cosine(4.0, 1.0));
    hsbd_field_add(&par.field, hsbd_field_tilt(boundary == HSBD_RODS_WALLS ? -3.0 : 0.8));
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    CHECK(rods != NULL, "alloc: %s", err.message);
    if (!rods) return;
    hsbd_rods_init_equilibrium(rods);
    double worst = 0;
    size_t merges = 0;
    for (int s = 0; s < 400; ++s) {
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        double x[N_MIX], force[N_MIX], g[N_MIX], mob[N_MIX], sig[N_MIX];
        hsbd_rng_normals(par.seed, HSBD_STREAM_NOISE, v.step, 0, N_MIX, g);
        for (size_t i = 0; i < N_MIX; ++i) {
            x[i] = v.z[i] + v.offset[i];
            mob[i] = v.species_mobility[v.species[i]];
            sig[i] = v.species_sigma[v.species[i]];
        }
        heun_total_forces(&par.field, &par.field, N_MIX, x, mob, g, par.kT, par.dt, force);
        const double shift = v.unwrap;
        merges +=
            oracle_step_general(N_MIX, x, force, mob, sig, par.length, boundary, par.dt, 1e-12);
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        const hsbd_rods_view w = hsbd_rods_get_view(rods);
        for (size_t i = 0; i < N_MIX; ++i)
            worst = fmax(worst, fabs((w.z[i] + w.offset[i] + w.unwrap) - (x[i] + shift)));
    }
    CHECK(worst <= 1e-12, "Heun mixture (boundary %d) vs oracle: max deviation %.3g", boundary,
          worst);
    CHECK(merges > 100, "only %zu merges exercised", merges);
    printf("Heun mixture step vs oracle (boundary %d): max deviation %.3g, %zu merges\n", boundary,
           worst, merges);
    hsbd_rods_free(rods);
}

/* Three rods far apart with a Yukawa force (reflect rule; no gap can close in a step of
 * 1e-4): the free end points are z + mu dt ((F(x) + F(x_p)) / 2 + f_pair(x)) + sqrt(2 D dt)
 * g with x_p = x + mu dt (F(x) + f_pair(x)) + sqrt(2 D dt) g. */
static void test_pair_force_in_predictor(void) {
    enum { N = 3 };
    hsbd_rods_params par = {.n = N,
                            .length = 6.0,
                            .sigma = 0.5,
                            .diffusion = 1.0,
                            .kT = 1.0,
                            .dt = 1e-4,
                            .seed = 19,
                            .hard_core = 1,
                            .field_step = HSBD_FIELD_STEP_HEUN};
    hsbd_field_add(&par.field, hsbd_field_cosine(6.0, 1.0));
    hsbd_pair_add(&par.pair, hsbd_pair_yukawa(0.5, 3.0, 2.0, 2.5));
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    const double x0[N] = {0.3, 2.2, 4.1};
    CHECK(rods && hsbd_rods_set_positions(rods, x0, &err) == HSBD_OK, "set: %s", err.message);
    if (!rods) return;
    double worst = 0;
    for (int s = 0; s < 20; ++s) {
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        double x[N], z[N], f[N], fp[N], xp[N], pair[N] = {0}, g[N];
        for (size_t i = 0; i < N; ++i)
            z[i] = v.z[i], x[i] = v.z[i] + v.offset[i];
        for (size_t i = 0; i < N; ++i) /* the three pairs, across the ring too */
            for (size_t j = i + 1; j < N; ++j) {
                const double d = x[j] - x[i], fr = hsbd_pair_force(&par.pair, d),
                             fw = hsbd_pair_force(&par.pair, par.length - d);
                pair[j] += fr - fw; /* on j from i to its left, minus from i to its right */
                pair[i] += fw - fr;
            }
        hsbd_rng_normals(par.seed, HSBD_STREAM_NOISE, v.step, 0, N, g);
        const double noise = sqrt(2 * par.diffusion * par.dt);
        hsbd_field_force(&par.field, N, x, f);
        for (size_t i = 0; i < N; ++i)
            xp[i] = x[i] + par.dt * (f[i] + pair[i]) + noise * g[i];
        hsbd_field_force(&par.field, N, xp, fp);
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        const hsbd_rods_view w = hsbd_rods_get_view(rods);
        for (size_t i = 0; i < N; ++i) {
            const double expect = z[i] + par.dt * (0.5 * (f[i] + fp[i]) + pair[i]) + noise * g[i];
            worst = fmax(worst, fabs(w.y[i] - expect));
        }
    }
    hsbd_rods_free(rods);
    CHECK(worst <= 1e-12, "pair force in Heun's predictor: max deviation %.3g", worst);
}

/* Free rods in a rocking tilt F(t) = 0.5 + 2 cos(3 t): every free end point moves by
 * mu dt (F(t) + F(t + dt)) / 2 + sqrt(2 D dt) g. */
static void test_driven_field_at_step_end(void) {
    enum { N = 4 };
    hsbd_rods_params par = {.n = N,
                            .length = 10.0,
                            .sigma = 0.0,
                            .diffusion = 0.7,
                            .kT = 1.0,
                            .dt = 0.05,
                            .seed = 5,
                            .hard_core = 0,
                            .field_step = HSBD_FIELD_STEP_HEUN};
    hsbd_field_term tilt = hsbd_field_tilt(0.5);
    hsbd_field_term_drive(&tilt, HSBD_DRIVE_STRENGTH, HSBD_WAVE_COSINE, 2.0, 3.0, 0.0, 0.0);
    hsbd_field_add(&par.field, tilt);
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    const double x0[N] = {1, 3, 5, 7};
    CHECK(rods && hsbd_rods_set_positions(rods, x0, &err) == HSBD_OK, "set");
    if (!rods) return;
    double worst = 0;
    for (int s = 0; s < 10; ++s) {
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        double before[N], g[N];
        for (size_t i = 0; i < N; ++i)
            before[i] = v.z[i] + v.offset[i] + v.unwrap;
        const double t = v.time, mu = par.diffusion / par.kT;
        const double f_mean = 0.5 * ((0.5 + 2 * cos(3 * t)) + (0.5 + 2 * cos(3 * (t + par.dt))));
        hsbd_rng_normals(par.seed, HSBD_STREAM_NOISE, v.step, 0, N, g);
        hsbd_rods_step(rods, NULL);
        const hsbd_rods_view w = hsbd_rods_get_view(rods);
        for (size_t i = 0; i < N; ++i) {
            const double move = w.z[i] + w.offset[i] + w.unwrap - before[i];
            worst = fmax(
                worst, fabs(move - mu * par.dt * f_mean - sqrt(2 * par.diffusion * par.dt) * g[i]));
        }
    }
    hsbd_rods_free(rods);
    CHECK(worst <= 1e-12, "driven field: Heun's predictor at t + dt, max deviation %.3g", worst);
}

/* positions of two runs of the same rods, one with Euler and one with Heun, after `steps` */
static int rods_same_bits(hsbd_rods_params par, int steps) {
    hsbd_error err;
    par.field_step = HSBD_FIELD_STEP_EULER;
    hsbd_rods *euler = hsbd_rods_alloc(&par, &err);
    par.field_step = HSBD_FIELD_STEP_HEUN;
    hsbd_rods *heun = hsbd_rods_alloc(&par, &err);
    if (!euler || !heun) return hsbd_rods_free(euler), hsbd_rods_free(heun), 0;
    hsbd_rods_init_equilibrium(euler);
    hsbd_rods_init_equilibrium(heun);
    for (int s = 0; s < steps; ++s) {
        hsbd_rods_step(euler, NULL);
        hsbd_rods_step(heun, NULL);
    }
    const hsbd_rods_view a = hsbd_rods_get_view(euler), b = hsbd_rods_get_view(heun);
    const int same = memcmp(a.z, b.z, par.n * sizeof *a.z) == 0 && a.unwrap == b.unwrap;
    hsbd_rods_free(euler);
    hsbd_rods_free(heun);
    return same;
}

/* A constant force: Heun's mean of two equal forces is the force, so the runs agree to the
 * bit: rods on a ring (reflect rule, dense) and between walls (a mixture, gravity). */
static void test_constant_force_rods(void) {
    hsbd_rods_params ring = {.n = 50,
                             .length = 40.0,
                             .sigma = 0.6,
                             .diffusion = 1.0,
                             .kT = 1.0,
                             .dt = 1e-3,
                             .seed = 8,
                             .hard_core = 1};
    hsbd_field_add(&ring.field, hsbd_field_tilt(0.8));
    CHECK(rods_same_bits(ring, 500), "ring, tilt: Heun and Euler differ");
    const int species[6] = {0, 1, 0, 1, 1, 0};
    const double sp_sigma[2] = {0.5, 0.8}, sp_d[2] = {1.0, 0.4};
    hsbd_rods_params walls = ring;
    walls.n = 6;
    walls.length = 6.0;
    walls.boundary = HSBD_RODS_WALLS;
    walls.nspecies = 2;
    walls.species = species;
    walls.species_sigma = sp_sigma;
    walls.species_diffusion = sp_d;
    walls.field.term[0] = hsbd_field_tilt(-2.0);
    CHECK(rods_same_bits(walls, 500), "walls, gravity: Heun and Euler differ");
}

/* spheres from a lattice in a box with walls along z and gravity along z */
static hsbd_spheres *spheres_in_gravity(const hsbd_field *gravity, int field_step) {
    hsbd_spheres_params p = {.n = 200,
                             .dimension = 3,
                             .sigma = 1.0,
                             .diffusion = 1.0,
                             .kT = 1.0,
                             .dt = 1e-3,
                             .seed = 4,
                             .hard_core = 1,
                             .box = {8.0, 8.0, 8.0},
                             .walls = {0, 0, 1},
                             .field = gravity,
                             .field_axis = 2,
                             .field_step = field_step};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    if (s && hsbd_spheres_init_lattice(s, &err) != HSBD_OK) hsbd_spheres_free(s), s = NULL;
    return s;
}

/* Spheres between walls under gravity (collisions, wall events and pushes): Heun's and
 * Euler's steps give the same bits. */
static void test_constant_force_spheres(void) {
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(-2.0));
    hsbd_spheres *euler = spheres_in_gravity(&gravity, HSBD_FIELD_STEP_EULER);
    hsbd_spheres *heun = spheres_in_gravity(&gravity, HSBD_FIELD_STEP_HEUN);
    CHECK(euler && heun, "spheres alloc");
    if (!euler || !heun) return;
    for (int s = 0; s < 200; ++s) {
        hsbd_spheres_step(euler);
        hsbd_spheres_step(heun);
    }
    const hsbd_spheres_view a = hsbd_spheres_get_view(euler), b = hsbd_spheres_get_view(heun);
    CHECK(memcmp(a.x, b.x, 3 * a.n * sizeof *a.x) == 0, "spheres, gravity: Heun and Euler differ");
    CHECK(hsbd_spheres_get_stats(heun).collisions > 1000 &&
              hsbd_spheres_get_stats(heun).wall_collisions +
                      hsbd_spheres_get_stats(heun).wall_pushes >
                  10,
          "collisions and walls exercised");
    hsbd_spheres_free(euler);
    hsbd_spheres_free(heun);
}

/* One free sphere in a harmonic field along z (stiffness 3, centre 4): each step moves z by
 * mu dt (F(z) + F(z_p)) / 2 + sqrt(2 D dt) g_z, z_p = z + mu dt F(z) + sqrt(2 D dt) g_z, and
 * x, y by their noise alone. */
static void test_spheres_heun_step(void) {
    hsbd_field trap = {0};
    hsbd_field_add(&trap, hsbd_field_harmonic(3.0, 4.0, 0.0));
    const double d = 0.8, kT = 1.3, dt = 0.02, mu = d / kT, noise = sqrt(2 * d * dt);
    hsbd_spheres_params p = {.n = 1,
                             .dimension = 3,
                             .sigma = 1.0,
                             .diffusion = d,
                             .kT = kT,
                             .dt = dt,
                             .seed = 12,
                             .hard_core = 0,
                             .box = {20.0, 20.0, 20.0},
                             .field = &trap,
                             .field_axis = 2,
                             .field_step = HSBD_FIELD_STEP_HEUN};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    const double x0[3] = {10.0, 10.0, 4.5};
    CHECK(s && hsbd_spheres_set_positions(s, x0, &err) == HSBD_OK, "spheres: %s", err.message);
    if (!s) return;
    double worst = 0;
    for (int k = 0; k < 20; ++k) {
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        double x[3], g[3];
        memcpy(x, v.x, sizeof x);
        hsbd_rng_normals(p.seed, HSBD_STREAM_NOISE, v.step, 0, 3, g);
        const double f = -3.0 * (x[2] - 4.0), zp = x[2] + mu * dt * f + noise * g[2];
        const double expect[3] = {x[0] + noise * g[0], x[1] + noise * g[1],
                                  x[2] + mu * dt * 0.5 * (f - 3.0 * (zp - 4.0)) + noise * g[2]};
        CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
        const hsbd_spheres_view w = hsbd_spheres_get_view(s);
        for (int a = 0; a < 3; ++a)
            worst = fmax(worst, fabs(w.x[a] - expect[a]));
    }
    CHECK(worst <= 1e-12, "spheres: Heun's step, max deviation %.3g", worst);
    hsbd_spheres_free(s);
}

/* An unknown field step is refused by both engines. */
static void test_refused(void) {
    hsbd_rods_params r = {.n = 2, .length = 5, .sigma = 0.5, .diffusion = 1, .kT = 1, .dt = 1e-3};
    r.field_step = 2;
    hsbd_error err;
    CHECK(hsbd_rods_alloc(&r, &err) == NULL && err.status == HSBD_EINPUT, "rods: step 2 refused");
    hsbd_spheres_params s = {.n = 1,
                             .dimension = 3,
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .box = {10, 10, 10},
                             .field_step = -1};
    CHECK(hsbd_spheres_alloc(&s, &err) == NULL && err.status == HSBD_EINPUT,
          "spheres: step -1 refused");
}

int main(void) {
    test_mixture_heun_vs_oracle(HSBD_RODS_PERIODIC);
    test_mixture_heun_vs_oracle(HSBD_RODS_WALLS);
    test_pair_force_in_predictor();
    test_driven_field_at_step_end();
    test_constant_force_rods();
    test_constant_force_spheres();
    test_spheres_heun_step();
    test_refused();
    return test_finish("test_field_step");
}
