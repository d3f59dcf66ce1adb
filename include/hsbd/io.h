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
/* The head of an extended-XYZ frame: its count *n (with at least that many particle lines
 * after the comment line) and, when the comment line has Lattice="...", its box (*has_box;
 * an axis-aligned lattice of lengths > 0). */
HSBD_API int hsbd_xyz_read_head(FILE *f, const char *name, size_t *n, double box[3], int *has_box,
                                hsbd_error *err);
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

/* ---- GSD input (src/io/gsd_read.c; docs/trajectories.md) ---- */

/* One frame of a GSD file read back: what the HOOMD schema gives a configuration, with
 * the schema's defaults (frame 0's chunk, else its default value) for chunks the frame
 * lacks. Arrays are allocated; hsbd_gsd_snapshot_free releases them. */
typedef struct hsbd_gsd_snapshot {
    uint64_t frame, frames; /* the frame read, and the frames of the file */
    int dimension;          /* configuration/dimensions: 2 or 3 */
    double box[3];          /* Lx Ly Lz of configuration/box (its tilt factors are 0) */
    size_t n, ntypes;       /* particles/N; the names of particles/types */
    char (*types)[HSBD_SPECIES_NAME];
    uint32_t *typeid;    /* n, each < ntypes */
    double *diameter;    /* n, >= 0 (default 1) */
    double *x;           /* 3 n, centred at the origin as stored */
    int exact;           /* x from hsbd's log/hsbd/position (float64), else particles/position */
    double *orientation; /* 4 n quaternions of particles/orientation, or NULL without */
} hsbd_gsd_snapshot;

/* Frame `frame` (-1: the last) of the GSD file at path (GSD 1.x or 2.x): HSBD_EINPUT with
 * the file's name and the reason for a file that is not GSD, is cut short, lacks the
 * positions, has no such frame, a tilted box or values out of range. */
HSBD_API int hsbd_gsd_read(const char *path, int64_t frame, hsbd_gsd_snapshot *s, hsbd_error *err);
/* The same from a seekable stream; `name` stands for the file in messages. */
HSBD_API int hsbd_gsd_read_stream(FILE *f, const char *name, int64_t frame, hsbd_gsd_snapshot *s,
                                  hsbd_error *err);
HSBD_API void hsbd_gsd_snapshot_free(hsbd_gsd_snapshot *s);
/* Whether path names a GSD file: it begins with GSD's magic number, or its name ends in
 * ".gsd" (then reading it says what is wrong). */
HSBD_API int hsbd_gsd_file(const char *path);
/* init.positions of a finalized configuration whose file is GSD (cfg->init.gsd), frame
 * init.frame: the positions moved from the file's box centred at the origin into hsbd's
 * (rods: N values of x, the file's y and z 0; disks and spheres: 3 N, z = 0 in 2D; wrapped
 * along periodic axes), and each particle's species (its type's place in species.names;
 * species may be NULL). Its orientations: hsbd_gsd_read_orientations. */
HSBD_API int hsbd_gsd_read_positions(const hsbd_config *cfg, double *x, int *species,
                                     hsbd_error *err);
/* Active particles: the orientations (3 N unit vectors, z = 0 in 2D) of that frame when it
 * has particles/orientation (quaternions w x y z; e = q (1, 0, 0) q*, HOOMD's body x axis;
 * in 2D its part in the plane), *found = 1; else *found = 0 and e is untouched. HSBD_EINPUT
 * naming the file, frame and particle for a quaternion that is not a rotation. */
HSBD_API int hsbd_gsd_read_orientations(const hsbd_config *cfg, double *e, int *found,
                                        hsbd_error *err);

#endif
