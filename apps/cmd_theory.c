/* hsbd theory: exact results (docs/theory.md). One table of subcommands, each with its table
 * of number flags, a check of the flags together, and the function that writes the result. */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "hsbd/field.h"
#include "hsbd/io.h"
#include "hsbd/theory.h"
#include "hsbd_version.h"

enum { THEORY_MAX_FLAGS = 10 };

/* A number flag: its default, the allowed range (each end open or closed), whether it must
 * be given, and its line of help. */
typedef struct theory_flag {
    const char *name;
    double value;
    double min, max;
    int open_min, open_max, required;
    const char *doc;
} theory_flag;

/* A subcommand; v[k] is the value of flags[k]. check and write return 0 or an exit status
 * after a message. */
typedef struct theory {
    const char *name, *synopsis, *about;
    int writes_file; /* --out FILE|- (required); else the result goes to standard output */
    theory_flag flags[THEORY_MAX_FLAGS];
    int (*check)(const double *v);
    int (*write)(const double *v, FILE *f);
} theory;

/* ---- the theories ---------------------------------------------------------------------- */

enum {
    BOX_N,
    BOX_L,
    BOX_SIGMA,
    BOX_U0,
    BOX_WAVELENGTH,
    BOX_FORCE,
    BOX_K,
    BOX_CENTER,
    BOX_BIN,
    BOX_POINTS
};

static int box_check(const double *v) {
    if (v[BOX_N] == floor(v[BOX_N]) && v[BOX_POINTS] == floor(v[BOX_POINTS]) &&
        v[BOX_N] * v[BOX_SIGMA] < v[BOX_L])
        return 0;
    fprintf(stderr, "hsbd theory box: need whole --N and --points, and N sigma < L\n");
    return EXIT_INPUT;
}

/* N rods between hard walls at 0 and L in cosine + tilt + harmonic fields: the exact
 * canonical profile (src/theory/box.c), bin averages. */
static int box_write(const double *v, FILE *f) {
    const double length = v[BOX_L], bin = v[BOX_BIN];
    const double center = isnan(v[BOX_CENTER]) ? 0.5 * length : v[BOX_CENTER];
    hsbd_field field = {0};
    if (v[BOX_U0] != 0) hsbd_field_add(&field, hsbd_field_cosine(v[BOX_U0], v[BOX_WAVELENGTH]));
    if (v[BOX_FORCE] != 0) hsbd_field_add(&field, hsbd_field_tilt(v[BOX_FORCE]));
    if (v[BOX_K] > 0) hsbd_field_add(&field, hsbd_field_harmonic(v[BOX_K], center, 0.0));
    const double points = v[BOX_POINTS] > 0 ? v[BOX_POINTS] /* memory N x points doubles */
                                            : fmin(1e5, fmax(2000, 2e7 / v[BOX_N]));
    hsbd_box_params p = {.n = (size_t)v[BOX_N],
                         .length = length,
                         .sigma = v[BOX_SIGMA],
                         .field = &field,
                         .points = (size_t)points};
    hsbd_box_result r;
    hsbd_error err;
    const int st = hsbd_box_solve(&p, bin, &r, &err);
    if (st != HSBD_OK) return cli_fail(st, err.message);
    fprintf(f,
            "# hsbd %s (git %s): N hard rods between hard walls, exact canonical profile "
            "(docs/theory.md), bin averages\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    fprintf(f,
            "# N = %zu\n# L = %.17g\n# sigma = %.17g\n# amplitude = %.17g\n# wavelength = %.17g\n"
            "# force = %.17g\n# stiffness = %.17g\n# center = %.17g\n# points = %zu\n"
            "# wall_left = %.12g\n# wall_right = %.12g\n",
            p.n, length, p.sigma, v[BOX_U0], v[BOX_WAVELENGTH], v[BOX_FORCE], v[BOX_K], center,
            p.points, r.wall_left, r.wall_right);
    fprintf(f, "# x\trho\trho2\n");
    for (size_t k = 0; k < r.nbins; ++k)
        fprintf(f, "%.10g\t%.12g\t%.12g\n", (k + 0.5) * bin, r.rho[k], r.rho2[k]);
    hsbd_box_result_free(&r);
    return 0;
}

enum { PERCUS_SIGMA, PERCUS_RHO, PERCUS_U0, PERCUS_GAMMA, PERCUS_WAVELENGTH, PERCUS_POINTS };

static int percus_check(const double *v) {
    const double rho = v[PERCUS_RHO], sigma = v[PERCUS_SIGMA];
    if (!(rho * sigma < 1)) {
        fprintf(stderr,
                "hsbd theory percus: --rho %g with --sigma %g: need rho*sigma < 1 (no "
                "room); allowed: rho < %g\n",
                rho, sigma, 1 / sigma);
        return EXIT_INPUT;
    }
    if (v[PERCUS_POINTS] == floor(v[PERCUS_POINTS])) return 0;
    fprintf(stderr, "hsbd theory percus: --points must be a whole number\n");
    return EXIT_INPUT;
}

static int percus_write(const double *v, FILE *f) {
    const double gamma = v[PERCUS_GAMMA];
    hsbd_percus_params p = {.sigma = v[PERCUS_SIGMA],
                            .rho_mean = v[PERCUS_RHO],
                            .amplitude = v[PERCUS_U0],
                            .wavelength = v[PERCUS_WAVELENGTH],
                            .gamma = gamma,
                            .points = (size_t)v[PERCUS_POINTS]};
    hsbd_percus_result r;
    hsbd_error err;
    const int st = hsbd_percus_solve(&p, &r, &err);
    if (st != HSBD_OK) return cli_fail(st, err.message);
    fprintf(f, "# hsbd %s (git %s): Percus exact equilibrium profile%s\n", HSBD_VERSION_STRING,
            HSBD_GIT_COMMIT, gamma > 0 ? " (sticky, Antonov Eqs. 34)" : " (Antonov Eqs. 20-23)");
    fprintf(f,
            "# sigma = %.17g\n# rho_mean = %.17g\n# amplitude = %.17g\n# wavelength = %.17g\n"
            "# gamma = %.17g\n# points = %zu\n# beta_mu = %.15g\n# iterations = %d\n"
            "# residual = %.3g\n",
            p.sigma, p.rho_mean, p.amplitude, p.wavelength, gamma, p.points, r.beta_mu,
            r.iterations, r.residual);
    if (gamma > 0) fprintf(f, "# rho2 is not available for gamma > 0 (nan)\n");
    fprintf(f, "# x\trho\trho2\n");
    for (size_t j = 0; j < r.m; ++j)
        fprintf(f, "%.10g\t%.12g\t%.12g\n", r.x[j], r.rho[j], r.rho2[j]);
    hsbd_percus_result_free(&r);
    return 0;
}

enum {
    WB_U0,
    WB_WAVELENGTH,
    WB_D,
    WB_KT,
    WB_FORCE,
    WB_FMIN,
    WB_FMAX,
    WB_NFORCES,
    WB_ROCKING,
    WB_TOL
};

/* one tilt (--force), or a grid of them (--force-min, --force-max, --forces) */
static int washboard_grid(const double *v) {
    return !isnan(v[WB_FMIN]) || !isnan(v[WB_FMAX]) || v[WB_NFORCES] > 0;
}

static int washboard_check(const double *v) {
    const int grid = washboard_grid(v);
    if (grid != !isnan(v[WB_FORCE]) &&
        (!grid || (!isnan(v[WB_FMIN]) && !isnan(v[WB_FMAX]) && v[WB_NFORCES] != 0)) &&
        v[WB_NFORCES] == floor(v[WB_NFORCES]) && (!grid || v[WB_FMAX] > v[WB_FMIN]))
        return 0;
    fprintf(stderr, "hsbd theory washboard: give --force F, or --force-min A --force-max B "
                    "--forces K with A < B and K whole (not both)\n");
    return EXIT_INPUT;
}

/* One overdamped particle in U0/2 cos(2 pi x / lambda) - F x: the exact mean velocity
 * (Stratonovich) and D_eff (Reimann et al. 2001) at each tilt, and the adiabatically rocked
 * drift for F(t) = F + F1 cos(omega t) (src/theory/washboard.c). */
static int washboard_write(const double *v, FILE *f) {
    const double u0 = v[WB_U0], wavelength = v[WB_WAVELENGTH], rocking = v[WB_ROCKING];
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_cosine(u0, wavelength));
    hsbd_washboard_params p = {.diffusion = v[WB_D],
                               .kT = v[WB_KT],
                               .period = wavelength,
                               .field = &field,
                               .tol = v[WB_TOL]};
    const size_t nf = washboard_grid(v) ? (size_t)v[WB_NFORCES] : 1;
    fprintf(f,
            "# hsbd %s (git %s): one particle in a tilted cosine, exact stationary drift and "
            "D_eff (docs/theory.md)\n# amplitude = %.17g\n# wavelength = %.17g\n# D = %.17g\n"
            "# kT = %.17g\n# critical_force = %.17g\n# rocking = %.17g\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT, u0, wavelength, p.diffusion, p.kT,
            3.141592653589793 * fabs(u0) / wavelength, rocking);
    fprintf(f, "# force\tvelocity\td_eff\trel_error%s\n", rocking > 0 ? "\tvelocity_rocking" : "");
    for (size_t k = 0; k < nf; ++k) {
        p.force = nf > 1 ? v[WB_FMIN] + (v[WB_FMAX] - v[WB_FMIN]) * (double)k / (double)(nf - 1)
                         : v[WB_FORCE];
        hsbd_washboard_result r;
        hsbd_washboard_rocking_result rr;
        hsbd_error err;
        int st = hsbd_washboard_solve(&p, &r, &err);
        if (st != HSBD_OK) return cli_fail(st, err.message);
        fprintf(f, "%.10g\t%.15g\t%.15g\t%.3g", p.force, r.velocity, r.diffusion_eff, r.error);
        hsbd_washboard_result_free(&r);
        if (rocking > 0 && (st = hsbd_washboard_rocking(&p, p.force, rocking, &rr, &err)) != 0)
            return cli_fail(st, err.message);
        if (rocking > 0) fprintf(f, "\t%.15g", rr.velocity);
        fputc('\n', f);
    }
    return 0;
}

enum { TONKS_SIGMA, TONKS_RHO, TONKS_GAMMA, TONKS_D };

static int tonks_check(const double *v) {
    if (v[TONKS_RHO] * v[TONKS_SIGMA] < 1) return 0;
    fprintf(stderr, "hsbd theory tonks: need rho*sigma < 1; allowed: rho < %g\n",
            1 / v[TONKS_SIGMA]);
    return EXIT_INPUT;
}

static int tonks_write(const double *v, FILE *f) {
    const double sigma = v[TONKS_SIGMA], rho = v[TONKS_RHO], gamma = v[TONKS_GAMMA];
    const double pi = 3.141592653589793;
    fprintf(f, "# homogeneous hard rods, sigma = %g, rho = %g (packing %g), kT = 1\n", sigma, rho,
            rho * sigma);
    fprintf(f, "beta_P = %.15g\n", hsbd_tonks_pressure(rho, sigma));
    fprintf(f, "beta_mu = %.15g\n", hsbd_tonks_beta_mu(rho, sigma));
    fprintf(f, "contact_density = %.15g\n", hsbd_tonks_contact(rho, sigma));
    fprintf(f, "g_contact = %.15g\n", 1.0 / (1.0 - rho * sigma));
    fprintf(f, "single_file_msd_prefactor = %.15g   # MSD -> prefactor * sqrt(t), D = %g\n",
            (1 - rho * sigma) / rho * sqrt(4 * v[TONKS_D] / pi), v[TONKS_D]);
    if (gamma > 0) {
        fprintf(f, "sticky_gamma = %g\n", gamma);
        fprintf(f, "sticky_beta_P = %.15g\n", hsbd_sticky_pressure(rho, sigma, gamma));
        fprintf(f, "sticky_beta_mu = %.15g\n", hsbd_sticky_beta_mu(rho, sigma, gamma));
    }
    return 0;
}

#define NO_BOUND 1e300 /* an open end of a range ("inf" in messages) */

static const theory theories[] = {
    {"percus",
     "hsbd theory percus --sigma S --rho R --amplitude U0 [--gamma G]\n"
     "                      [--wavelength W] [--points M] --out FILE|-\n"
     "                                       exact equilibrium profile (x rho rho2)\n",
     "The exact equilibrium profile of hard rods on a line in the cosine field (Percus,\n"
     "Antonov Eqs. 20-23; sticky rods with --gamma, Eqs. 34), columns x rho rho2.",
     1,
     {{"--sigma", 0, 0, NO_BOUND, 0, 1, 1, "rod length"},
      {"--rho", 0, 0, NO_BOUND, 1, 1, 1, "mean density (rho sigma < 1)"},
      {"--amplitude", 0, 0, 1e6, 0, 0, 1, "cosine amplitude U0 in kT"},
      {"--gamma", 0, 0, 1e12, 0, 0, 0, "Baxter stickiness (default 0: hard rods)"},
      {"--wavelength", 1, 0, NO_BOUND, 1, 1, 0, "cosine wavelength (default 1)"},
      {"--points", 2000, 16, 1e8, 0, 0, 0, "grid points per wavelength (whole; default 2000)"}},
     percus_check,
     percus_write},
    {"tonks",
     "hsbd theory tonks --sigma S --rho R [--gamma G] [--D D]\n"
     "                                       closed forms of the homogeneous fluid\n",
     "Closed forms of the homogeneous hard-rod fluid (Tonks gas; sticky with --gamma):\n"
     "pressure, chemical potential, contact density and the single-file MSD\n"
     "prefactor, on standard output.",
     0,
     {{"--sigma", 0, 0, NO_BOUND, 0, 1, 1, "rod length"},
      {"--rho", 0, 0, NO_BOUND, 1, 1, 1, "density (rho sigma < 1)"},
      {"--gamma", 0, 0, 1e12, 0, 0, 0, "Baxter stickiness (default 0)"},
      {"--D", 1, 0, NO_BOUND, 1, 1, 0, "diffusion coefficient (default 1)"}},
     tonks_check,
     tonks_write},
    {"box",
     "hsbd theory box --N N --L L --sigma S [--force F] [--stiffness K]\n"
     "                      [--center C] [--amplitude U0] [--wavelength W] [--bin W]\n"
     "                      [--points M] --out FILE|-\n"
     "                                       exact profile between hard walls\n",
     "The exact canonical density profile of N hard rods between hard walls at 0 and L\n"
     "in cosine, tilt and harmonic fields, as bin averages (columns x rho rho2; "
     "docs/theory.md).",
     1,
     {{"--N", 0, 1, 1e7, 0, 0, 1, "number of rods (whole)"},
      {"--L", 0, 0, NO_BOUND, 1, 1, 1, "distance between the walls"},
      {"--sigma", 0, 0, NO_BOUND, 0, 1, 1, "rod length (N sigma < L)"},
      {"--amplitude", 0, -1e6, 1e6, 0, 0, 0, "cosine amplitude U0 in kT (default 0)"},
      {"--wavelength", 1, 0, NO_BOUND, 1, 1, 0, "cosine wavelength (default 1)"},
      {"--force", 0, -1e6, 1e6, 0, 0, 0, "constant force in kT/length (default 0)"},
      {"--stiffness", 0, 0, 1e6, 0, 0, 0, "harmonic trap stiffness (default 0)"},
      {"--center", NAN, -NO_BOUND, NO_BOUND, 0, 0, 0, "harmonic trap centre (default L/2)"},
      {"--bin", 0.01, 0, NO_BOUND, 1, 1, 0, "bin width of the profile (default 0.01)"},
      {"--points", 0, 16, 1e8, 0, 0, 0, "grid points (whole; default min(1e5, max(2000, 2e7/N)))"}},
     box_check,
     box_write},
    {"washboard",
     "hsbd theory washboard --amplitude U0 [--wavelength W] [--D D] [--kT kT]\n"
     "                      [--force F | --force-min A --force-max B --forces K]\n"
     "                      [--rocking F1] [--tol T] --out FILE|-\n"
     "                                       one particle in a tilted cosine: <v>, D_eff\n",
     "One overdamped Brownian particle in U(x) = (U0/2) cos(2 pi x / lambda) - F x: the exact\n"
     "mean velocity (Stratonovich) and effective diffusion coefficient D_eff (Reimann et al.,\n"
     "PRL 87, 010602 (2001)); columns force velocity d_eff rel_error [velocity_rocking]\n"
     "(docs/theory.md). Critical tilt: pi U0 / lambda.",
     1,
     {{"--amplitude", 0, -1e4, 1e4, 0, 0, 1, "cosine amplitude U0 (energy)"},
      {"--wavelength", 1, 0, NO_BOUND, 1, 1, 0, "wavelength lambda (default 1)"},
      {"--D", 1, 0, NO_BOUND, 1, 1, 0, "diffusion coefficient (default 1)"},
      {"--kT", 1, 0, NO_BOUND, 1, 1, 0, "thermal energy (default 1)"},
      {"--force", NAN, -1e6, 1e6, 0, 0, 0, "tilt F (energy/length); or a grid:"},
      {"--force-min", NAN, -1e6, 1e6, 0, 0, 0, "first tilt of the grid"},
      {"--force-max", NAN, -1e6, 1e6, 0, 0, 0, "last tilt of the grid"},
      {"--forces", 0, 2, 1e5, 0, 0, 0, "tilts in the grid (whole)"},
      {"--rocking", 0, 0, 1e6, 0, 0, 0,
       "F1: add the adiabatic drift of F(t) = F + F1 cos(omega t) (default 0: none)"},
      {"--tol", 1e-10, 1e-14, 1e-2, 0, 0, 0, "relative accuracy (default 1e-10)"}},
     washboard_check,
     washboard_write},
};
enum { NTHEORIES = sizeof theories / sizeof theories[0] };

void cmd_theory_synopses(FILE *out) {
    for (size_t k = 0; k < NTHEORIES; ++k)
        fprintf(out, "       %s", theories[k].synopsis);
}

/* ---- flags ----------------------------------------------------------------------------- */

static size_t flag_count(const theory *t) {
    size_t n = 0;
    while (n < THEORY_MAX_FLAGS && t->flags[n].name)
        ++n;
    return n;
}

/* "-inf", "inf" for the tables' 1e300 bounds, else %g */
static const char *bound_text(double v, char *buf, size_t len) {
    if (fabs(v) >= NO_BOUND) return v < 0 ? "-inf" : "inf";
    snprintf(buf, len, "%g", v);
    return buf;
}

/* "lo <= name < hi" of a flag */
static void flag_range(const theory_flag *f, char *buf, size_t len) {
    char lo[32], hi[32];
    snprintf(buf, len, "%s %s %s %s %s", bound_text(f->min, lo, sizeof lo),
             f->open_min ? "<" : "<=", f->name + 2,
             f->open_max ? "<" : "<=", bound_text(f->max, hi, sizeof hi));
}

/* "  --name  doc; allowed: range (required)" per flag, after the synopsis */
static void theory_help(const theory *t) {
    printf("usage: %s\n%s\n", t->synopsis, t->about);
    for (size_t k = 0; k < flag_count(t); ++k) {
        const theory_flag *f = &t->flags[k];
        char range[96];
        flag_range(f, range, sizeof range);
        printf("  %-13s %s; allowed: %s%s\n", f->name, f->doc, range,
               f->required ? " (required)" : "");
    }
    if (t->writes_file)
        printf("  %-13s output file, written atomically, or - for standard output (required)\n",
               "--out");
}

/* One flag's value into v; 0, or EXIT_INPUT after a message. */
static int flag_number(const char *cmd, const theory_flag *f, const char *text, double *v) {
    char *end;
    const double x = strtod(text, &end);
    const int low_ok = f->open_min ? x > f->min : x >= f->min;
    const int high_ok = f->open_max ? x < f->max : x <= f->max;
    if (end != text && !*end && isfinite(x) && low_ok && high_ok) return *v = x, 0;
    char range[96];
    flag_range(f, range, sizeof range);
    fprintf(stderr, "hsbd %s: %s = '%.60s'; allowed: %s\n", cmd, f->name, text, range);
    return EXIT_INPUT;
}

/* "--name value" pairs into v (and --out into *out); 0, -1 for --help, or an exit status. */
static int parse_flags(const char *cmd, const theory *t, int argc, char **argv, double *v,
                       const char **out) {
    const size_t n = flag_count(t);
    int seen[THEORY_MAX_FLAGS] = {0};
    for (int i = 3; i < argc; ++i) {
        if (cli_is_help(argv[i])) return -1;
        if (t->writes_file && !strcmp(argv[i], "--out")) {
            if (!(*out = cli_flag_value(cmd, argc, argv, &i, stderr))) return EXIT_INPUT;
            continue;
        }
        size_t k = 0;
        while (k < n && strcmp(argv[i], t->flags[k].name))
            ++k;
        if (k == n) {
            fprintf(stderr, "hsbd %s: unknown option '%.60s' (hsbd %s --help)\n", cmd, argv[i],
                    cmd);
            return EXIT_INPUT;
        }
        const char *text = cli_flag_value(cmd, argc, argv, &i, stderr);
        if (!text || flag_number(cmd, &t->flags[k], text, &v[k])) return EXIT_INPUT;
        seen[k] = 1;
    }
    for (size_t k = 0; k < n; ++k)
        if (t->flags[k].required && !seen[k]) {
            fprintf(stderr, "hsbd %s: %s is required (hsbd %s --help)\n", cmd, t->flags[k].name,
                    cmd);
            return EXIT_INPUT;
        }
    if (!t->writes_file || *out) return 0;
    fprintf(stderr, "hsbd %s: --out FILE (or - for standard output) is required\n", cmd);
    return EXIT_INPUT;
}

/* ---- the output ------------------------------------------------------------------------- */

/* --out FILE (written atomically) or - (standard output), opened before the work so that
 * an unusable location is a bad input (exit 2) found at once */
static int open_output(const char *cmd, const char *out, hsbd_outfile *o, FILE **f) {
    *f = stdout;
    if (!strcmp(out, "-")) return 0;
    struct stat st;
    const size_t len = strlen(out);
    const char *why = NULL;
    if (len == 0 || out[len - 1] == '/' || (stat(out, &st) == 0 && S_ISDIR(st.st_mode)))
        why = "it names a directory; allowed: a file name";
    else if (len >= HSBD_PATH_MAX)
        why = "the path is too long";
    char dir[HSBD_PATH_MAX], name[HSBD_PATH_MAX];
    const char *slash = strrchr(out, '/');
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - out) : 1, slash ? out : ".");
    snprintf(name, sizeof name, "%s", slash ? slash + 1 : out);
    hsbd_error err;
    if (!why && hsbd_outfile_open(o, slash == out ? "" : dir, name, &err) != HSBD_OK)
        why = strerror(errno);
    if (why) {
        fprintf(stderr, "hsbd %s: --out '%.200s': cannot write there: %s\n", cmd, out, why);
        return EXIT_INPUT;
    }
    *f = o->f;
    return 0;
}

/* The output committed (a write error is exit 1), or discarded when rc != 0. */
static int close_output(hsbd_outfile *o, FILE *f, int rc) {
    hsbd_error err;
    if (f == stdout) return rc;
    if (rc != 0) return hsbd_outfile_discard(o), rc;
    return hsbd_outfile_commit(o, &err) == HSBD_OK ? 0 : cli_fail(err.status, err.message);
}

static int run_theory(const theory *t, int argc, char **argv) {
    char cmd[64];
    snprintf(cmd, sizeof cmd, "theory %s", t->name);
    double v[THEORY_MAX_FLAGS];
    for (size_t k = 0; k < THEORY_MAX_FLAGS; ++k)
        v[k] = t->flags[k].value;
    const char *out = NULL;
    int rc = parse_flags(cmd, t, argc, argv, v, &out);
    if (rc < 0) return theory_help(t), 0;
    if (rc || (rc = t->check(v)) != 0) return rc;
    if (!t->writes_file) return t->write(v, stdout);
    hsbd_outfile o = {0};
    FILE *f;
    if (open_output(cmd, out, &o, &f)) return EXIT_INPUT;
    return close_output(&o, f, t->write(v, f));
}

int cmd_theory(int argc, char **argv) {
    for (size_t k = 0; argc >= 3 && k < NTHEORIES; ++k)
        if (!strcmp(argv[2], theories[k].name)) return run_theory(&theories[k], argc, argv);
    if (argc >= 3 && cli_is_help(argv[2])) {
        printf("usage: %s", theories[0].synopsis);
        for (size_t k = 1; k < NTHEORIES; ++k)
            printf("       %s", theories[k].synopsis);
        return 0;
    }
    if (argc >= 3)
        fprintf(stderr,
                "hsbd theory: unknown theory '%.60s'; allowed: percus, tonks, box, washboard "
                "(hsbd theory --help)\n",
                argv[2]);
    else
        fprintf(stderr, "hsbd theory: which theory? allowed: percus, tonks, box, "
                        "washboard (hsbd theory --help)\n");
    return EXIT_INPUT;
}
