/* The validation suite: simulations next to exact theory, with a pass/fail table. */
#ifndef HSBD_VALIDATE_H
#define HSBD_VALIDATE_H

#include "hsbd/export.h"
#include <stdio.h>

#include "hsbd/error.h"

typedef struct hsbd_validate_options {
    const char *out_dir;  /* one run directory per case below it */
    int quick;            /* minutes instead of an hour */
    int jobs;             /* simulations run in parallel (processes) */
    const char *only;     /* run only cases whose name contains this (NULL: all) */
    int dt_scan;          /* add the time-step convergence cases */
    int sticky;           /* run the paper's sticky contact rule instead of the default reflect */
    unsigned seed_offset; /* added to every case's seed: the same grid with other noise */
    int list;             /* only print the cases' names to `report`, one per line */
} hsbd_validate_options;

/* Runs the cases, prints the table to `report`, writes validation.tsv and validation.md
 * into out_dir. Returns HSBD_OK when every case passes, HSBD_ENUMERIC when one fails. */
HSBD_API int hsbd_validate(const hsbd_validate_options *opt, FILE *report, hsbd_error *err);

#endif
