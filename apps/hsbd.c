/* hsbd: command-line front end. Subcommands: run, bench, config-doc, version. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "hsbd/config.h"
#include "hsbd/io.h"
#include "hsbd/spheres.h"
#include "hsbd/rods.h"
#include "hsbd/run.h"
#include "hsbd/theory.h"
#include "hsbd/validate.h"
#include "hsbd_version.h"

enum { EXIT_INPUT = 2, EXIT_INTERRUPTED = 130 };

static volatile sig_atomic_t stop_flag = 0;

/* SIGINT, SIGTERM, SIGHUP: the run writes a checkpoint and its results so far, then
 * exits with 128 + the signal's number; a second signal ends it at once. */
static void on_signal(int sig) {
    if (stop_flag) {
        signal(sig, SIG_DFL);
        raise(sig);
    }
    stop_flag = sig;
}

static void catch_stop_signals(void) {
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGHUP, on_signal);
}

static int exit_code_for(int status) {
    switch (status) {
    case HSBD_OK:
        return 0;
    case HSBD_EINPUT:
        return EXIT_INPUT;
    case HSBD_EINTERRUPT:
        return stop_flag ? 128 + (int)stop_flag : EXIT_INTERRUPTED;
    default:
        return 1;
    }
}

/* The whole file (for the run's checkpoints); NULL when it cannot be read. */
static char *read_whole_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += got;
        if (n == cap) {
            char *b = realloc(buf, 2 * cap);
            if (!b) free(buf);
            buf = b, cap *= 2;
        }
    }
    fclose(f);
    if (buf) *len = n;
    return buf;
}

static int fail(int status, const char *msg) {
    fprintf(stderr, "hsbd: %s\n", msg);
    return exit_code_for(status);
}

static void usage(FILE *out) {
    fprintf(out,
            "usage: hsbd run CONFIG.ini [options]   simulate (see 'hsbd run --help')\n"
            "       hsbd resume DIR [--set run.t_total=T] [--quiet]\n"
            "                                       continue a stopped run from its checkpoint\n"
            "       hsbd bench [--seconds S] [--case NAME]\n"
            "                                       throughput, with the free-particle bound\n"
            "       hsbd theory percus --sigma S --rho R --amplitude U0 [--gamma G]\n"
            "                      [--wavelength W] [--points M] --out FILE|-\n"
            "                                       exact equilibrium profile (x rho rho2)\n"
            "       hsbd theory tonks --sigma S --rho R [--gamma G] [--D D]\n"
            "                                       closed forms of the homogeneous fluid\n"
            "       hsbd theory box --N N --L L --sigma S [--force F] [--stiffness K]\n"
            "                      [--center C] [--amplitude U0] [--wavelength W] [--bin W]\n"
            "                      [--points M] --out FILE|-\n"
            "                                       exact profile between hard walls\n"
            "       hsbd validate [--quick] [--dt-scan] [--sticky] [--out DIR] [--case TEXT]\n"
            "                     [--jobs N] [--seed-offset K]\n"
            "                                       simulations against exact theory\n"
            "       hsbd config-doc                 print the configuration reference (Markdown)\n"
            "       hsbd version\n");
}

static void run_help(void) {
    printf("usage: hsbd run CONFIG.ini [--set section.key=value]... [--out DIR] [--seed S]\n"
           "                [--force] [--check] [--quiet]\n\n"
           "  --set k=v   override any key (repeatable)\n"
           "  --out DIR   run directory (same as --set output.dir=DIR)\n"
           "  --seed S    random seed (same as --set system.seed=S)\n"
           "  --force     write into an existing, non-empty run directory\n"
           "  --check     verify the hard core after every step (slower)\n"
           "  --quiet     no progress line\n\n"
           "Writes density.tsv, contact.tsv, msd.tsv, clusters.tsv, summary.json (and\n"
           "trajectory.xyz, current.tsv when asked) atomically. Exit status: 0 done, 2 bad\n"
           "input, 130 interrupted (results so far written), 1 other errors.\n\n"
           "Configuration keys:\n");
    hsbd_config_write_reference(stdout, 0);
}

/* runs/<config file name without directory and extension> */
static void default_out_dir(const char *config_path, char *out, size_t len) {
    const char *base = strrchr(config_path, '/');
    base = base ? base + 1 : config_path;
    const char *dot = strrchr(base, '.');
    const int n = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
    snprintf(out, len, "runs/%.*s", n, base);
}

static int cmd_run(int argc, char **argv) {
    const char *config_path = NULL;
    hsbd_run_options opt = {.progress = isatty(STDERR_FILENO), .stop = &stop_flag};
    hsbd_config cfg;
    hsbd_error err;
    hsbd_config_defaults(&cfg);
    /* first pass: flags that need no configuration, and the file itself */
    for (int i = 2; i < argc; ++i) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            run_help();
            return 0;
        }
        if (argv[i][0] != '-') {
            if (config_path) {
                fprintf(stderr, "hsbd run: more than one configuration file ('%s', '%s')\n",
                        config_path, argv[i]);
                return EXIT_INPUT;
            }
            config_path = argv[i];
        } else if (!strcmp(argv[i], "--set") || !strcmp(argv[i], "--out") ||
                   !strcmp(argv[i], "--seed")) {
            ++i; /* value handled below */
        }
    }
    if (!config_path) {
        fprintf(stderr, "hsbd run: no configuration file given (hsbd run --help)\n");
        return EXIT_INPUT;
    }
    if (hsbd_config_load_file(&cfg, config_path, &err) != HSBD_OK)
        return fail(err.status, err.message);
    if (!cfg.output.dir[0]) default_out_dir(config_path, cfg.output.dir, sizeof cfg.output.dir);
    /* the source of the configuration goes into the checkpoints (hsbd resume) */
    hsbd_run_source source = {.name = config_path};
    source.text = read_whole_file(config_path, &source.text_len);
    char(*sets)[HSBD_PATH_MAX + 64] = calloc((size_t)argc, sizeof *sets);
    const char **set_list = calloc((size_t)argc, sizeof *set_list);
    if (!source.text || !sets || !set_list) {
        free((char *)source.text), free(sets), free(set_list);
        fprintf(stderr, "hsbd run: cannot read '%s' again\n", config_path);
        return EXIT_INPUT;
    }
    source.sets = set_list;
    opt.source = &source;
    /* second pass: overrides in command-line order */
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        char buf[HSBD_PATH_MAX + 64];
        if (a[0] != '-') continue;
        const int takes_value = !strcmp(a, "--set") || !strcmp(a, "--out") || !strcmp(a, "--seed");
        if (takes_value && i + 1 >= argc) {
            fprintf(stderr, "hsbd run: %s needs a value\n", a);
            return EXIT_INPUT;
        }
        if (!strcmp(a, "--set"))
            snprintf(buf, sizeof buf, "%s", argv[++i]);
        else if (!strcmp(a, "--out"))
            snprintf(buf, sizeof buf, "output.dir=%s", argv[++i]);
        else if (!strcmp(a, "--seed"))
            snprintf(buf, sizeof buf, "system.seed=%s", argv[++i]);
        else if (!strcmp(a, "--force")) {
            opt.force = 1;
            continue;
        } else if (!strcmp(a, "--check")) {
            opt.check = 1;
            continue;
        } else if (!strcmp(a, "--quiet")) {
            opt.progress = 0;
            continue;
        } else {
            fprintf(stderr, "hsbd run: unknown option '%s' (hsbd run --help)\n", a);
            return EXIT_INPUT;
        }
        char origin[64];
        snprintf(origin, sizeof origin, "command line (%s)", a);
        snprintf(sets[source.nsets], sizeof sets[0], "%s", buf);
        set_list[source.nsets] = sets[source.nsets];
        source.nsets += 1;
        if (hsbd_config_set(&cfg, buf, origin, &err) != HSBD_OK) {
            free((char *)source.text), free(sets), free(set_list);
            return fail(err.status, err.message);
        }
    }
    int rc = hsbd_config_finalize(&cfg, &err);
    if (rc == HSBD_OK) {
        catch_stop_signals();
        rc = hsbd_run(&cfg, &opt, &err);
    }
    free((char *)source.text), free(sets), free(set_list);
    if (rc != HSBD_OK) return fail(rc, err.message);
    if (opt.progress) fprintf(stderr, "hsbd: results in %s/\n", cfg.output.dir);
    return 0;
}

static void resume_help(void) {
    printf("usage: hsbd resume DIR [--set run.t_total=T] [--quiet]\n\n"
           "Continues the run in DIR from its newest checkpoint (checkpoint.hsbd, or\n"
           "checkpoint.prev.hsbd when the newest is damaged). The configuration is the run's\n"
           "own, read again from the checkpoint; stream files (trajectory.xyz, current.tsv) are\n"
           "cut back to the checkpoint. The results equal those of a run never stopped.\n\n"
           "  --set run.t_total=T  a longer production time: extends the run (also a\n"
           "                       completed one)\n"
           "  --quiet              no progress line\n\n"
           "Exit status: 0 done, 2 bad input (no or a damaged checkpoint, a completed run\n"
           "without a longer run.t_total), 129/130/143 stopped by SIGHUP/SIGINT/SIGTERM (a\n"
           "checkpoint and the results so far written), 1 other errors.\n");
}

static int cmd_resume(int argc, char **argv) {
    const char *dir = NULL;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    size_t nsets = 0;
    hsbd_run_options opt = {.progress = isatty(STDERR_FILENO), .stop = &stop_flag};
    int rc = sets ? 0 : 1;
    for (int i = 2; i < argc && rc == 0; ++i) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            resume_help();
            free(sets);
            return 0;
        } else if (!strcmp(argv[i], "--quiet")) {
            opt.progress = 0;
        } else if (!strcmp(argv[i], "--set")) {
            if (i + 1 >= argc || argv[i + 1][0] == '-') {
                fprintf(stderr, "hsbd resume: --set needs a value (--set run.t_total=T)\n");
                rc = EXIT_INPUT;
            } else {
                sets[nsets++] = argv[++i];
            }
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "hsbd resume: unknown option '%s' (hsbd resume --help)\n", argv[i]);
            rc = EXIT_INPUT;
        } else if (dir) {
            fprintf(stderr, "hsbd resume: more than one run directory ('%s', '%s')\n", dir,
                    argv[i]);
            rc = EXIT_INPUT;
        } else {
            dir = argv[i];
        }
    }
    if (rc == 0 && !dir) {
        fprintf(stderr, "hsbd resume: no run directory given (hsbd resume --help)\n");
        rc = EXIT_INPUT;
    }
    if (rc == 0) {
        hsbd_error err;
        catch_stop_signals();
        const int status = hsbd_resume(dir, sets, nsets, &opt, &err);
        rc = status == HSBD_OK ? 0 : fail(status, err.message);
        if (status == HSBD_OK && opt.progress) fprintf(stderr, "hsbd: results in %s/\n", dir);
    }
    free(sets);
    return rc;
}

/* ---- bench ------------------------------------------------------------------------- */

typedef struct bench_case {
    const char *name;
    double sigma, rho;
    size_t n; /* 0: L = 100 */
} bench_case;

static const bench_case bench_cases[] = {
    {"s0.5-rho0.2", 0.5, 0.2, 0},
    {"s0.5-rho0.5", 0.5, 0.5, 0},
    {"s0.5-rho0.8", 0.5, 0.8, 0},
    {"s0.1-rho0.8", 0.1, 0.8, 0},
    {"s0.5-rho0.5-N1e4", 0.5, 0.5, 10000},
    {"s0.5-rho0.5-N1e6", 0.5, 0.5, 1000000},
    {"dense-s0.9-rho1.0-N1e4", 0.9, 1.0, 10000},
};

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* particle-steps per second of the bare integrator over at least `seconds`, with the
 * given contact rule (hard_core = 0: free particles, the rule is not used) */
static double bench_rate(const bench_case *c, int hard_core, int contact_rule, double seconds) {
    const size_t n = c->n ? c->n : (size_t)llround(c->rho * 100.0);
    const double L = c->n ? (double)c->n / c->rho : 100.0;
    hsbd_rods_params p = {.n = n,
                          .length = L,
                          .sigma = c->sigma,
                          .diffusion = 1,
                          .kT = 1,
                          .dt = 1e-4,
                          .seed = 1,
                          .hard_core = hard_core,
                          .contact_rule = contact_rule};
    hsbd_field_add(&p.field, hsbd_field_cosine(6.0, 1.0));
    hsbd_error err;
    hsbd_rods *r = hsbd_rods_alloc(&p, &err);
    if (!r) return NAN;
    hsbd_rods_init_equilibrium(r);
    uint64_t batch = 1 + (uint64_t)(2e6 / (double)n), steps = 0;
    for (uint64_t k = 0; k < batch; ++k)
        if (hsbd_rods_step(r, NULL) != HSBD_OK) return hsbd_rods_free(r), NAN; /* warm-up */
    const double t0 = now_seconds();
    double t = t0;
    while (t - t0 < seconds) {
        for (uint64_t k = 0; k < batch; ++k)
            if (hsbd_rods_step(r, NULL) != HSBD_OK) return hsbd_rods_free(r), NAN;
        steps += batch;
        t = now_seconds();
    }
    hsbd_rods_free(r);
    return (double)n * (double)steps / (t - t0);
}

/* EDBD of monodisperse spheres: 3D, D = sigma = 1, from an fcc lattice. */
typedef struct sphere_bench_case {
    const char *name;
    size_t n;
    double phi, dt;
} sphere_bench_case;

static const sphere_bench_case sphere_bench_cases[] = {
    {"spheres-N4000-phi0.3-dt1e-3", 4000, 0.3, 1e-3},
    {"spheres-N4000-phi0.3-dt1e-4", 4000, 0.3, 1e-4},
    {"spheres-N4000-phi0.5-dt1e-3", 4000, 0.5, 1e-3},
    {"spheres-N4000-phi0.5-dt1e-4", 4000, 0.5, 1e-4},
    {"spheres-N1e5-phi0.3-dt1e-3", 100000, 0.3, 1e-3},
    {"spheres-N1e5-phi0.5-dt1e-4", 100000, 0.5, 1e-4},
    {"spheres-N1e6-phi0.3-dt1e-3", 1000000, 0.3, 1e-3}, /* scaling in N; events by group */
};

/* steps per second; *coll: collisions per step */
static double sphere_bench_rate(const sphere_bench_case *c, int hard_core, double seconds,
                                double *coll) {
    const double side = cbrt((double)c->n * 3.14159265358979323846 / 6 / c->phi);
    const hsbd_spheres_params p = {.n = c->n,
                                   .dimension = 3,
                                   .box = {side, side, side},
                                   .sigma = 1,
                                   .diffusion = 1,
                                   .kT = 1,
                                   .dt = c->dt,
                                   .seed = 1,
                                   .hard_core = hard_core};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    if (!s || hsbd_spheres_init_lattice(s, &err) != HSBD_OK) {
        hsbd_spheres_free(s);
        return NAN;
    }
    const uint64_t batch = 1 + (uint64_t)(1e6 / (double)c->n);
    /* warm-up: 0.3 Brownian times melt the lattice and let the neighbour rows reach the
     * capacity the fluid needs (a short warm-up measured a lattice-like state at N 1e5) */
    const uint64_t warm = (uint64_t)fmax(5.0 * (double)batch, ceil(0.3 / c->dt));
    for (uint64_t k = 0; k < warm; ++k)
        if (hsbd_spheres_step(s) != HSBD_OK) return hsbd_spheres_free(s), NAN;
    hsbd_spheres_reset_stats(s);
    uint64_t steps = 0;
    const double t0 = now_seconds();
    double t = t0;
    while (t - t0 < seconds) {
        for (uint64_t k = 0; k < batch; ++k)
            if (hsbd_spheres_step(s) != HSBD_OK) return hsbd_spheres_free(s), NAN;
        steps += batch;
        t = now_seconds();
    }
    *coll = (double)hsbd_spheres_get_stats(s).collisions / (double)steps;
    hsbd_spheres_free(s);
    return (double)steps / (t - t0);
}

static void sphere_bench(const char *only, double seconds, int *found) {
    int header = 0;
    for (size_t k = 0; k < sizeof sphere_bench_cases / sizeof sphere_bench_cases[0]; ++k) {
        const sphere_bench_case *c = &sphere_bench_cases[k];
        if (only && strcmp(only, c->name)) continue;
        if (!header++)
            printf("# EDBD, 3D monodisperse spheres, D = sigma = 1, from an fcc lattice after 0.3 "
                   "Brownian times of warm-up;\n# BT/s = Brownian times (sigma^2/D) simulated "
                   "per second; free = hard core off\n"
                   "%-30s %7s %9s %9s %10s %9s %9s %7s\n",
                   "case", "N", "BT/s", "ns/p-step", "ns/coll", "coll/p-st", "free BT/s", "ratio");
        *found = 1;
        double coll = 0, coll_free = 0;
        const double hard = sphere_bench_rate(c, 1, seconds, &coll);
        const double free_ = sphere_bench_rate(c, 0, seconds, &coll_free);
        const double n = (double)c->n;
        printf("%-30s %7zu %9.3f %9.1f %10.1f %9.4f %9.3f %7.2f\n", c->name, c->n, hard * c->dt,
               1e9 / (hard * n), coll > 0 ? 1e9 / (hard * coll) : NAN, coll / n, free_ * c->dt,
               free_ / hard);
        fflush(stdout);
    }
}

static int cmd_bench(int argc, char **argv) {
    double seconds = 2.0;
    const char *only = NULL;
    for (int i = 2; i < argc; ++i) {
        if (!strcmp(argv[i], "--seconds") && i + 1 < argc) {
            char *end;
            seconds = strtod(argv[++i], &end);
            if (*end || !(seconds > 0 && seconds < 3600)) {
                fprintf(stderr, "hsbd bench: --seconds = '%s'; allowed: 0 < S < 3600\n", argv[i]);
                return EXIT_INPUT;
            }
        } else if (!strcmp(argv[i], "--case") && i + 1 < argc) {
            only = argv[++i];
        } else {
            fprintf(stderr, "hsbd bench: unknown option '%s'\n", argv[i]);
            return EXIT_INPUT;
        }
    }
    printf("# hsbd %s (git %s) bench: BCD step, cosine field U0=6 lambda=1, D=1, dt=1e-4,\n"
           "# one core; M = 10^6 particle-steps per second; reflect = the default contact rule,\n"
           "# sticky = the paper's rule; free = same system, hard core off; cost = free/hard\n",
           HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    printf("%-26s %9s %12s %12s %12s %8s %8s\n", "case", "N", "reflect M/s", "sticky M/s",
           "free M/s", "cost", "cost st.");
    int found = 0;
    for (size_t k = 0; k < sizeof bench_cases / sizeof bench_cases[0]; ++k) {
        const bench_case *c = &bench_cases[k];
        if (only && strcmp(only, c->name)) continue;
        found = 1;
        const double reflect = bench_rate(c, 1, HSBD_CONTACT_REFLECT, seconds);
        const double sticky = bench_rate(c, 1, HSBD_CONTACT_STICKY, seconds);
        const double free_ = bench_rate(c, 0, HSBD_CONTACT_REFLECT, seconds);
        const size_t n = c->n ? c->n : (size_t)llround(c->rho * 100.0);
        printf("%-26s %9zu %12.1f %12.1f %12.1f %8.2f %8.2f\n", c->name, n, reflect / 1e6,
               sticky / 1e6, free_ / 1e6, free_ / reflect, free_ / sticky);
        fflush(stdout);
    }
    sphere_bench(only, seconds, &found);
    if (!found) {
        fprintf(stderr, "hsbd bench: no case named '%s'\n", only);
        return EXIT_INPUT;
    }
    return 0;
}

/* ---- theory ------------------------------------------------------------------------ */

typedef struct num_flag {
    const char *name;
    double *value;
    double min, max;
    int open_min, open_max;
    int required, seen;
} num_flag;

/* Parse "--name value" pairs into the table; 0 or an exit status. */
static int parse_num_flags(const char *cmd, int argc, char **argv, int first, num_flag *flags,
                           size_t nflags, const char **out_path) {
    for (int i = first; i < argc; ++i) {
        if (out_path && !strcmp(argv[i], "--out") && i + 1 < argc) {
            *out_path = argv[++i];
            continue;
        }
        num_flag *f = NULL;
        for (size_t k = 0; k < nflags; ++k)
            if (!strcmp(argv[i], flags[k].name)) f = &flags[k];
        if (!f || i + 1 >= argc) {
            fprintf(stderr, "hsbd %s: %s '%s'\n", cmd, f ? "missing value for" : "unknown option",
                    argv[i]);
            return EXIT_INPUT;
        }
        char *end;
        const char *text = argv[++i];
        const double v = strtod(text, &end);
        const int low_ok = f->open_min ? v > f->min : v >= f->min;
        const int high_ok = f->open_max ? v < f->max : v <= f->max;
        if (end == text || *end || !isfinite(v) || !low_ok || !high_ok) {
            fprintf(stderr, "hsbd %s: %s = '%s'; allowed: %g %s %s %s %g\n", cmd, f->name, text,
                    f->min, f->open_min ? "<" : "<=", f->name + 2,
                    f->open_max ? "<" : "<=", f->max);
            return EXIT_INPUT;
        }
        *f->value = v;
        f->seen = 1;
    }
    for (size_t k = 0; k < nflags; ++k)
        if (flags[k].required && !flags[k].seen) {
            fprintf(stderr, "hsbd %s: %s is required\n", cmd, flags[k].name);
            return EXIT_INPUT;
        }
    return 0;
}

/* --out FILE (written atomically) or - (standard output) */
static int open_theory_output(const char *out, hsbd_outfile *o, FILE **f, hsbd_error *err) {
    if (!strcmp(out, "-")) return HSBD_OK;
    char dir[HSBD_PATH_MAX], name[HSBD_PATH_MAX];
    const char *slash = strrchr(out, '/');
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - out) : 1, slash ? out : ".");
    snprintf(name, sizeof name, "%s", slash ? slash + 1 : out);
    if (hsbd_outfile_open(o, dir, name, err) != HSBD_OK) return err->status;
    *f = o->f;
    return HSBD_OK;
}

/* N rods between hard walls at 0 and L in cosine + tilt + harmonic fields: the exact
 * canonical profile (src/theory/box.c), bin averages. */
static int cmd_theory_box(int argc, char **argv) {
    double n = 0, length = 0, sigma = 0, u0 = 0, wavelength = 1, force = 0, stiffness = 0,
           center = NAN, bin = 0.01, points = 0;
    const char *out = NULL;
    num_flag flags[] = {
        {"--N", &n, 1, 1e7, 0, 0, 1, 0},
        {"--L", &length, 0, 1e300, 1, 1, 1, 0},
        {"--sigma", &sigma, 0, 1e300, 0, 1, 1, 0},
        {"--amplitude", &u0, -1e6, 1e6, 0, 0, 0, 0},
        {"--wavelength", &wavelength, 0, 1e300, 1, 1, 0, 0},
        {"--force", &force, -1e6, 1e6, 0, 0, 0, 0},
        {"--stiffness", &stiffness, 0, 1e6, 0, 0, 0, 0},
        {"--center", &center, -1e300, 1e300, 0, 0, 0, 0},
        {"--bin", &bin, 0, 1e300, 1, 1, 0, 0},
        {"--points", &points, 16, 1e8, 0, 0, 0, 0},
    };
    const int rc =
        parse_num_flags("theory box", argc, argv, 3, flags, sizeof flags / sizeof flags[0], &out);
    if (rc) return rc;
    if (!out || n != floor(n) || points != floor(points) || !(n * sigma < length)) {
        fprintf(stderr, "hsbd theory box: need --out FILE|-, whole --N and --points, and "
                        "N sigma < L\n");
        return EXIT_INPUT;
    }
    hsbd_field field = {0};
    if (u0 != 0) hsbd_field_add(&field, hsbd_field_cosine(u0, wavelength));
    if (force != 0) hsbd_field_add(&field, hsbd_field_tilt(force));
    if (stiffness > 0)
        hsbd_field_add(&field,
                       hsbd_field_harmonic(stiffness, isnan(center) ? 0.5 * length : center, 0.0));
    if (points == 0) points = fmin(1e5, fmax(2000, 2e7 / n)); /* memory N x points doubles */
    hsbd_box_params p = {.n = (size_t)n,
                         .length = length,
                         .sigma = sigma,
                         .field = &field,
                         .points = (size_t)points};
    hsbd_box_result r;
    hsbd_error err;
    const int st = hsbd_box_solve(&p, bin, &r, &err);
    if (st != HSBD_OK) return fail(st, err.message);
    FILE *f = stdout;
    hsbd_outfile o = {0};
    if (open_theory_output(out, &o, &f, &err) != HSBD_OK) {
        hsbd_box_result_free(&r);
        return fail(err.status, err.message);
    }
    fprintf(f,
            "# hsbd %s (git %s): N hard rods between hard walls, exact canonical profile "
            "(docs/theory.md), bin averages\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    fprintf(f,
            "# N = %zu\n# L = %.17g\n# sigma = %.17g\n# amplitude = %.17g\n# wavelength = %.17g\n"
            "# force = %.17g\n# stiffness = %.17g\n# center = %.17g\n# points = %zu\n"
            "# wall_left = %.12g\n# wall_right = %.12g\n",
            p.n, length, sigma, u0, wavelength, force, stiffness,
            isnan(center) ? 0.5 * length : center, p.points, r.wall_left, r.wall_right);
    fprintf(f, "x\trho\trho2\n");
    for (size_t k = 0; k < r.nbins; ++k)
        fprintf(f, "%.10g\t%.12g\t%.12g\n", (k + 0.5) * bin, r.rho[k], r.rho2[k]);
    hsbd_box_result_free(&r);
    if (f != stdout && hsbd_outfile_commit(&o, &err) != HSBD_OK)
        return fail(err.status, err.message);
    return 0;
}

static int cmd_theory_percus(int argc, char **argv) {
    double sigma = 0, rho = 0, u0 = 0, gamma = 0, wavelength = 1, points = 2000;
    const char *out = NULL;
    num_flag flags[] = {
        {"--sigma", &sigma, 0, 1e300, 0, 1, 1, 0},
        {"--rho", &rho, 0, 1e300, 1, 1, 1, 0},
        {"--amplitude", &u0, 0, 1e6, 0, 0, 1, 0},
        {"--gamma", &gamma, 0, 1e12, 0, 0, 0, 0},
        {"--wavelength", &wavelength, 0, 1e300, 1, 1, 0, 0},
        {"--points", &points, 16, 1e8, 0, 0, 0, 0},
    };
    const int rc = parse_num_flags("theory percus", argc, argv, 3, flags,
                                   sizeof flags / sizeof flags[0], &out);
    if (rc) return rc;
    if (!out) {
        fprintf(stderr, "hsbd theory percus: --out FILE (or - for standard output) is required\n");
        return EXIT_INPUT;
    }
    if (!(rho * sigma < 1)) {
        fprintf(stderr,
                "hsbd theory percus: --rho %g with --sigma %g: need rho*sigma < 1 (no "
                "room); allowed: rho < %g\n",
                rho, sigma, 1 / sigma);
        return EXIT_INPUT;
    }
    if (points != floor(points)) {
        fprintf(stderr, "hsbd theory percus: --points must be a whole number\n");
        return EXIT_INPUT;
    }
    hsbd_percus_params p = {.sigma = sigma,
                            .rho_mean = rho,
                            .amplitude = u0,
                            .wavelength = wavelength,
                            .gamma = gamma,
                            .points = (size_t)points};
    hsbd_percus_result r;
    hsbd_error err;
    const int st = hsbd_percus_solve(&p, &r, &err);
    if (st != HSBD_OK) return fail(st, err.message);
    FILE *f = stdout;
    hsbd_outfile o = {0};
    if (open_theory_output(out, &o, &f, &err) != HSBD_OK) {
        hsbd_percus_result_free(&r);
        return fail(err.status, err.message);
    }
    fprintf(f, "# hsbd %s (git %s): Percus exact equilibrium profile%s\n", HSBD_VERSION_STRING,
            HSBD_GIT_COMMIT, gamma > 0 ? " (sticky, Antonov Eqs. 34)" : " (Antonov Eqs. 20-23)");
    fprintf(f,
            "# sigma = %.17g\n# rho_mean = %.17g\n# amplitude = %.17g\n# wavelength = %.17g\n"
            "# gamma = %.17g\n# points = %zu\n# beta_mu = %.15g\n# iterations = %d\n"
            "# residual = %.3g\n",
            sigma, rho, u0, wavelength, gamma, p.points, r.beta_mu, r.iterations, r.residual);
    if (gamma > 0) fprintf(f, "# rho2 is not available for gamma > 0 (nan)\n");
    fprintf(f, "x\trho\trho2\n");
    for (size_t j = 0; j < r.m; ++j)
        fprintf(f, "%.10g\t%.12g\t%.12g\n", r.x[j], r.rho[j], r.rho2[j]);
    hsbd_percus_result_free(&r);
    if (f != stdout && hsbd_outfile_commit(&o, &err) != HSBD_OK)
        return fail(err.status, err.message);
    return 0;
}

static int cmd_theory_tonks(int argc, char **argv) {
    double sigma = 0, rho = 0, gamma = 0, d = 1;
    num_flag flags[] = {
        {"--sigma", &sigma, 0, 1e300, 0, 1, 1, 0},
        {"--rho", &rho, 0, 1e300, 1, 1, 1, 0},
        {"--gamma", &gamma, 0, 1e12, 0, 0, 0, 0},
        {"--D", &d, 0, 1e300, 1, 1, 0, 0},
    };
    const int rc =
        parse_num_flags("theory tonks", argc, argv, 3, flags, sizeof flags / sizeof flags[0], NULL);
    if (rc) return rc;
    if (!(rho * sigma < 1)) {
        fprintf(stderr, "hsbd theory tonks: need rho*sigma < 1; allowed: rho < %g\n", 1 / sigma);
        return EXIT_INPUT;
    }
    const double pi = 3.141592653589793;
    printf("# homogeneous hard rods, sigma = %g, rho = %g (packing %g), kT = 1\n", sigma, rho,
           rho * sigma);
    printf("beta_P = %.15g\n", hsbd_tonks_pressure(rho, sigma));
    printf("beta_mu = %.15g\n", hsbd_tonks_beta_mu(rho, sigma));
    printf("contact_density = %.15g\n", hsbd_tonks_contact(rho, sigma));
    printf("g_contact = %.15g\n", 1.0 / (1.0 - rho * sigma));
    printf("single_file_msd_prefactor = %.15g   # MSD -> prefactor * sqrt(t), D = %g\n",
           (1 - rho * sigma) / rho * sqrt(4 * d / pi), d);
    if (gamma > 0) {
        printf("sticky_gamma = %g\n", gamma);
        printf("sticky_beta_P = %.15g\n", hsbd_sticky_pressure(rho, sigma, gamma));
        printf("sticky_beta_mu = %.15g\n", hsbd_sticky_beta_mu(rho, sigma, gamma));
    }
    return 0;
}

static int cmd_validate(int argc, char **argv) {
    hsbd_validate_options opt = {.out_dir = "runs/validate", .jobs = 2};
    for (int i = 2; i < argc; ++i) {
        if (!strcmp(argv[i], "--quick"))
            opt.quick = 1;
        else if (!strcmp(argv[i], "--dt-scan"))
            opt.dt_scan = 1;
        else if (!strcmp(argv[i], "--sticky"))
            opt.sticky = 1;
        else if (!strcmp(argv[i], "--out") && i + 1 < argc)
            opt.out_dir = argv[++i];
        else if (!strcmp(argv[i], "--case") && i + 1 < argc)
            opt.only = argv[++i];
        else if (!strcmp(argv[i], "--jobs") && i + 1 < argc) {
            char *end;
            const long j = strtol(argv[++i], &end, 10);
            if (*end || j < 1 || j > 64) {
                fprintf(stderr, "hsbd validate: --jobs = '%s'; allowed: 1 <= jobs <= 64\n",
                        argv[i]);
                return EXIT_INPUT;
            }
            opt.jobs = (int)j;
        } else if (!strcmp(argv[i], "--seed-offset") && i + 1 < argc) {
            char *end;
            const long k = strtol(argv[++i], &end, 10);
            if (*end || k < 0 || k > 1000000) {
                fprintf(stderr,
                        "hsbd validate: --seed-offset = '%s'; allowed: 0 <= offset <= 1000000\n",
                        argv[i]);
                return EXIT_INPUT;
            }
            opt.seed_offset = (unsigned)k;
        } else {
            fprintf(stderr,
                    "hsbd validate: unknown option '%s' (--quick, --dt-scan, --sticky, --out DIR, "
                    "--case TEXT, --jobs N, --seed-offset K)\n",
                    argv[i]);
            return EXIT_INPUT;
        }
    }
    hsbd_error err;
    const int rc = hsbd_validate(&opt, stdout, &err);
    if (rc != HSBD_OK) return fail(rc, err.message);
    printf("all cases pass; table in %s/validation.md\n", opt.out_dir);
    return 0;
}

static int cmd_theory(int argc, char **argv) {
    if (argc >= 3 && !strcmp(argv[2], "percus")) return cmd_theory_percus(argc, argv);
    if (argc >= 3 && !strcmp(argv[2], "tonks")) return cmd_theory_tonks(argc, argv);
    if (argc >= 3 && !strcmp(argv[2], "box")) return cmd_theory_box(argc, argv);
    fprintf(stderr, "hsbd theory: expected 'percus', 'tonks' or 'box'\n");
    usage(stderr);
    return EXIT_INPUT;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        usage(stderr);
        return EXIT_INPUT;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "run")) return cmd_run(argc, argv);
    if (!strcmp(cmd, "resume")) return cmd_resume(argc, argv);
    if (!strcmp(cmd, "bench")) return cmd_bench(argc, argv);
    if (!strcmp(cmd, "theory")) return cmd_theory(argc, argv);
    if (!strcmp(cmd, "validate")) return cmd_validate(argc, argv);
    if (!strcmp(cmd, "config-doc")) {
        hsbd_config_write_reference(stdout, 1);
        return 0;
    }
    if (!strcmp(cmd, "version") || !strcmp(cmd, "--version")) {
        printf("hsbd %s (git %s)\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
        return 0;
    }
    if (!strcmp(cmd, "help") || !strcmp(cmd, "--help") || !strcmp(cmd, "-h")) {
        usage(stdout);
        return 0;
    }
    fprintf(stderr, "hsbd: unknown command '%s'\n", cmd);
    usage(stderr);
    return EXIT_INPUT;
}
