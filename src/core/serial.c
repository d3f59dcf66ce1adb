/* Checkpoint serialisation (see serial.h). */
#include "core/serial.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { TAG_LEN = 16 };

void hsbd_writer_init(hsbd_writer *w) {
    memset(w, 0, sizeof *w);
}

void hsbd_writer_free(hsbd_writer *w) {
    free(w->data);
    memset(w, 0, sizeof *w);
}

void hsbd_put_bytes(hsbd_writer *w, const void *p, size_t n) {
    if (w->oom || n == 0) return;
    if (w->len + n > w->cap) {
        size_t cap = w->cap ? w->cap : 4096;
        while (cap < w->len + n)
            cap *= 2;
        unsigned char *d = realloc(w->data, cap);
        if (!d) {
            w->oom = 1;
            return;
        }
        w->data = d, w->cap = cap;
    }
    memcpy(w->data + w->len, p, n);
    w->len += n;
}

void hsbd_put_u64(hsbd_writer *w, uint64_t v) {
    unsigned char b[8];
    for (int k = 0; k < 8; ++k)
        b[k] = (unsigned char)(v >> (8 * k));
    hsbd_put_bytes(w, b, 8);
}

void hsbd_put_i64(hsbd_writer *w, int64_t v) {
    hsbd_put_u64(w, (uint64_t)v);
}

void hsbd_put_f64(hsbd_writer *w, double v) {
    uint64_t u;
    memcpy(&u, &v, sizeof u);
    hsbd_put_u64(w, u);
}

void hsbd_put_tag(hsbd_writer *w, const char *tag) {
    char t[TAG_LEN] = {0};
    snprintf(t, sizeof t, "%s", tag);
    hsbd_put_bytes(w, t, TAG_LEN);
}

/* On little-endian hosts an array's bytes are its serial form: copied at once. */
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
enum { NATIVE_LITTLE_ENDIAN = 1 };
#else
enum { NATIVE_LITTLE_ENDIAN = 0 };
#endif

void hsbd_put_f64s(hsbd_writer *w, const double *v, size_t n) {
    hsbd_put_u64(w, n);
    if (NATIVE_LITTLE_ENDIAN) {
        hsbd_put_bytes(w, v, n * sizeof *v);
        return;
    }
    for (size_t i = 0; i < n; ++i)
        hsbd_put_f64(w, v[i]);
}

void hsbd_put_u64s(hsbd_writer *w, const uint64_t *v, size_t n) {
    hsbd_put_u64(w, n);
    for (size_t i = 0; i < n; ++i)
        hsbd_put_u64(w, v[i]);
}

void hsbd_put_i64s(hsbd_writer *w, const int64_t *v, size_t n) {
    hsbd_put_u64(w, n);
    for (size_t i = 0; i < n; ++i)
        hsbd_put_i64(w, v[i]);
}

void hsbd_put_ints(hsbd_writer *w, const int *v, size_t n) {
    hsbd_put_u64(w, n);
    for (size_t i = 0; i < n; ++i)
        hsbd_put_i64(w, v[i]);
}

void hsbd_put_string(hsbd_writer *w, const char *s) {
    const size_t n = strlen(s);
    hsbd_put_u64(w, n);
    hsbd_put_bytes(w, s, n);
}

void hsbd_reader_init(hsbd_reader *r, const void *data, size_t len) {
    memset(r, 0, sizeof *r);
    r->data = data;
    r->len = len;
}

int hsbd_reader_fail(hsbd_reader *r, const char *why) {
    if (!r->bad) snprintf(r->why, sizeof r->why, "%s (at byte %zu)", why, r->pos);
    r->bad = 1;
    return -1;
}

int hsbd_reader_oom(hsbd_reader *r, const char *what) {
    char why[128];
    snprintf(why, sizeof why, "out of memory for %s", what);
    if (!r->bad) r->oom = 1;
    return hsbd_reader_fail(r, why);
}

int hsbd_get_bytes(hsbd_reader *r, void *p, size_t n) {
    if (r->bad) return -1;
    if (n > r->len - r->pos) return hsbd_reader_fail(r, "the data end early");
    memcpy(p, r->data + r->pos, n);
    r->pos += n;
    return 0;
}

int hsbd_get_u64(hsbd_reader *r, uint64_t *v) {
    unsigned char b[8];
    if (hsbd_get_bytes(r, b, 8)) return -1;
    uint64_t u = 0;
    for (int k = 0; k < 8; ++k)
        u |= (uint64_t)b[k] << (8 * k);
    *v = u;
    return 0;
}

int hsbd_get_i64(hsbd_reader *r, int64_t *v) {
    uint64_t u;
    if (hsbd_get_u64(r, &u)) return -1;
    *v = (int64_t)u;
    return 0;
}

int hsbd_get_f64(hsbd_reader *r, double *v) {
    uint64_t u;
    if (hsbd_get_u64(r, &u)) return -1;
    memcpy(v, &u, sizeof *v);
    return 0;
}

int hsbd_get_tag(hsbd_reader *r, const char *tag) {
    char t[TAG_LEN], want[TAG_LEN] = {0};
    snprintf(want, sizeof want, "%s", tag);
    if (hsbd_get_bytes(r, t, TAG_LEN)) return -1;
    if (memcmp(t, want, TAG_LEN)) {
        char msg[64];
        snprintf(msg, sizeof msg, "section '%s' expected", want);
        return hsbd_reader_fail(r, msg);
    }
    return 0;
}

int hsbd_get_count(hsbd_reader *r, uint64_t want, const char *what) {
    uint64_t n;
    if (hsbd_get_u64(r, &n)) return -1;
    if (n != want) {
        char msg[128];
        snprintf(msg, sizeof msg, "%s: %llu values stored, %llu expected", what,
                 (unsigned long long)n, (unsigned long long)want);
        return hsbd_reader_fail(r, msg);
    }
    return 0;
}

int hsbd_get_f64s(hsbd_reader *r, double *v, size_t n) {
    if (hsbd_get_count(r, n, "array")) return -1;
    if (NATIVE_LITTLE_ENDIAN) return hsbd_get_bytes(r, v, n * sizeof *v);
    for (size_t i = 0; i < n; ++i)
        if (hsbd_get_f64(r, &v[i])) return -1;
    return 0;
}

int hsbd_get_u64s(hsbd_reader *r, uint64_t *v, size_t n) {
    if (hsbd_get_count(r, n, "array")) return -1;
    for (size_t i = 0; i < n; ++i)
        if (hsbd_get_u64(r, &v[i])) return -1;
    return 0;
}

int hsbd_get_i64s(hsbd_reader *r, int64_t *v, size_t n) {
    if (hsbd_get_count(r, n, "array")) return -1;
    for (size_t i = 0; i < n; ++i)
        if (hsbd_get_i64(r, &v[i])) return -1;
    return 0;
}

int hsbd_get_ints(hsbd_reader *r, int *v, size_t n) {
    if (hsbd_get_count(r, n, "array")) return -1;
    for (size_t i = 0; i < n; ++i) {
        int64_t x;
        if (hsbd_get_i64(r, &x)) return -1;
        if (x < -2147483647 - 1 || x > 2147483647) return hsbd_reader_fail(r, "int out of range");
        v[i] = (int)x;
    }
    return 0;
}

int hsbd_get_string(hsbd_reader *r, char *buf, size_t size) {
    uint64_t n;
    if (hsbd_get_u64(r, &n)) return -1;
    if (n >= size) return hsbd_reader_fail(r, "string too long");
    if (hsbd_get_bytes(r, buf, (size_t)n)) return -1;
    buf[n] = '\0';
    return 0;
}

uint64_t hsbd_crc64(uint64_t crc, const void *data, size_t n) {
    const uint64_t poly = 0xC96C5795D7870F42ull; /* ECMA-182, reflected */
    uint64_t table[256];
    for (uint64_t i = 0; i < 256; ++i) {
        uint64_t c = i;
        for (int k = 0; k < 8; ++k)
            c = c & 1 ? (c >> 1) ^ poly : c >> 1;
        table[i] = c;
    }
    const unsigned char *p = data;
    crc = ~crc;
    for (size_t i = 0; i < n; ++i)
        crc = table[(crc ^ p[i]) & 0xff] ^ (crc >> 8);
    return ~crc;
}
