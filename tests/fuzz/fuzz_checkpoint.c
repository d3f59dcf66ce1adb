/* Fuzz target: the payload of a checkpoint (what follows the magic, format and length, and
 * precedes the CRC-64: a damaged file is refused by its CRC before any of it is read, so
 * the payload is what a hostile file could make hsbd parse). The harness writes it as a
 * checkpoint with a valid CRC into a scratch directory and loads the run from it as
 * `hsbd resume` does, without running it. The payload's git commit is replaced by this
 * build's (another commit only prints a warning), and configurations beyond FUZZ_MAX_N
 * particles are skipped. */
#include "fuzz.h"

#include <stdbool.h>
#include <unistd.h>

#include "hsbd_version.h"
#include "run/checkpoint.h"

/* A scratch directory for the checkpoint file, in memory when the machine has one. */
static char scratch_dir[64];

static void remove_scratch(void) {
    rmdir(scratch_dir);
}

static const char *scratch(void) {
    if (!scratch_dir[0]) {
        snprintf(scratch_dir, sizeof scratch_dir, "%s", "/dev/shm/hsbd-fuzz-XXXXXX");
        if (!mkdtemp(scratch_dir)) {
            snprintf(scratch_dir, sizeof scratch_dir, "%s", "/tmp/hsbd-fuzz-XXXXXX");
            if (!mkdtemp(scratch_dir)) abort();
        }
        atexit(remove_scratch);
    }
    return scratch_dir;
}

/* The configuration the payload's source gives is small (or cannot be read at all). */
static bool source_small(const uint8_t *data, size_t size) {
    hsbd_reader rd;
    hsbd_reader_init(&rd, data, size);
    run_source_copy src;
    const int got = run_checkpoint_read_source(&rd, &src);
    bool small = true;
    hsbd_config *cfg = malloc(sizeof *cfg);
    if (!cfg) abort();
    hsbd_config_defaults(cfg);
    hsbd_error err;
    int rc = HSBD_OK;
    if (got == 0 && src.has_file) {
        FILE *f = fuzz_stream((const uint8_t *)src.text, src.text_len);
        rc = f ? hsbd_config_load_stream(cfg, f, "source", &err) : HSBD_EIO;
        if (f) fclose(f);
    }
    for (size_t k = 0; got == 0 && rc == HSBD_OK && k < src.nsets; ++k)
        rc = hsbd_config_set(cfg, src.sets[k], "source", &err);
    if (got == 0 && rc == HSBD_OK) small = fuzz_small(cfg);
    free(cfg);
    run_source_copy_free(&src);
    return small;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (!source_small(data, size)) return 0;
    hsbd_writer w;
    hsbd_writer_init(&w);
    /* the git commit (header: tag, version, git) becomes this build's */
    hsbd_reader rd;
    hsbd_reader_init(&rd, data, size);
    char text[256];
    size_t start = 0, end = 0;
    if (!hsbd_get_tag(&rd, "header") && !hsbd_get_string(&rd, text, sizeof text)) {
        start = rd.pos;
        if (!hsbd_get_string(&rd, text, sizeof text)) end = rd.pos;
    }
    if (end) {
        hsbd_put_bytes(&w, data, start);
        hsbd_put_string(&w, HSBD_GIT_COMMIT);
        hsbd_put_bytes(&w, data + end, size - end);
    } else {
        hsbd_put_bytes(&w, data, size);
    }
    char path[128];
    snprintf(path, sizeof path, "%s/%s", scratch(), HSBD_CHECKPOINT_FILE);
    hsbd_error err;
    if (w.oom || run_checkpoint_write_file(path, &w, &err) != HSBD_OK) abort();
    hsbd_writer_free(&w);
    const int rc = run_checkpoint_try_load(scratch(), &err);
    if (getenv("FUZZ_VERBOSE"))
        fprintf(stderr, "fuzz: %s\n", rc == HSBD_OK ? "loaded" : err.message);
    if (rc != HSBD_OK && err.status != HSBD_EINPUT) {
        fprintf(stderr, "fuzz: refused with status %d: %s\n", err.status, err.message);
        abort();
    }
    remove(path);
    return 0;
}
