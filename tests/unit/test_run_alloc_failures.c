/* Every allocation failure of a whole run surfaces as an error: hsbd_run and hsbd_resume
 * of small rods and spheres runs (every observer on, trajectories (rods XYZ, spheres GSD),
 * currents, checkpoints)
 * are made once counting their allocations K, then once for every k from 1 to K with the
 * k-th failing. Checked: the call returns HSBD_ENOMEM exactly when an allocation failed
 * during it (never HSBD_OK after a failure, never a failure without one), and nothing
 * crashes (the ASan build also checks for leaks and use after free on every error path).
 * Linked with -Wl,--wrap=malloc,--wrap=calloc,--wrap=realloc like test_alloc_failures:
 * the library's calls come here first. */
#include <inttypes.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../test_util.h"
#include "hsbd/config.h"
#include "hsbd/run.h"

void *__real_malloc(size_t size);
void *__real_calloc(size_t count, size_t size);
void *__real_realloc(void *p, size_t size);
void *__real_aligned_alloc(size_t alignment, size_t size);
void *__wrap_malloc(size_t size);
void *__wrap_calloc(size_t count, size_t size);
void *__wrap_realloc(void *p, size_t size);
void *__wrap_aligned_alloc(size_t alignment, size_t size);

static uint64_t allocations, fail_at;

static int fails(void) {
    return ++allocations == fail_at;
}
void *__wrap_malloc(size_t size) {
    return fails() ? NULL : __real_malloc(size);
}
void *__wrap_calloc(size_t count, size_t size) {
    return fails() ? NULL : __real_calloc(count, size);
}
void *__wrap_realloc(void *p, size_t size) {
    return fails() ? NULL : __real_realloc(p, size);
}

void *__wrap_aligned_alloc(size_t alignment, size_t size) {
    return fails() ? NULL : __real_aligned_alloc(alignment, size);
}

static const char *const rods_keys[] = {"system.N=20",
                                        "system.L=20",
                                        "field.type=cosine+tilt+harmonic",
                                        "drive.parameter=force",
                                        "drive.wave=cosine",
                                        "drive.amplitude=1",
                                        "drive.period=0.05",
                                        "sample.phases=2",
                                        "field.force=0.2",
                                        "run.dt=1e-3",
                                        "run.t_equil=0.02",
                                        "run.t_total=0.1",
                                        "sample.blocks=4",
                                        "sample.current_every=0.05",
                                        "sample.bin_width=0.1",
                                        "output.trajectory=xyz",
                                        "output.checkpoint_every=0.03"};
static const char *const spheres_keys[] = {"system.model=spheres",
                                           "system.N=60",
                                           "system.packing_fraction=0.2",
                                           "species.names=A,B",
                                           "species.fraction=0.5,0.5",
                                           "species.sigma=1,1.2",
                                           "species.D=1,0.8",
                                           "run.dt=1e-3",
                                           "run.t_equil=0.01",
                                           "run.t_total=0.05",
                                           "sample.blocks=4",
                                           "sample.gr_every=5",
                                           "sample.every=5",
                                           "output.trajectory=gsd",
                                           "output.checkpoint_every=0.02"};

static int build_config(hsbd_config *cfg, const char *const *keys, size_t n, const char *dir) {
    hsbd_error err;
    hsbd_config_defaults(cfg);
    for (size_t k = 0; k < n; ++k)
        if (hsbd_config_set(cfg, keys[k], "test", &err) != HSBD_OK) return -1;
    char out[320];
    snprintf(out, sizeof out, "output.dir=%s", dir);
    if (hsbd_config_set(cfg, out, "test", &err) != HSBD_OK) return -1;
    return hsbd_config_finalize(cfg, &err) == HSBD_OK ? 0 : -1;
}

/* One run (fresh directory) with allocation fail_at failing; returns its status. */
static int run_once(const char *name, const char *const *keys, size_t n, const char *dir,
                    hsbd_error *err) {
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) return -1;
    static hsbd_config cfg;
    fail_at = 0;
    if (build_config(&cfg, keys, n, dir) != 0) return -1;
    hsbd_run_source src = {.name = NULL, .text = "", .text_len = 0, .sets = keys, .nsets = n};
    const hsbd_run_options opt = {.source = &src};
    (void)name;
    return hsbd_run(&cfg, &opt, err);
}

static void sweep(const char *name, const char *const *keys, size_t n, const char *base) {
    char dir[256];
    snprintf(dir, sizeof dir, "%s/%s", base, name);
    hsbd_error err;
    /* the count of a run without failures */
    const uint64_t before = allocations;
    fail_at = 0;
    int rc = run_once(name, keys, n, dir, &err);
    CHECK(rc == HSBD_OK, "%s: the run without failures: %s", name, err.message);
    const uint64_t total = allocations - before;
    int wrong = 0;
    for (uint64_t k = 1; k <= total; ++k) {
        char cmd[512];
        snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
        if (system(cmd) != 0) break;
        static hsbd_config cfg;
        if (build_config(&cfg, keys, n, dir) != 0) break;
        hsbd_run_source src = {.sets = keys, .nsets = n};
        const hsbd_run_options opt = {.source = &src};
        const uint64_t start = allocations;
        fail_at = start + k;
        rc = hsbd_run(&cfg, &opt, &err);
        const int hit = fail_at <= allocations;
        fail_at = 0;
        if (hit ? rc != HSBD_ENOMEM : rc != HSBD_OK) {
            if (wrong++ < 5)
                CHECK(0, "%s, allocation %" PRIu64 " of %" PRIu64 " failing: status %d (%s)", name,
                      k, total, rc, rc ? err.message : "ok");
        }
    }
    printf("  %s: %" PRIu64 " allocations, each failing once: %d wrong\n", name, total, wrong);
    CHECK(wrong == 0, "%s: %d runs reported the wrong status", name, wrong);
}

/* hsbd_resume of a stopped run, with each of its allocations failing in turn. */
static void sweep_resume(const char *base) {
    char dir[256], cmd[1024];
    snprintf(dir, sizeof dir, "%s/resumed", base);
    hsbd_error err;
    const size_t n = sizeof rods_keys / sizeof rods_keys[0];
    CHECK(run_once("resume-source", rods_keys, n, dir, &err) == HSBD_OK, "%s", err.message);
    /* the checkpoint of the finished run, extended */
    snprintf(cmd, sizeof cmd, "cp -r '%s' '%s.copy'", dir, dir);
    CHECK(system(cmd) == 0, "copy");
    const char *sets[1] = {"run.t_total=0.2"};
    const hsbd_run_options opt = {0};
    const uint64_t before = allocations;
    CHECK(hsbd_resume(dir, sets, 1, &opt, &err) == HSBD_OK, "resume: %s", err.message);
    const uint64_t total = allocations - before;
    int wrong = 0;
    for (uint64_t k = 1; k <= total; ++k) {
        snprintf(cmd, sizeof cmd, "rm -rf '%s' && cp -r '%s.copy' '%s'", dir, dir, dir);
        if (system(cmd) != 0) break;
        fail_at = allocations + k;
        const int rc = hsbd_resume(dir, sets, 1, &opt, &err);
        const int hit = fail_at <= allocations;
        fail_at = 0;
        if (hit ? rc != HSBD_ENOMEM : rc != HSBD_OK)
            if (wrong++ < 5)
                CHECK(0, "resume, allocation %" PRIu64 " of %" PRIu64 " failing: status %d (%s)", k,
                      total, rc, rc ? err.message : "ok");
    }
    printf("  resume: %" PRIu64 " allocations, each failing once: %d wrong\n", total, wrong);
    CHECK(wrong == 0, "resume: %d wrong", wrong);
}

int main(void) {
    char base[] = "/tmp/hsbd-run-alloc-XXXXXX";
    CHECK(mkdtemp(base) != NULL, "mkdtemp");
    sweep("rods", rods_keys, sizeof rods_keys / sizeof rods_keys[0], base);
    sweep("spheres", spheres_keys, sizeof spheres_keys / sizeof spheres_keys[0], base);
    sweep_resume(base);
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", base);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", base);
    return test_finish("test_run_alloc_failures");
}
