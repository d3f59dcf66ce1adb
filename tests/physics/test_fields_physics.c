/* A tabulated field on a ring reproduces the analytic field's equilibrium, across the
 * boundary x = 0 = L too. The table samples U(x) = (U0/2) cos(2 pi x) with U0 = -6 kT
 * at spacing 0.05 on a ring of one period, L = 1, so that the well straddles x = 0 = L;
 * ideal particles (system.hard_core = off, sigma = 0) then have the exact profile
 * rho(x) = N exp(-U(x)/kT) / Z, Z = int_0^1 exp(-U/kT) dx. The runs go through the
 * configuration and the run driver (what a user runs) and read density.tsv back: the
 * table's run and the analytic cosine's run must both match the Boltzmann profile (bin
 * averages) within their block errors (20 time blocks). Both runs use the same noise,
 * so their difference isolates the table's interpolation error (a spline potential within
 * 8e-5 kT of the cosine): every bin must agree within 0.5 of its error bar. A natural
 * spline, which forces U'' = 0 at x = 0 where U'' is largest, moves the peak bins by 4-5
 * error bars (measured: chi^2/dof 3.2 against the theory, 4.5 error bars at x = 0.98).
 *
 * Fixed seed; N = 200 particles, 10 time units after 0.5 of equilibration (the well's
 * relaxation time 1/(mu U'') is 0.0085); dt = 2e-5 keeps the Euler broadening of the
 * well, a relative k dt / 2 = 0.12 % of its variance, below a fifth of an error bar.
 * Pass: chi^2/dof < 1 + 4 sqrt(2/bins) and every bin within 4.5 error bars.
 * HSBD_VALIDATE=long: 10 times longer. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../test_util.h"
#include "hsbd/config.h"
#include "hsbd/run.h"

enum { NBINS = 25, MAXROWS = 64 };
static const double U0 = -6.0;

static double potential(double x) {
    return 0.5 * U0 * cos(6.283185307179586 * x);
}

/* the Boltzmann profile N exp(-U) / Z averaged over [a, b] */
static double boltzmann_bin(double a, double b, double n) {
    enum { Q = 20000 };
    double z = 0, in = 0;
    for (int k = 0; k < Q; ++k) {
        const double x = (k + 0.5) / Q, w = exp(-potential(x));
        z += w / Q;
        if (x >= a && x < b) in += w / Q;
    }
    return n * in / z / (b - a);
}

/* x, rho, rho_err of density.tsv; returns the number of rows */
static size_t read_density(const char *path, double *x, double *rho, double *err) {
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char line[4096];
    size_t n = 0;
    while (fgets(line, sizeof line, f) && n < MAXROWS)
        if (line[0] != '#' && sscanf(line, "%lf %lf %lf", &x[n], &rho[n], &err[n]) == 3) ++n;
    fclose(f);
    return n;
}

/* Runs the configuration, compares density.tsv with the Boltzmann profile and returns
 * the profile and its errors (NBINS rows). */
static void run_and_compare(const char *name, const char *dir, const char *const *settings,
                            size_t nsettings, double scale, double *rho, double *e) {
    hsbd_config cfg;
    hsbd_error err;
    hsbd_config_defaults(&cfg);
    char buf[HSBD_PATH_MAX + 64];
    for (size_t k = 0; k < nsettings; ++k)
        CHECK(hsbd_config_set(&cfg, settings[k], "test", &err) == HSBD_OK, "%s", err.message);
    snprintf(buf, sizeof buf, "run.t_total=%g", 10 * scale);
    hsbd_config_set(&cfg, buf, "test", &err);
    snprintf(buf, sizeof buf, "output.dir=%s", dir);
    hsbd_config_set(&cfg, buf, "test", &err);
    CHECK(hsbd_config_finalize(&cfg, &err) == HSBD_OK, "%s: %s", name, err.message);
    const hsbd_run_options opt = {.force = 1};
    CHECK(hsbd_run_rods(&cfg, &opt, &err) == HSBD_OK, "%s: %s", name, err.message);
    double x[MAXROWS];
    snprintf(buf, sizeof buf, "%s/density.tsv", dir);
    const size_t rows = read_density(buf, x, rho, e);
    CHECK(rows == NBINS, "%s: %zu rows in density.tsv", name, rows);
    double chi2 = 0, worst = 0, worst_x = 0;
    const double w = 1.0 / NBINS;
    for (size_t k = 0; k < rows; ++k) {
        const double th = boltzmann_bin(x[k] - w / 2, x[k] + w / 2, (double)cfg.system.n);
        const double d = (rho[k] - th) / e[k];
        if (getenv("HSBD_VERBOSE"))
            printf("    x %.3f sim %.4f +- %.4f theory %.4f (%+.2f)\n", x[k], rho[k], e[k], th, d);
        chi2 += d * d;
        if (fabs(d) > worst) worst = fabs(d), worst_x = x[k];
    }
    printf("  %-34s chi^2/dof = %.3f, max |dev|/err = %.2f at x = %.2f\n", name, chi2 / NBINS,
           worst, worst_x);
    CHECK(chi2 / NBINS < 1 + 4 * sqrt(2.0 / NBINS), "%s: chi2/dof %.3f", name, chi2 / NBINS);
    CHECK(worst < 4.5, "%s: a bin is %.2f error bars off", name, worst);
}

int main(void) {
    const char *v = getenv("HSBD_VALIDATE");
    const double scale = v && !strcmp(v, "long") ? 10.0 : 1.0;
    char tmp[] = "/tmp/hsbd-fields-XXXXXX";
    CHECK(mkdtemp(tmp) != NULL, "mkdtemp");
    char table[128], dir_table[128], dir_cos[128], key[160];
    snprintf(table, sizeof table, "%s/cosine.tsv", tmp);
    FILE *f = fopen(table, "w");
    for (int i = 0; i <= 20; ++i)
        fprintf(f, "%.17g %.17g\n", i * 0.05, potential(i * 0.05));
    fclose(f);
    snprintf(dir_table, sizeof dir_table, "%s/table", tmp);
    snprintf(dir_cos, sizeof dir_cos, "%s/cosine", tmp);
    snprintf(key, sizeof key, "field.table=%s", table);
    const char *common[] = {
        "system.N=200",    "system.L=1",     "system.sigma=0",  "system.hard_core=off",
        "system.seed=5",   "run.dt=2e-5",    "run.t_equil=0.5", "sample.bin_width=0.04",
        "sample.every=50", "sample.period=1"};
    enum { NC = sizeof common / sizeof common[0] };
    const char *with_table[NC + 2], *with_cosine[NC + 2];
    memcpy(with_table, common, sizeof common);
    memcpy(with_cosine, common, sizeof common);
    with_table[NC] = "field.type=table";
    with_table[NC + 1] = key;
    with_cosine[NC] = "field.type=cosine";
    with_cosine[NC + 1] = "field.amplitude=-6";
    double rt[MAXROWS], et[MAXROWS], rc[MAXROWS], ec[MAXROWS];
    run_and_compare("periodic table of the cosine", dir_table, with_table, NC + 2, scale, rt, et);
    run_and_compare("analytic cosine", dir_cos, with_cosine, NC + 2, scale, rc, ec);
    double paired = 0;
    for (size_t k = 0; k < NBINS; ++k)
        paired = fmax(paired, fabs(rt[k] - rc[k]) / ec[k]);
    printf("  table vs cosine, same noise: max |difference|/err = %.3f\n", paired);
    CHECK(paired < 0.5, "the table's profile differs from the cosine's by %.2f error bars", paired);
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmp);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", tmp);
    return test_finish("test_fields_physics");
}
