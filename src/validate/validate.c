/* Validation: runs the simulator and the exact theory side by side.
 *
 * Families: "percus" (paper Figs. 3-4: hard rods in U = (U0/2) cos(2 pi x), U0 = 6,
 * sigma x rho grid, run on a long ring so that the O(1/N) canonical correction is
 * negligible), "tonks" (U0 = 0 ring, exact canonical results), "single-file" (tagged
 * MSD against its exact law at all times), "spheres" (EDBD disks / spheres: equations of
 * state, contact values, long-time diffusion at low density), and with dt_scan the
 * time-step convergence of two Percus cases and of one spheres case. Every comparison is in
 * units of the block-average error bars of the run. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "hsbd/config.h"
#include "hsbd/io.h"
#include "hsbd/run.h"
#include "hsbd/theory.h"
#include "core/progress.h"
#include "core/threads.h"
#include "hsbd/validate.h"
#include "rundir/rundir.h"
#include "validate/report.h"

enum family { FAMILY_PERCUS, FAMILY_STICKY, FAMILY_TONKS, FAMILY_SINGLE_FILE, FAMILY_SPHERES };
/* spheres cases: one size, a binary (1 / 1.4, D ~ 1/sigma), Gaussian polydispersity 0.1,
 * disks; and for D_L per species: equal sizes with D 1 / 0.25 (half and half), and tracers
 * (D 1, 40 %) among immobile obstacles (D 0) */
enum sphere_kind {
    SPHERES_ONE,
    SPHERES_BINARY,
    SPHERES_POLY,
    SPHERES_DISKS,
    SPHERES_UNEQUAL_D,
    SPHERES_OBSTACLES
};
/* the two species of the D_L cases: number fractions and D */
static const double UNEQUAL_D_FRACTION[2] = {0.5, 0.5}, UNEQUAL_D[2] = {1, 0.25};
static const double OBSTACLES_FRACTION[2] = {0.4, 0.6}, OBSTACLES_D[2] = {1, 0};
/* sticky contact representation of the paper's Fig. 6: p = 3, epsilon = 0.05 */
static const double STICKY_ORDER = 3, STICKY_EPSILON = 0.05;
/* contact window of the extrapolated estimator under the reflect rule */
static const double REFLECT_CONTACT_WIDTH = 0.02;
enum { MAX_CASES = 64, MAX_ROWS = 200000 };
static const double PI = 3.14159265358979323846;
/* contact.tsv: x, then value and error of rho2 (default), theorem, window, extrapolated */
enum { CONTACT_COLUMNS = 9, COL_THEOREM = 3, COL_WINDOW = 5, COL_EXTRAP = 7 };

typedef struct vcase {
    char name[64];
    enum family family;
    double sigma, rho, u0, length, dt, t_total, t_equil, bin_width;
    double gamma; /* sticky family */
    int every;
    /* spheres family: N, packing fraction, enum sphere_kind, error blocks (0: 20) */
    long n;
    double phi;
    int kind, blocks;
} vcase;

typedef struct table {
    size_t rows, cols;
    double *v; /* rows x cols */
} table;

/* ---- reading our own TSV tables ------------------------------------------------------ */

static int read_table(const char *path, size_t cols, table *t, hsbd_error *err) {
    FILE *f = fopen(path, "r");
    if (!f)
        return hsbd_error_set(err, HSBD_EIO, "validate: cannot read %s: %s", path, strerror(errno));
    t->cols = cols;
    t->rows = 0;
    t->v = malloc(MAX_ROWS * cols * sizeof *t->v);
    char line[4096];
    while (t->v && fgets(line, sizeof line, f) && t->rows < MAX_ROWS) {
        if (line[0] == '#' || (line[0] >= 'a' && line[0] <= 'z')) continue;
        char *p = line;
        for (size_t c = 0; c < cols; ++c)
            t->v[t->rows * cols + c] = strtod(p, &p);
        ++t->rows;
    }
    fclose(f);
    return t->v ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "validate: out of memory");
}

/* A per-block table (x, block_1 .. block_n; written by hsbd run since the blocks
 * output exists): the number of columns from its header. Missing file: rows = 0. */
static void read_blocks_table(const char *path, table *t) {
    FILE *f = fopen(path, "r");
    t->rows = 0;
    t->v = NULL;
    if (!f) return;
    char line[4096];
    size_t cols = 0;
    while (fgets(line, sizeof line, f))
        if (!strncmp(line, "# x\t", 4)) { /* the column names */
            cols = 1;
            for (const char *c = line; *c; ++c)
                cols += *c == '\t';
            break;
        }
    fclose(f);
    hsbd_error ignored;
    if (cols >= 4 && read_table(path, cols, t, &ignored) != HSBD_OK) t->rows = 0;
}

static double cell(const table *t, size_t r, size_t c) {
    return t->v[r * t->cols + c];
}

/* ---- the cases ----------------------------------------------------------------------- */

/* Spheres (3D, docs/spheres.md): phi 0.3 one size against Kolafa-Labik-Malijevsky, the
 * binary and a polydisperse system against BMCSL (Z as information only: BMCSL inherits
 * the 0.26 % deficit of Carnahan-Starling, several error bars at this length), and D_L at
 * phi 0.02 and 0.05 against 1 - 2 phi (the O(phi^2) term is below the error there). N 4000,
 * dt 1e-3, 20 time units (quick: N 1000, 8 units); D_L at dt 5e-4 (it is 0.6 % low at
 * 1e-3), N 4000, 100 units (quick 40). D_L per species, against the first order in density
 * at the run's lags (hsbd_hs_msd_slope_ratio; the long-time limit as information): equal
 * spheres with D 1 / 0.25 at phi 0.05 (N 4000), and tracers among immobile obstacles, phi
 * 0.01 + 0.015 (N 6000), dt 5e-4, 100 units (quick 40).
 * dt_scan: the phi 0.3 case at dt 4e-3 .. 2.5e-4. */
static size_t make_sphere_cases(const hsbd_validate_options *opt, vcase *cases) {
    const int q = opt->quick;
    const long n = q ? 1000 : 4000;
    const double t = q ? 8 : 20;
    size_t k = 0;
    /* phi 0.3: one size, the binary, polydispersity */
    static const char *const dense[] = {"spheres-3d-phi0.3", "spheres-binary-phi0.3",
                                        "spheres-poly0.1-phi0.3"};
    static const int kinds[] = {SPHERES_ONE, SPHERES_BINARY, SPHERES_POLY};
    for (int d = 0; d < 3; ++d) {
        vcase *c = &cases[k++];
        *c = (vcase){.family = FAMILY_SPHERES,
                     .n = n,
                     .phi = 0.3,
                     .dt = 1e-3,
                     .t_total = t,
                     .t_equil = 2,
                     .kind = kinds[d]};
        snprintf(c->name, sizeof c->name, "%s", dense[d]);
    }
    /* D_L: the largest lag (where the slope is taken) no longer than an error block, or
     * the blocks' MSDs at that lag overlap and their scatter understates the error (a
     * 20-unit run with 1-unit blocks and lag 5 gave 0.978 +- 0.0055 at phi 0.02) */
    const double dilute[] = {0.02, 0.05};
    for (int d = 0; d < 2; ++d) {
        vcase *c = &cases[k++];
        *c = (vcase){.family = FAMILY_SPHERES,
                     .n = 4000,
                     .phi = dilute[d],
                     .dt = 5e-4,
                     .t_total = q ? 40 : 100,
                     .t_equil = 1,
                     .blocks = 10};
        snprintf(c->name, sizeof c->name, "spheres-dilute-phi%g", dilute[d]);
    }
    /* D_L per species against the first order in density at the estimator's lags: D 1 /
     * 0.25 at phi 0.05, and tracers among immobile obstacles (phi 0.01 + 0.015) */
    static const char *const mixed[] = {"spheres-D1-0.25-phi0.05", "spheres-obstacles-phi0.025"};
    static const int mixed_kinds[] = {SPHERES_UNEQUAL_D, SPHERES_OBSTACLES};
    static const double mixed_phi[] = {0.05, 0.025};
    static const long mixed_n[] = {4000, 6000};
    for (int d = 0; d < 2; ++d) {
        vcase *c = &cases[k++];
        *c = (vcase){.family = FAMILY_SPHERES,
                     .n = mixed_n[d],
                     .phi = mixed_phi[d],
                     .dt = 5e-4,
                     .t_total = q ? 40 : 100,
                     .t_equil = 1,
                     .blocks = 10,
                     .kind = mixed_kinds[d]};
        snprintf(c->name, sizeof c->name, "%s", mixed[d]);
    }
    /* 2D disks at phi 0.4 against the virial series to B10 (Henderson is 0.14 % high
     * there); blocks of 10 units outlast the box's slow density modes (seeds of 8-unit
     * runs at N 1000 scattered more than their 0.4-unit blocks said, docs/spheres.md) */
    cases[k] = (vcase){.family = FAMILY_SPHERES,
                       .n = n,
                       .phi = 0.4,
                       .dt = 1e-3,
                       .t_total = q ? 20 : 100,
                       .t_equil = 5,
                       .blocks = 10,
                       .kind = SPHERES_DISKS};
    snprintf(cases[k++].name, sizeof cases[0].name, "disks-2d-phi0.4");
    if (opt->dt_scan) {
        const double dts[] = {4e-3, 2e-3, 5e-4, 2.5e-4};
        for (int d = 0; d < 4; ++d) {
            vcase *c = &cases[k++];
            *c = cases[0]; /* the one-size phi 0.3 case at other steps */
            c->dt = dts[d];
            snprintf(c->name, sizeof c->name, "spheres-dt%.1e-phi0.3", dts[d]);
        }
    }
    return k;
}

static size_t make_cases(const hsbd_validate_options *opt, vcase *cases) {
    size_t n = 0;
    const double sigmas[] = {0.1, 0.5, 0.9}, rhos[] = {0.2, 0.5, 0.8};
    const double q = opt->quick ? 1.0 : 0.0;
    /* Percus grid: 2000 periods (space-blocked errors over 20 segments of 100), dt 2.5e-5
     * (the density's Euler error is below the errors there, docs/validation.md), equilibrated
     * for 200 time units at that step: the wells' occupations relax by barrier hopping and
     * 40-60 units leave a broadening of the wells at 2-4 error bars. The dense case
     * (sigma 0.9, rho 0.8) needs dt 1e-6 (measured scan): 400 periods there. Quick: three
     * cases with >= 200 rods on 400 periods, same steps, sampled 60 units in bins of 0.04
     * (shorter runs have too few contacts per segment for Gaussian error bars). */
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            const int dense = sigmas[a] == 0.9 && rhos[b] == 0.8;
            const int quick_case = (a == 0 && b == 2) || (a == 1 && b == 1) || (a == 2 && b == 1);
            if (q && !quick_case) continue; /* quick: (0.1, 0.8), (0.5, 0.5), (0.9, 0.5) */
            vcase *c = &cases[n++];
            *c = (vcase){.family = FAMILY_PERCUS,
                         .sigma = sigmas[a],
                         .rho = rhos[b],
                         .u0 = 6,
                         .length = q || dense ? 400 : 2000,
                         .dt = dense ? 1e-6 : 2.5e-5,
                         .t_total = dense ? 10
                                    : q   ? 60
                                          : 20,
                         .t_equil = dense ? 60 : 200,
                         .bin_width = q ? 0.04 : 0.02,
                         .every = dense ? 1000 : 40};
            snprintf(c->name, sizeof c->name, "percus-s%.1f-rho%.1f", c->sigma, c->rho);
        }
    /* Sticky rods (paper Fig. 6): gamma 0.1, 1, 10 x rho 0.2, 0.5, 0.8 at sigma = 0.5,
     * U0 = 6, p = 3, eps = 0.05, against the exact theory of this delta_eps model (transfer
     * operator); the distance to Baxter's eps -> 0 limit (Eqs. 34) is reported beside it.
     * dt 1e-5 keeps mu max|f| dt / eps (Eq. 33) at 0.013-0.06; 400 periods, 100 units of
     * equilibration, 10 sampled. Quick: gamma = 1, rho = 0.5. */
    const double gammas[] = {0.1, 1, 10};
    for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
            if (q && !(a == 1 && b == 1)) continue;
            vcase *c = &cases[n++];
            *c = (vcase){.family = FAMILY_STICKY,
                         .sigma = 0.5,
                         .rho = rhos[b],
                         .u0 = 6,
                         .gamma = gammas[a],
                         .length = 400,
                         .dt = 1e-5,
                         .t_total = 10,
                         .t_equil = q ? 60 : 100,
                         .bin_width = q ? 0.04 : 0.02,
                         .every = 100};
            /* strongly sticky and dilute: bound clusters form and break slowly under the
             * reflect rule (rods bounce instead of merging). Sampling 10 units after 100,
             * 400, 1000, 2000 units of equilibration gave density chi^2/dof 6.1, 3.1, 0.41,
             * 3.4: the state drifts slower than 10 units can average; 200 units after 500
             * give 0.26 and 1.5 for two seeds (docs/validation.md section 12) */
            if (a == 2 && b == 0 && !opt->sticky) c->t_equil = 500, c->t_total = 200;
            snprintf(c->name, sizeof c->name, "sticky-g%g-rho%.1f", c->gamma, c->rho);
        }
    /* U0 = 0: exact canonical ring values, 20 replicas each from its own exact sample with
     * 0.5 units for the O(dt) contact structure of the step; dt = 1e-4. Single file: the
     * tagged MSD at all lags against its exact law. */
    cases[n++] = (vcase){.name = "tonks-s0.5-rho0.5",
                         .family = FAMILY_TONKS,
                         .sigma = 0.5,
                         .rho = 0.5,
                         .length = q ? 200 : 2000,
                         .dt = 1e-4,
                         .t_total = q ? 20 : 200,
                         .t_equil = 0.5,
                         .bin_width = 1.0,
                         .every = 1};
    cases[n++] = (vcase){.name = "single-file-s0.5-rho0.5",
                         .family = FAMILY_SINGLE_FILE,
                         .sigma = 0.5,
                         .rho = 0.5,
                         .length = q ? 2000 : 20000,
                         .dt = 1e-4,
                         .t_total = q ? 100 : 400,
                         .t_equil = 10,
                         .bin_width = 1.0,
                         .every = 100};
    if (opt->dt_scan) { /* equilibrated at the production step: slow modes carry its bias */
        const double dts[] = {1e-3, 3e-4, 1e-4, 3e-5};
        const double scan[][2] = {{0.5, 0.5}, {0.9, 0.8}};
        for (int k = 0; k < 2; ++k)
            for (int d = 0; d < 4; ++d) {
                vcase *c = &cases[n++];
                *c = (vcase){.family = FAMILY_PERCUS,
                             .sigma = scan[k][0],
                             .rho = scan[k][1],
                             .u0 = 6,
                             .length = q ? 400 : 2000,
                             .dt = dts[d],
                             .t_total = q ? 10 : 20,
                             .t_equil = q ? 20 : 60,
                             .bin_width = 0.02,
                             .every = (int)fmax(1, round(1e-3 / dts[d]))};
                snprintf(c->name, sizeof c->name, "dt%.0e-s%.1f-rho%.1f", dts[d], c->sigma, c->rho);
            }
    }
    n += make_sphere_cases(opt, cases + n);
    size_t kept = 0;
    for (size_t i = 0; i < n; ++i)
        if (!opt->only || strstr(cases[i].name, opt->only)) cases[kept++] = cases[i];
    return kept;
}

static int case_config(const vcase *c, int reflect, unsigned seed_offset, const char *dir,
                       hsbd_config *cfg, hsbd_error *err) {
    hsbd_config_defaults(cfg);
    const long n = lround(c->rho * c->length);
    const char *sets[24];
    char store[24][HSBD_PATH_MAX + 64];
    int k = 0;
#define SET(...) (snprintf(store[k], sizeof store[k], __VA_ARGS__), sets[k] = store[k], ++k)
    SET("system.N=%ld", n);
    SET("system.L=%.17g", c->length);
    SET("system.sigma=%.17g", c->sigma);
    SET("system.seed=%u",
        1000u + (unsigned)(c->sigma * 10) * 10 + (unsigned)(c->rho * 10) + seed_offset);
    SET("field.type=%s", c->u0 != 0 ? "cosine" : "none");
    SET("field.amplitude=%.17g", c->u0);
    SET("run.dt=%.17g", c->dt);
    SET("run.t_total=%.17g", c->t_total);
    SET("run.t_equil=%.17g", c->t_equil);
    SET("sample.bin_width=%.17g", c->bin_width);
    const int profile = c->family == FAMILY_PERCUS || c->family == FAMILY_STICKY;
    SET("sample.period=%.17g", profile ? 1.0 : c->bin_width);
    SET("sample.every=%d", c->every);
    /* the ring's slowest density modes outlive any run: time blocks understate the
     * Tonks errors 2.5-fold (docs/validation.md section 14); independent replicas from
     * exact samples do not */
    SET("sample.blocking=%s", c->family == FAMILY_TONKS ? "replicas" : "space");
    if (c->family == FAMILY_STICKY) {
        SET("contact.gamma=%.17g", c->gamma);
        SET("contact.order=%.17g", STICKY_ORDER);
        SET("contact.epsilon=%.17g", STICKY_EPSILON);
    }
    if (profile) {
        /* window: 5 rms steps (sticky); with reflect there is no contact layer and a
         * narrow window serves the extrapolation */
        SET("sample.contact_width=%.17g", reflect ? REFLECT_CONTACT_WIDTH : 5 * sqrt(4 * c->dt));
    }
    SET("sample.msd_max_lag=%.17g", c->family == FAMILY_SINGLE_FILE ? c->t_total / 4 : 1.0);
    SET("output.dir=%s", dir);
    SET("system.contact_rule=%s", reflect ? "reflect" : "sticky");
#undef SET
    for (int i = 0; i < k; ++i)
        if (hsbd_config_set(cfg, sets[i], "validate", err) != HSBD_OK) return err->status;
    return hsbd_config_finalize(cfg, err);
}

static int sphere_case_config(const vcase *c, unsigned seed_offset, const char *dir,
                              hsbd_config *cfg, hsbd_error *err) {
    hsbd_config_defaults(cfg);
    char sets[20][HSBD_PATH_MAX + 64];
    int k = 0;
    snprintf(sets[k++], sizeof sets[0], "system.model=spheres");
    if (c->kind == SPHERES_DISKS) snprintf(sets[k++], sizeof sets[0], "system.dimension=2");
    snprintf(sets[k++], sizeof sets[0], "system.N=%ld", c->n);
    snprintf(sets[k++], sizeof sets[0], "system.packing_fraction=%.17g", c->phi);
    snprintf(sets[k++], sizeof sets[0], "system.seed=%u",
             2000u + (unsigned)(c->phi * 100) + seed_offset);
    snprintf(sets[k++], sizeof sets[0], "run.dt=%.17g", c->dt);
    snprintf(sets[k++], sizeof sets[0], "run.t_total=%.17g", c->t_total);
    snprintf(sets[k++], sizeof sets[0], "run.t_equil=%.17g", c->t_equil);
    const int blocks = c->blocks ? c->blocks : 20;
    snprintf(sets[k++], sizeof sets[0], "sample.blocks=%d", blocks);
    snprintf(sets[k++], sizeof sets[0], "sample.msd_max_lag=%.17g", c->t_total / blocks);
    snprintf(sets[k++], sizeof sets[0], "output.dir=%s", dir);
    if (c->kind == SPHERES_BINARY) {
        snprintf(sets[k++], sizeof sets[0], "species.names=A B");
        snprintf(sets[k++], sizeof sets[0], "species.fraction=0.5 0.5");
        snprintf(sets[k++], sizeof sets[0], "species.sigma=1 1.4");
        snprintf(sets[k++], sizeof sets[0], "species.D_law=stokes-einstein");
    } else if (c->kind == SPHERES_POLY) {
        snprintf(sets[k++], sizeof sets[0], "species.polydispersity=0.1");
        snprintf(sets[k++], sizeof sets[0], "species.D_law=stokes-einstein");
    } else if (c->kind == SPHERES_UNEQUAL_D || c->kind == SPHERES_OBSTACLES) {
        const int obst = c->kind == SPHERES_OBSTACLES;
        const double *x = obst ? OBSTACLES_FRACTION : UNEQUAL_D_FRACTION;
        const double *dif = obst ? OBSTACLES_D : UNEQUAL_D;
        snprintf(sets[k++], sizeof sets[0], "species.names=A B");
        snprintf(sets[k++], sizeof sets[0], "species.fraction=%.17g %.17g", x[0], x[1]);
        snprintf(sets[k++], sizeof sets[0], "species.sigma=1 1");
        snprintf(sets[k++], sizeof sets[0], "species.D=%.17g %.17g", dif[0], dif[1]);
        snprintf(sets[k++], sizeof sets[0], "init.method=random"); /* obstacles cannot compress */
        snprintf(sets[k++], sizeof sets[0], "sample.gr_every=1000");
    }
    for (int i = 0; i < k; ++i)
        if (hsbd_config_set(cfg, sets[i], "validate", err) != HSBD_OK) return err->status;
    return hsbd_config_finalize(cfg, err);
}

static void case_dir(const hsbd_validate_options *opt, const vcase *c, char *dir, size_t len) {
    snprintf(dir, len, "%.900s/%.63s", opt->out_dir, c->name); /* lengths checked on entry */
}

/* Run one case's simulation (in a child process). */
static int run_case(const hsbd_validate_options *opt, const vcase *c) {
    char dir[HSBD_PATH_MAX];
    case_dir(opt, c, dir, sizeof dir);
    hsbd_config cfg;
    hsbd_error err;
    const int spheres = c->family == FAMILY_SPHERES;
    if ((spheres ? sphere_case_config(c, opt->seed_offset, dir, &cfg, &err)
                 : case_config(c, !opt->sticky, opt->seed_offset, dir, &cfg, &err)) != HSBD_OK) {
        fprintf(stderr, "validate %s: %s\n", c->name, err.message);
        return 1;
    }
    /* the jobs share the cores: each simulation takes its share of threads, so they do not
     * oversubscribe the machine (the results do not depend on the thread count) */
    const int cores = hsbd_threads_available(), jobs = opt->jobs > 0 ? opt->jobs : 1;
    cfg.run.threads = cores > jobs ? cores / jobs : 1;
    hsbd_run_options ro = {.force = 1};
    if ((spheres ? hsbd_run_spheres(&cfg, &ro, &err) : hsbd_run_rods(&cfg, &ro, &err)) != HSBD_OK) {
        fprintf(stderr, "validate %s: %s\n", c->name, err.message);
        return 1;
    }
    return 0;
}

/* A line on stderr as each case's simulation ends: "[k/n] name: simulated in T s". */
static void case_done(const vcase *c, size_t done, size_t n, double seconds, int ok) {
    fprintf(stderr, "hsbd validate: [%zu/%zu] %s: %s in %.0f s\n", done, n, c->name,
            ok ? "simulated" : "FAILED", seconds);
}

static int run_all(const hsbd_validate_options *opt, const vcase *cases, size_t n) {
    const int jobs = opt->jobs > 0 ? opt->jobs : 1;
    int running = 0, failed = 0;
    size_t done = 0;
    pid_t *pids = calloc(n ? n : 1, sizeof *pids);
    double *start = calloc(n ? n : 1, sizeof *start);
    if (!pids || !start) return free(pids), free(start), 1;
    for (size_t i = 0; i <= n; ++i) {
        while (running >= jobs || (i == n && running > 0)) {
            int status;
            const pid_t pid = wait(&status);
            if (pid <= 0) continue;
            --running;
            const int ok = WIFEXITED(status) && WEXITSTATUS(status) == 0;
            failed |= !ok;
            for (size_t k = 0; k < i; ++k)
                if (pids[k] == pid)
                    case_done(&cases[k], ++done, n, hsbd_wall_seconds() - start[k], ok);
        }
        if (i == n) break;
        fflush(NULL);
        start[i] = hsbd_wall_seconds();
        const pid_t pid = fork();
        if (pid == 0) _exit(run_case(opt, &cases[i]));
        if (pid < 0) {
            const int bad = run_case(opt, &cases[i]);
            failed |= bad;
            case_done(&cases[i], ++done, n, hsbd_wall_seconds() - start[i], !bad);
        } else {
            pids[i] = pid, ++running;
        }
    }
    free(pids);
    free(start);
    return failed;
}

/* ---- comparisons --------------------------------------------------------------------- */

typedef struct verdict {
    char observable[32];
    size_t points;
    double eff_dof; /* points^2 / tr(R^2), R the correlation of the bins' errors */
    double chi2_dof, max_dev, mean_rel;
    double p_value; /* Hotelling's T^2 on coarse groups of bins (NaN without blocks) */
    int pass;
} verdict;

/* Regularised incomplete beta I_x(a, b) (continued fraction, modified Lentz). */
static double incomplete_beta(double a, double b, double x) {
    if (x <= 0) return 0;
    if (x >= 1) return 1;
    if (x > (a + 1) / (a + b + 2)) return 1 - incomplete_beta(b, a, 1 - x);
    const double front =
        exp(lgamma(a + b) - lgamma(a) - lgamma(b) + a * log(x) + b * log1p(-x)) / a;
    const double tiny = 1e-300;
    double f = 1, c = 1, d = 0;
    for (int i = 0; i <= 400; ++i) {
        const int m = i / 2;
        double num;
        if (i == 0)
            num = 1;
        else if (i % 2 == 0)
            num = m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
        else
            num = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
        d = 1 + num * d;
        d = fabs(d) < tiny ? tiny : d;
        d = 1 / d;
        c = 1 + num / c;
        c = fabs(c) < tiny ? tiny : c;
        const double cd = c * d;
        f *= cd;
        if (fabs(1 - cd) < 1e-14) break;
    }
    return front * (f - 1);
}

/* P(F > f) for the F distribution with (d1, d2) degrees of freedom */
static double f_distribution_upper(double f, double d1, double d2) {
    return incomplete_beta(0.5 * d2, 0.5 * d1, d2 / (d2 + d1 * f));
}

/* Cholesky solve of the small symmetric positive definite system a x = b (in place);
 * -1 when a is not positive definite (e.g. groups summing to a fixed total). */
static int cholesky_solve(int n, double *a, double *b) {
    for (int j = 0; j < n; ++j) {
        double d = a[j * n + j];
        for (int k = 0; k < j; ++k)
            d -= a[j * n + k] * a[j * n + k];
        if (!(d > 1e-12 * fabs(a[j * n + j])) || !(d > 0)) return -1;
        a[j * n + j] = sqrt(d);
        for (int i = j + 1; i < n; ++i) {
            double v = a[i * n + j];
            for (int k = 0; k < j; ++k)
                v -= a[i * n + k] * a[j * n + k];
            a[i * n + j] = v / a[j * n + j];
        }
    }
    for (int i = 0; i < n; ++i) { /* L y = b */
        for (int k = 0; k < i; ++k)
            b[i] -= a[i * n + k] * b[k];
        b[i] /= a[i * n + i];
    }
    for (int i = n; i-- > 0;) { /* L^T x = y */
        for (int k = i + 1; k < n; ++k)
            b[i] -= a[k * n + i] * b[k];
        b[i] /= a[i * n + i];
    }
    return 0;
}

enum { HOTELLING_GROUPS = 5 };

/* Hotelling's T^2 test of the simulated profile against the exact one, with the
 * covariance measured from the blocks: the used bins are summed into up to 5 contiguous
 * groups (the blocks, 20, must outnumber them), T^2 = nb d^T S^-1 d with d the block-mean
 * deviation of the group sums and S their covariance between blocks, and
 * (nb - p) / (p (nb - 1)) T^2 follows F(p, nb - p). Unlike a diagonal chi^2 it sees a
 * deviation along a direction the correlated errors do not explain. When the groups sum to
 * a fixed total (density of a fixed N) S is singular and the last group is dropped.
 * Returns the p-value, NaN when it cannot be formed. */
static double hotelling_groups(const table *blk, const size_t *used, size_t n,
                               const double *theory) {
    const size_t nb = blk->cols - 1;
    int p = (int)(n < HOTELLING_GROUPS ? n : HOTELLING_GROUPS);
    if (p < 1 || nb < (size_t)p + 3) return NAN;
    double y[HOTELLING_GROUPS * 64], t[HOTELLING_GROUPS] = {0}, mean[HOTELLING_GROUPS] = {0};
    if (nb > 64) return NAN;
    for (int g = 0; g < p; ++g) {
        const size_t lo = (size_t)g * n / (size_t)p, hi = (size_t)(g + 1) * n / (size_t)p;
        for (size_t b = 0; b < nb; ++b) {
            double sum = 0;
            for (size_t q = lo; q < hi; ++q)
                sum += cell(blk, used[q], b + 1);
            y[g * 64 + b] = sum;
            mean[g] += sum / (double)nb;
        }
        for (size_t q = lo; q < hi; ++q)
            t[g] += theory[used[q]];
    }
    for (; p >= 1; --p) {
        double cov[HOTELLING_GROUPS * HOTELLING_GROUPS], d[HOTELLING_GROUPS];
        for (int g = 0; g < p; ++g) {
            d[g] = mean[g] - t[g];
            for (int h = 0; h < p; ++h) {
                double c = 0;
                for (size_t b = 0; b < nb; ++b)
                    c += (y[g * 64 + b] - mean[g]) * (y[h * 64 + b] - mean[h]);
                cov[g * p + h] = c / (double)(nb - 1);
            }
        }
        double x[HOTELLING_GROUPS];
        for (int g = 0; g < p; ++g)
            x[g] = d[g];
        if (cholesky_solve(p, cov, x) != 0) continue;
        double t2 = 0;
        for (int g = 0; g < p; ++g)
            t2 += d[g] * x[g];
        t2 *= (double)nb;
        const double f = (double)(nb - (size_t)p) / ((double)p * (double)(nb - 1)) * t2;
        return f_distribution_upper(f, p, (double)(nb - (size_t)p));
    }
    return NAN;
}

/* tr(R^2) over the bins `used` of the correlation matrix R of their errors, estimated
 * from the per-block profiles (rows: bins, columns 1..nb: blocks). Each off-diagonal r^2
 * is debiased, (r^2 (nb - 1) - 1) / (nb - 2) floored at 0: uncorrelated bins give
 * E[r^2] = 1/(nb - 1). Independent bins: tr = points. */
static double correlation_trace(const table *blk, const size_t *used, size_t n) {
    const size_t nb = blk->cols - 1;
    double *z = malloc(n * nb * sizeof *z); /* standardised block values */
    if (!z || nb < 3) {
        free(z);
        return (double)n;
    }
    for (size_t a = 0; a < n; ++a) {
        double m = 0, v = 0;
        for (size_t b = 0; b < nb; ++b)
            m += cell(blk, used[a], b + 1) / (double)nb;
        for (size_t b = 0; b < nb; ++b) {
            const double d = cell(blk, used[a], b + 1) - m;
            v += d * d;
        }
        const double sd = sqrt(v);
        for (size_t b = 0; b < nb; ++b)
            z[a * nb + b] = sd > 0 ? (cell(blk, used[a], b + 1) - m) / sd : 0.0;
    }
    double tr = (double)n;
    for (size_t a = 0; a < n; ++a)
        for (size_t c = a + 1; c < n; ++c) {
            double r = 0;
            for (size_t b = 0; b < nb; ++b)
                r += z[a * nb + b] * z[c * nb + b];
            const double rho2 = (r * r * (double)(nb - 1) - 1.0) / (double)(nb - 2);
            if (rho2 > 0 && isfinite(rho2)) tr += 2.0 * rho2;
        }
    free(z);
    return tr;
}

/* chi^2/dof below 1 + 4 sd, and no single point beyond the 4.5-sigma band. With errors
 * from 20 blocks each bin's deviation is Student-t with 19 degrees of freedom, P(|t| >
 * 4.5) = 2.5e-4 per bin, so the band alone fails an unbiased profile of 34 bins in
 * 0.6-0.9 % of runs, and all rules together in 1.5-2 % (measured with synthetic runs of
 * the measured covariance, docs/validation.md section 16). The sd of chi^2/dof is sqrt(2
 * tr(R^2))/points with R the correlation of the bins' errors, from the per-block profiles `blk`
 * when given (neighbouring bins of a profile share fluctuations; for independent bins it is
 * sqrt(2/points)). chi^2/dof well below 1 means conservative error bars (spatial blocks
 * of a fixed-N ring: the segments' numbers fluctuate, the total does not); it is
 * reported, not failed. */
static void judge(verdict *v, const char *what, const double *sim, const double *err,
                  const double *theory, size_t n, const table *blk) {
    double chi2 = 0, maxd = 0, rel = 0, tmax = 0;
    size_t used = 0;
    size_t *idx = malloc((n ? n : 1) * sizeof *idx);
    for (size_t k = 0; k < n; ++k)
        tmax = fmax(tmax, fabs(theory[k]));
    for (size_t k = 0; k < n; ++k) {
        /* bins with signal only: where the theory is below 1 % of its maximum the counts
         * are a handful of rare events per segment and Gaussian error bars mean nothing */
        if (!(err[k] > 0) || !isfinite(sim[k]) || fabs(theory[k]) < 0.01 * tmax) continue;
        const double d = (sim[k] - theory[k]) / err[k];
        chi2 += d * d;
        maxd = fmax(maxd, fabs(d));
        rel += theory[k] != 0 ? fabs(sim[k] / theory[k] - 1) : 0;
        if (idx) idx[used] = k;
        ++used;
    }
    const int have_blocks = blk && idx && blk->rows == n;
    const double tr = have_blocks ? correlation_trace(blk, idx, used) : (double)used;
    v->p_value = have_blocks ? hotelling_groups(blk, idx, used, theory) : NAN;
    free(idx);
    snprintf(v->observable, sizeof v->observable, "%s", what);
    v->points = used;
    v->eff_dof = used ? (double)used * (double)used / tr : NAN;
    v->chi2_dof = used ? chi2 / (double)used : NAN;
    v->max_dev = maxd;
    v->mean_rel = used ? rel / (double)used : NAN;
    v->pass = used > 0 && v->chi2_dof - 1 < 4 * sqrt(2.0 * tr) / (double)used && maxd < 4.5 &&
              !(v->p_value < 1e-3);
}

enum { MIN_EVENTS_PER_BLOCK = 25 };

/* Contact densities of dilute profiles rest on few pairs per bin: where a bin sees fewer
 * than MIN_EVENTS_PER_BLOCK pairs in its window per error block, its block values are
 * not Gaussian (Poisson counts of a handful, the extrapolated estimator even negative)
 * and an error bar means little. Such bins are merged with their neighbours, in order,
 * until every group has that many events per block; a group's value is the mean of its
 * bins, its block values the means of theirs, so the errors and their correlations come
 * from the blocks as before. `events` holds each bin's expected pairs per block. On
 * return sim, err, theory and the block table hold the groups; returns their number. */
static size_t group_sparse_bins(size_t n, const double *events, double *sim, double *err,
                                double *theory, table *blk) {
    const size_t nb = blk->cols - 1, cols = blk->cols;
    size_t *first = malloc((n + 1) * sizeof *first); /* group g: bins [first[g], first[g+1]) */
    double *orig = malloc(n * cols * sizeof *orig), *s0 = malloc(2 * n * sizeof *s0);
    if (!first || !orig || !s0 || nb < 2) {
        free(first), free(orig), free(s0);
        return n;
    }
    memcpy(orig, blk->v, n * cols * sizeof *orig);
    memcpy(s0, sim, n * sizeof *s0);
    memcpy(s0 + n, theory, n * sizeof *s0);
    size_t groups = 0;
    double acc = 0;
    first[0] = 0;
    for (size_t k = 0; k < n; ++k) {
        acc += events[k];
        if (acc >= MIN_EVENTS_PER_BLOCK) first[++groups] = k + 1, acc = 0;
    }
    if (groups == 0) groups = 1; /* too few events anywhere: one group */
    first[groups] = n;           /* a short tail joins the last group */
    for (size_t g = 0; g < groups; ++g) {
        const size_t lo = first[g], hi = first[g + 1];
        const double m = (double)(hi - lo);
        double ssum = 0, tsum = 0, mean = 0, var = 0;
        for (size_t q = lo; q < hi; ++q)
            ssum += s0[q], tsum += s0[n + q];
        double *row = blk->v + g * cols;
        row[0] = orig[lo * cols];
        for (size_t b = 1; b <= nb; ++b) {
            double v = 0;
            for (size_t q = lo; q < hi; ++q)
                v += orig[q * cols + b];
            row[b] = v / m;
            mean += row[b] / (double)nb;
        }
        for (size_t b = 1; b <= nb; ++b)
            var += (row[b] - mean) * (row[b] - mean);
        sim[g] = ssum / m;
        theory[g] = tsum / m;
        err[g] = sqrt(var / ((double)nb * (double)(nb - 1)));
    }
    blk->rows = groups;
    free(first), free(orig), free(s0);
    return groups;
}

/* theory averaged over each simulation bin of width w centred at x[k] */
static void bin_average(const hsbd_percus_result *r, const double *f, const double *x, size_t n,
                        double w, double *out) {
    for (size_t k = 0; k < n; ++k)
        out[k] = hsbd_periodic_bin_average(f, r->m, r->x[1] - r->x[0], x[k], w);
}

static int compare_percus(const hsbd_validate_options *opt, const vcase *c, verdict *v, int *nv,
                          hsbd_error *err) {
    char dir[HSBD_PATH_MAX], path[HSBD_PATH_MAX + 32];
    case_dir(opt, c, dir, sizeof dir);
    hsbd_percus_params pp = {.sigma = c->sigma,
                             .rho_mean = c->rho,
                             .amplitude = c->u0,
                             .wavelength = 1.0,
                             .points = 4000};
    hsbd_percus_result th, baxter = {0};
    hsbd_pair sticky = {0};
    const int is_sticky = c->family == FAMILY_STICKY;
    if (is_sticky) { /* exact for the delta_eps model; Eqs. 34 for its eps -> 0 limit */
        pp.points = 2000;
        hsbd_pair_add(&sticky,
                      hsbd_pair_sticky(c->sigma, c->gamma, STICKY_ORDER, STICKY_EPSILON, 1.0));
        if (hsbd_nn_transfer_solve(&pp, &sticky, &th, err) != HSBD_OK) return err->status;
        pp.gamma = c->gamma;
        if (hsbd_percus_solve(&pp, &baxter, err) != HSBD_OK) {
            hsbd_percus_result_free(&th);
            return err->status;
        }
    } else if (hsbd_percus_solve(&pp, &th, err) != HSBD_OK) {
        return err->status;
    }
    /* keep the theory next to the run for the plots */
    hsbd_outfile o;
    if (hsbd_outfile_open(&o, dir, "theory.tsv", err) == HSBD_OK) {
        if (is_sticky)
            fprintf(o.f,
                    "# exact profile of sticky rods (delta_eps, p = %g, eps = %g; transfer "
                    "operator), sigma = %g, rho = %g, U0 = %g, gamma = %g\n# x\trho\trho2\n",
                    STICKY_ORDER, STICKY_EPSILON, c->sigma, c->rho, c->u0, c->gamma);
        else
            fprintf(o.f, "# Percus exact profile, sigma = %g, rho = %g, U0 = %g\n# x\trho\trho2\n",
                    c->sigma, c->rho, c->u0);
        for (size_t j = 0; j < th.m; j += is_sticky ? 2 : 4)
            fprintf(o.f, "%.8g\t%.10g\t%.10g\n", th.x[j], th.rho[j], th.rho2[j]);
        hsbd_outfile_commit(&o, err);
    }
    table d = {0}, ct = {0}, db = {0}, cb = {0};
    snprintf(path, sizeof path, "%s/density.tsv", dir);
    int rc = read_table(path, 3, &d, err);
    snprintf(path, sizeof path, "%s/contact.tsv", dir);
    if (rc == HSBD_OK) rc = read_table(path, CONTACT_COLUMNS, &ct, err);
    snprintf(path, sizeof path, "%s/density_blocks.tsv", dir);
    read_blocks_table(path, &db);
    snprintf(path, sizeof path, "%s/contact_blocks.tsv", dir); /* the default estimator's */
    read_blocks_table(path, &cb);
    const table *dblk = db.rows ? &db : NULL, *cblk = cb.rows ? &cb : NULL;
    if (rc == HSBD_OK) {
        const size_t n = d.rows;
        double *x = malloc(n * sizeof *x), *s = malloc(n * sizeof *s), *e = malloc(n * sizeof *e),
               *t = malloc(n * sizeof *t);
        for (size_t k = 0; k < n; ++k)
            x[k] = cell(&d, k, 0), s[k] = cell(&d, k, 1), e[k] = cell(&d, k, 2);
        bin_average(&th, th.rho, x, n, c->bin_width, t);
        judge(&v[(*nv)++], "density", s, e, t, n, dblk);
        if (is_sticky) {
            /* the simulated model against Baxter's limit: how far eps = 0.05 is from it */
            bin_average(&baxter, baxter.rho, x, n, c->bin_width, t);
            judge(&v[(*nv)++], "density vs Eq. 34", s, e, t, n, dblk);
            v[*nv - 1].pass = -1;
            bin_average(&th, th.rho2, x, n, c->bin_width, t);
            for (size_t k = 0; k < n; ++k)
                s[k] = cell(&ct, k, COL_THEOREM), e[k] = cell(&ct, k, COL_THEOREM + 1);
            judge(&v[(*nv)++], "contact (theorem)", s, e, t, n, NULL);
            v[*nv - 1].pass = -1; /* info: the O(dt) bias of the impulses near a steep force */
            free(x), free(s), free(e), free(t);
            goto done;
        }
        bin_average(&th, th.rho2, x, n, c->bin_width, t);
        for (size_t k = 0; k < n; ++k)
            s[k] = cell(&ct, k, COL_THEOREM), e[k] = cell(&ct, k, COL_THEOREM + 1);
        judge(&v[(*nv)++], "contact (theorem)", s, e, t, n, opt->sticky ? cblk : NULL);
        for (size_t k = 0; k < n; ++k)
            s[k] = cell(&ct, k, COL_WINDOW), e[k] = cell(&ct, k, COL_WINDOW + 1);
        judge(&v[(*nv)++], "contact (window)", s, e, t, n, NULL);
        v[*nv - 1].pass = -1; /* informative only: the windowed estimator is biased */
        for (size_t k = 0; k < n; ++k)
            s[k] = cell(&ct, k, COL_EXTRAP), e[k] = cell(&ct, k, COL_EXTRAP + 1);
        size_t ng = n;
        if (cblk && !opt->sticky && cb.rows == n) {
            /* pairs per block in each bin's window: rho2 bw cw (L / period) samples / blocks */
            const double samples = floor(c->t_total / c->dt / c->every + 1e-9);
            const double per_block =
                c->bin_width * REFLECT_CONTACT_WIDTH * c->length * samples / (double)(cb.cols - 1);
            for (size_t k = 0; k < n; ++k)
                x[k] = fmax(0.0, cell(&ct, k, COL_WINDOW)) * per_block; /* x reused: events */
            ng = group_sparse_bins(n, x, s, e, t, &cb);
        }
        judge(&v[(*nv)++], "contact (extrapolated)", s, e, t, ng, opt->sticky ? NULL : cblk);
        if (opt->sticky) v[*nv - 1].pass = -1; /* sticky: the contact layer spoils it */
        free(x), free(s), free(e), free(t);
    }
done:
    free(d.v), free(ct.v), free(db.v), free(cb.v);
    hsbd_percus_result_free(&th);
    hsbd_percus_result_free(&baxter);
    return rc;
}

static int compare_tonks(const hsbd_validate_options *opt, const vcase *c, verdict *v, int *nv,
                         hsbd_error *err) {
    char dir[HSBD_PATH_MAX], path[HSBD_PATH_MAX + 32];
    case_dir(opt, c, dir, sizeof dir);
    table d = {0}, ct = {0};
    snprintf(path, sizeof path, "%s/density.tsv", dir);
    int rc = read_table(path, 3, &d, err);
    snprintf(path, sizeof path, "%s/contact.tsv", dir);
    if (rc == HSBD_OK) rc = read_table(path, CONTACT_COLUMNS, &ct, err);
    if (rc == HSBD_OK && d.rows && ct.rows) {
        const double n = round(c->rho * c->length);
        double s = cell(&d, 0, 1), t = n / c->length;
        /* the period is one bin: the density is N/L exactly, its error is 0 */
        verdict *vd = &v[(*nv)++];
        snprintf(vd->observable, sizeof vd->observable, "density (= N/L)");
        vd->points = 1, vd->eff_dof = 1, vd->chi2_dof = NAN, vd->max_dev = NAN;
        vd->p_value = NAN;
        vd->mean_rel = fabs(s / t - 1), vd->pass = vd->mean_rel < 1e-12;
        s = cell(&ct, 0, COL_THEOREM);
        double e = cell(&ct, 0, COL_THEOREM + 1);
        t = hsbd_tonks_ring_contact(n, c->length, c->sigma);
        judge(&v[(*nv)++], "contact (theorem)", &s, &e, &t, 1, NULL);
        s = cell(&ct, 0, COL_EXTRAP), e = cell(&ct, 0, COL_EXTRAP + 1);
        judge(&v[(*nv)++], "contact (extrapolated)", &s, &e, &t, 1, NULL);
        if (opt->sticky) v[*nv - 1].pass = -1; /* sticky: the contact layer spoils it */
    }
    free(d.v), free(ct.v);
    return rc;
}

static int compare_single_file(const hsbd_validate_options *opt, const vcase *c, verdict *v,
                               int *nv, hsbd_error *err) {
    char dir[HSBD_PATH_MAX], path[HSBD_PATH_MAX + 32];
    case_dir(opt, c, dir, sizeof dir);
    table m = {0};
    snprintf(path, sizeof path, "%s/msd.tsv", dir);
    int rc = read_table(path, 4, &m, err);
    if (rc == HSBD_OK) {
        double s[64], e[64], t[64];
        size_t n = 0;
        /* every lag from 100 steps on: the exact law covers the crossover from 2 D t to
         * the sqrt(t) regime (hsbd_single_file_msd_exact); the ring's O(1/N) canonical
         * correction is 1e-4 here */
        const double t_min = 100 * c->dt;
        for (size_t k = 0; k < m.rows && n < 64; ++k) {
            if (cell(&m, k, 0) < t_min) continue;
            s[n] = cell(&m, k, 1), e[n] = cell(&m, k, 2);
            t[n] = hsbd_single_file_msd_exact(cell(&m, k, 0), c->rho, c->sigma, 1.0);
            ++n;
        }
        judge(&v[(*nv)++], "tagged MSD (exact law)", s, e, t, n, NULL);
    }
    free(m.v);
    return rc;
}

/* The value after the `nth` (0-based) occurrence of "key": in a summary.json hsbd wrote. */
static double json_value(const char *text, const char *key, int nth) {
    char pattern[80];
    snprintf(pattern, sizeof pattern, "\"%s\": ", key);
    const char *p = text;
    for (int k = 0; p && k <= nth; ++k)
        if ((p = strstr(p, pattern))) p += strlen(pattern);
    return p ? strtod(p, NULL) : NAN;
}

static void judge_value(verdict *v, const char *what, double sim, double err, double theory,
                        int informative) {
    judge(v, what, &sim, &err, &theory, 1, NULL);
    if (informative) v->pass = -1;
}

/* "name": [value, error] of a summary's "D_long_species" */
static void json_pair(const char *text, const char *name, double *value, double *err) {
    char pattern[80];
    snprintf(pattern, sizeof pattern, "\"%s\": [", name);
    const char *p = strstr(text, "\"D_long_species\"");
    p = p ? strstr(p, pattern) : NULL;
    *value = *err = NAN;
    if (!p) return;
    char *end;
    *value = strtod(p + strlen(pattern), &end);
    *err = strtod(end + 1, NULL);
}

/* The lags t0 < t1 of the run's D_L slope (hsbd_msd_long_time_lags) from msd.tsv: the
 * largest lag with two origins and the first at a tenth of it or beyond. */
static int msd_lags(const char *dir, double *t0, double *t1, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/msd.tsv", dir);
    table t;
    if (read_table(path, 4, &t, err) != HSBD_OK) return err->status;
    size_t last = t.rows;
    for (size_t r = t.rows; r-- > 0;)
        if (cell(&t, r, 3) >= 2) {
            last = r;
            break;
        }
    *t0 = *t1 = NAN;
    for (size_t r = 0; last < t.rows && r < last; ++r)
        if (cell(&t, r, 0) >= 0.1 * cell(&t, last, 0)) {
            *t0 = cell(&t, r, 0), *t1 = cell(&t, last, 0);
            break;
        }
    free(t.v);
    return isnan(*t0) ? hsbd_error_set(err, HSBD_ENUMERIC, "validate: too few MSD lags in %s", path)
                      : HSBD_OK;
}

/* D_L of each mobile species against the first order in density at the run's lags (judged)
 * and its long-time limit (information) */
static int compare_species_dl(const vcase *c, const char *dir, const char *text, verdict *v,
                              int *nv, hsbd_error *err) {
    const int obst = c->kind == SPHERES_OBSTACLES;
    const double *x = obst ? OBSTACLES_FRACTION : UNEQUAL_D_FRACTION;
    const double *dif = obst ? OBSTACLES_D : UNEQUAL_D;
    const double rho = 6 * c->phi / PI, dens[2] = {x[0] * rho, x[1] * rho}, sig[2] = {1, 1};
    const hsbd_hs_mixture mix = {3, 2, dens, sig, dif, NULL};
    double t0 = NAN, t1 = NAN;
    if (msd_lags(dir, &t0, &t1, err) != HSBD_OK) return err->status;
    static const char *const name[2] = {"A", "B"};
    for (size_t a = 0; a < 2; ++a) {
        if (!(dif[a] > 0)) continue;
        double dl, e;
        json_pair(text, name[a], &dl, &e);
        char what[64];
        snprintf(what, sizeof what, "D_L,%s/D O(phi), lags", name[a]);
        judge_value(&v[(*nv)++], what, dl / dif[a], e / dif[a],
                    hsbd_hs_msd_slope_ratio(&mix, a, t0, t1), 0);
        snprintf(what, sizeof what, "D_L,%s/D O(phi), t->inf", name[a]);
        judge_value(&v[(*nv)++], what, dl / dif[a], e / dif[a], hsbd_hs_long_time_ratio(&mix, a),
                    1);
    }
    return HSBD_OK;
}

static int compare_spheres(const hsbd_validate_options *opt, const vcase *c, verdict *v, int *nv,
                           hsbd_error *err) {
    char dir[HSBD_PATH_MAX], path[HSBD_PATH_MAX + 32];
    case_dir(opt, c, dir, sizeof dir);
    snprintf(path, sizeof path, "%s/summary.json", dir);
    FILE *f = fopen(path, "r");
    if (!f) return hsbd_error_set(err, HSBD_EIO, "validate: cannot read %s", path);
    static char text[1 << 20];
    text[fread(text, 1, sizeof text - 1, f)] = 0;
    fclose(f);
    if (c->kind == SPHERES_UNEQUAL_D || c->kind == SPHERES_OBSTACLES)
        return compare_species_dl(c, dir, text, v, nv, err);
    if (c->phi < 0.1) { /* D_L -> D_0 (1 - 2 phi) */
        judge_value(&v[(*nv)++], "D_L vs 1 - 2 phi", json_value(text, "D_long", 0),
                    json_value(text, "D_long_err", 0), 1 - 2 * c->phi, 0);
        return HSBD_OK;
    }
    const double zv = json_value(text, "Z_virial", 0), ze = json_value(text, "Z_virial_err", 0);
    if (c->kind == SPHERES_DISKS) {
        judge_value(&v[(*nv)++], "Z_virial vs B2-B10", zv, ze, json_value(text, "Z_theory", 0), 0);
        judge_value(&v[(*nv)++], "Z_virial vs Henderson", zv, ze, hsbd_hd_z_henderson(c->phi), 1);
        return HSBD_OK;
    }
    if (c->kind == SPHERES_ONE) {
        judge_value(&v[(*nv)++], "Z_virial vs KLM", zv, ze, json_value(text, "Z_theory_klm", 0), 0);
        judge_value(&v[(*nv)++], "g(sigma+) vs KLM", json_value(text, "g_contact", 0),
                    json_value(text, "g_contact_err", 0),
                    json_value(text, "g_contact_theory_klm", 0), 0);
        judge_value(&v[(*nv)++], "D_L (information)", json_value(text, "D_long", 0),
                    json_value(text, "D_long_err", 0), json_value(text, "D_long", 0), 1);
        return HSBD_OK;
    }
    judge_value(&v[(*nv)++], "Z_virial vs BMCSL (info)", zv, ze, json_value(text, "Z_theory", 0),
                1);
    static const char *const pair[] = {"g_AA vs BMCSL", "g_AB vs BMCSL", "g_BB vs BMCSL"};
    const int pairs = c->kind == SPHERES_BINARY ? 3 : 1;
    for (int p = 0; p < pairs; ++p)
        judge_value(&v[(*nv)++], pairs == 1 ? "g(sigma_ij+) vs BMCSL" : pair[p],
                    json_value(text, "g_contact", p), json_value(text, "g_contact_err", p),
                    json_value(text, "theory", p), 0);
    return HSBD_OK;
}

int hsbd_validate(const hsbd_validate_options *opt, FILE *report, hsbd_error *err) {
    static vcase cases[MAX_CASES];
    if (strlen(opt->out_dir) > 900)
        return hsbd_error_set(err, HSBD_EINPUT, "validate: --out path longer than 900 characters");
    const size_t n = make_cases(opt, cases);
    if (n == 0)
        return hsbd_error_set(err, HSBD_EINPUT, "validate: no case matches '%s'", opt->only);
    for (size_t i = 0; opt->list && i < n; ++i)
        fprintf(report, "%s\n", cases[i].name);
    if (opt->list) return HSBD_OK;
    if (rundir_create(opt->out_dir, err) != HSBD_OK) return err->status;
    if (run_all(opt, cases, n))
        return hsbd_error_set(err, HSBD_ENUMERIC, "validate: a simulation failed (see above)");
    hsbd_outfile tsv, md;
    if (hsbd_outfile_open(&tsv, opt->out_dir, "validation.tsv", err) != HSBD_OK) return err->status;
    if (hsbd_outfile_open(&md, opt->out_dir, "validation.md", err) != HSBD_OK) {
        hsbd_outfile_discard(&tsv);
        return err->status;
    }
    validation_write_header(tsv.f, md.f);
    fprintf(report, "%-26s %-20s %6s %9s %9s %9s %9s %s\n", "case", "observable", "points",
            "chi2/dof", "max|d|/e", "rel.dev", "Hotell.p", "result");
    int all_pass = 1;
    for (size_t i = 0; i < n; ++i) {
        verdict v[6];
        int nv = 0;
        const vcase *c = &cases[i];
        const int profile = c->family == FAMILY_PERCUS || c->family == FAMILY_STICKY;
        int rc = profile                       ? compare_percus(opt, c, v, &nv, err)
                 : c->family == FAMILY_TONKS   ? compare_tonks(opt, c, v, &nv, err)
                 : c->family == FAMILY_SPHERES ? compare_spheres(opt, c, v, &nv, err)
                                               : compare_single_file(opt, c, v, &nv, err);
        if (rc != HSBD_OK) {
            hsbd_outfile_discard(&tsv);
            hsbd_outfile_discard(&md);
            return rc;
        }
        for (int k = 0; k < nv; ++k) {
            const char *res = v[k].pass < 0 ? "info" : v[k].pass ? "pass" : "FAIL";
            if (v[k].pass == 0) all_pass = 0;
            fprintf(report, "%-26s %-20s %6zu %9.3f %9.2f %8.2f%% %9.2g %s\n", c->name,
                    v[k].observable, v[k].points, v[k].chi2_dof, v[k].max_dev, 100 * v[k].mean_rel,
                    v[k].p_value, res);
            const validation_row row = {.case_name = c->name,
                                        .observable = v[k].observable,
                                        .result = res,
                                        .dt = c->dt,
                                        .t_total = c->t_total,
                                        .points = v[k].points,
                                        .eff_dof = v[k].eff_dof,
                                        .chi2_dof = v[k].chi2_dof,
                                        .max_dev = v[k].max_dev,
                                        .mean_rel = v[k].mean_rel,
                                        .p_value = v[k].p_value};
            validation_write_row(tsv.f, md.f, &row);
        }
    }
    if (hsbd_outfile_commit(&tsv, err) != HSBD_OK || hsbd_outfile_commit(&md, err) != HSBD_OK)
        return err->status;
    return all_pass ? HSBD_OK : hsbd_error_set(err, HSBD_ENUMERIC, "validate: some cases FAIL");
}
