/* Fuzz target: a configuration file (hsbd's sections or the authors' section-less keys),
 * read, finalised when small (FUZZ_MAX_N), and written back as headers and JSON. */
#include "fuzz.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static hsbd_config config; /* reused: a fresh 24 kB allocation per input is slow */
    hsbd_config *cfg = &config;
    FILE *in = fuzz_stream(data, size), *sink = fopen("/dev/null", "w");
    if (!in || !sink) abort();
    hsbd_config_defaults(cfg);
    hsbd_error err;
    int rc = hsbd_config_load_stream(cfg, in, "fuzz.ini", &err);
    if (rc != HSBD_OK) fuzz_expect_refusal(&err, "fuzz.ini");
    if (rc == HSBD_OK && fuzz_small(cfg)) {
        rc = hsbd_config_finalize(cfg, &err);
        if (rc != HSBD_OK) fuzz_expect_refusal(&err, "fuzz.ini");
        if (rc == HSBD_OK) {
            hsbd_config_write_header(cfg, sink, "# ");
            hsbd_config_write_json(cfg, sink, 2);
        }
    }
    fclose(in);
    fclose(sink);
    return 0;
}
