/* Fuzz target: --set assignments, one per line of the input, applied in order to the
 * defaults; the configuration is then finalised when small (FUZZ_MAX_N). */
#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static hsbd_config config; /* reused: a fresh 24 kB allocation per input is slow */
    hsbd_config *cfg = &config;
    char *text = malloc(size + 1);
    if (!text) abort();
    memcpy(text, data, size);
    text[size] = '\0';
    hsbd_config_defaults(cfg);
    hsbd_error err;
    int rc = HSBD_OK;
    for (char *line = text, *next; rc == HSBD_OK && line; line = next) {
        next = memchr(line, '\n', (size_t)(text + size - line));
        if (next) *next++ = '\0';
        rc = hsbd_config_set(cfg, line, "--set", &err);
        if (rc != HSBD_OK) fuzz_expect_refusal(&err, "--set");
    }
    if (rc == HSBD_OK && fuzz_small(cfg)) {
        rc = hsbd_config_finalize(cfg, &err);
        if (rc != HSBD_OK && err.status != HSBD_EINPUT) fuzz_expect_refusal(&err, "--set");
    }
    free(text);
    return 0;
}
