/* Throughput of the two engines (hsbd bench): particle-steps per second of the bare
 * integrators and, in the same run, the free-particle bound (the same particles with the
 * hard core switched off). Rods: the default contact rule and the paper's; spheres: from
 * a lattice after a warm-up. One core is what is measured (bench/run pins it). */
#include "hsbd/bench.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/threads.h"
#include "hsbd/rods.h"
#include "hsbd/spheres.h"
#include "hsbd_version.h"

/* the field of a case: the cosine, plus a static tilt, or plus a rocking tilt */
enum { BENCH_COSINE = 0, BENCH_TILT, BENCH_ROCKING };

typedef struct bench_case {
    const char *name;
    double sigma, rho;
    size_t n;  /* 0: L = 100 */
    int field; /* BENCH_COSINE (0), BENCH_TILT or BENCH_ROCKING */
} bench_case;

static const bench_case bench_cases[] = {
    {"s0.5-rho0.2", 0.5, 0.2, 0, BENCH_COSINE},
    {"s0.5-rho0.5", 0.5, 0.5, 0, BENCH_COSINE},
    {"s0.5-rho0.8", 0.5, 0.8, 0, BENCH_COSINE},
    {"s0.1-rho0.8", 0.1, 0.8, 0, BENCH_COSINE},
    {"s0.5-rho0.5-N1e4", 0.5, 0.5, 10000, BENCH_COSINE},
    {"s0.5-rho0.5-N1e5", 0.5, 0.5, 100000, BENCH_COSINE},
    {"s0.5-rho0.5-N1e6", 0.5, 0.5, 1000000, BENCH_COSINE},
    {"dense-s0.9-rho1.0-N1e4", 0.9, 1.0, 10000, BENCH_COSINE},
    /* a driven field against its static twin: F = 3 + 9 cos(2 pi t) against F = 3 */
    {"tilt-s0.5-rho0.5-N1e4", 0.5, 0.5, 10000, BENCH_TILT},
    {"rocking-s0.5-rho0.5-N1e4", 0.5, 0.5, 10000, BENCH_ROCKING},
};

/* CPU time of the calling thread: on a shared machine the wall clock also counts the time
 * slices other processes take, the thread's CPU time only the work measured */
static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* wall-clock seconds (the threads' speed-up: CPU time would add up every thread's) */
static double wall_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Rods of the block a large system is tiled from, and the time every rods case runs before
 * it is measured (time units of the bench: D = 1, the field's period 1). */
enum { BENCH_BLOCK = 1000 };
static const double bench_warm_time = 10.0;

/* the field-free equilibrium sample, then `steps` steps; 0 on success */
static int run_from_field_free(hsbd_rods *r, uint64_t steps) {
    hsbd_rods_init_equilibrium(r);
    for (uint64_t k = 0; k < steps; ++k)
        if (hsbd_rods_step(r, NULL) != HSBD_OK) return -1;
    return 0;
}

/* A stationary state of the case's system in r. The field-free equilibrium it starts from
 * relaxes into the field for a few time units (at first about ten times as many gaps can
 * close within a step as later: the reflect rule's cost depends on it), so every case first
 * runs bench_warm_time of its own dynamics: directly up to BENCH_BLOCK rods, and larger
 * systems are copies end to end of a block of BENCH_BLOCK rods so warmed up (the case's L
 * is a whole number of blocks and each block a whole number of field periods). 0 on
 * success. Free particles (no hard core) start from the field-free sample: their cost does
 * not depend on the state. */
static int bench_rods_warm(hsbd_rods *r, const hsbd_rods_params *p) {
    if (!p->hard_core) return run_from_field_free(r, 0); /* every state costs the same */
    const uint64_t steps = (uint64_t)llround(bench_warm_time / p->dt);
    if (p->n <= BENCH_BLOCK) return run_from_field_free(r, steps);
    hsbd_rods_params q = *p;
    q.n = BENCH_BLOCK;
    q.length = p->length * (double)BENCH_BLOCK / (double)p->n;
    hsbd_error err;
    hsbd_rods *block = hsbd_rods_alloc(&q, &err);
    double *x = malloc(p->n * sizeof *x);
    int rc = block && x && p->n % BENCH_BLOCK == 0 ? run_from_field_free(block, steps) : -1;
    if (!rc) {
        const hsbd_rods_view v = hsbd_rods_get_view(block);
        for (size_t i = 0; i < BENCH_BLOCK; ++i) {
            const double xi = v.z[i] + v.offset[i];
            const double in_block = xi - q.length * floor(xi / q.length);
            for (size_t c = 0; c < p->n / BENCH_BLOCK; ++c)
                x[c * BENCH_BLOCK + i] = in_block + (double)c * q.length;
        }
        rc = hsbd_rods_set_positions(r, x, &err) == HSBD_OK ? 0 : -1;
    }
    free(x);
    hsbd_rods_free(block);
    return rc;
}

/* the number of rods of a case: c->n, or the rods of L = 100 at density rho */
static size_t bench_rods_n(const bench_case *c) {
    return c->n ? c->n : (size_t)llround(c->rho * 100.0);
}

/* The case's rods with the given contact rule (hard_core = 0: free particles, the rule is
 * not used) on `threads` threads, warmed up (bench_rods_warm, then one batch of steps), or
 * NULL. */
static hsbd_rods *bench_rods_system(const bench_case *c, int hard_core, int contact_rule,
                                    int threads, uint64_t batch) {
    const size_t n = bench_rods_n(c);
    const double L = c->n ? (double)c->n / c->rho : 100.0;
    hsbd_rods_params p = {.n = n,
                          .length = L,
                          .sigma = c->sigma,
                          .diffusion = 1,
                          .kT = 1,
                          .dt = 1e-4,
                          .seed = 1,
                          .hard_core = hard_core,
                          .contact_rule = contact_rule,
                          .threads = threads};
    hsbd_field_add(&p.field, hsbd_field_cosine(6.0, 1.0));
    hsbd_field_term tilt = hsbd_field_tilt(3.0);
    if (c->field == BENCH_ROCKING)
        hsbd_field_term_drive(&tilt, HSBD_DRIVE_STRENGTH, HSBD_WAVE_COSINE, 9.0,
                              2 * 3.141592653589793, 0, 0);
    if (c->field != BENCH_COSINE) hsbd_field_add(&p.field, tilt);
    hsbd_error err;
    hsbd_rods *r = hsbd_rods_alloc(&p, &err);
    if (!r) return NULL;
    int rc = bench_rods_warm(r, &p);
    for (uint64_t k = 0; k < batch && !rc; ++k)
        rc = hsbd_rods_step(r, NULL) != HSBD_OK;
    if (rc) hsbd_rods_free(r);
    return rc ? NULL : r;
}

/* One system of a case, measured in turns with the case's other variants (bench_turns):
 * the rods or the spheres (the other NULL), the threads it steps on, and what the turns
 * added up. */
typedef struct bench_variant {
    hsbd_rods *rods;
    hsbd_spheres *spheres;
    int threads; /* spheres: set before each turn, so one system can be two variants */
    uint64_t steps;
    double elapsed;
} bench_variant;

/* Steps v in batches for at least `seconds` of `clock`; 0, or -1 when a step fails. */
static int bench_variant_run_for(bench_variant *v, uint64_t batch, double seconds,
                                 double (*clock)(void)) {
    if (v->spheres) hsbd_spheres_set_threads(v->spheres, v->threads);
    const double t0 = clock();
    double t = t0;
    while (t - t0 < seconds) {
        for (uint64_t k = 0; k < batch; ++k)
            if (v->rods ? hsbd_rods_step(v->rods, NULL) != HSBD_OK
                        : hsbd_spheres_step(v->spheres) != HSBD_OK)
                return -1;
        v->steps += batch;
        t = clock();
    }
    v->elapsed += t - t0;
    return 0;
}

/* The variants of a case take BENCH_TURNS turns each, in alternation, of seconds /
 * BENCH_TURNS: this machine's speed drifts by up to 25 % within minutes, and variants run
 * one after the other would see different drifts (a ratio below 1 for the same work was
 * seen so). Every system must be there (non-NULL). 0, or -1 when a step fails. */
enum { BENCH_TURNS = 6 };
static int bench_turns(bench_variant *v, int count, uint64_t batch, double seconds,
                       double (*clock)(void)) {
    for (int k = 0; k < count; ++k)
        if (!v[k].rods && !v[k].spheres) return -1;
    for (int turn = 0; turn < BENCH_TURNS; ++turn)
        for (int k = 0; k < count; ++k)
            if (bench_variant_run_for(&v[k], batch, seconds / BENCH_TURNS, clock)) return -1;
    return 0;
}

/* steps per second (of the turns' clock) of a measured variant */
static double bench_variant_rate(const bench_variant *v) {
    return (double)v->steps / v->elapsed;
}

/* rods steps of a case between two reads of the clock (a batch of about 2e6 rod-steps) */
static uint64_t bench_rods_batch(size_t n) {
    return 1 + (uint64_t)(2e6 / (double)n);
}

/* The rods variants v[0 .. count-1] (filled by the caller) measured in turns; frees them. 0,
 * or -1 when one failed. */
static int bench_rods_turns(bench_variant *v, int count, uint64_t batch, double seconds,
                            double (*clock)(void)) {
    const int rc = bench_turns(v, count, batch, seconds, clock);
    for (int k = 0; k < count; ++k)
        hsbd_rods_free(v[k].rods);
    return rc;
}

static void sphere_bench_threads(const char *only, double seconds, int all, FILE *out);

void hsbd_bench_threads(const char *only, double seconds, FILE *out) {
    const int all = hsbd_threads_available();
    fprintf(out,
            "# rods, default rule (reflect), one thread against all %d threads the process may "
            "use,\n# wall clock, the two in turns; M = 10^6 particle-steps per second; N >= 10^4 "
            "only\n"
            "%-26s %9s %12s %12s %8s\n",
            all, "case", "N", "1 thr. M/s", "all M/s", "speed-up");
    for (size_t k = 0; k < sizeof bench_cases / sizeof bench_cases[0]; ++k) {
        const bench_case *c = &bench_cases[k];
        if ((only && strcmp(only, c->name)) || c->n < 10000) continue;
        const uint64_t batch = bench_rods_batch(c->n);
        bench_variant v[2] = {{.rods = bench_rods_system(c, 1, HSBD_CONTACT_REFLECT, 1, batch)},
                              {.rods = bench_rods_system(c, 1, HSBD_CONTACT_REFLECT, all, batch)}};
        const int rc = bench_rods_turns(v, 2, batch, seconds, wall_seconds);
        const double n = (double)c->n;
        const double one = rc ? NAN : n * bench_variant_rate(&v[0]),
                     many = rc ? NAN : n * bench_variant_rate(&v[1]);
        fprintf(out, "%-26s %9zu %12.1f %12.1f %8.2f\n", c->name, c->n, one / 1e6, many / 1e6,
                many / one);
        fflush(out);
    }
    sphere_bench_threads(only, seconds, all, out);
}

/* EDBD of monodisperse spheres: 3D, D = sigma = 1, from an fcc lattice (2D: disks from a
 * centred rectangular one). */
typedef struct sphere_bench_case {
    const char *name;
    size_t n;
    double phi, dt;
    int sediment; /* walls at z = 0 and L, gravity force -0.5 kT / sigma along z */
    hsbd_spheres_event_order events;
    /* 1: two species alternating, D 1 and 0.5, couplings 1 and 3 (drifts -0.5 and -0.75:
     * the pair rule acts), with the pair rule below */
    int mixture;
    hsbd_pair_rule pair_rule;
    int dimension;
    double v0; /* active particles: propulsion speed (Pe = v0 sigma / D), D_r = 3 */
} sphere_bench_case;

static const sphere_bench_case sphere_bench_cases[] = {
    {"spheres-N4000-phi0.3-dt1e-3", 4000, 0.3, 1e-3, 0, HSBD_EVENTS_AUTO, 0, HSBD_PAIR_EXACT, 3, 0},
    {"spheres-N4000-phi0.3-dt1e-3-sediment", 4000, 0.3, 1e-3, 1, HSBD_EVENTS_AUTO, 0,
     HSBD_PAIR_EXACT, 3, 0},
    /* a sediment whose pairs have relative drifts: the exact pair rule and the mirror */
    {"spheres-N4000-sediment-mix", 4000, 0.3, 1e-3, 1, HSBD_EVENTS_AUTO, 1, HSBD_PAIR_EXACT, 3, 0},
    {"spheres-N4000-sediment-mix-mirror", 4000, 0.3, 1e-3, 1, HSBD_EVENTS_AUTO, 1, HSBD_PAIR_MIRROR,
     3, 0},
    {"spheres-N4000-phi0.3-dt1e-4", 4000, 0.3, 1e-4, 0, HSBD_EVENTS_AUTO, 0, HSBD_PAIR_EXACT, 3, 0},
    {"spheres-N4000-phi0.5-dt1e-3", 4000, 0.5, 1e-3, 0, HSBD_EVENTS_AUTO, 0, HSBD_PAIR_EXACT, 3, 0},
    {"spheres-N4000-phi0.5-dt1e-4", 4000, 0.5, 1e-4, 0, HSBD_EVENTS_AUTO, 0, HSBD_PAIR_EXACT, 3, 0},
    {"spheres-N1e5-phi0.3-dt1e-3", 100000, 0.3, 1e-3, 0, HSBD_EVENTS_AUTO, 0, HSBD_PAIR_EXACT, 3,
     0},
    /* the same with the events group by group (run.events = groups), which run on threads */
    {"spheres-N1e5-phi0.3-dt1e-3-groups", 100000, 0.3, 1e-3, 0, HSBD_EVENTS_GROUPS, 0,
     HSBD_PAIR_EXACT, 3, 0},
    {"spheres-N1e5-phi0.5-dt1e-4", 100000, 0.5, 1e-4, 0, HSBD_EVENTS_AUTO, 0, HSBD_PAIR_EXACT, 3,
     0},
    {"spheres-N1e6-phi0.3-dt1e-3", 1000000, 0.3, 1e-3, 0, HSBD_EVENTS_AUTO, 0, HSBD_PAIR_EXACT, 3,
     0}, /* scaling in N; events by group */
    /* active Brownian disks at the density and Peclet number of motility-induced phase
     * separation (docs/active.md), with the exact pair rule and with the mirror */
    {"active-disks-N4000-phi0.6-Pe100-dt1e-4", 4000, 0.6, 1e-4, 0, HSBD_EVENTS_AUTO, 0,
     HSBD_PAIR_EXACT, 2, 100},
    {"active-disks-N4000-phi0.6-Pe100-dt1e-4-mirror", 4000, 0.6, 1e-4, 0, HSBD_EVENTS_AUTO, 0,
     HSBD_PAIR_MIRROR, 2, 100},
};

/* The case's system on `threads` threads after 0.3 Brownian times of warm-up from the
 * lattice (they melt it and let the neighbour rows reach the capacity the fluid needs: a
 * short warm-up measured a lattice-like state at N 1e5), or NULL. *gravity (empty on
 * entry) must live as long as the system. */
static hsbd_spheres *sphere_bench_system(const sphere_bench_case *c, int hard_core, int threads,
                                         hsbd_field *gravity) {
    const int dim = c->dimension;
    const double pi = 3.14159265358979323846;
    const double side =
        dim == 3 ? cbrt((double)c->n * pi / 6 / c->phi) : sqrt((double)c->n * pi / 4 / c->phi);
    hsbd_field_add(gravity, hsbd_field_tilt(-0.5));
    static const double sp_sigma[2] = {1, 1}, sp_diffusion[2] = {1, 0.5}, sp_coupling[2] = {1, 3};
    int *species = c->mixture ? malloc(c->n * sizeof *species) : NULL;
    if (c->mixture && !species) return NULL;
    for (size_t i = 0; species && i < c->n; ++i)
        species[i] = (int)(i % 2);
    double *v0 = NULL, *dr = NULL;
    if (c->v0 > 0 && (v0 = malloc(2 * c->n * sizeof *v0))) {
        dr = v0 + c->n;
        for (size_t i = 0; i < c->n; ++i)
            v0[i] = c->v0, dr[i] = 3; /* 3 D / sigma^2 */
    }
    if (c->v0 > 0 && !v0) return free(species), NULL;
    const hsbd_spheres_params p = {.n = c->n,
                                   .dimension = dim,
                                   .box = {side, side, side},
                                   .sigma = 1,
                                   .diffusion = 1,
                                   .kT = 1,
                                   .dt = c->dt,
                                   .seed = 1,
                                   .hard_core = hard_core,
                                   .walls = {0, 0, c->sediment},
                                   .field = c->sediment ? gravity : NULL,
                                   .field_axis = 2,
                                   .event_order = c->events,
                                   .threads = threads,
                                   .nspecies = c->mixture ? 2 : 0,
                                   .species = species,
                                   .species_sigma = sp_sigma,
                                   .species_diffusion = sp_diffusion,
                                   .species_coupling = c->mixture ? sp_coupling : NULL,
                                   .pair_rule = c->pair_rule,
                                   .particle_v0 = v0,
                                   .particle_rotational_diffusion = dr};
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&p, &err);
    free(species); /* copied */
    free(v0);
    if (!s || hsbd_spheres_init_lattice(s, &err) != HSBD_OK) {
        hsbd_spheres_free(s);
        return NULL;
    }
    const uint64_t warm = (uint64_t)fmax(5.0 * (1 + 1e6 / (double)c->n), ceil(0.3 / c->dt));
    for (uint64_t k = 0; k < warm; ++k)
        if (hsbd_spheres_step(s) != HSBD_OK) return hsbd_spheres_free(s), NULL;
    return s;
}

/* spheres steps of a case between two reads of the clock (about 1e6 particle-steps) */
static uint64_t sphere_bench_batch(size_t n) {
    return 1 + (uint64_t)(1e6 / (double)n);
}

static void sphere_bench(const char *only, double seconds, FILE *out) {
    int header = 0;
    for (size_t k = 0; k < sizeof sphere_bench_cases / sizeof sphere_bench_cases[0]; ++k) {
        const sphere_bench_case *c = &sphere_bench_cases[k];
        if (only && strcmp(only, c->name)) continue;
        if (!header++)
            fprintf(
                out,
                "# EDBD, 3D monodisperse spheres, D = sigma = 1, from an fcc lattice after 0.3 "
                "Brownian times of warm-up;\n# sediment: walls at z = 0 and L, gravity -0.5 "
                "kT/sigma along z (phi 0.3 on average);\n# sediment-mix: two species "
                "alternating, D 1 and 0.5, couplings 1 and 3, the exact pair rule or the "
                "mirror;\n# active-disks: 2D active Brownian disks, v0 = Pe D / sigma, D_r = 3 D "
                "/ sigma^2 (the free bound with propulsion and rotation);\n# BT/s = Brownian times "
                "(sigma^2/D) simulated per CPU-second; free = "
                "hard core off; the two measured in turns\n"
                "%-30s %7s %9s %9s %10s %9s %9s %7s\n",
                "case", "N", "BT/s", "ns/p-step", "ns/coll", "coll/p-st", "free BT/s", "ratio");
        hsbd_field gravity[2] = {{0}, {0}};
        bench_variant v[2] = {{.spheres = sphere_bench_system(c, 1, 1, &gravity[0]), .threads = 1},
                              {.spheres = sphere_bench_system(c, 0, 1, &gravity[1]), .threads = 1}};
        if (v[0].spheres) hsbd_spheres_reset_stats(v[0].spheres);
        double hard = NAN, free_ = NAN, coll = NAN;
        if (!bench_turns(v, 2, sphere_bench_batch(c->n), seconds, now_seconds)) {
            hard = bench_variant_rate(&v[0]);
            free_ = bench_variant_rate(&v[1]);
            coll = (double)hsbd_spheres_get_stats(v[0].spheres).collisions / (double)v[0].steps;
        }
        hsbd_spheres_free(v[0].spheres);
        hsbd_spheres_free(v[1].spheres);
        const double n = (double)c->n;
        fprintf(out, "%-30s %7zu %9.3f %9.1f %10.1f %9.4f %9.3f %7.2f\n", c->name, c->n,
                hard * c->dt, 1e9 / (hard * n), coll > 0 ? 1e9 / (hard * coll) : NAN, coll / n,
                free_ * c->dt, free_ / hard);
        fflush(out);
    }
}

/* The spheres cases of N >= 10^5 on one thread and on all: one system, warmed up on all
 * threads, then stepped in turns on one thread and on all (the same statistical state). */
static void sphere_bench_threads(const char *only, double seconds, int all, FILE *out) {
    int header = 0;
    for (size_t k = 0; k < sizeof sphere_bench_cases / sizeof sphere_bench_cases[0]; ++k) {
        const sphere_bench_case *c = &sphere_bench_cases[k];
        if ((only && strcmp(only, c->name)) || c->n < 100000) continue;
        if (!header++)
            fprintf(out,
                    "# spheres (the cases above), one thread against all %d threads, wall clock; "
                    "N >= 10^5 only\n%-30s %9s %12s %12s %8s\n",
                    all, "case", "N", "1 thr. ns/ps", "all ns/ps", "speed-up");
        hsbd_field gravity = {0};
        hsbd_spheres *s = sphere_bench_system(c, 1, all, &gravity);
        bench_variant v[2] = {{.spheres = s, .threads = 1}, {.spheres = s, .threads = all}};
        double one = NAN, many = NAN;
        if (!bench_turns(v, 2, sphere_bench_batch(c->n), seconds, wall_seconds))
            one = bench_variant_rate(&v[0]), many = bench_variant_rate(&v[1]);
        hsbd_spheres_free(s);
        const double n = (double)c->n;
        fprintf(out, "%-30s %9zu %12.1f %12.1f %8.2f\n", c->name, c->n, 1e9 / (one * n),
                1e9 / (many * n), many / one);
        fflush(out);
    }
}

void hsbd_bench_list(FILE *out) {
    for (size_t k = 0; k < sizeof bench_cases / sizeof bench_cases[0]; ++k)
        fprintf(out, "%s\n", bench_cases[k].name);
    for (size_t k = 0; k < sizeof sphere_bench_cases / sizeof sphere_bench_cases[0]; ++k)
        fprintf(out, "%s\n", sphere_bench_cases[k].name);
}

int hsbd_bench_has_case(const char *name) {
    for (size_t k = 0; k < sizeof bench_cases / sizeof bench_cases[0]; ++k)
        if (!strcmp(name, bench_cases[k].name)) return 1;
    for (size_t k = 0; k < sizeof sphere_bench_cases / sizeof sphere_bench_cases[0]; ++k)
        if (!strcmp(name, sphere_bench_cases[k].name)) return 1;
    return 0;
}

void hsbd_bench_run(const char *only, double seconds, FILE *out) {
    fprintf(out,
            "# hsbd %s (git %s) bench: BCD step, cosine field U0=6 lambda=1, D=1, dt=1e-4,\n"
            "# one core, CPU time; M = 10^6 particle-steps per CPU-second; reflect = the default "
            "contact rule,\n"
            "# sticky = the paper's rule; free = same system, hard core off; cost = free/hard;\n"
            "# measured after 10 time units of each rule's own dynamics (N > 1000: copies of a\n"
            "# block of 1000 rods so warmed up); the three variants measured in turns\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    fprintf(out, "%-26s %9s %12s %12s %12s %8s %8s\n", "case", "N", "reflect M/s", "sticky M/s",
            "free M/s", "cost", "cost st.");
    for (size_t k = 0; k < sizeof bench_cases / sizeof bench_cases[0]; ++k) {
        const bench_case *c = &bench_cases[k];
        if (only && strcmp(only, c->name)) continue;
        const size_t n = bench_rods_n(c);
        const uint64_t batch = bench_rods_batch(n);
        bench_variant v[3] = {{.rods = bench_rods_system(c, 1, HSBD_CONTACT_REFLECT, 1, batch)},
                              {.rods = bench_rods_system(c, 1, HSBD_CONTACT_STICKY, 1, batch)},
                              {.rods = bench_rods_system(c, 0, HSBD_CONTACT_REFLECT, 1, batch)}};
        const int rc = bench_rods_turns(v, 3, batch, seconds, now_seconds);
        const double reflect = rc ? NAN : (double)n * bench_variant_rate(&v[0]),
                     sticky = rc ? NAN : (double)n * bench_variant_rate(&v[1]),
                     free_ = rc ? NAN : (double)n * bench_variant_rate(&v[2]);
        fprintf(out, "%-26s %9zu %12.1f %12.1f %12.1f %8.2f %8.2f\n", c->name, n, reflect / 1e6,
                sticky / 1e6, free_ / 1e6, free_ / reflect, free_ / sticky);
        fflush(out);
    }
    sphere_bench(only, seconds, out);
}
