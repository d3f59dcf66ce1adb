/* Result tables: TSV files with a '#' header (version, every parameter, the column names), written
 * atomically into the run directory, and the pieces of summary.json. Writers only: the
 * values come from the observers, through the run's models (src/run/). */
#ifndef HSBD_IO_TABLES_H
#define HSBD_IO_TABLES_H

#include <stdio.h>

#include <stdint.h>

#include "hsbd/config.h"
#include "hsbd/error.h"

/* "# hsbd <version> (git ...): what", every configuration key, then "# " and the column
 * names (every header line a comment: numpy.loadtxt reads the table as it is). */
void hsbd_write_table_header(FILE *f, const hsbd_config *cfg, const char *what,
                             const char *columns);
/* Table rows: x[k], then `pairs` value/error columns laid out as val[2 p rows + k] (value)
 * and val[(2 p + 1) rows + k] (error). */
void hsbd_write_value_columns(FILE *f, size_t rows, const double *x, size_t pairs,
                              const double *val);
/* "  "key": value," at the summary's indent; non-finite values as null. */
/* a JSON string literal of s (quotes and control characters escaped) */
void hsbd_json_string(FILE *f, const char *s);
void hsbd_json_number(FILE *f, const char *key, double v, int comma);

/* A table of rows x[k] with `pairs` value/error columns (layout as above), written
 * atomically to dir/name under a header saying `what` and naming the columns. */
int hsbd_write_columns_table(const char *dir, const char *name, const hsbd_config *cfg,
                             const char *what, const char *columns, size_t rows, const double *x,
                             size_t pairs, const double *val, hsbd_error *err);
/* One profile per error block: x = (k + 1/2) width, then block_1 .. block_n columns;
 * val[b rows + k] is block b's value in row k. */
int hsbd_write_blocks_table(const char *dir, const char *name, const hsbd_config *cfg,
                            const char *what, size_t rows, size_t nblocks, double width,
                            const double *val, hsbd_error *err);
/* Lag tables (MSD, F_s): per row the lag t, `pairs` value/error columns (the first one
 * also followed by the origins), rows without origins left out. val[2 p rows + k] and
 * val[(2 p + 1) rows + k] as above. */
int hsbd_write_lag_table(const char *dir, const char *name, const hsbd_config *cfg,
                         const char *what, const char *columns, size_t rows, const double *t,
                         const size_t *origins, size_t pairs, const double *val, hsbd_error *err);
/* "size fraction" rows for sizes 1 .. max */
int hsbd_write_sizes_table(const char *dir, const char *name, const hsbd_config *cfg,
                           const char *what, size_t max, const double *fraction, hsbd_error *err);

/* The status of a run whose own steps succeeded: the writers' error (write_rc, werr), or
 * HSBD_EINTERRUPT naming how far it got when it did not complete, else HSBD_OK. */
int hsbd_run_outcome(const hsbd_config *cfg, int write_rc, const hsbd_error *werr, int completed,
                     uint64_t steps_done, hsbd_error *err);

#endif
