/* Pieces shared by the run drivers' writers (internal to src/io). */
#ifndef HSBD_IO_REPORT_H
#define HSBD_IO_REPORT_H

#include <stdio.h>

#include <stdint.h>

#include "hsbd/config.h"
#include "hsbd/error.h"

/* "# hsbd <version> (git ...): what", every configuration key, then the column names. */
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

/* The status of a run whose own steps succeeded: the writers' error (write_rc, werr), or
 * HSBD_EINTERRUPT naming how far it got when it did not complete, else HSBD_OK. */
int hsbd_run_outcome(const hsbd_config *cfg, int write_rc, const hsbd_error *werr, int completed,
                     uint64_t steps_done, hsbd_error *err);

#endif
