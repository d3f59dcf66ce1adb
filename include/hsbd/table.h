/* Tabulated functions read from two-column text files (x, value), interpolated by a
 * cubic spline: continuous value and first two derivatives, exact integrals of the
 * interpolant. The spline is natural (zero second derivative at the ends) unless made
 * periodic. Used for tabulated external potentials/forces and pair forces. */
#ifndef HSBD_TABLE_H
#define HSBD_TABLE_H

#include "hsbd/export.h"
#include <stddef.h>
#include <stdio.h>

#include "hsbd/error.h"

typedef struct hsbd_table hsbd_table;

/* From arrays: at least 2 points, finite, strictly increasing x. NULL and HSBD_EINPUT
 * (the message names `what`, e.g. the key) otherwise. */
HSBD_API hsbd_table *hsbd_table_alloc(size_t n, const double *x, const double *y, const char *what,
                                      hsbd_error *err);
/* From a file: '#' comments and blank lines skipped, two decimal numbers per line (further
 * columns ignored). Errors name the file and line. */
HSBD_API hsbd_table *hsbd_table_load(const char *path, hsbd_error *err);
/* The same from an open stream; `name` stands for the file in messages. */
HSBD_API hsbd_table *hsbd_table_read(FILE *f, const char *name, hsbd_error *err);
HSBD_API void hsbd_table_free(hsbd_table *t);
/* Turn the spline into the periodic one over [x_min, x_max] (value and first two
 * derivatives continuous across the ends), for a function of period x_max - x_min. The
 * end values must agree within 1e-9 of the largest |value| (HSBD_EINPUT naming `what`
 * otherwise); the last value is then set to the first. */
HSBD_API int hsbd_table_make_periodic(hsbd_table *t, const char *what, hsbd_error *err);

HSBD_API size_t hsbd_table_size(const hsbd_table *t);
HSBD_API double hsbd_table_x_min(const hsbd_table *t);
HSBD_API double hsbd_table_x_max(const hsbd_table *t);
/* value at the last point (end of the table) */
HSBD_API double hsbd_table_last_value(const hsbd_table *t);
/* Interpolant and its derivative at x (clamped to the table's range). */
HSBD_API double hsbd_table_value(const hsbd_table *t, double x);
HSBD_API double hsbd_table_derivative(const hsbd_table *t, double x);
/* Integral of the interpolant from x_min to x (x clamped to the range). */
HSBD_API double hsbd_table_integral(const hsbd_table *t, double x);

#endif
