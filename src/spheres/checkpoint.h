/* Checkpoints of the EDBD engine: everything a continued run needs to take the same
 * steps bit for bit. Besides positions, image counters, clock and statistics this is the
 * engine's own history where it enters the arithmetic: the shell centres (a particle's
 * shell exit moves it along its path at that moment, so the shells decide where rounding
 * happens), the internal order of the particles, and the automatic event order's pause.
 * The neighbour lists and cells are built again from the shells (their order does not
 * enter the results). Loaded into an engine allocated with the same parameters. */
#ifndef HSBD_SPHERES_CHECKPOINT_H
#define HSBD_SPHERES_CHECKPOINT_H

#include "core/serial.h"
#include "hsbd/spheres.h"

void hsbd_spheres_save(const hsbd_spheres *s, hsbd_writer *w);
/* -1 (reader bad; oom set when memory ran out) for another system or a state that breaks
 * the engine's invariants (non-finite values, positions outside the box, a label that is
 * not a permutation, overlaps are left to the caller's checks). */
int hsbd_spheres_load(hsbd_spheres *s, hsbd_reader *r);

#endif
