/* Files: atomic outputs (temporary name, then rename), run directories, input positions. */
#ifndef HSBD_IO_H
#define HSBD_IO_H

#include <stddef.h>
#include <stdio.h>

#include "hsbd/config.h"
#include "hsbd/error.h"
#include "hsbd/rods.h"

/* An output file written under "<name>.part" and renamed to "<name>" on commit, so an
 * interrupted run never leaves a truncated file under the final name. */
typedef struct hsbd_outfile {
    FILE *f;
    char path[HSBD_PATH_MAX + 64];
    char tmp[HSBD_PATH_MAX + 72];
} hsbd_outfile;

int hsbd_outfile_open(hsbd_outfile *o, const char *dir, const char *name, hsbd_error *err);
/* Flush, fsync, close and rename; reports write errors (disk full...). */
int hsbd_outfile_commit(hsbd_outfile *o, hsbd_error *err);
/* Close and delete the temporary file. */
void hsbd_outfile_discard(hsbd_outfile *o);

/* Create the run directory (and parents). An existing non-empty directory is refused
 * (HSBD_EINPUT) unless force is set. */
int hsbd_run_dir_prepare(const char *dir, int force, hsbd_error *err);

/* Read n positions (one number per line; blank lines and '#' comments allowed); for a
 * mixture (nspecies > 0) each line is 'x name' and species[i] gets the name's index. */
int hsbd_read_positions(const char *path, size_t n, double *x, size_t nspecies,
                        const char (*names)[HSBD_SPECIES_NAME], int *species, hsbd_error *err);

/* One extended-XYZ frame of the rods (wrapped positions, unwrapped column, radius); names:
 * the species names of a mixture (NULL: every rod is "R"). */
void hsbd_xyz_write_rods(FILE *f, const hsbd_rods_view *v, const char (*names)[HSBD_SPECIES_NAME]);

#endif
