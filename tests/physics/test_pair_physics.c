/* Rods with pair forces against the exact nearest-neighbour theory (Takahashi's gap law,
 * src/theory/transfer.c): a weak Yukawa repulsion and Baxter's sticky contact in its
 * delta_eps form (Antonov Eqs. 31-32), both at U0 = 0 where the pair density near contact
 * is rho p(h), p the nearest-neighbour gap density of the infinite fluid.
 *
 * Fixed seeds; a comparison passes when |simulation - exact| < 4 standard errors from
 * block averages in the same run (20 blocks). The ring's canonical O(1/N) correction
 * (-1/N relative for hard rods) is below a third of the error bar at N = 300. The
 * deviations are printed in units of the error. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/observe.h"
#include "hsbd/pair.h"
#include "hsbd/rods.h"
#include "hsbd/theory.h"

static int within(const char *what, double sim, double err, double exact) {
    const double dev = (sim - exact) / err;
    printf("  %-48s sim %.6g +- %.2g, exact %.6g: %+.2f sigma\n", what, sim, err, exact, dev);
    return isfinite(dev) && fabs(dev) < 4.0;
}

/* rho (1/w) int_0^w p(h) dh with p(h) = (rho2(0+)/rho) e^{-V(sigma+h)} e^{-bP h} / e^{-V(sigma)} */
static double window_theory(const hsbd_pair *pair, double sigma, double rho, double width) {
    double bp, c0;
    hsbd_nn_homogeneous_solve(pair, sigma, rho, &bp, &c0, NULL);
    const double v0 = hsbd_pair_potential(pair, sigma);
    enum { Q = 20000 };
    double s = 0;
    for (int k = 0; k < Q; ++k) {
        const double h = width * (k + 0.5) / Q;
        s += exp(v0 - hsbd_pair_potential(pair, sigma + h) - bp * h);
    }
    return c0 * s / Q;
}

typedef struct pair_case {
    const char *name;
    hsbd_pair pair;
    double dt, window, t_sample;
    double dt_equil, t_equil; /* equilibration from the hard-rod sample. The excess of
                                 close pairs relaxes slowly: a Yukawa run is still +6 % high
                                 after 2 time units, within error after 20; equilibrated at
                                 dt 5e-4 instead of 5e-5 it stays +5 % high for 10 units
                                 after the switch (docs/validation.md) */
    uint64_t seed;
    /* the extrapolation to zero gap assumes a gap density that is linear over the 0.02
     * window; the sticky one varies on the scale eps (Eq. 31) and is not (measured: -5 %) */
    int check_extrapolated;
} pair_case;

static void run_case(const pair_case *pc) {
    const size_t n = 300, nblocks = 20, every = 20;
    const double L = 600, sigma = 0.5, rho = (double)n / L;
    hsbd_rods_params par = {.n = n,
                            .length = L,
                            .sigma = sigma,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = pc->dt,
                            .seed = pc->seed,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_REFLECT,
                            .pair = pc->pair};
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    CHECK(rods != NULL, "%s", err.message);
    hsbd_rods_init_equilibrium(rods);
    const uint64_t equil = (uint64_t)llround(pc->t_equil / pc->dt_equil);
    const uint64_t steps = (uint64_t)llround(pc->t_sample / pc->dt);
    hsbd_rods_set_dt(rods, pc->dt_equil);
    for (uint64_t k = 0; k < equil; ++k)
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
    hsbd_rods_set_dt(rods, pc->dt); /* then 0.5 time units for the step's own distortion */
    for (uint64_t k = 0; k < (uint64_t)llround(0.5 / pc->dt); ++k)
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
    hsbd_profile *wide = hsbd_profile_alloc(1.0, 1.0, pc->window, nblocks, steps / every, &err);
    hsbd_profile *narrow = hsbd_profile_alloc(1.0, 1.0, 0.02, nblocks, steps / every, &err);
    for (uint64_t k = 1; k <= steps; ++k) {
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        if (k % every) continue;
        const hsbd_rods_view v = hsbd_rods_get_view(rods);
        hsbd_profile_sample(wide, &v);
        hsbd_profile_sample(narrow, &v);
    }
    double x, c, e, bp, c0;
    char what[128];
    hsbd_nn_homogeneous_solve(&pc->pair, sigma, rho, &bp, &c0, NULL);
    hsbd_profile_contact_window(wide, &x, &c, &e);
    snprintf(what, sizeof what, "%s: pairs with gap < %g", pc->name, pc->window);
    CHECK(within(what, c, e, window_theory(&pc->pair, sigma, rho, pc->window)), "%s", what);
    const double tonks = hsbd_tonks_contact(rho, sigma);
    printf("  %-48s (hard rods: %.6g, %+.0f sigma away)\n", "", tonks, (c - tonks) / e);
    hsbd_profile_contact_extrapolated(narrow, &x, &c, &e);
    snprintf(what, sizeof what, "%s: rho2(sigma+), extrapolated", pc->name);
    if (pc->check_extrapolated) CHECK(within(what, c, e, c0), "%s", what);
    CHECK(hsbd_profile_min_gap(wide) >= 0, "negative gap %g", hsbd_profile_min_gap(wide));
    hsbd_profile_free(wide);
    hsbd_profile_free(narrow);
    hsbd_rods_free(rods);
}

int main(void) {
    pair_case yukawa = {.name = "Yukawa A=1 kappa=2",
                        .dt = 5e-5,
                        .window = 0.2,
                        .t_sample = 10,
                        .dt_equil = 5e-5,
                        .t_equil = 20,
                        .seed = 41,
                        .check_extrapolated = 1};
    hsbd_pair_add(&yukawa.pair, hsbd_pair_yukawa(0.5, 1.0, 2.0, 0.9));
    run_case(&yukawa);
    pair_case sticky = {.name = "sticky gamma=1 eps=0.05",
                        .dt = 2e-5,
                        .window = 0.05,
                        .t_sample = 4,
                        .dt_equil = 2e-5,
                        .t_equil = 8,
                        .seed = 43};
    hsbd_pair_add(&sticky.pair, hsbd_pair_sticky(0.5, 1.0, 3.0, 0.05, 1.0));
    run_case(&sticky);
    return test_finish("test_pair_physics");
}
