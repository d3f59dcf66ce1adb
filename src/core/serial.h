/* Binary serialisation for checkpoints: a growable little-endian writer and a bounds-checked
 * reader. Every read checks the remaining length and, for arrays, that the stored count is
 * the one the reader expects (so a hostile file can never make the reader allocate or
 * index beyond what the configuration already sized); a failed read marks the reader bad
 * and every later read fails too, so callers may check once at the end. */
#ifndef HSBD_CORE_SERIAL_H
#define HSBD_CORE_SERIAL_H

#include <stddef.h>
#include <stdint.h>

#include "hsbd/error.h"

typedef struct hsbd_writer {
    unsigned char *data;
    size_t len, cap;
    int oom; /* an allocation failed: the contents are incomplete */
} hsbd_writer;

void hsbd_writer_init(hsbd_writer *w);
void hsbd_writer_free(hsbd_writer *w);
void hsbd_put_bytes(hsbd_writer *w, const void *p, size_t n);
void hsbd_put_u64(hsbd_writer *w, uint64_t v);
void hsbd_put_i64(hsbd_writer *w, int64_t v);
void hsbd_put_f64(hsbd_writer *w, double v);
/* a section name (at most 15 characters), checked by hsbd_get_tag */
void hsbd_put_tag(hsbd_writer *w, const char *tag);
/* arrays: the count, then the values */
void hsbd_put_f64s(hsbd_writer *w, const double *v, size_t n);
void hsbd_put_u64s(hsbd_writer *w, const uint64_t *v, size_t n);
void hsbd_put_i64s(hsbd_writer *w, const int64_t *v, size_t n);
void hsbd_put_ints(hsbd_writer *w, const int *v, size_t n);
/* a string: its length, then its bytes */
void hsbd_put_string(hsbd_writer *w, const char *s);

typedef struct hsbd_reader {
    const unsigned char *data;
    size_t len, pos;
    int bad;
    int oom;       /* the failure was an allocation, not the data */
    char why[160]; /* the first failure */
} hsbd_reader;

void hsbd_reader_init(hsbd_reader *r, const void *data, size_t len);
/* Each returns 0, or -1 (reader bad) when the data end or do not match. */
int hsbd_get_bytes(hsbd_reader *r, void *p, size_t n);
int hsbd_get_u64(hsbd_reader *r, uint64_t *v);
int hsbd_get_i64(hsbd_reader *r, int64_t *v);
int hsbd_get_f64(hsbd_reader *r, double *v);
int hsbd_get_tag(hsbd_reader *r, const char *tag);
/* arrays of exactly n values (the stored count must be n) */
int hsbd_get_f64s(hsbd_reader *r, double *v, size_t n);
int hsbd_get_u64s(hsbd_reader *r, uint64_t *v, size_t n);
int hsbd_get_i64s(hsbd_reader *r, int64_t *v, size_t n);
int hsbd_get_ints(hsbd_reader *r, int *v, size_t n);
/* a string into buf (refused when it does not fit, with its NUL) */
int hsbd_get_string(hsbd_reader *r, char *buf, size_t size);
/* a stored count that must equal `want` (for the caller's own arrays); -1 otherwise */
int hsbd_get_count(hsbd_reader *r, uint64_t want, const char *what);
/* mark the reader bad with a reason (for checks of values read) */
int hsbd_reader_fail(hsbd_reader *r, const char *why);
/* the same when memory for what was read ran out (HSBD_ENOMEM, not bad data) */
int hsbd_reader_oom(hsbd_reader *r, const char *what);

/* CRC-64 (ECMA-182 polynomial, reflected, as in XZ) of n bytes, continuing from crc
 * (start with 0). */
uint64_t hsbd_crc64(uint64_t crc, const void *data, size_t n);

#endif
