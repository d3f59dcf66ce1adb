/* Checkpoints of the rods engine: the state a step depends on (contact-offset
 * coordinates, the ring's wrap count, step counter, time, the current dt, a mixture's
 * species along the line). The counter-based noise makes the step number the whole
 * random state, so a run continued from a load is bit-identical to one never stopped. */
#ifndef HSBD_RODS1D_CHECKPOINT_H
#define HSBD_RODS1D_CHECKPOINT_H

#include "core/serial.h"
#include "hsbd/rods.h"

void hsbd_rods_save(const hsbd_rods *r, hsbd_writer *w);
/* Into rods allocated with the same parameters; -1 (reader bad) for another shape or a
 * state that breaks the engine's invariants (order, walls, finite values). */
int hsbd_rods_load(hsbd_rods *r, hsbd_reader *rd);

#endif
