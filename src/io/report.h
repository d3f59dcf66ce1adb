/* Pieces shared by the run drivers' writers (internal to src/io). */
#ifndef HSBD_IO_REPORT_H
#define HSBD_IO_REPORT_H

#include <stdio.h>

#include "hsbd/config.h"

/* "# hsbd <version> (git ...): what", every configuration key, then the column names. */
void hsbd_write_table_header(FILE *f, const hsbd_config *cfg, const char *what,
                             const char *columns);
/* "  "key": value," at the summary's indent; non-finite values as null. */
void hsbd_json_number(FILE *f, const char *key, double v, int comma);

#endif
