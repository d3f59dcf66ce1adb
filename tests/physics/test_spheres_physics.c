/* EDBD of hard disks and spheres against equations of state, fixed seeds. Each case
 * equilibrates from a lattice for 2 time units (sigma^2/D) and samples for 8; error bars
 * are block averages over 20 time blocks, and every check is |sim - theory| <= 3 error
 * bars, with no allowance for the equations of state.
 *   - 3D, phi 0.3: Z from the collisional virial and from the contact value vs
 *     Kolafa-Labik-Malijevsky (KLM). Carnahan-Starling is 0.26 % low there: at N 4000 and
 *     20 time units hsbd gives Z = 3.983 +- 0.002 for every dt from 2.5e-4 to 4e-3, KLM
 *     3.9843, CS 3.9738 (docs/validation.md, spheres section);
 *   - BMCSL, the mixture form of CS, inherits that deficit (1 to 3 of the error bars
 *     below), so the mixtures are compared with "BMCSL-KLM": every BMCSL contact value
 *     times g_KLM / g_CS at the same packing fraction (KLM in the one-component limit).
 *     Over 28 runs of each mixture below, Z_virial then lies within -2.3 to +1.9 error
 *     bars of it (rms 0.97-1.08; against BMCSL itself on average +1.5);
 *   - (2D disks vs the virial series to B10 are in make validate, not here: at N 1000
 *     the box's slowest density modes relax over ~10 time units, longer than the time
 *     blocks a quick test can afford, so its block errors understate the scatter between
 *     seeds; docs/spheres.md);
 *   - 3D binary mixture (size ratio 1.4, equal numbers, D ~ 1/sigma), phi 0.3: Z_virial
 *     vs Z from the BMCSL-KLM contact values, and vs Z from the measured contact values
 *     (the contact theorem, exact; their errors added linearly, a bound for any
 *     correlation, so this check only catches errors of a few percent). The three partial
 *     contact values are printed against BMCSL-KLM as information: over 28 runs
 *     (seed 31 and 13 others, each with the species in halves and alternating; the
 *     lattice takes its sites in random order, so both are the same ensemble) g_12 lay
 *     0.57 % below it (2.8 standard errors of the mean) and g_22 0.34 % above (1.5), and
 *     their scatter was 1.06-1.24 times the block errors, so a 3-error-bar check fails a
 *     few runs in a hundred (seed 31 once gave g_22 +3.6 error bars). The offsets are
 *     not BMCSL's alone: at N 4000 g_AB lay 0.56 % above plain BMCSL (make validate, 20
 *     time units), so the small box and the fit add their own. make validate checks the
 *     partial contact values there (docs/validation.md, section 15);
 *   - 3D continuous polydispersity (Gaussian, width 0.1, Stokes-Einstein D), phi 0.3,
 *     compressed from random insertion: Z_virial and the sigma_ij^3-weighted contact
 *     value vs BMCSL-KLM summed exactly over all pairs of the drawn diameters;
 *   - the short-time MSD of each species of a dilute mixture (phi 0.02) at one step of
 *     1e-5 is 2 d D_a dt: the first-collision correction, -c_a t^(3/2) (docs/theory.md,
 *     mixture dynamics), is 0.12 % and 0.085 % of the free MSD of the two species at a lag
 *     of 1e-3, so about a hundredth of a percent at this lag, far below the error bar. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../test_util.h"
#include "../unit/sphere_checks.h"
#include "hsbd/observe.h"
#include "hsbd/spheres.h"
#include "hsbd/theory.h"

static const double PI = 3.14159265358979323846;
enum { BLOCKS = 20 };

typedef struct outcome {
    double z_virial, z_virial_err;
    double g[3], g_err[3]; /* contact values per pair (11, 12, 22 or one) */
} outcome;

static outcome run_case(const hsbd_spheres_params *p, double t_equil, double t_total,
                        int compress) {
    outcome out = {0};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(p, &err);
    CHECK(s != NULL, "alloc: %s", err.message);
    if (!s) return out;
    CHECK((compress ? hsbd_spheres_init_compress(s, &err) : hsbd_spheres_init_lattice(s, &err)) ==
              HSBD_OK,
          "initial state: %s", err.message);
    const uint64_t equil = (uint64_t)llround(t_equil / p->dt);
    const uint64_t steps = (uint64_t)llround(t_total / p->dt), every = 20;
    for (uint64_t k = 0; k < equil; ++k)
        CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
    hsbd_spheres_view v = hsbd_spheres_get_view(s);
    hsbd_gr *gr = hsbd_gr_alloc(&v, 2.0, 0.05, 0.1, BLOCKS, steps / every, &err);
    hsbd_blocks *vir = hsbd_blocks_alloc(1, BLOCKS, steps / every);
    hsbd_spheres_reset_stats(s);
    double last = 0;
    for (uint64_t k = 1; k <= steps; ++k) {
        CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
        if (k % every) continue;
        v = hsbd_spheres_get_view(s);
        hsbd_gr_sample(gr, &v);
        const double now = hsbd_spheres_get_stats(s).virial;
        hsbd_blocks_acc(vir)[0] += now - last;
        hsbd_blocks_end_sample(vir);
        last = now;
    }
    double m, e;
    hsbd_blocks_result(vir, &m, &e);
    const double per = p->dt * (double)every * p->dimension * (double)p->n;
    out.z_virial = 1 + m / per, out.z_virial_err = e / per;
    for (size_t q = 0; q < hsbd_gr_pairs(gr) && q < 3; ++q)
        hsbd_gr_contact(gr, q, &out.g[q], &out.g_err[q]);
    int finite;
    CHECK(hsbd_spheres_min_gap(s, &finite) >= -1e-9 && finite, "overlap or NaN at the end");
    hsbd_gr_free(gr);
    hsbd_blocks_free(vir);
    hsbd_spheres_free(s);
    return out;
}

static void print_within(const char *what, double sim, double err, double theory) {
    printf("  %-36s %.5f +- %.5f   theory %.5f   (%+.2f error bars)\n", what, sim, err, theory,
           (sim - theory) / err);
}

static void check_within(const char *what, double sim, double err, double theory) {
    print_within(what, sim, err, theory);
    CHECK(err > 0 && fabs(sim - theory) <= 3 * err, "%s: %g +- %g vs %g", what, sim, err, theory);
}

static void test_monodisperse(int dim, double phi, unsigned seed) {
    const size_t n = 1000;
    const hsbd_spheres_params p = fluid_params(dim, n, phi, seed);
    const outcome o = run_case(&p, 2.0, 8.0, 0);
    const double z = dim == 3 ? hsbd_hs_z_klm(phi) : hsbd_hd_z_virial(phi);
    const double g = dim == 3 ? hsbd_hs_contact_klm(phi) : hsbd_hd_contact_virial(phi);
    printf("%dD, phi %.2f, N %zu, dt 1e-3, seed %u:\n", dim, phi, n, seed);
    check_within("Z (collisional virial)", o.z_virial, o.z_virial_err, z);
    check_within("g(sigma+) (quadratic fit)", o.g[0], o.g_err[0], g);
}

/* The one-component contact value's correction from Carnahan-Starling to KLM at the same
 * packing fraction, applied to every BMCSL contact value (exact in the one-component
 * limit, where BMCSL is CS). */
static double klm_over_cs(double phi) {
    return hsbd_hs_contact_klm(phi) / hsbd_hs_contact_cs(phi);
}

static void test_binary(void) {
    static int species[1000];
    const double sig[2] = {1.0, 1.4}, dif[2] = {1.0, 1.0 / 1.4}, phi = 0.3;
    for (int i = 0; i < 1000; ++i)
        species[i] = i >= 500; /* the lattice takes its sites in random order */
    const double vol = 500 * PI / 6 * (1 + 1.4 * 1.4 * 1.4) / phi, side = cbrt(vol);
    const hsbd_spheres_params p = {.n = 1000,
                                   .dimension = 3,
                                   .box = {side, side, side},
                                   .kT = 1,
                                   .dt = 1e-3,
                                   .seed = 31,
                                   .hard_core = 1,
                                   .nspecies = 2,
                                   .species = species,
                                   .species_sigma = sig,
                                   .species_diffusion = dif};
    const outcome o = run_case(&p, 2.0, 8.0, 0);
    const double x[2] = {0.5, 0.5}, rho = 1000 / vol;
    double g[4];
    for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b)
            g[2 * a + b] =
                hsbd_hs_contact_bmcsl(2, x, sig, rho, (size_t)a, (size_t)b) * klm_over_cs(phi);
    printf("3D binary (sigma 1 / 1.4, D 1 / 0.714), phi 0.3, seed 31:\n");
    check_within("Z (collisional virial) vs BMCSL-KLM", o.z_virial, o.z_virial_err,
                 hsbd_hs_z_from_contacts(3, 2, x, sig, rho, g));
    /* the contact theorem, exact: Z = 1 + sum_ab w_ab g_ab with the measured contact
     * values; their errors summed linearly (a bound for any correlation between them) */
    const double measured[4] = {o.g[0], o.g[1], o.g[1], o.g[2]};
    const double err[3] = {o.g_err[0], o.g_err[1], o.g_err[2]};
    double z_contacts_err = 0;
    static const int cells[3][2] = {{0, 0}, {1, 2}, {3, 3}}; /* 11, 12 and 21, 22 */
    for (int q = 0; q < 3; ++q) {
        double unit[4] = {0};
        unit[cells[q][0]] = unit[cells[q][1]] = 1;
        z_contacts_err += (hsbd_hs_z_from_contacts(3, 2, x, sig, rho, unit) - 1) * err[q];
    }
    check_within("Z (collisional virial) vs contacts", o.z_virial, o.z_virial_err + z_contacts_err,
                 hsbd_hs_z_from_contacts(3, 2, x, sig, rho, measured));
    print_within("g_11(sigma_11+) (information)", o.g[0], o.g_err[0], g[0]);
    print_within("g_12(sigma_12+) (information)", o.g[1], o.g_err[1], g[1]);
    print_within("g_22(sigma_22+) (information)", o.g[2], o.g_err[2], g[3]);
}

static void test_polydisperse(void) {
    enum { N = 1000 };
    static double mean[N], sg[N], dif[N];
    const double width = 0.1, phi = 0.3;
    for (size_t i = 0; i < N; ++i)
        mean[i] = 1.0;
    hsbd_error err;
    hsbd_spheres_draw_diameters(41, N, mean, width, HSBD_SIZES_GAUSSIAN, sg, &err);
    double m[4] = {0};
    for (size_t i = 0; i < N; ++i) {
        dif[i] = 1.0 / sg[i]; /* Stokes-Einstein, D_0 = 1 at sigma_0 = 1 */
        for (int k = 0; k < 4; ++k)
            m[k] += pow(sg[i], k) / N;
    }
    const double vol = N * PI / 6 * m[3] / phi, side = cbrt(vol), rho = N / vol;
    const hsbd_spheres_params p = {.n = N,
                                   .dimension = 3,
                                   .box = {side, side, side},
                                   .kT = 1,
                                   .dt = 1e-3,
                                   .seed = 41,
                                   .hard_core = 1,
                                   .particle_sigma = sg,
                                   .particle_diffusion = dif};
    const outcome o = run_case(&p, 2.0, 8.0, 1);
    /* BMCSL over every pair: g_ij = 1/q + 3 xi2 z/q^2 + 2 xi2^2 z^2/q^3, z = s_i s_j/(s_i+s_j),
     * times klm_over_cs */
    const double xi2 = PI / 6 * rho * m[2], q = 1 - PI / 6 * rho * m[3];
    double num = 0, den = 0;
    for (size_t i = 0; i < N; ++i)
        for (size_t j = i + 1; j < N; ++j) {
            const double z = sg[i] * sg[j] / (sg[i] + sg[j]), sij = 0.5 * (sg[i] + sg[j]);
            const double g = 1 / q + 3 * xi2 * z / (q * q) + 2 * xi2 * xi2 * z * z / (q * q * q);
            num += sij * sij * sij * g * klm_over_cs(phi), den += sij * sij * sij;
        }
    printf("3D polydisperse (Gaussian width 0.1, D = 1/sigma), phi 0.3, seed 41:\n");
    check_within("Z (collisional virial) vs BMCSL-KLM", o.z_virial, o.z_virial_err,
                 1 + 4 * PI / (3 * vol * N) * num);
    check_within("g(sigma_ij+), sigma^3-weighted", o.g[0], o.g_err[0], num / den);
}

static void test_short_time_msd(void) {
    static int species[2000];
    const double sig[2] = {1.0, 2.0}, dif[2] = {1.0, 0.25}, phi = 0.02, dt = 1e-5;
    for (int i = 0; i < 2000; ++i)
        species[i] = i % 2;
    const double side = cbrt(1000 * PI / 6 * (1 + 8) / phi);
    const hsbd_spheres_params p = {.n = 2000,
                                   .dimension = 3,
                                   .box = {side, side, side},
                                   .kT = 1,
                                   .dt = dt,
                                   .seed = 41,
                                   .hard_core = 1,
                                   .nspecies = 2,
                                   .species = species,
                                   .species_sigma = sig,
                                   .species_diffusion = dif};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    CHECK(s && hsbd_spheres_init_random(s, &err) == HSBD_OK, "init: %s", err.message);
    if (!s) return;
    /* one-step squared displacements per species, 20 blocks of 50 steps */
    double block[2][BLOCKS] = {{0}};
    double prev[3 * 2000];
    for (int b = 0; b < BLOCKS; ++b)
        for (int k = 0; k < 50; ++k) {
            hsbd_spheres_view v = hsbd_spheres_get_view(s);
            for (size_t i = 0; i < 3 * 2000; ++i)
                prev[i] = v.x[i] + (double)v.image[i] * v.box[i % 3];
            CHECK(hsbd_spheres_step(s) == HSBD_OK, "step");
            v = hsbd_spheres_get_view(s);
            for (size_t i = 0; i < 2000; ++i)
                for (int a = 0; a < 3; ++a) {
                    const double d =
                        v.x[3 * i + a] + (double)v.image[3 * i + a] * v.box[a] - prev[3 * i + a];
                    block[i % 2][b] += d * d / (1000.0 * 50.0);
                }
        }
    printf("short-time MSD, dilute binary (phi 0.02), lag dt = 1e-5, seed 41:\n");
    for (int a = 0; a < 2; ++a) {
        double m = 0, m2 = 0;
        for (int b = 0; b < BLOCKS; ++b)
            m += block[a][b] / BLOCKS, m2 += block[a][b] * block[a][b] / BLOCKS;
        const double e = sqrt((m2 - m * m) / (BLOCKS - 1));
        check_within(a ? "MSD(dt) species 2 / (6 D_2 dt)" : "MSD(dt) species 1 / (6 D_1 dt)",
                     m / (6 * dif[a] * dt), e / (6 * dif[a] * dt), 1.0);
    }
    hsbd_spheres_free(s);
}

int main(void) {
    test_monodisperse(3, 0.3, 21);
    test_binary();
    test_polydisperse();
    test_short_time_msd();
    return test_finish("test_spheres_physics");
}
