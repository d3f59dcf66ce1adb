/* One configuration of the particles of either model (rods on a line, disks, spheres) as
 * the writers (extended XYZ, GSD), frame-based observers (MSD, F_s, S(k)) and the Python
 * views see it. A frame points into its model's memory: valid until the next step. */
#ifndef HSBD_FRAME_H
#define HSBD_FRAME_H

#include <stddef.h>
#include <stdint.h>

#include "hsbd/config.h"

typedef struct hsbd_frame {
    uint64_t step;
    double time;
    int dimension;        /* 1: rods on a line; 2: disks; 3: spheres */
    size_t n;             /* particles */
    double box[3];        /* box lengths (rods: L along x, 0 for the unused axes) */
    int periodic[3];      /* 1: periodic along the axis; 0: hard walls, or unused */
    const double *x;      /* 3 n positions wrapped into the box (unused coordinates 0) */
    const int64_t *image; /* 3 n image counters (0 across walls and unused axes) */
    /* dimension x n unwrapped coordinates, exact (x + image box would round) */
    const double *unwrapped;
    const double *diameter;                 /* n */
    const int *species;                     /* n species indices, or NULL: one species */
    size_t nspecies;                        /* species of the configuration (0: one, unnamed) */
    const char (*names)[HSBD_SPECIES_NAME]; /* their names, or NULL */
    const char *one_name; /* the particles' name without species: "R" rods, "S" spheres */
    /* active particles: 3 n unit vectors, their orientations (z = 0 in 2D); else NULL */
    const double *orientation;
} hsbd_frame;

#endif
