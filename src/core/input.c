/* Text inputs: files, lines and numbers (see core/input.h). */
#include "core/input.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

FILE *hsbd_input_open(const char *path, const char *what, hsbd_error *err) {
    FILE *f = fopen(path, "r");
    if (!f)
        return hsbd_error_set(err, HSBD_EINPUT, "cannot read %s '%s': %s", what, path,
                              strerror(errno)),
               NULL;
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        fclose(f);
        return hsbd_error_set(err, HSBD_EINPUT, "cannot read %s '%s': %s", what, path,
                              strerror(EISDIR)),
               NULL;
    }
    return f;
}

void hsbd_lines_init(hsbd_lines *r, FILE *f, const char *name) {
    memset(r, 0, sizeof *r);
    r->f = f;
    r->name = name;
}

void hsbd_lines_free(hsbd_lines *r) {
    free(r->text);
    r->text = NULL;
    r->len = r->cap = 0;
}

/* append one byte, growing the buffer (doubling); -1 when out of memory */
static int push(hsbd_lines *r, char c) {
    if (r->len + 1 >= r->cap) {
        const size_t cap = r->cap ? 2 * r->cap : 256;
        char *t = realloc(r->text, cap);
        if (!t) return -1;
        r->text = t, r->cap = cap;
    }
    r->text[r->len++] = c;
    return 0;
}

int hsbd_lines_next(hsbd_lines *r, hsbd_error *err) {
    r->len = 0;
    int c = getc_unlocked(r->f);
    if (c == EOF) {
        if (ferror(r->f))
            return hsbd_error_set(err, HSBD_EIO, "%s: read error after line %ld: %s", r->name,
                                  r->number, strerror(errno)),
                   -1;
        return 0;
    }
    ++r->number;
    int nul = 0;
    for (; c != EOF && c != '\n'; c = getc_unlocked(r->f)) {
        if (c == '\0') nul = 1;
        if (r->len >= HSBD_LINE_MAX)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: line longer than %d bytes; allowed: shorter lines",
                                  r->name, r->number, HSBD_LINE_MAX),
                   -1;
        if (push(r, (char)c) != 0)
            return hsbd_error_set(err, HSBD_ENOMEM, "%s:%ld: out of memory", r->name, r->number),
                   -1;
    }
    if (ferror(r->f))
        return hsbd_error_set(err, HSBD_EIO, "%s:%ld: read error: %s", r->name, r->number,
                              strerror(errno)),
               -1;
    if (nul)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:%ld: NUL byte in the line (a binary file?); allowed: text",
                              r->name, r->number),
               -1;
    if (r->len > 0 && r->text[r->len - 1] == '\r') --r->len;
    if (push(r, '\0') != 0)
        return hsbd_error_set(err, HSBD_ENOMEM, "%s:%ld: out of memory", r->name, r->number), -1;
    --r->len;
    return 1;
}

static int is_digit(char c) {
    return c >= '0' && c <= '9';
}

size_t hsbd_scan_decimal(const char *s, double *v) {
    const char *p = s;
    if (*p == '+' || *p == '-') ++p;
    size_t digits = 0;
    for (; is_digit(*p); ++p)
        ++digits;
    if (*p == '.')
        for (++p; is_digit(*p); ++p)
            ++digits;
    if (digits == 0) return 0;
    if (*p == 'e' || *p == 'E') {
        const char *q = p + 1;
        if (*q == '+' || *q == '-') ++q;
        if (is_digit(*q)) {
            while (is_digit(*q))
                ++q;
            p = q;
        }
    }
    /* the grammar is a part of strtod's: the same length means the same number */
    char *end;
    *v = strtod(s, &end);
    return end == p ? (size_t)(p - s) : 0;
}
