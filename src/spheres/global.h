/* The global calendar (internal to src/spheres): one time-ordered calendar for every
 * event of the step in the whole box. */
#ifndef HSBD_SPHERES_GLOBAL_H
#define HSBD_SPHERES_GLOBAL_H

#include "spheres/state.h"

/* Runs every event in s->calendar (started and filled with the step's first events) in
 * time order, with the new predictions each one makes, to the end of the step. Returns
 * 0, or -1 when out of memory (the step is then cut short: the caller fails it). */
int sph_global_run(hsbd_spheres *s);

#endif
