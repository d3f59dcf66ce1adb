/* Shared by the fuzz harnesses (tests/fuzz/fuzz_*.c). Each harness defines the libFuzzer
 * entry point LLVMFuzzerTestOneInput; `make fuzz` links it with libFuzzer (clang), and
 * every build links it with replay.c, which calls it with each file of the harness's
 * corpus (tests/fuzz/corpus/<target>/) under CTest. An input the code refuses is fine; a
 * crash, a sanitizer report, a refusal that is not HSBD_EINPUT with a message naming the
 * input, or more than a second for one input is a finding (the harness aborts on the
 * broken promises). */
#ifndef HSBD_FUZZ_H
#define HSBD_FUZZ_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/config.h"
#include "hsbd/error.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The largest system a harness carries past the reader: the inputs explore the checks,
 * not the machine's memory (hsbd refuses only beyond 80% of physical memory, which a
 * fuzzer's memory limit of 2 GiB would report as a finding). */
enum { FUZZ_MAX_N = 20000 };

/* The input as a read-only stream (an empty input reads as an empty file). */
static inline FILE *fuzz_stream(const uint8_t *data, size_t size) {
    return size ? fmemopen((void *)(uintptr_t)data, size, "r") : fopen("/dev/null", "r");
}

/* A refusal must be bad input, with a message that names `where`. */
static inline void fuzz_expect_refusal(const hsbd_error *err, const char *where) {
    if (err->status != HSBD_EINPUT || !strstr(err->message, where)) {
        fprintf(stderr, "fuzz: refused with status %d and a message without '%s': %s\n",
                err->status, where, err->message);
        abort();
    }
}

/* Small enough to finalise and build (see FUZZ_MAX_N). */
static inline int fuzz_small(const hsbd_config *cfg) {
    return cfg->system.n <= FUZZ_MAX_N;
}

/* A configuration from "section.key=value" assignments on top of the defaults, finalised
 * (aborts when refused: the harness's own setting is wrong). */
static inline void fuzz_configure(hsbd_config *cfg, const char *const *sets, size_t nsets) {
    hsbd_error err;
    hsbd_config_defaults(cfg);
    for (size_t k = 0; k < nsets; ++k)
        if (hsbd_config_set(cfg, sets[k], "fuzz", &err) != HSBD_OK) {
            fprintf(stderr, "fuzz: %s\n", err.message);
            abort();
        }
    if (hsbd_config_finalize(cfg, &err) != HSBD_OK) {
        fprintf(stderr, "fuzz: %s\n", err.message);
        abort();
    }
}

#endif
