/* Reading the configuration: values of every type, INI files line by line, and
 * "section.key=value" assignments from --set. */
#include "config/schema.h"

#include <errno.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/input.h"

static int in_range(const key_spec *k, double v) {
    if (k->flags & OPEN_MIN ? !(v > k->min) : !(v >= k->min)) return 0;
    if (k->flags & OPEN_MAX ? !(v < k->max) : !(v <= k->max)) return 0;
    return 1;
}

char *config_trim(char *s) {
    while (*s == ' ' || *s == '\t')
        ++s;
    char *e = s + strlen(s);
    while (e > s && (e[-1] == ' ' || e[-1] == '\t' || e[-1] == '\r' || e[-1] == '\n'))
        --e;
    *e = '\0';
    return s;
}

/* Position of the word [w, w + len) in "a|b|c", or -1. */
static int choice_index(const char *choices, const char *w, size_t len) {
    const char *c = choices;
    for (int idx = 0; *c; ++idx) {
        const char *bar = strchr(c, '|');
        const size_t l = bar ? (size_t)(bar - c) : strlen(c);
        if (l == len && !strncmp(w, c, len)) return idx;
        c += l + (bar ? 1 : 0);
    }
    return -1;
}

/* "a+b+c" -> bits of the choices (choice k > 0 is bit k-1; "none" alone is 0); -1 when a
 * term is unknown, repeated or "none" is combined. */
static int parse_terms(const char *choices, const char *v) {
    if (!strcmp(v, "none")) return 0;
    int bits = 0;
    for (const char *w = v;;) {
        const char *plus = strchr(w, '+');
        const size_t len = plus ? (size_t)(plus - w) : strlen(w);
        const int idx = choice_index(choices, w, len);
        if (idx <= 0 || (bits & (1 << (idx - 1)))) return -1;
        bits |= 1 << (idx - 1);
        if (!plus) return bits;
        w = plus + 1;
    }
}

int config_parse_number(const char *v, double *d, const char **why) {
    const char *digits = v + (*v == '+' || *v == '-');
    if (digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X'))
        return *why = "is hexadecimal (only decimal numbers are read)", -1;
    const size_t len = hsbd_scan_decimal(v, d);
    if (len == 0 || v[len] != '\0') return *why = NULL, -1;
    if (digits[0] == '0' && digits[1] >= '0' && digits[1] <= '9')
        return *why = "has a leading zero (octal numbers are not read; leave the zero out)", -1;
    if (!isfinite(*d)) return *why = "is beyond the range of double precision", -1;
    return 0;
}

int config_parse_value(hsbd_config *cfg, const key_spec *k, const char *text, const char *where,
                       hsbd_error *err) {
    char buf[HSBD_PATH_MAX], range[160];
    const char *start = text;
    while (*start == ' ' || *start == '\t')
        ++start;
    if (strlen(start) >= sizeof buf)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: %s.%s: the value is longer than %d characters; allowed: "
                              "shorter values",
                              where, k->section, k->key, HSBD_PATH_MAX - 1);
    strcpy(buf, start);
    char *v = config_trim(buf);
    config_format_range(k, range, sizeof range);
    switch (k->type) {
    case K_INT:
    case K_DOUBLE: {
        double d;
        const char *why;
        if (config_parse_number(v, &d, &why) != 0) {
            if (why)
                return hsbd_error_set(err, HSBD_EINPUT, "%s: %s.%s = '%.60s' %s; allowed: %s",
                                      where, k->section, k->key, v, why, range);
            return hsbd_error_set(
                err, HSBD_EINPUT, "%s: %s.%s = '%.60s' is not a %s number; allowed: %s", where,
                k->section, k->key, v, k->type == K_INT ? "whole" : "finite", range);
        }
        if (k->type == K_INT && d != floor(d))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s = '%.60s' is not a whole number; allowed: %s", where,
                                  k->section, k->key, v, range);
        if (!in_range(k, d))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s = %.60s is out of range; allowed: %s", where,
                                  k->section, k->key, v, range);
        if (k->type == K_INT)
            *(int64_t *)config_slot(cfg, k) = (int64_t)d;
        else
            *(double *)config_slot(cfg, k) = d;
        return HSBD_OK;
    }
    case K_UINT64: {
        const char *digits = v + (*v == '+');
        int ok = *digits != '\0' && strlen(digits) <= 20 && (digits[0] != '0' || !digits[1]);
        for (const char *c = digits; ok && *c; ++c)
            ok = *c >= '0' && *c <= '9';
        errno = 0;
        const unsigned long long u = ok ? strtoull(digits, NULL, 10) : 0;
        if (!ok || errno == ERANGE)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: %s.%s = '%.60s' is not a valid integer; allowed: %s "
                                  "(decimal digits, no leading zero)",
                                  where, k->section, k->key, v, range);
        *(uint64_t *)config_slot(cfg, k) = (uint64_t)u;
        return HSBD_OK;
    }
    case K_STRING:
        strcpy((char *)config_slot(cfg, k), v);
        return HSBD_OK;
    case K_BOOL: {
        static const char *yes[] = {"on", "true", "yes", "1"}, *no[] = {"off", "false", "no", "0"};
        for (int i = 0; i < 4; ++i) {
            if (!strcmp(v, yes[i])) return *(int *)config_slot(cfg, k) = 1, HSBD_OK;
            if (!strcmp(v, no[i])) return *(int *)config_slot(cfg, k) = 0, HSBD_OK;
        }
        return hsbd_error_set(err, HSBD_EINPUT, "%s: %s.%s = '%.60s' is not a switch; allowed: %s",
                              where, k->section, k->key, v, range);
    }
    case K_ENUM:
    case K_TERMS: {
        const int value =
            k->type == K_ENUM ? choice_index(k->choices, v, strlen(v)) : parse_terms(k->choices, v);
        if (value >= 0) return *(int *)config_slot(cfg, k) = value, HSBD_OK;
        return hsbd_error_set(err, HSBD_EINPUT, "%s: %s.%s = '%.60s' is not known; allowed: %s",
                              where, k->section, k->key, v, range);
    }
    }
    return HSBD_OK;
}

void config_format_value(const hsbd_config *cfg, const key_spec *k, char *buf, size_t len) {
    const void *p = config_cslot(cfg, k);
    switch (k->type) {
    case K_INT:
        snprintf(buf, len, "%lld", (long long)*(const int64_t *)p);
        break;
    case K_UINT64:
        snprintf(buf, len, "%llu", (unsigned long long)*(const uint64_t *)p);
        break;
    case K_DOUBLE: { /* shortest text that reads back as the same double */
        const double d = *(const double *)p;
        for (int prec = 6; prec <= 17; ++prec) {
            snprintf(buf, len, "%.*g", prec, d);
            if (strtod(buf, NULL) == d) break;
        }
        break;
    }
    case K_STRING:
        snprintf(buf, len, "%s", (const char *)p);
        break;
    case K_BOOL:
        snprintf(buf, len, "%s", *(const int *)p ? "on" : "off");
        break;
    case K_ENUM: {
        const char *c = k->choices;
        for (int idx = 0; *c; ++idx) {
            const char *bar = strchr(c, '|');
            const int l = bar ? (int)(bar - c) : (int)strlen(c);
            if (idx == *(const int *)p) {
                snprintf(buf, len, "%.*s", l, c);
                return;
            }
            c += l + (bar ? 1 : 0);
        }
        snprintf(buf, len, "?");
        break;
    }
    case K_TERMS: {
        const int bits = *(const int *)p;
        snprintf(buf, len, "none");
        size_t used = 0;
        const char *c = strchr(k->choices, '|') + 1;
        for (int bit = 0; *c; ++bit) {
            const char *bar = strchr(c, '|');
            const int l = bar ? (int)(bar - c) : (int)strlen(c);
            if ((bits & (1 << bit)) && used < len)
                used += (size_t)snprintf(buf + used, len - used, "%s%.*s", used ? "+" : "", l, c);
            c += l + (bar ? 1 : 0);
        }
    }
    }
}

void hsbd_config_defaults(hsbd_config *cfg) {
    memset(cfg, 0, sizeof *cfg); /* and every key's origin: the default */
    for (size_t i = 0; i < config_nkeys; ++i) {
        const key_spec *k = &config_schema[i];
        if (k->def[0] || k->type == K_STRING) config_parse_value(cfg, k, k->def, "default", NULL);
    }
    cfg->sample.period = NAN;    /* derived in finalize unless set */
    cfg->field.center = NAN;     /* L/2 unless set */
    cfg->output.log_every = NAN; /* run.t_total/1000 unless set */
}

/* ---- INI files ---------------------------------------------------------------------- */

int config_assign(ini_state *st, const key_spec *k, const char *value, const char *as) {
    char where[HSBD_ORIGIN_MAX];
    snprintf(where, sizeof where, "%s:%ld", st->path, st->line);
    const size_t idx = config_key_index(k);
    if (st->set_at[idx])
        return hsbd_error_set(st->err, HSBD_EINPUT, "%s: %s is set twice (first at %s)", where, as,
                              config_origin_text(st->cfg, k));
    if (config_parse_value(st->cfg, k, value, where, st->err) != HSBD_OK) return st->err->status;
    st->set_at[idx] = 1;
    st->keys++;
    config_origin_from_file(st->cfg, k, st->path, st->line);
    return HSBD_OK;
}

/* "[name]" (text after ']' only a comment): opens a schema section */
static int open_section(ini_state *st, char *s) {
    char *close = strchr(s, ']');
    const char *rest = close ? config_trim(close + 1) : "";
    if (!close || (*rest && *rest != ';' && *rest != '#'))
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: malformed section line; allowed: '[section]', optionally "
                              "followed by a comment",
                              st->path, st->line);
    *close = '\0';
    const char *name = config_trim(s + 1);
    if (st->first_authors)
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: [%.60s] after the authors' section-less keys (from line "
                              "%ld); allowed: either the authors' keys without sections or hsbd's "
                              "sections, not both in one file",
                              st->path, st->line, name, st->first_authors);
    if (!config_section_known(name)) {
        size_t best;
        const char *near = config_nearest_section(name, &best);
        char sections[256];
        config_section_list(sections, sizeof sections);
        return hsbd_error_set(st->err, HSBD_EINPUT, "%s:%ld: unknown section [%.60s]%s%s%s",
                              st->path, st->line, name,
                              best <= 2 ? "; did you mean [" : "; allowed: ", best <= 2 ? near : "",
                              best <= 2 ? "]?" : sections);
    }
    for (size_t i = 0; i < config_nkeys; ++i) /* the table's own string, alive after the line */
        if (!strcmp(config_schema[i].section, name)) st->section = config_schema[i].section;
    if (!st->first_section) st->first_section = st->line;
    return HSBD_OK;
}

/* "key = value" in the open section, or an authors' key before any section */
static int assign_line(ini_state *st, char *s) {
    char *eq = strchr(s, '=');
    if (!eq)
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: malformed line; allowed: 'key = value', '[section]', or a "
                              "comment starting with '#' or ';'",
                              st->path, st->line);
    *eq = '\0';
    char *key = config_trim(s), *value = config_trim(eq + 1);
    for (char *c = value; *c; ++c) /* inline comments: " ; ..." or " # ..." */
        if ((*c == ';' || *c == '#') && c > value && (c[-1] == ' ' || c[-1] == '\t')) {
            *c = '\0';
            value = config_trim(value);
            break;
        }
    if (!*key)
        return hsbd_error_set(st->err, HSBD_EINPUT,
                              "%s:%ld: a value without a key; allowed: "
                              "'key = value'",
                              st->path, st->line);
    if (!st->section) {
        if (!st->first_authors) st->first_authors = st->line;
        return config_authors_assign(st, key, value);
    }
    const key_spec *k = config_find_key(st->section, key);
    if (!k) {
        char near[256];
        const char *s2 = config_suggest(st->section, key, near, sizeof near);
        const authors_key *a = config_find_authors_key(key);
        char hint[160] = "";
        if (a)
            snprintf(hint, sizeof hint,
                     " ('%s' is the authors' name of %s.%s, read only in "
                     "files without sections)",
                     key, a->section, a->key);
        return hsbd_error_set(
            st->err, HSBD_EINPUT, "%s:%ld: unknown key '%.60s' in section [%s]%s%s%s%s", st->path,
            st->line, key, st->section, s2 ? "; did you mean '" : "", s2 ? s2 : "",
            s2 ? "'?" : (a ? "" : " (hsbd run --help lists all keys)"), hint);
    }
    char as[128];
    snprintf(as, sizeof as, "%s.%s", st->section, key);
    return config_assign(st, k, value, as);
}

/* One line: blank, a comment (the whole line, whatever it holds), a section or a key. */
static int parse_line(ini_state *st, char *text) {
    if (st->line == 1 && !strncmp(text, "\xEF\xBB\xBF", 3)) text += 3; /* UTF-8 mark */
    char *s = config_trim(text);
    if (!*s || *s == ';' || *s == '#') return HSBD_OK;
    for (const char *c = s; *c; ++c)
        if (((unsigned char)*c < 0x20 && *c != '\t') || *c == 0x7f)
            return hsbd_error_set(st->err, HSBD_EINPUT,
                                  "%s:%ld: control character 0x%02x in the line (a binary "
                                  "file?); allowed: text",
                                  st->path, st->line, (unsigned)(unsigned char)*c);
    return *s == '[' ? open_section(st, s) : assign_line(st, s);
}

int hsbd_config_load_stream(hsbd_config *cfg, FILE *f, const char *name, hsbd_error *err) {
    hsbd_error_clear(err);
    ini_state st = {.cfg = cfg, .path = name, .err = err};
    hsbd_lines in;
    hsbd_lines_init(&in, f, name);
    int got, rc = HSBD_OK;
    while (rc == HSBD_OK && (got = hsbd_lines_next(&in, err)) > 0) {
        st.line = in.number;
        rc = parse_line(&st, in.text);
    }
    if (rc == HSBD_OK && got < 0) rc = err->status;
    hsbd_lines_free(&in);
    if (rc != HSBD_OK) return rc;
    if (st.keys == 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: the configuration sets no key (the file is empty, or holds "
                              "only comments and sections); 'hsbd run --defaults' runs the "
                              "defaults without a file",
                              name);
    snprintf(cfg->file, sizeof cfg->file, "%s", name);
    if (st.first_authors) config_authors_finish(cfg);
    return HSBD_OK;
}

int hsbd_config_load_file(hsbd_config *cfg, const char *path, hsbd_error *err) {
    hsbd_error_clear(err);
    FILE *f = hsbd_input_open(path, "configuration file", err);
    if (!f) return err->status;
    const int rc = hsbd_config_load_stream(cfg, f, path, err);
    fclose(f);
    return rc;
}

int hsbd_config_set(hsbd_config *cfg, const char *assignment, const char *origin, hsbd_error *err) {
    hsbd_error_clear(err);
    char buf[HSBD_PATH_MAX + 128];
    if (strlen(assignment) >= sizeof buf)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s: '%.40s...' is longer than %zu characters; allowed: "
                              "section.key=value with a value of at most %d characters",
                              origin, assignment, sizeof buf - 1, HSBD_PATH_MAX - 1);
    for (const char *c = assignment; *c; ++c)
        if (((unsigned char)*c < 0x20 && *c != '\t') || *c == 0x7f)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s: control character 0x%02x at position %d of the "
                                  "assignment; allowed: text",
                                  origin, (unsigned)(unsigned char)*c, (int)(c - assignment) + 1);
    strcpy(buf, assignment);
    char *eq = strchr(buf, '='), *dot = strchr(buf, '.');
    if (!eq || !dot || dot > eq)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s '%.60s': expected section.key=value (e.g. run.t_total=200)",
                              origin, assignment);
    *eq = '\0', *dot = '\0';
    const char *section = config_trim(buf), *key = config_trim(dot + 1), *value = eq + 1;
    const key_spec *k = config_find_key(section, key);
    if (!k) {
        char near[256];
        const char *s = config_suggest(section, key, near, sizeof near);
        return hsbd_error_set(err, HSBD_EINPUT, "%s: unknown key '%.60s.%.60s'%s%s%s", origin,
                              section, key, s ? "; did you mean '" : "", s ? s : "",
                              s ? "'?" : " (hsbd run --help lists all keys)");
    }
    const int rc = config_parse_value(cfg, k, value, origin, err);
    if (rc == HSBD_OK) config_origin_from_set(cfg, k, origin);
    return rc;
}
