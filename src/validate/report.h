/* The validation report: one row per observable of a case, written to validation.tsv and
 * validation.md from one list of columns, so headers and rows always agree. */
#ifndef HSBD_VALIDATE_REPORT_H
#define HSBD_VALIDATE_REPORT_H

#include <stddef.h>
#include <stdio.h>

typedef struct validation_row {
    const char *case_name, *observable, *result; /* result: pass, FAIL or info */
    double dt, t_total;
    size_t points;
    double eff_dof; /* effective points, points^2 / tr R^2 */
    double chi2_dof, max_dev, mean_rel, p_value;
} validation_row;

/* Number of columns of both tables. */
size_t validation_columns(void);
/* The TSV column names line, and the Markdown header with its rule line. */
void validation_write_header(FILE *tsv, FILE *md);
void validation_write_row(FILE *tsv, FILE *md, const validation_row *r);

#endif
