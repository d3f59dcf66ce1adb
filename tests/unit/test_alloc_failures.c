/* Every allocation failure is reported. This executable is linked with
 * -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc (tests/CMakeLists.txt): every call of the
 * static library to those functions comes here first, is counted, and the k-th one can be
 * made to fail. For each small run (allocation, initial state, steps, observers) the run
 * is first made without failures, counting its allocations K; then once for every k from
 * 1 to K with the k-th allocation failing. Checked: the library call during which the
 * failure happened reports it (HSBD_ENOMEM, or NaN from the observers' void results), no
 * call reports a failure that did not happen, and nothing crashes (the ASan build also
 * checks that no error path leaks or touches freed memory). A failed EDBD step must
 * leave the state of its start (positions, image counters, clock, statistics); the run
 * then goes on without failures, and every later step must succeed without overlaps.
 *
 * The rods library is swept the same way (hsbd_rods_alloc, hsbd_rods_set_positions), and
 * hsbd_rods_init_equilibrium and hsbd_rods_step are checked to allocate nothing.
 *
 * The counter and the failing index are globals of this test (the library has none). In
 * the ASan build the wrapped calls reach the sanitizer's malloc through __real_malloc, so
 * the sweep runs there as well, with the same counts, and LeakSanitizer then checks that
 * no error path leaks (checked: dropping one free() on an error path of the spatial sort
 * makes this test fail there). */
#include <inttypes.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../test_util.h"
#include "sphere_checks.h"
#include "hsbd/observe.h"
#include "hsbd/rods.h"
#include "hsbd/spheres.h"

void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t size);
void *__real_aligned_alloc(size_t alignment, size_t size);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t count, size_t size);
void *__wrap_realloc(void *p, size_t size);
void *__wrap_aligned_alloc(size_t alignment, size_t size);

static uint64_t allocations; /* since the start of the process */
static uint64_t fail_at;     /* this allocation fails (0: none) */
static uint64_t run_start;   /* allocations before the current run */
enum { MAX_SITES = 512 };
static void *sites[MAX_SITES]; /* distinct callers seen while counting */
static size_t nsites;
static int record_sites;

static int this_one_fails(void *caller) {
    ++allocations;
    if (record_sites) {
        size_t k = 0;
        while (k < nsites && sites[k] != caller)
            ++k;
        if (k == nsites && nsites < MAX_SITES) sites[nsites++] = caller;
    }
    return allocations == fail_at;
}

void *__wrap_malloc(size_t size) {
    return this_one_fails(__builtin_return_address(0)) ? NULL : __real_malloc(size);
}

void *__wrap_calloc(size_t count, size_t size) {
    return this_one_fails(__builtin_return_address(0)) ? NULL : __real_calloc(count, size);
}

void *__wrap_realloc(void *p, size_t size) {
    return this_one_fails(__builtin_return_address(0)) ? NULL : __real_realloc(p, size);
}

void *__wrap_aligned_alloc(size_t alignment, size_t size) {
    return this_one_fails(__builtin_return_address(0)) ? NULL
                                                       : __real_aligned_alloc(alignment, size);
}

/* After a library call that made the allocations (before, allocations]: it reports a
 * failure exactly when the failing one was among them. Returns 1 when it reported one. */
static int reported(const char *run, uint64_t before, int ok, const char *what) {
    const int hit = fail_at > before && fail_at <= allocations;
    CHECK(ok != hit, "%s, allocation %" PRIu64 " of the run failing: %s %s", run,
          fail_at ? fail_at - run_start : 0, what,
          hit ? "succeeded after a failed allocation" : "failed without a failed allocation");
    return !ok;
}

/* What a user sees of the state: positions, images, clock, statistics. */
static uint64_t view_hash(const hsbd_spheres *s) {
    const hsbd_spheres_view v = hsbd_spheres_get_view(s);
    const hsbd_spheres_stats st = hsbd_spheres_get_stats(s);
    uint64_t h = fnv1a(positions_hash(s), &v.step, sizeof v.step);
    h = fnv1a(h, &v.time, sizeof v.time);
    return fnv1a(h, &st, sizeof st);
}

/* ---- spheres ---- */

enum { INIT_LATTICE, INIT_RANDOM, INIT_COMPRESS, INIT_POSITIONS };
enum { MAX_N = 200 };

typedef struct sphere_case {
    const char *name;
    hsbd_spheres_params par;
    int init, steps, observers;
    const double *positions; /* INIT_POSITIONS, and again after the steps when reinit */
    int reinit;              /* new positions after the steps (the engine's order undone) */
} sphere_case;

static int sphere_init(const sphere_case *c, hsbd_spheres *s, hsbd_error *err) {
    switch (c->init) {
    case INIT_LATTICE:
        return hsbd_spheres_init_lattice(s, err);
    case INIT_RANDOM:
        return hsbd_spheres_init_random(s, err);
    case INIT_COMPRESS:
        return hsbd_spheres_init_compress(s, err);
    default:
        return hsbd_spheres_set_positions(s, c->positions, err);
    }
}

/* g(r) and the MSD of the state after the steps, with their results. Returns 1 when a
 * call reported a failure. */
static int sphere_observers(const char *name, hsbd_spheres *s) {
    static double unwrapped[3 * MAX_N], r[256], g[256], e[256];
    hsbd_error err;
    const hsbd_spheres_view v = hsbd_spheres_get_view(s);
    uint64_t before = allocations;
    hsbd_gr *gr = hsbd_gr_alloc(&v, 2.0, 0.1, 0.2, 2, 4, &err);
    if (reported(name, before, gr != NULL, "hsbd_gr_alloc")) {
        CHECK(err.status == HSBD_ENOMEM, "%s: g(r) alloc status %d", name, err.status);
        return 1;
    }
    before = allocations;
    hsbd_msd *msd = hsbd_msd_alloc(3 * v.n, 1.0, 4, 3.0, 4, 2, &err);
    int failed = reported(name, before, msd != NULL, "hsbd_msd_alloc");
    if (!failed) {
        before = allocations;
        failed = reported(name, before, hsbd_msd_set_wavenumber(msd, 6.0, &err) == HSBD_OK,
                          "hsbd_msd_set_wavenumber");
    }
    for (int k = 0; k < 4 && !failed; ++k) {
        before = allocations;
        failed = reported(name, before, hsbd_gr_sample(gr, &v) == HSBD_OK, "hsbd_gr_sample");
        for (size_t i = 0; i < 3 * v.n; ++i)
            unwrapped[i] = v.x[i] + (double)v.image[i] * v.box[i % 3] + 0.01 * k;
        before = allocations;
        hsbd_msd_sample_values(msd, unwrapped);
        CHECK(allocations == before, "%s: hsbd_msd_sample_values allocates", name);
    }
    if (!failed) {
        double value, error;
        before = allocations;
        hsbd_gr_contact(gr, 0, &value, &error);
        failed = reported(name, before, !isnan(value) && !isnan(error), "hsbd_gr_contact (NaN)");
    }
    if (!failed && hsbd_gr_bins(gr) <= 256) {
        before = allocations;
        hsbd_gr_result(gr, 0, r, g, e);
        int finite = 1;
        for (size_t k = 0; k < hsbd_gr_bins(gr); ++k)
            finite &= !isnan(g[k]) && !isnan(e[k]);
        failed = reported(name, before, finite, "hsbd_gr_result (NaN)");
    }
    if (!failed) {
        double t, m, me;
        size_t origins;
        before = allocations;
        hsbd_msd_result(msd, 0, &t, &m, &me, &origins);
        CHECK(allocations == before, "%s: hsbd_msd_result allocates", name);
        CHECK(!isnan(m), "%s: MSD not finite", name);
    }
    hsbd_msd_free(msd);
    hsbd_gr_free(gr);
    return failed;
}

/* One run; returns 1 when some call reported a failure. */
static int sphere_run(const sphere_case *c) {
    hsbd_error err;
    uint64_t before = allocations;
    hsbd_spheres *s = hsbd_spheres_alloc(&c->par, &err);
    if (reported(c->name, before, s != NULL, "hsbd_spheres_alloc")) {
        CHECK(err.status == HSBD_ENOMEM, "%s: alloc status %d", c->name, err.status);
        return 1;
    }
    before = allocations;
    int rc = sphere_init(c, s, &err);
    int failed = reported(c->name, before, rc == HSBD_OK, "init");
    if (failed) CHECK(rc == HSBD_ENOMEM, "%s: init returned %d: %s", c->name, rc, err.message);
    int step_failed = 0;
    for (int k = 0; k < c->steps && !failed; ++k) {
        const uint64_t at_start = view_hash(s);
        before = allocations;
        rc = hsbd_spheres_step(s);
        if (reported(c->name, before, rc == HSBD_OK, "hsbd_spheres_step")) {
            CHECK(rc == HSBD_ENOMEM, "%s: step returned %d", c->name, rc);
            CHECK(view_hash(s) == at_start,
                  "%s: a failed step changed the state (allocation %" PRIu64
                  " of the run failing, step %d)",
                  c->name, fail_at - run_start, k);
            step_failed = 1;
            --k; /* the same step again: later allocations do not fail */
        }
    }
    if (step_failed) {
        const hsbd_spheres_view v = hsbd_spheres_get_view(s);
        int finite = 0;
        const double gap = brute_min_gap(&v), gap_nb = hsbd_spheres_min_gap(s, &finite);
        CHECK(v.step == (uint64_t)c->steps && finite && gap >= -1e-9 && gap_nb >= gap - 1e-12,
              "%s, allocation %" PRIu64 " of the run failing: after the retried step, step %llu, "
              "min gap %g (neighbour lists %g)",
              c->name, fail_at - run_start, (unsigned long long)v.step, gap, gap_nb);
    }
    if (!failed && c->reinit) {
        before = allocations;
        rc = hsbd_spheres_set_positions(s, c->positions, &err);
        failed = reported(c->name, before, rc == HSBD_OK, "set_positions after the steps");
        before = allocations;
        if (!failed) failed = reported(c->name, before, hsbd_spheres_step(s) == HSBD_OK, "step");
    }
    if (!failed && c->observers) failed = sphere_observers(c->name, s);
    hsbd_spheres_free(s);
    return failed || step_failed;
}

/* The run without failures, then with each of its allocations failing in turn. Returns
 * the number of allocations swept. */
static uint64_t sweep_spheres(const sphere_case *c) {
    fail_at = 0;
    record_sites = 1;
    const size_t sites_before = nsites;
    const uint64_t start = run_start = allocations;
    CHECK(sphere_run(c) == 0, "%s: the run without failures failed", c->name);
    const uint64_t count = allocations - start;
    record_sites = 0;
    size_t reported_runs = 0;
    for (uint64_t k = 1; k <= count; ++k) {
        run_start = allocations;
        fail_at = run_start + k;
        reported_runs += (size_t)sphere_run(c);
        CHECK(allocations >= fail_at, "%s: allocation %" PRIu64 " of %" PRIu64 " never happened",
              c->name, k, count);
    }
    fail_at = 0;
    printf("%s: %" PRIu64 " allocations (%zu new call sites), each failed once: %zu runs "
           "reported it\n",
           c->name, count, nsites - sites_before, reported_runs);
    CHECK(reported_runs == count, "%s: %zu of %" PRIu64 " failures reported", c->name,
          reported_runs, count);
    return count;
}

/* ---- rods ---- */

typedef struct rod_case {
    const char *name;
    hsbd_rods_params par;
    const double *positions; /* NULL: hsbd_rods_init_equilibrium */
    int steps;
} rod_case;

static int rod_run(const rod_case *c) {
    hsbd_error err;
    uint64_t before = allocations;
    hsbd_rods *r = hsbd_rods_alloc(&c->par, &err);
    if (reported(c->name, before, r != NULL, "hsbd_rods_alloc")) {
        CHECK(err.status == HSBD_ENOMEM, "%s: alloc status %d", c->name, err.status);
        return 1;
    }
    int failed = 0;
    before = allocations;
    if (c->positions) {
        const int rc = hsbd_rods_set_positions(r, c->positions, &err);
        failed = reported(c->name, before, rc == HSBD_OK, "hsbd_rods_set_positions");
        if (failed) CHECK(rc == HSBD_ENOMEM, "%s: set_positions returned %d", c->name, rc);
    } else {
        hsbd_rods_init_equilibrium(r);
        CHECK(allocations == before, "%s: hsbd_rods_init_equilibrium allocates", c->name);
    }
    before = allocations;
    for (int k = 0; k < c->steps && !failed; ++k) {
        hsbd_rods_step_stats st;
        CHECK(hsbd_rods_step(r, k % 2 ? &st : NULL) == HSBD_OK, "%s: step", c->name);
    }
    CHECK(allocations == before, "%s: hsbd_rods_step allocates (%" PRIu64 ")", c->name,
          allocations - before);
    hsbd_rods_free(r);
    return failed;
}

static uint64_t sweep_rods(const rod_case *c) {
    fail_at = 0;
    const uint64_t start = run_start = allocations;
    CHECK(rod_run(c) == 0, "%s: the run without failures failed", c->name);
    const uint64_t count = allocations - start;
    size_t reported_runs = 0;
    for (uint64_t k = 1; k <= count; ++k) {
        run_start = allocations;
        fail_at = run_start + k;
        reported_runs += (size_t)rod_run(c);
    }
    fail_at = 0;
    printf("%s: %" PRIu64 " allocations, each failed once: %zu runs reported it\n", c->name, count,
           reported_runs);
    CHECK(reported_runs == count, "%s: %zu of %" PRIu64 " failures reported", c->name,
          reported_runs, count);
    return count;
}

int main(void) {
    const double pi = 3.14159265358979323846;
    uint64_t swept = 0;

    /* spheres: large steps (dt 5e-3: shells left inside the step, sorts every 20 steps) */
    hsbd_spheres_params mono = {.n = 108,
                                .dimension = 3,
                                .sigma = 1,
                                .diffusion = 1,
                                .kT = 1,
                                .dt = 5e-3,
                                .seed = 3,
                                .hard_core = 1,
                                .event_order = HSBD_EVENTS_GLOBAL};
    mono.box[0] = mono.box[1] = mono.box[2] = cbrt(108 * pi / 6 / 0.4);
    static int species[MAX_N];
    for (int i = 0; i < MAX_N; ++i)
        species[i] = i % 3 == 0 ? 1 : i % 29 == 4 ? 2 : 0;
    static const double sp_sigma[3] = {1.0, 1.3, 1.1}, sp_diffusion[3] = {1.0, 0.8, 0.0};
    hsbd_spheres_params mix = mono;
    mix.n = 150, mix.nspecies = 3, mix.species = species, mix.species_sigma = sp_sigma;
    mix.species_diffusion = sp_diffusion, mix.dt = 2e-3, mix.event_order = HSBD_EVENTS_GROUPS;
    mix.box[0] = mix.box[1] = mix.box[2] = cbrt(150 * pi / 6 * (2 + 1.3 * 1.3 * 1.3) / 3 / 0.3);
    hsbd_spheres_params disks = mono;
    disks.n = 120, disks.dimension = 2, disks.dt = 1e-3, disks.event_order = HSBD_EVENTS_AUTO;
    disks.groups_min_n = 1; /* AUTO with groups, handing dense steps to the global calendar */
    disks.box[0] = disks.box[1] = sqrt(120 * pi / 4 / 0.6);
    hsbd_spheres_params dense = mono;
    dense.n = 100, dense.dt = 1e-3, dense.keep_order = 1;
    dense.box[0] = dense.box[1] = dense.box[2] = cbrt(100 * pi / 6 / 0.5);

    /* given positions: a lattice of the same box, taken before the sweeps */
    static double lattice[3 * MAX_N];
    hsbd_error err;
    hsbd_spheres *s = hsbd_spheres_alloc(&mono, &err);
    CHECK(s && hsbd_spheres_init_lattice(s, &err) == HSBD_OK, "lattice positions");
    if (s) memcpy(lattice, hsbd_spheres_get_view(s).x, 3 * mono.n * sizeof *lattice);
    hsbd_spheres_free(s);

    static hsbd_field gravity; /* a mixture between walls on z in gravity */
    hsbd_field_add(&gravity, hsbd_field_tilt(-2.0));
    static const double coupling[3] = {1.0, 2.0, 0.0};
    hsbd_spheres_params walled = mix;
    walled.walls[2] = 1, walled.field = &gravity, walled.field_axis = 2;
    walled.species_coupling = coupling;
    hsbd_spheres_params groups = mono;
    groups.event_order = HSBD_EVENTS_GROUPS;
    groups.dt = 2e-3; /* at 5e-3 the groups percolate and re-run: 5 times the time */
    /* a long box, cut into slabs for the groups' first pass (re-runs inside a slab, and
     * runs undone with the groups they rewound); one thread, since which worker grows its
     * lists first depends on the timing of two (the results do not) */
    hsbd_spheres_params slabs = groups;
    slabs.n = 2400, slabs.threads = 1, slabs.seed = 6;
    slabs.box[0] = slabs.box[1] = 9;
    slabs.box[2] = 2400 * pi / 6 / 0.45 / 81;
    const sphere_case spheres[] = {
        {"spheres phi 0.4, global calendar, g(r) and MSD", mono, INIT_LATTICE, 50, 1, NULL, 0},
        {"spheres phi 0.4, groups, given positions (twice)", groups, INIT_POSITIONS, 50, 0, lattice,
         1},
        {"mixture with an obstacle, groups, random insertion", mix, INIT_RANDOM, 50, 1, NULL, 0},
        {"disks phi 0.6, auto with groups", disks, INIT_LATTICE, 50, 0, NULL, 0},
        {"spheres compressed to phi 0.5", dense, INIT_COMPRESS, 20, 0, NULL, 0},
        {"mixture between walls in gravity, groups", walled, INIT_RANDOM, 50, 0, NULL, 0},
        {"spheres phi 0.45 in a long box, groups in slabs", slabs, INIT_LATTICE, 12, 0, NULL, 0},
    };
    for (size_t k = 0; k < sizeof spheres / sizeof spheres[0]; ++k)
        swept += sweep_spheres(&spheres[k]);

    /* rods: a mixture between walls with the reflecting rule and a field; one species on a
     * ring with pair forces, from given positions */
    static int rod_species[100];
    for (int i = 0; i < 100; ++i)
        rod_species[i] = i % 2;
    static const double rod_sigma[2] = {0.5, 0.3}, rod_diffusion[2] = {1.0, 2.0};
    hsbd_rods_params walls = {.n = 100,
                              .length = 100,
                              .sigma = 0.5,
                              .diffusion = 1,
                              .kT = 1,
                              .dt = 1e-3,
                              .seed = 4,
                              .hard_core = 1,
                              .contact_rule = HSBD_CONTACT_REFLECT,
                              .boundary = HSBD_RODS_WALLS,
                              .nspecies = 2,
                              .species = rod_species,
                              .species_sigma = rod_sigma,
                              .species_diffusion = rod_diffusion};
    hsbd_field_add(&walls.field, hsbd_field_cosine(2.0, 1.0));
    hsbd_rods_params ring = {.n = 100,
                             .length = 100,
                             .sigma = 0.5,
                             .diffusion = 1,
                             .kT = 1,
                             .dt = 1e-3,
                             .seed = 5,
                             .hard_core = 1};
    hsbd_pair_add(&ring.pair, hsbd_pair_yukawa(0.5, 1.0, 2.0, 1.5));
    static double rod_x[100];
    for (int i = 0; i < 100; ++i)
        rod_x[i] = 0.3 + 0.97 * i;
    const rod_case rods[] = {
        {"rods: mixture between walls, reflecting rule", walls, NULL, 200},
        {"rods: ring with pair forces, given positions", ring, rod_x, 200},
    };
    for (size_t k = 0; k < sizeof rods / sizeof rods[0]; ++k)
        swept += sweep_rods(&rods[k]);
    printf("%" PRIu64 " allocations swept, %zu distinct call sites in the spheres runs\n", swept,
           nsites);
    return test_finish("test_alloc_failures");
}
