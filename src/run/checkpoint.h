/* Checkpoint files of a run: everything the run needs to continue bit for bit (the
 * configuration, the lifecycle's counters, the model's state and its observers'
 * accumulators, how far each stream file was written), in one file with a CRC-64, written
 * atomically: a temporary file, fsync, the previous checkpoint kept as
 * checkpoint.prev.hsbd, then a rename. */
#ifndef HSBD_RUN_CHECKPOINT_H
#define HSBD_RUN_CHECKPOINT_H

#include "run/run.h"

/* Wall time between checkpoints when output.checkpoint_every is 0 (seconds). */
#define HSBD_CHECKPOINT_WALL 600.0
#define HSBD_CHECKPOINT_FILE "checkpoint.hsbd"
#define HSBD_CHECKPOINT_PREV "checkpoint.prev.hsbd"

int run_checkpoint_write(run *r, hsbd_error *err);

#endif
