/* Quick comparison with Percus' exact theory (paper Fig. 3/4 case sigma = 0.5, rho = 0.5,
 * U0 = 6) with the default contact rule (reflect): density profile and contact density
 * (the default extrapolated estimator over a 0.02 window, and the contact theorem).
 *
 * 400 periods, equilibrated 40 time units (two barrier-hopping times) at the production
 * step dt = 2.5e-5. The Euler error of the field step broadens the wells by k dt / 2
 * (k = U'' = 118): at dt = 1e-4 this run's long version sees the peak 0.25 % low and the
 * flanks 1-3 % high (chi^2/dof 5.4); at 2.5e-5 it is four times smaller, below the errors.
 * Errors from 20 spatial blocks of 20 periods, the density's as the scatter of the shape
 * (N is fixed). Fixed seed; pass: chi^2/dof < 1 + 4 sqrt(2/bins) and every bin within
 * 4.5 error bars. HSBD_VALIDATE=long: 10 times longer. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "hsbd/observe.h"
#include "hsbd/rods.h"
#include "hsbd/theory.h"

enum { NBINS = 25 };

static void compare(const char *what, const double *x, const double *sim, const double *err,
                    const hsbd_percus_result *th, const double *theory_col, double width) {
    double chi2 = 0, worst = 0;
    const double h = th->x[1] - th->x[0];
    for (size_t k = 0; k < NBINS; ++k) {
        const double t = hsbd_periodic_bin_average(theory_col, th->m, h, x[k], width);
        const double d = (sim[k] - t) / err[k];
        if (getenv("HSBD_VERBOSE"))
            printf("    x %.3f sim %.5f err %.5f (%.3f%%) theory %.5f rel dev %+.3f%% (%+.2f)\n",
                   x[k], sim[k], err[k], 100 * err[k] / sim[k], t, 100 * (sim[k] / t - 1), d);
        chi2 += d * d;
        worst = fmax(worst, fabs(d));
    }
    printf("  %-30s chi^2/dof = %.3f, max |dev|/err = %.2f over %d bins\n", what, chi2 / NBINS,
           worst, NBINS);
    CHECK(chi2 / NBINS < 1 + 4 * sqrt(2.0 / NBINS), "%s: chi2/dof %.3f", what, chi2 / NBINS);
    CHECK(worst < 4.5, "%s: a bin is %.2f error bars off", what, worst);
}

int main(void) {
    const char *v = getenv("HSBD_VALIDATE");
    const double scale = v && !strcmp(v, "long") ? 10.0 : 1.0;
    const double sigma = 0.5, rho = 0.5, dt = 2.5e-5, L = 400;
    const size_t n = (size_t)(rho * L);
    hsbd_rods_params par = {.n = n,
                            .length = L,
                            .sigma = sigma,
                            .diffusion = 1,
                            .kT = 1,
                            .dt = dt,
                            .seed = 2022,
                            .hard_core = 1,
                            .contact_rule = HSBD_CONTACT_REFLECT};
    hsbd_field_add(&par.field, hsbd_field_cosine(6.0, 1.0));
    hsbd_error err;
    hsbd_rods *rods = hsbd_rods_alloc(&par, &err);
    hsbd_rods_init_equilibrium(rods);
    /* equilibration from the uniform start: the wells' occupations relax by barrier
     * hopping, which needs ~200 time units (40 left chi^2/dof ~2 in every observable);
     * done at dt 1e-4, then 10 units at the production step for the fast modes */
    hsbd_rods_set_dt(rods, 1e-4);
    for (uint64_t k = 0; k < (uint64_t)(200 / 1e-4); ++k)
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
    hsbd_rods_set_dt(rods, dt);
    for (uint64_t k = 0; k < (uint64_t)(30 / dt); ++k)
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
    hsbd_profile *prof = hsbd_profile_alloc_spatial(1.0, 1.0 / NBINS, 0.02, 20, &err);
    const uint64_t steps = (uint64_t)(60 * scale / dt);
    for (uint64_t k = 1; k <= steps; ++k) {
        CHECK(hsbd_rods_step(rods, NULL) == HSBD_OK, "step");
        if (k % 40) continue;
        const hsbd_rods_view view = hsbd_rods_get_view(rods);
        hsbd_profile_sample(prof, &view);
    }
    hsbd_percus_params pp = {
        .sigma = sigma, .rho_mean = rho, .amplitude = 6, .wavelength = 1, .points = 2000};
    hsbd_percus_result th;
    CHECK(hsbd_percus_solve(&pp, &th, &err) == HSBD_OK, "theory: %s", err.message);
    double x[NBINS], s[NBINS], e[NBINS];
    hsbd_profile_density(prof, x, s, e);
    compare("density", x, s, e, &th, th.rho, 1.0 / NBINS);
    hsbd_profile_contact_extrapolated(prof, x, s, e);
    compare("contact density (extrapolated)", x, s, e, &th, th.rho2, 1.0 / NBINS);
    hsbd_profile_contact(prof, x, s, e);
    compare("contact density (theorem)", x, s, e, &th, th.rho2, 1.0 / NBINS);
    hsbd_percus_result_free(&th);
    hsbd_profile_free(prof);
    hsbd_rods_free(rods);
    return test_finish("test_percus_quick");
}
