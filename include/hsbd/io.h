/* Files: atomic outputs (temporary name, then rename), input positions, extended-XYZ
 * frames (written as trajectories, read back as initial states). */
#ifndef HSBD_IO_H
#define HSBD_IO_H

#include "hsbd/export.h"
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "hsbd/config.h"
#include "hsbd/error.h"
#include "hsbd/frame.h"
#include "hsbd/rods.h"
#include "hsbd/spheres.h"

/* An output file written under "<name>.part" and renamed to "<name>" on commit, so an
 * interrupted run never leaves a truncated file under the final name. */
typedef struct hsbd_outfile {
    FILE *f;
    char path[HSBD_PATH_MAX + 64];
    char tmp[HSBD_PATH_MAX + 72];
} hsbd_outfile;

HSBD_API int hsbd_outfile_open(hsbd_outfile *o, const char *dir, const char *name, hsbd_error *err);
/* Open an output file again to append to it after its first `length` bytes (a resumed
 * run): its temporary "<name>.part", or the committed "<name>" moved back to that name;
 * anything after `length` (written after the checkpoint) is cut off. HSBD_EINPUT when
 * the file is missing or shorter. */
HSBD_API int hsbd_outfile_reopen(hsbd_outfile *o, const char *dir, const char *name, int64_t length,
                                 hsbd_error *err);
/* Whether hsbd_outfile_reopen would find the file (either name) with at least `length`
 * bytes, touching nothing: HSBD_OK, or HSBD_EINPUT with its message (the reopen's own
 * first check). */
HSBD_API int hsbd_outfile_can_reopen(const char *dir, const char *name, int64_t length,
                                     hsbd_error *err);
/* Flush, fsync, close and rename; reports write errors (disk full...). */
HSBD_API int hsbd_outfile_commit(hsbd_outfile *o, hsbd_error *err);
/* Close and delete the temporary file. */
HSBD_API void hsbd_outfile_discard(hsbd_outfile *o);

/* init.positions of a finalized rods configuration: system.N positions, one per line
 * (blank lines and '#' comment lines allowed); for a mixture each line is 'x name' and
 * species[i] gets the name's index (species may be NULL for one species). Every position
 * lies on the ring, 0 <= x <= L (not wrapped), or between the walls, and with the hard core
 * no two rods overlap; errors name the file and line. */
HSBD_API int hsbd_read_positions(const hsbd_config *cfg, double *x, int *species, hsbd_error *err);
/* The same from an open stream; `name` stands for the file in messages. */
HSBD_API int hsbd_read_positions_stream(FILE *f, const char *name, const hsbd_config *cfg,
                                        double *x, int *species, hsbd_error *err);

/* ---- extended XYZ (src/io/xyz.c) ---- */

/* One extended-XYZ frame: species name, wrapped position, radius, then rods the exact
 * unwrapped position, disks and spheres the image counters, and an id per particle. */
HSBD_API void hsbd_xyz_write(FILE *f, const hsbd_frame *frame);

/* The species name of spheres without species.names */
#define HSBD_XYZ_ONE_SPECIES "S"

/* What a frame read back must match. */
typedef struct hsbd_xyz_expect {
    size_t n;          /* particles (line 1) */
    int dimension;     /* 2 (z = 0) or 3 */
    const double *box; /* 3 lengths: coordinates in [0, box], and the Lattice, when given */
    size_t nspecies;   /* 0: one species named HSBD_XYZ_ONE_SPECIES; else the names */
    const char (*names)[HSBD_SPECIES_NAME];
    const int64_t *count;      /* particles per species, or NULL (not checked) */
    const char *radius_reason; /* non-NULL: a radius column is read (why, for messages) */
} hsbd_xyz_expect;

/* Reads one frame of spheres from f (`name` for messages): line 1 the count, line 2 a
 * comment (its Lattice="..." and Properties=... are checked when present), then one line
 * "name x y z [radius ...]" per particle (z may be left out in 2D), then nothing but blank
 * lines. Fills x (3 n, z = 0 in 2D), species (n) and, when e->radius_reason, radius (n).
 * HSBD_EINPUT with the file and line for anything that does not fit. */
HSBD_API int hsbd_xyz_read_spheres(FILE *f, const char *name, const hsbd_xyz_expect *e, double *x,
                                   int *species, double *radius, hsbd_error *err);
/* init.positions of a finalized spheres configuration: x (3 N), species (N) and, when
 * species.polydispersity > 0, each diameter sigma (N) from the file's radii. */
HSBD_API int hsbd_xyz_read_positions(const hsbd_config *cfg, double *x, int *species, double *sigma,
                                     hsbd_error *err);

/* Active particles: the orientations (3 N unit vectors, z = 0 in 2D) of the frame in
 * init.positions when its Properties=... has an orientation:R:4 column (a quaternion x y z
 * w, as hsbd writes it: e = q (1, 0, 0) q*; in 2D its part in the plane), *found = 1; else
 * *found = 0 and e is untouched. For a file hsbd_xyz_read_positions accepted; HSBD_EINPUT
 * with the file and line for a quaternion that is not one. */
HSBD_API int hsbd_xyz_read_orientations(const hsbd_config *cfg, double *e, int *found,
                                        hsbd_error *err);

/* ---- GSD trajectories (src/io/gsd.c; docs/trajectories.md) ---- */

/* Rods in a GSD file: a 2D box of length L along x and this height along y, the rods at
 * y = 0. */
#define HSBD_GSD_RODS_HEIGHT 1.0

/* A GSD 2.0 file (HOOMD schema 1.4) being written: the layout of its index (all that a
 * checkpoint keeps besides the file's length) and a scratch buffer. */
typedef struct hsbd_gsd {
    FILE *f;
    const char *name;                        /* the file, for messages */
    uint64_t index_location, index_capacity; /* the index block */
    uint64_t entries, frames;                /* written so far */
    uint64_t end;                            /* the file's length */
    unsigned char *buf;
    size_t buf_size;
} hsbd_gsd;

/* A new file in f (opened for update, empty): header, an empty index, the name list;
 * name: the file, for messages (kept, not copied). */
HSBD_API int hsbd_gsd_start(hsbd_gsd *g, FILE *f, const char *name, hsbd_error *err);
/* Continues a file cut back to `length` bytes whose layout (index_location, index_capacity,
 * entries, frames) g holds from the moment it had that length: the header and the unused
 * index entries, written in place since, are restored. */
HSBD_API int hsbd_gsd_continue(hsbd_gsd *g, FILE *f, const char *name, int64_t length,
                               hsbd_error *err);
HSBD_API void hsbd_gsd_free(hsbd_gsd *g);
/* One frame: configuration/step, box, particles/N, position (float32, centred at the
 * origin), image, log/hsbd/time and log/hsbd/position (float64, the same positions);
 * the first frame also configuration/dimensions, particles/types (the species names, or
 * the frame's one_name), typeid, diameter. Rods are a 2D box of height
 * HSBD_GSD_RODS_HEIGHT. */
HSBD_API int hsbd_gsd_write(hsbd_gsd *g, const hsbd_frame *frame, hsbd_error *err);

#endif
