/* Text inputs (internal): files read line by line, lines of any length up to HSBD_LINE_MAX,
 * with every way a file can be unfit for reading (a directory, a NUL byte, a line too long,
 * a read error) reported with the file's name and the line number; strict decimal numbers. */
#ifndef HSBD_CORE_INPUT_H
#define HSBD_CORE_INPUT_H

#include <stddef.h>
#include <stdio.h>

#include "hsbd/error.h"

enum { HSBD_LINE_MAX = 1 << 20 }; /* longest line read, in bytes (1 MiB) */

typedef struct hsbd_lines {
    FILE *f;
    const char *name; /* file name for messages */
    char *text;       /* the current line without its end ("\n" or "\r\n"), NUL-terminated */
    size_t len, cap;
    long number; /* of the current line, from 1 */
} hsbd_lines;

/* fopen(path, "r") for an input named `what` (e.g. "configuration file"); a directory or an
 * unreadable path is HSBD_EINPUT: "cannot read <what> '<path>': <reason>". */
FILE *hsbd_input_open(const char *path, const char *what, hsbd_error *err);

void hsbd_lines_init(hsbd_lines *r, FILE *f, const char *name);
/* The next line into r->text: 1, or 0 at the end of the file, or -1 with err set
 * (HSBD_EINPUT for a NUL byte or a line longer than HSBD_LINE_MAX, HSBD_EIO for a read
 * error). */
int hsbd_lines_next(hsbd_lines *r, hsbd_error *err);
void hsbd_lines_free(hsbd_lines *r);

/* A decimal number at the start of s: [+-] digits [. digits] [(e|E) [+-] digits], or the
 * same with no digit before the point; no hexadecimal, inf or nan. Returns its length
 * (0: none) and its value in *v (+-inf or 0 when out of the double range: check
 * isfinite). */
size_t hsbd_scan_decimal(const char *s, double *v);

#endif
