/* Checkpoint files of a run: everything the run needs to continue bit for bit (the
 * configuration, the lifecycle's counters, the model's state and its observers'
 * accumulators, how far each stream file was written), in one file with a CRC-64, written
 * atomically: a temporary file, fsync, the previous checkpoint kept as
 * checkpoint.prev.hsbd, then a rename. */
#ifndef HSBD_RUN_CHECKPOINT_H
#define HSBD_RUN_CHECKPOINT_H

#include "run/run.h"

#define HSBD_CHECKPOINT_FILE "checkpoint.hsbd"
#define HSBD_CHECKPOINT_PREV "checkpoint.prev.hsbd"

int run_checkpoint_write(run *r, hsbd_error *err);
/* The file: magic, format, the payload's length, the payload, its CRC-64 (no copy of the
 * payload is made: it can be most of the run's memory). */
int run_checkpoint_write_file(const char *path, const hsbd_writer *payload, hsbd_error *err);

/* The payload of the newest valid checkpoint in dir (the previous one, with a warning on
 * stderr, when the newest is missing or damaged): size, magic, format and CRC checked.
 * HSBD_EINPUT naming the files and what is wrong with them otherwise. */
typedef struct run_checkpoint_data {
    unsigned char *data;
    size_t len;
    char path[HSBD_PATH_MAX + 32];
    int fell_back; /* the newest was not usable: this is checkpoint.prev.hsbd */
} run_checkpoint_data;
int run_checkpoint_read(const char *dir, run_checkpoint_data *ck, hsbd_error *err);
void run_checkpoint_data_free(run_checkpoint_data *ck);

/* The configuration's source as stored in a checkpoint. */
typedef struct run_source_copy {
    char name[HSBD_PATH_MAX];
    int has_file;
    char *text;
    size_t text_len;
    size_t nsets;
    char (*sets)[HSBD_PATH_MAX + 64];
    char cwd[HSBD_PATH_MAX];
    run_input inputs[RUN_MAX_INPUTS];
    size_t ninputs;
    char model[32], version[64], git[64];
} run_source_copy;
/* Reads the header and the source; the reader is then at the lifecycle's section. */
int run_checkpoint_read_source(hsbd_reader *rd, run_source_copy *src);
void run_source_copy_free(run_source_copy *src);
/* The lifecycle's counters and the streams' lengths (the model follows). */
int run_checkpoint_load_run(run *r, hsbd_reader *rd);
/* Loads the run of the checkpoint in dir as hsbd resume does (the configuration from its
 * source, the model, its state and accumulators, the counters) and releases it, without
 * running or touching the run's files: the status resume would start with (HSBD_EINPUT
 * for a checkpoint it refuses). Checks of hostile checkpoints use it. */
int run_checkpoint_try_load(const char *dir, hsbd_error *err);
/* CRC-64 of a regular file's contents; -1 when it cannot be read or is no regular file. */
int run_file_crc(const char *path, uint64_t *crc);

#endif
