/* Disks and spheres between walls and in gravity against exact results, fixed seeds;
 * errors are block averages over 20 time blocks, every check |sim - theory| <= 4 error
 * bars unless said otherwise.
 *   - Ideal particles (hard_core = off) of two species (sigma 1 and 1.4, D 1 and 0.714,
 *     couplings 1 and 2) in gravity between walls, dt = 0.05 (a step of 0.3 sigma): the
 *     barometric profile of each species, exact at any dt (the isolated particle's
 *     Skorokhod step): chi^2 of the profile bins below 5 sigma from the floor within
 *     bins + 4 sqrt(2 bins), and the contact densities from the walls' impulses at both
 *     walls; and g(r) of each species pair (profile-weighted reference, bins of 0.1 up to
 *     2) = 1: chi^2 over the 20 bins within 20 + 4 sqrt(40), every bin within 4.5 error
 *     bars.
 *   - Free particles in a slit whose room (0.3) is shorter than a step (dt 0.05): the wall
 *     theorem below, exact at any dt (end points beyond both walls fold back).
 *   - Hard spheres (3D), disks (2D), a binary mixture (3D, couplings 1 and 2.744) and a
 *     polydisperse one (sizes 0.8 - 1.2, D 1 / sigma, couplings sigma^3) in gravity between
 *     walls: the wall theorem, kT (rho_low - rho_high) = the total weight per wall area,
 *     sum_i coupling_i |F| / A, with the contact densities from the walls' impulses. Exact
 *     in the stationary state at any dt (the collisions and the exact pair rule's pushes,
 *     which act in both mixtures, conserve sum_i dr_i / D_i, so the walls take up the
 *     field's impulse); the error bar is that of the difference (the blocks of the two
 *     walls added as independent).
 *   - Hard spheres in a slit of H = 12 sigma without field, phi 0.25 on average: the
 *     contact density at each wall against beta P(rho_mid) from the Kolafa-Labik-
 *     Malijevsky equation of state at the density measured in the middle 4 sigma of the
 *     slit; allowance: 4 error bars of the contact density plus the pressure change of 4
 *     error bars of rho_mid. And g(sigma+) of the pairs with both centres in those middle
 *     4 sigma against KLM's contact value at rho_mid, with the same kind of allowance.
 *   - A common drift v of a hard-sphere mixture (D 1 and 0.5) in a periodic box: against
 *     the same run without drift, sum_i dr_i / D_i differs by exactly t v sum_i 1 / D_i
 *     (relative 1e-9: round-off), each row of Scala's C_Brown summing to 1.
 * HSBD_VALIDATE=long (make validate): the sampled times 10 times longer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/field.h"
#include "hsbd/observe.h"
#include "hsbd/spheres.h"
#include "hsbd/theory.h"

static const double PI = 3.14159265358979323846;
enum { BLOCKS = 20, EVERY = 10 };

/* the sampled time of a case: 10 times longer under HSBD_VALIDATE=long */
static double sampled_time(double t) {
    const char *v = getenv("HSBD_VALIDATE");
    return v && !strcmp(v, "long") ? 10 * t : t;
}

typedef struct sampled {
    hsbd_slab *slab;
    hsbd_blocks *impulse; /* 6 ns increments per sample */
    size_t ns;
    hsbd_gr *gr; /* g(r) up to 2, bins of 0.1, contact fit over 0.1 (when asked) */
} sampled;

/* Runs t_equil, then samples the profile along `axis` and the wall impulses for t_total;
 * g(r) too when gr_window is given: between walls with both centres in [gr_window[0],
 * gr_window[1]) along the walls axis (gr_window[0] < 0: the whole slab). */
static sampled run_sampled(hsbd_spheres *s, int axis, double t_equil, double t_total, double bin,
                           const double *gr_window) {
    sampled out = {0};
    hsbd_error err;
    const double dt = hsbd_spheres_get_params(s)->dt;
    for (uint64_t k = 0; k < (uint64_t)llround(t_equil / dt); ++k)
        CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
    const uint64_t steps = (uint64_t)llround(t_total / dt);
    hsbd_spheres_view v = hsbd_spheres_get_view(s);
    out.ns = v.nspecies;
    out.slab = hsbd_slab_alloc(&v, axis, v.box[axis], bin, 0.1, BLOCKS, steps / EVERY, &err);
    out.impulse = hsbd_blocks_alloc(6 * out.ns, BLOCKS, steps / EVERY);
    CHECK(out.slab && out.impulse, "observers: %s", err.message);
    if (gr_window) {
        out.gr = hsbd_gr_alloc(&v, 2.0, 0.1, 0.1, BLOCKS, steps / EVERY, &err);
        CHECK(out.gr && (gr_window[0] < 0 ||
                         hsbd_gr_set_window(out.gr, gr_window[0], gr_window[1], &err) == HSBD_OK),
              "g(r): %s", err.message);
    }
    double last[6 * 4] = {0}, now[6 * 4];
    hsbd_spheres_reset_stats(s);
    for (uint64_t k = 1; k <= steps; ++k) {
        CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
        if (k % EVERY) continue;
        v = hsbd_spheres_get_view(s);
        hsbd_slab_sample(out.slab, &v);
        if (out.gr) CHECK(hsbd_gr_sample(out.gr, &v) == HSBD_OK, "g(r) sample");
        hsbd_spheres_wall_impulses(s, now);
        double *acc = hsbd_blocks_acc(out.impulse);
        for (size_t q = 0; q < 6 * out.ns; ++q)
            acc[q] += now[q] - last[q], last[q] = now[q];
        hsbd_blocks_end_sample(out.impulse);
    }
    return out;
}

static void sampled_free(sampled *o) {
    hsbd_slab_free(o->slab);
    hsbd_blocks_free(o->impulse);
    hsbd_gr_free(o->gr);
}

/* Contact densities from the impulses: value q (6 k + 2 axis + side), or the sum over the
 * species (k < 0), per block; mean and error of (side 0) - (side 1) when diff, else of one
 * side. */
static void contact_from_impulses(const sampled *o, int species, int axis, int side, int diff,
                                  double per_sample, double *val, double *err) {
    const size_t nb = BLOCKS;
    double rows[BLOCKS * 6 * 4], sum = 0, sum2 = 0;
    hsbd_blocks_block_means(o->impulse, 0, rows);
    for (size_t b = 0; b < nb; ++b) {
        double x = 0;
        for (size_t k = 0; k < o->ns; ++k) {
            if (species >= 0 && (size_t)species != k) continue;
            const double *r = rows + b * 6 * o->ns + 6 * k + 2 * axis;
            x += diff ? r[0] - r[1] : r[side];
        }
        x /= per_sample;
        sum += x, sum2 += x * x;
    }
    *val = sum / nb;
    *err = sqrt(fmax(0, sum2 / nb - *val * *val) / (nb - 1));
}

/* ---- ideal particles: the barometric profile ---- */

/* The mean over [a, b] of N kappa / (A (1 - e^(-kappa h))) e^(-kappa (z - lo)) on [lo, hi]. */
static double barometric_bin(double n, double kappa, double area, double lo, double hi, double a,
                             double b) {
    const double from = fmax(a, lo), to = fmin(b, hi);
    if (!(to > from)) return 0;
    const double c = n * kappa / (area * (1 - exp(-kappa * (hi - lo))));
    return c * (exp(-kappa * (from - lo)) - exp(-kappa * (to - lo))) / kappa / (b - a);
}

static void test_barometric(void) {
    static int species[400];
    for (int i = 0; i < 400; ++i)
        species[i] = i % 2;
    static const double sig[2] = {1.0, 1.4}, dif[2] = {1.0, 0.714}, coupling[2] = {1.0, 2.0};
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(-1.0));
    const double box[3] = {4, 4, 6};
    hsbd_spheres_params p = {.n = 400,
                             .dimension = 3,
                             .box = {box[0], box[1], box[2]},
                             .kT = 1,
                             .dt = 0.05,
                             .seed = 21,
                             .hard_core = 0,
                             .nspecies = 2,
                             .species = species,
                             .species_sigma = sig,
                             .species_diffusion = dif,
                             .walls = {0, 0, 1},
                             .field = &gravity,
                             .field_axis = 2,
                             .species_coupling = coupling};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    double *pos = malloc(3 * p.n * sizeof *pos); /* ideal: anywhere between the walls */
    for (size_t i = 0; i < p.n; ++i)
        for (int a = 0; a < 3; ++a)
            pos[3 * i + a] = 0.7 + (box[a] - 1.4) * (double)((i * (7 + 5 * a)) % 97) / 97.0;
    CHECK(s && hsbd_spheres_set_positions(s, pos, &err) == HSBD_OK, "init: %s", err.message);
    free(pos);
    if (!s) return;
    const double whole[2] = {-1, 0};
    sampled o = run_sampled(s, 2, 20, sampled_time(1000), 0.1, whole);
    const double area = box[0] * box[1];
    const size_t nb = hsbd_slab_bins(o.slab);
    double x[128], rho[128], e[128];
    for (int k = 0; k < 2; ++k) {
        const double kappa = coupling[k], lo = 0.5 * sig[k], hi = box[2] - lo;
        hsbd_slab_density(o.slab, k, x, rho, e);
        double chi2 = 0;
        int bins = 0;
        for (size_t b = 0; b < nb && b < 128; ++b) {
            const double th = barometric_bin(200, kappa, area, lo, hi, x[b] - 0.05, x[b] + 0.05);
            if (th <= 0 || x[b] > lo + 5 / kappa || !(e[b] > 0)) continue;
            chi2 += (rho[b] - th) * (rho[b] - th) / (e[b] * e[b]), bins++;
        }
        double c_low, c_low_err, c_high, c_high_err;
        const double per = p.dt * EVERY * area;
        contact_from_impulses(&o, k, 2, 0, 0, per, &c_low, &c_low_err);
        contact_from_impulses(&o, k, 2, 1, 0, per, &c_high, &c_high_err);
        const double c = 200 * kappa / (area * (1 - exp(-kappa * (hi - lo))));
        const double th_low = c, th_high = c * exp(-kappa * (hi - lo));
        printf("barometric, species %d (coupling %g, dt %g): chi^2 %.1f over %d bins; contact "
               "low %.4f +- %.4f (exact %.4f, %+.2f), high %.5f +- %.5f (exact %.5f, %+.2f)\n",
               k, kappa, p.dt, chi2, bins, c_low, c_low_err, th_low, (c_low - th_low) / c_low_err,
               c_high, c_high_err, th_high, (c_high - th_high) / c_high_err);
        CHECK(bins > 10 && chi2 < bins + 4 * sqrt(2.0 * bins), "species %d: chi^2 %.1f over %d", k,
              chi2, bins);
        CHECK(fabs(c_low - th_low) <= 4 * c_low_err, "species %d: low contact", k);
        CHECK(fabs(c_high - th_high) <= 4 * c_high_err, "species %d: high contact", k);
    }
    /* g(r) against the profile-weighted ideal reference: 1 in every bin of every pair */
    for (size_t q = 0; q < hsbd_gr_pairs(o.gr); ++q) {
        double r[32], g[32], ge[32], chi2 = 0, worst = 0;
        const size_t nr = hsbd_gr_bins(o.gr);
        hsbd_gr_result(o.gr, q, r, g, ge);
        for (size_t k = 0; k < nr; ++k) {
            const double d = (g[k] - 1) / ge[k];
            chi2 += d * d, worst = fmax(worst, fabs(d));
            if (getenv("HSBD_VERBOSE"))
                printf("    r %.2f g %.5f +- %.5f (%+.2f)\n", r[k], g[k], ge[k], d);
        }
        printf("barometric, g(r) of pair %zu between walls in gravity: chi^2 %.1f over %zu bins "
               "(r %.2f .. %.2f), largest deviation %.2f error bars, g(%.2f) = %.4f +- %.4f\n",
               q, chi2, nr, r[0], r[nr - 1], worst, r[nr - 1], g[nr - 1], ge[nr - 1]);
        CHECK(chi2 < (double)nr + 4 * sqrt(2.0 * (double)nr) && worst < 4.5,
              "pair %zu: g(r) of ideal particles is not 1", q);
    }
    sampled_free(&o);
    hsbd_spheres_free(s);
}

/* ---- ideal particles in a slit narrower than a step: the wall theorem ---- */

/* Free particles (sigma 0.1) whose centres have 0.3 of room, gravity -1, dt 0.05 (a step of
 * 0.32 rms, longer than the room, so free end points land beyond both walls and fold): the
 * wall theorem, exact at any dt whatever the two independent bridges make of the profile. */
static void test_narrow_slit(void) {
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(-1.0));
    hsbd_spheres_params p = {.n = 200,
                             .dimension = 3,
                             .box = {4, 4, 0.4},
                             .sigma = 0.1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 0.05,
                             .seed = 61,
                             .hard_core = 0,
                             .walls = {0, 0, 1},
                             .field = &gravity,
                             .field_axis = 2};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s && hsbd_spheres_init_random(s, &err) == HSBD_OK, "init: %s", err.message);
    if (!s) return;
    sampled o = run_sampled(s, 2, 2, sampled_time(200), 0.01, NULL);
    double diff, diff_err;
    contact_from_impulses(&o, -1, 2, 0, 1, p.dt * EVERY * 16, &diff, &diff_err);
    printf("narrow slit (room 0.3, dt 0.05), free particles: rho_low - rho_high %.4f +- %.4f, "
           "weight per area %.4f (%+.2f error bars)\n",
           diff, diff_err, 12.5, (diff - 12.5) / diff_err);
    CHECK(fabs(diff - 12.5) <= 4 * diff_err, "narrow slit: wall theorem");
    sampled_free(&o);
    hsbd_spheres_free(s);
}

/* ---- hard spheres: the wall theorem ---- */

static void wall_theorem_case(const char *name, hsbd_spheres_params p, double force, double t_equil,
                              double t_total) {
    hsbd_field gravity = {0};
    hsbd_field_add(&gravity, hsbd_field_tilt(force));
    const int axis = p.dimension - 1;
    p.walls[axis] = 1, p.field = &gravity, p.field_axis = axis;
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s && hsbd_spheres_init_random(s, &err) == HSBD_OK, "%s: init: %s", name, err.message);
    if (!s) return;
    sampled o = run_sampled(s, axis, t_equil, sampled_time(t_total), 0.1, NULL);
    double area = 1, weight = 0;
    for (int a = 0; a < axis; ++a)
        area *= p.box[a];
    for (size_t i = 0; i < p.n; ++i)
        weight += (p.particle_coupling  ? p.particle_coupling[i]
                   : p.species_coupling ? p.species_coupling[p.species[i]]
                                        : 1.0) *
                  fabs(force);
    double diff, diff_err;
    contact_from_impulses(&o, -1, axis, 0, 1, p.dt * EVERY * area, &diff, &diff_err);
    int finite = 0;
    const double gap = hsbd_spheres_min_gap(s, &finite);
    const hsbd_spheres_stats st = hsbd_spheres_get_stats(s);
    printf("wall theorem, %s (dt %g, %g + %g time units): rho_low - rho_high %.4f +- %.4f, "
           "weight per area %.4f (%+.2f error bars); %.3f collisions, %.3f pair pushes and %.4f "
           "wall events per particle-step, min gap %.2g\n",
           name, p.dt, t_equil, t_total, diff, diff_err, weight / area,
           (diff - weight / area) / diff_err, (double)st.collisions / st.steps / p.n,
           (double)st.pair_corrections / st.steps / p.n,
           (double)(st.wall_collisions + st.wall_pushes) / st.steps / p.n, gap);
    CHECK(fabs(diff - weight / area) <= 4 * diff_err, "%s: wall theorem", name);
    /* drift factors D coupling that differ: the exact pair rule acts */
    const int relative = p.particle_coupling || p.species_coupling;
    CHECK(relative ? st.pair_corrections > 0 : st.pair_corrections == 0, "%s: %llu pair pushes",
          name, (unsigned long long)st.pair_corrections);
    CHECK(finite && gap >= -1e-9, "%s: overlap %g", name, gap);
    sampled_free(&o);
    hsbd_spheres_free(s);
}

static void test_wall_theorem(void) {
    hsbd_spheres_params p = {.n = 200,
                             .dimension = 3,
                             .box = {5, 5, 14},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 2e-3,
                             .seed = 31,
                             .hard_core = 1};
    wall_theorem_case("3D, phi 0.3 on average, F = -0.5", p, -0.5, 20, 60);
    hsbd_spheres_params d = p;
    d.dimension = 2, d.n = 150, d.box[0] = 12, d.box[1] = 150 * PI / 4 / 0.4 / 12, d.seed = 32;
    wall_theorem_case("2D disks, phi 0.4 on average, F = -0.5", d, -0.5, 20, 60);
    static int species[200];
    for (int i = 0; i < 200; ++i)
        species[i] = i % 2;
    static const double sig[2] = {1.0, 1.4}, dif[2] = {1.0, 1 / 1.4}, coupling[2] = {1, 2.744};
    hsbd_spheres_params m = p;
    m.nspecies = 2, m.species = species, m.species_sigma = sig, m.species_diffusion = dif;
    m.species_coupling = coupling, m.seed = 33;
    m.box[2] = 100 * PI / 6 * (1 + 2.744) / 0.25 / 25;
    wall_theorem_case("3D binary 1 / 1.4, couplings 1 / 2.744", m, -0.3, 20, 60);
    /* polydisperse, sizes uniform over 0.8 .. 1.2, D = 1 / sigma (Stokes-Einstein), buoyant
     * masses sigma^3: every pair has its own relative drift */
    static double poly_sigma[200], poly_d[200], poly_c[200];
    for (int i = 0; i < 200; ++i) {
        poly_sigma[i] = 0.8 + 0.4 * ((i * 7919) % 200) / 199.0;
        poly_d[i] = 1 / poly_sigma[i], poly_c[i] = pow(poly_sigma[i], 3);
    }
    hsbd_spheres_params q = p;
    q.particle_sigma = poly_sigma, q.particle_diffusion = poly_d, q.particle_coupling = poly_c;
    q.seed = 34, q.box[2] = 15;
    wall_theorem_case("3D polydisperse 0.8 - 1.2, D 1 / sigma, couplings sigma^3", q, -0.5, 40, 60);
}

/* ---- a wide slit: contact density vs the bulk pressure in the middle ---- */

static void test_slit_klm(void) {
    const double side = 6, height = 12;
    hsbd_spheres_params p = {.n = (size_t)llround(0.25 * side * side * height / (PI / 6)),
                             .dimension = 3,
                             .box = {side, side, height},
                             .sigma = 1,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 2e-3,
                             .seed = 41,
                             .hard_core = 1,
                             .walls = {0, 0, 1}};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s && hsbd_spheres_init_random(s, &err) == HSBD_OK, "init: %s", err.message);
    if (!s) return;
    const double t_total = 60;
    const double middle[2] = {0.5 * height - 2, 0.5 * height + 2};
    sampled o = run_sampled(s, 2, 5, sampled_time(t_total), 0.5, middle);
    double x[64], rho[64], e[64], mid = 0, mid_var = 0;
    hsbd_slab_density(o.slab, -1, x, rho, e);
    int in = 0;
    for (size_t b = 0; b < hsbd_slab_bins(o.slab); ++b)
        if (fabs(x[b] - 0.5 * height) < 2) mid += rho[b], mid_var += e[b] * e[b], in++;
    mid /= in;
    const double mid_err = sqrt(mid_var) / in; /* bins as independent */
    const double phi = mid * PI / 6, beta_p = mid * hsbd_hs_z_klm(phi);
    const double dp = (mid + 1e-4) * hsbd_hs_z_klm((mid + 1e-4) * PI / 6) - beta_p;
    const double p_err = dp / 1e-4 * mid_err;
    for (int side_k = 0; side_k < 2; ++side_k) {
        double c, c_err;
        contact_from_impulses(&o, -1, 2, side_k, 0, p.dt * EVERY * side * side, &c, &c_err);
        printf("slit H = %g, wall %d: contact density %.4f +- %.4f; mid-slit rho %.4f +- %.4f "
               "(phi %.4f), KLM beta P %.4f +- %.4f (%+.2f combined error bars)\n",
               height, side_k, c, c_err, mid, mid_err, phi, beta_p, p_err,
               (c - beta_p) / sqrt(c_err * c_err + p_err * p_err));
        CHECK(fabs(c - beta_p) <= 4 * (c_err + p_err), "slit wall %d", side_k);
    }
    double g_mid, g_mid_err;
    hsbd_gr_contact(o.gr, 0, &g_mid, &g_mid_err);
    const double g_klm = hsbd_hs_contact_klm(phi);
    const double dg = hsbd_hs_contact_klm(phi + 1e-4) - g_klm,
                 g_klm_err = dg / 1e-4 * mid_err * PI / 6;
    printf("slit H = %g, pairs in the middle 4 sigma: g(sigma+) %.4f +- %.4f, KLM at rho_mid "
           "%.4f +- %.4f (%+.2f combined error bars)\n",
           height, g_mid, g_mid_err, g_klm, g_klm_err,
           (g_mid - g_klm) / sqrt(g_mid_err * g_mid_err + g_klm_err * g_klm_err));
    CHECK(fabs(g_mid - g_klm) <= 4 * (g_mid_err + g_klm_err), "slit: g(sigma+) in the middle");
    sampled_free(&o);
    hsbd_spheres_free(s);
}

/* ---- a common drift moves the friction-weighted centre by exactly v t ---- */

static double weighted_displacement(const hsbd_spheres *s, const double *x0, int axis) {
    const hsbd_spheres_view v = hsbd_spheres_get_view(s);
    double sum = 0;
    for (size_t i = 0; i < v.n; ++i)
        sum +=
            (v.x[3 * i + axis] + (double)v.image[3 * i + axis] * v.box[axis] - x0[3 * i + axis]) /
            v.diffusion[i];
    return sum;
}

static void test_common_drift(void) {
    static int species[500];
    for (int i = 0; i < 500; ++i)
        species[i] = i % 2;
    static const double sig[2] = {1.0, 1.0}, dif[2] = {1.0, 0.5};
    const double side = cbrt(500 * PI / 6 / 0.3);
    hsbd_spheres_params p = {.n = 500,
                             .dimension = 3,
                             .box = {side, side, side},
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 51,
                             .hard_core = 1,
                             .nspecies = 2,
                             .species = species,
                             .species_sigma = sig,
                             .species_diffusion = dif};
    hsbd_error err;
    hsbd_spheres *a = hsbd_spheres_alloc(&p, &err);
    p.drift[0] = 2.5;
    hsbd_spheres *b = hsbd_spheres_alloc(&p, &err);
    CHECK(a && b, "alloc");
    if (!a || !b) return;
    CHECK(hsbd_spheres_init_lattice(a, &err) == HSBD_OK, "init");
    CHECK(hsbd_spheres_init_lattice(b, &err) == HSBD_OK, "init");
    double *x0 = malloc(3 * p.n * sizeof *x0);
    memcpy(x0, hsbd_spheres_get_view(a).x, 3 * p.n * sizeof *x0);
    const int steps = 400;
    for (int k = 0; k < steps; ++k)
        CHECK(hsbd_spheres_step(a) == HSBD_OK && hsbd_spheres_step(b) == HSBD_OK, "step");
    double inv_d = 0;
    for (size_t i = 0; i < p.n; ++i)
        inv_d += 1 / dif[species[i]];
    const double moved = weighted_displacement(b, x0, 0) - weighted_displacement(a, x0, 0);
    const double exact = steps * p.dt * p.drift[0] * inv_d;
    printf("common drift: sum dr/D with drift minus without %.12g, t v sum 1/D %.12g (%llu and "
           "%llu collisions)\n",
           moved, exact, (unsigned long long)hsbd_spheres_get_stats(a).collisions,
           (unsigned long long)hsbd_spheres_get_stats(b).collisions);
    CHECK(fabs(moved - exact) <= 1e-9 * exact, "drift: %.12g vs %.12g", moved, exact);
    free(x0);
    hsbd_spheres_free(a);
    hsbd_spheres_free(b);
}

int main(void) {
    test_barometric();
    test_narrow_slit();
    test_wall_theorem();
    test_slit_klm();
    test_common_drift();
    return test_finish("test_spheres_walls_physics");
}
