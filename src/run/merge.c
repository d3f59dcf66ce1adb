/* The merge of an ensemble's replicas (see hsbd/run.h, docs/scaling.md): the run
 * directories of replicas of one configuration become one result whose means are the
 * replicas' means and whose errors come from their scatter (standard error of the mean
 * over replicas, as sample.blocking = replicas does with blocks). Every sum runs over the
 * replicas in the order of their index, so the bytes depend only on the set of replicas.
 *
 * Each table X.tsv is merged row by row: the first column (abscissa) must agree (cluster
 * size distributions are padded with zeros), a column `c_err` next to a column `c` gets
 * the scatter of `c`, `origins` (counts) are summed, every other column is averaged.
 * X_blocks.tsv gets one column per replica: the replica's value of X. summary.json keeps
 * the values all replicas share, averages the others (with their scatter as KEY_err)
 * and leaves out timings (wall and CPU seconds, rates); nested objects (rods' contacts per species
 * pair) stay in the replicas' summaries, but for the input files' checksums, which must agree.
 * A table must be whole in every replica (every line ended, every cell a number), and every
 * replica must hold the same tables. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/input.h"
#include "hsbd/io.h"
#include "io/files.h"
#include "io/tables.h"
#include "run/run.h"

/* ---- text files as lines ----------------------------------------------------------- */

typedef struct text_lines {
    char *buf;
    char **line;
    size_t n;
    int cut; /* the last line has no newline: the file was cut short */
} text_lines;

static void text_free(text_lines *t) {
    free(t->buf), free(t->line);
    t->buf = NULL, t->line = NULL, t->n = 0;
}

/* The file's lines (without their newlines); -1 when it cannot be read, -2 out of memory,
 * -3 when it is no regular file (a FIFO would block the merge). */
static int text_read(const char *path, text_lines *t) {
    memset(t, 0, sizeof *t);
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return -1;
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) return close(fd), -3;
    FILE *f = fdopen(fd, "rb");
    if (!f) return close(fd), -1;
    size_t cap = 1 << 16, len = 0;
    t->buf = malloc(cap + 1);
    for (size_t got; t->buf && (got = fread(t->buf + len, 1, cap - len, f)) > 0;) {
        len += got;
        if (len == cap) {
            char *b = realloc(t->buf, 2 * cap + 1);
            if (!b) free(t->buf);
            t->buf = b, cap *= 2;
        }
    }
    const int bad = ferror(f);
    fclose(f);
    if (!t->buf) return -2;
    if (bad) return text_free(t), -1;
    t->buf[len] = '\0';
    t->cut = len > 0 && t->buf[len - 1] != '\n';
    size_t lines = 1;
    for (size_t k = 0; k < len; ++k)
        lines += t->buf[k] == '\n';
    t->line = malloc(lines * sizeof *t->line);
    if (!t->line) return text_free(t), -2;
    char *p = t->buf;
    while (*p) {
        t->line[t->n++] = p;
        char *nl = strchr(p, '\n');
        if (!nl) break;
        *nl = '\0';
        p = nl + 1;
    }
    return 0;
}

static int read_in(const char *dir, const char *name, text_lines *t, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    const int rc = text_read(path, t);
    if (rc == -2) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory reading '%s'", path);
    if (rc == -3)
        return hsbd_error_set(err, HSBD_EINPUT, "merge: '%s' is not a regular file", path);
    if (rc != 0)
        return hsbd_error_set(err, HSBD_EINPUT, "merge: cannot read '%s': %s", path,
                              strerror(errno));
    return HSBD_OK;
}

/* ---- the replicas' summaries --------------------------------------------------------- */

typedef struct merge_source {
    const char *dir;
    int lock;       /* its shared lock (run_dir_claim), or -1 */
    long index;     /* run.replica */
    long planned;   /* run.replicas (0: as many as mpirun had ranks) */
    text_lines sum; /* summary.json */
    size_t params;  /* its line `  "parameters": {` */
} merge_source;

/* A summary line `<indent>"key": value`: the key (into key) and the value; NULL if none. */
static const char *json_entry(const char *line, size_t indent, char *key, size_t keylen) {
    for (size_t k = 0; k < indent; ++k)
        if (line[k] != ' ') return NULL;
    if (line[indent] != '"') return NULL;
    const char *q = strchr(line + indent + 1, '"');
    if (!q || q[1] != ':' || q[2] != ' ') return NULL;
    snprintf(key, keylen, "%.*s", (int)(q - line - indent - 1), line + indent + 1);
    return q + 3;
}

/* Parameters that differ between replicas of one configuration (or do not change
 * results: the threads). */
static int replica_parameter(const char *key) {
    return !strcmp(key, "replica") || !strcmp(key, "replicas") || !strcmp(key, "dir") ||
           !strcmp(key, "threads");
}

/* A summary's run.replica value ("-1" or digits, then a comma or the end) into *index. */
static int replica_index(const char *v, long *index) {
    char *end;
    errno = 0;
    *index = strtol(v, &end, 10);
    const int digits = end > v && (v[0] == '-' || (v[0] >= '0' && v[0] <= '9'));
    return digits && errno == 0 && (*end == ',' || *end == '\0') && *index >= -1;
}

static int load_source(merge_source *s, hsbd_error *err) {
    int rc = read_in(s->dir, "summary.json", &s->sum, err);
    char path[HSBD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/summary.json", s->dir);
    if (rc != HSBD_OK && access(path, F_OK) == 0) return rc; /* there, but not readable */
    if (rc != HSBD_OK && run_dir_holds(s->dir, "checkpoint.hsbd"))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: the run in '%s' did not finish (a checkpoint, no "
                              "summary.json: it was stopped); continue it first (hsbd resume %s)",
                              s->dir, s->dir);
    if (rc != HSBD_OK)
        return hsbd_error_set(err, rc,
                              "merge: '%s' holds no readable summary.json: not a run "
                              "directory of hsbd",
                              s->dir);
    if (s->sum.cut)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s/summary.json' ends inside a line: the file was cut "
                              "short",
                              s->dir);
    int completed = 0, found = 0;
    s->params = 0;
    for (size_t k = 0; k < s->sum.n; ++k) {
        char key[64];
        const char *v = json_entry(s->sum.line[k], 2, key, sizeof key);
        if (v && !strcmp(key, "completed")) completed = !strncmp(v, "true", 4);
        if (v && !strcmp(key, "parameters")) s->params = k;
        if (!s->params || k <= s->params || !(v = json_entry(s->sum.line[k], 6, key, sizeof key)))
            continue; /* below: run.replica and run.replicas, in the parameters */
        if (!strcmp(key, "replica")) found = replica_index(v, &s->index) ? 1 : -1;
        if (!strcmp(key, "replicas")) s->planned = strtol(v, NULL, 10);
    }
    if (found < 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s/summary.json' gives run.replica as something other "
                              "than a whole number: the file was edited or damaged",
                              s->dir);
    if (!s->params || !found)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s/summary.json' has no parameters with run.replica: not "
                              "a run of this hsbd",
                              s->dir);
    if (!completed)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: the run in '%s' did not complete; continue it first "
                              "(hsbd resume %s)",
                              s->dir, s->dir);
    if (s->index < 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' is no replica of an ensemble (run.replica = -1); run "
                              "replicas with hsbd run CONFIG --replica K",
                              s->dir);
    return HSBD_OK;
}

/* a value without its trailing comma */
static int value_len(const char *v) {
    const size_t len = strlen(v);
    return (int)(len && v[len - 1] == ',' ? len - 1 : len);
}

/* The value of top-level key in summary s as text (NULL if absent). */
static const char *summary_value(const merge_source *s, const char *key) {
    for (size_t k = 1; k < s->params; ++k) {
        char kk[64];
        const char *v = json_entry(s->sum.line[k], 2, kk, sizeof kk);
        if (v && !strcmp(kk, key)) return v;
    }
    return NULL;
}

/* The checksums of the input files a run read (its summary's "input_checksums"), or "". */
static const char *input_checksums(const merge_source *s) {
    const char *v = summary_value(s, "input_checksums");
    return v ? v : "";
}

/* The replicas read the same bytes from their input files (field or pair tables, initial
 * positions): the parameters name the files, not what they held. */
static int same_inputs(const merge_source *a, const merge_source *b, hsbd_error *err) {
    const char *ia = input_checksums(a), *ib = input_checksums(b);
    if (!strcmp(ia, ib)) return HSBD_OK;
    const int la = ia[0] ? value_len(ia) : 4, lb = ib[0] ? value_len(ib) : 4;
    return hsbd_error_set(err, HSBD_EINPUT,
                          "merge: '%s' and '%s' read different contents of their input files "
                          "(checksums %.*s in the first, %.*s in the second); only runs of the "
                          "same input can be merged",
                          a->dir, b->dir, la > 300 ? 300 : la, ia[0] ? ia : "none",
                          lb > 300 ? 300 : lb, ib[0] ? ib : "none");
}

/* The replicas were made by one build of hsbd (the summaries' version and git): another
 * build may give other results, and the merged files name one. */
static int same_build(const merge_source *a, const merge_source *b, hsbd_error *err) {
    static const char *const keys[] = {"version", "git"};
    for (size_t k = 0; k < 2; ++k) {
        const char *va = summary_value(a, keys[k]), *vb = summary_value(b, keys[k]);
        if (!va) va = "none";
        if (!vb) vb = "none";
        const int la = value_len(va), lb = value_len(vb);
        if (la == lb && !strncmp(va, vb, (size_t)la)) continue;
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' and '%s' were made by different builds of hsbd (%s "
                              "%.*s in the first, %.*s in the second); another build may give "
                              "other results: run all replicas with one build",
                              a->dir, b->dir, keys[k], la > 80 ? 80 : la, va, lb > 80 ? 80 : lb,
                              vb);
    }
    return HSBD_OK;
}

static int by_index(const void *a, const void *b) {
    const long x = ((const merge_source *)a)->index, y = ((const merge_source *)b)->index;
    return (x > y) - (x < y);
}

/* The section.key of summary line k of a's parameters (indent 6, inside a section at
 * indent 4), and its value without the trailing comma, for messages. */
static void parameter_at(const merge_source *a, size_t k, char *name, size_t len, const char **val,
                         int *vlen) {
    char key[64] = "", section[64] = "";
    *val = "(none)";
    *vlen = 6;
    if (k >= a->sum.n) {
        snprintf(name, len, "(the end of the parameters)");
        return;
    }
    const char *v = json_entry(a->sum.line[k], 6, key, sizeof key);
    for (size_t j = k; j > a->params && !section[0]; --j)
        json_entry(a->sum.line[j], 4, section, sizeof section);
    if (!v) {
        snprintf(name, len, "%s (a section)", section[0] ? section : key);
        return;
    }
    snprintf(name, len, "%s%s%s", section, section[0] ? "." : "", key);
    *val = v;
    *vlen = value_len(v);
}

/* The names of the parameters that differ after lines i of a and j of b, while both list
 * the same parameters, as "; also: x.y, ..." (empty when none): a derived value that
 * differs (a default box centre, say) comes before the key the user set in the summary's
 * order, so the message names them all. */
static void other_differences(const merge_source *a, const merge_source *b, size_t i, size_t j,
                              char *out, size_t len) {
    char ka[64], kb[64], name[140];
    const char *v;
    int vlen, listed = 0;
    size_t used = 0;
    out[0] = '\0';
    for (; i < a->sum.n && j < b->sum.n; ++i, ++j) {
        const int pa = json_entry(a->sum.line[i], 6, ka, sizeof ka) != NULL;
        const int pb = json_entry(b->sum.line[j], 6, kb, sizeof kb) != NULL;
        if (pa != pb || (pa && strcmp(ka, kb))) break; /* the lists part: stop there */
        if (!pa || replica_parameter(ka) || !strcmp(a->sum.line[i], b->sum.line[j])) continue;
        parameter_at(a, i, name, sizeof name, &v, &vlen);
        const int n = snprintf(out + used, len - used, "%s%s", listed++ ? ", " : "; also: ", name);
        if (n < 0 || (size_t)n >= len - used) break;
        used += (size_t)n;
    }
}

/* The same configuration: every parameter but the replica's own (index, count, dir). */
static int same_parameters(const merge_source *a, const merge_source *b, hsbd_error *err) {
    size_t i = a->params, j = b->params;
    char ka[64], kb[64];
    for (;; ++i, ++j) {
        while (i < a->sum.n && json_entry(a->sum.line[i], 6, ka, sizeof ka) &&
               replica_parameter(ka))
            ++i;
        while (j < b->sum.n && json_entry(b->sum.line[j], 6, kb, sizeof kb) &&
               replica_parameter(kb))
            ++j;
        if (i == a->sum.n || j == b->sum.n) break;
        if (strcmp(a->sum.line[i], b->sum.line[j])) break;
    }
    if (i == a->sum.n && j == b->sum.n) return HSBD_OK;
    char na[140], nb[140];
    const char *va, *vb;
    int la, lb;
    parameter_at(a, i, na, sizeof na, &va, &la);
    parameter_at(b, j, nb, sizeof nb, &vb, &lb);
    if (strcmp(na, nb))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' and '%s' are not replicas of one configuration: their "
                              "parameters differ at %s in the first and %s in the second; only "
                              "runs of the same configuration (apart from run.replica) can be "
                              "merged",
                              a->dir, b->dir, na, nb);
    char others[400];
    other_differences(a, b, i + 1, j + 1, others, sizeof others);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "merge: '%s' and '%s' are not replicas of one configuration: %s = "
                          "%.*s in the first, %.*s in the second%s; only runs of the same "
                          "configuration (apart from run.replica) can be merged",
                          a->dir, b->dir, na, la > 200 ? 200 : la, va, lb > 200 ? 200 : lb, vb,
                          others);
}

/* ---- tables ----------------------------------------------------------------------------- */

/* mean and standard error of the mean of v[0..n-1], summed in order */
static void mean_and_error(const double *v, size_t n, double *mean, double *err) {
    double s = 0;
    for (size_t k = 0; k < n; ++k)
        s += v[k];
    const double m = s / (double)n;
    double q = 0;
    for (size_t k = 0; k < n; ++k)
        q += (v[k] - m) * (v[k] - m);
    *mean = m;
    *err = n > 1 ? sqrt(q / ((double)n * (double)(n - 1))) : NAN;
}

static size_t comment_lines(const text_lines *t) {
    size_t c = 0;
    while (c < t->n && t->line[c][0] == '#')
        ++c;
    return c;
}

static int replica_comment(const char *line) {
    return !strncmp(line, "# run.replica = ", 16) || !strncmp(line, "# run.replicas = ", 17);
}

/* The header lines of a merged table: the first line's description with `what_more`, the
 * configuration lines (the replica's own with the ensemble's values). */
static void write_comments(FILE *f, const text_lines *t, size_t nreplicas, const char *what) {
    const size_t c = comment_lines(t);
    const char *colon = strstr(t->line[0], "): ");
    if (what && colon)
        fprintf(f, "%.*s): %s\n", (int)(colon - t->line[0]), t->line[0], what);
    else
        fprintf(f,
                "%s; merged over %zu replicas: means of the replicas' values, errors from "
                "their scatter\n",
                t->line[0], nreplicas);
    for (size_t k = 1; k < c; ++k) {
        if (!strncmp(t->line[k], "# run.replica = ", 16))
            fprintf(f, "# run.replica = -1\n");
        else if (!strncmp(t->line[k], "# run.replicas = ", 17))
            fprintf(f, "# run.replicas = %zu\n", nreplicas);
        else
            fprintf(f, "%s\n", t->line[k]);
    }
}

/* The tables of the replicas agree in their headers (configuration and columns). */
static int same_header(const text_lines *a, const text_lines *b, const char *dira, const char *dirb,
                       const char *name, hsbd_error *err) {
    const size_t ca = comment_lines(a), cb = comment_lines(b);
    size_t i = 1, j = 1;
    for (;; ++i, ++j) {
        while (i < ca && replica_comment(a->line[i]))
            ++i;
        while (j < cb && replica_comment(b->line[j]))
            ++j;
        if (i >= ca || j >= cb || strcmp(a->line[i], b->line[j])) break;
    }
    if (i >= ca && j >= cb && ca < a->n && cb < b->n && !strcmp(a->line[ca], b->line[cb]))
        return HSBD_OK;
    return hsbd_error_set(err, HSBD_EINPUT,
                          "merge: %s of '%s' and of '%s' differ in their header (%.200s); only "
                          "runs of the same configuration can be merged",
                          name, dira, dirb, i < ca ? a->line[i] + 2 : "the columns");
}

/* Splits a row at tabs into at most max cells; returns the count. */
static size_t split_tabs(char *row, char **cell, size_t max) {
    size_t n = 0;
    for (char *p = row; n < max;) {
        cell[n++] = p;
        char *t = strchr(p, '\t');
        if (!t) break;
        *t = '\0';
        p = t + 1;
    }
    return n;
}

/* cells of a row: its tabs plus one */
static size_t count_cells(const char *row) {
    size_t n = 1;
    for (const char *p = row; (p = strchr(p, '\t')); ++p)
        ++n;
    return n;
}

enum column_kind { COLUMN_MEAN, COLUMN_ERROR, COLUMN_COUNT };

/* One table of every replica: its values as numbers, rows x columns each. */
typedef struct table_set {
    text_lines *text;
    size_t *comments;      /* [replica]: its comment lines (the header, configuration) */
    size_t ncol, rows;     /* rows of the longest */
    char **names;          /* [ncol] */
    int *kind;             /* [ncol] */
    size_t *base;          /* [ncol] COLUMN_ERROR: its value column */
    char **cell;           /* [ncol + 1] a row's cells */
    double *val;           /* [replica][row][column], zero-padded */
    const char **abscissa; /* [row]: the first column of the longest */
} table_set;

static void table_set_free(table_set *t, size_t n) {
    for (size_t k = 0; t->text && k < n; ++k)
        text_free(&t->text[k]);
    free(t->text), free(t->comments), free(t->val), free(t->abscissa);
    free(t->names), free(t->kind), free(t->base), free(t->cell);
}

static void classify_columns(table_set *t) {
    for (size_t j = 1; j < t->ncol; ++j) {
        t->kind[j] = !strcmp(t->names[j], "origins") ? COLUMN_COUNT : COLUMN_MEAN;
        const size_t len = strlen(t->names[j]);
        if (len <= 4 || strcmp(t->names[j] + len - 4, "_err")) continue;
        for (size_t b = 1; b < t->ncol; ++b)
            if (strlen(t->names[b]) == len - 4 && !strncmp(t->names[b], t->names[j], len - 4))
                t->kind[j] = COLUMN_ERROR, t->base[j] = b;
    }
}

/* Reads table `name` of replica k into t->text[k]: a whole table of hsbd (comments, a
 * line of columns, every line ended) whose header agrees with replica 0's. */
static int read_table(const char *name, const merge_source *src, size_t k, table_set *t,
                      hsbd_error *err) {
    int rc = read_in(src[k].dir, name, &t->text[k], err);
    if (rc != HSBD_OK) return rc;
    const text_lines *tx = &t->text[k];
    t->comments[k] = comment_lines(tx);
    if (t->comments[k] == 0 || t->comments[k] >= tx->n)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s/%s' is not a table of hsbd (no header or no columns)",
                              src[k].dir, name);
    if (tx->cut)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s/%s' ends inside line %zu: the file was cut short",
                              src[k].dir, name, tx->n);
    return k > 0 ? same_header(&t->text[0], &t->text[k], src[0].dir, src[k].dir, name, err)
                 : HSBD_OK;
}

/* The columns of the table from replica 0's line of names. */
static int table_columns(table_set *t, hsbd_error *err) {
    char *header = t->text[0].line[t->comments[0]];
    t->ncol = count_cells(header);
    t->names = calloc(t->ncol, sizeof *t->names);
    t->kind = calloc(t->ncol, sizeof *t->kind);
    t->base = calloc(t->ncol, sizeof *t->base);
    t->cell = calloc(t->ncol + 1, sizeof *t->cell);
    if (!t->names || !t->kind || !t->base || !t->cell)
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    split_tabs(header, t->names, t->ncol);
    classify_columns(t);
    return HSBD_OK;
}

/* A cell as the tables write it (printf's %g): a decimal number, or nan, -nan, inf, -inf
 * (an estimate without data); nothing before or after it. */
static int table_number(const char *cell, double *v) {
    static const char *const special[] = {"nan", "-nan", "inf", "-inf"};
    static const double value[] = {NAN, NAN, INFINITY, -INFINITY};
    for (size_t k = 0; k < 4; ++k)
        if (!strcmp(cell, special[k])) return *v = value[k], 1;
    const size_t len = hsbd_scan_decimal(cell, v);
    return len > 0 && cell[len] == '\0' && isfinite(*v);
}

/* Row i of replica k's table into t->val: ncol cells, each a whole number. */
static int parse_row(table_set *t, const char *name, const merge_source *src, size_t k, size_t i,
                     hsbd_error *err) {
    const size_t line = t->comments[k] + 1 + i; /* 0-based */
    const size_t nc = split_tabs(t->text[k].line[line], t->cell, t->ncol + 1);
    if (nc != t->ncol)
        return hsbd_error_set(err, HSBD_EINPUT, "merge: '%s/%s' line %zu has %zu columns, not %zu",
                              src[k].dir, name, line + 1, nc, t->ncol);
    for (size_t j = 1; j < nc; ++j) {
        double v;
        if (!table_number(t->cell[j], &v))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "merge: '%s/%s' line %zu, column %s: '%.40s' is not a number",
                                  src[k].dir, name, line + 1, t->names[j], t->cell[j]);
        t->val[(k * t->rows + i) * t->ncol + j] = v;
    }
    return HSBD_OK;
}

/* Reads table `name` of every replica into t. Rows must agree in their first column;
 * size distributions (padded) may be longer in some replicas. */
static int load_tables(const char *name, const merge_source *src, size_t n, table_set *t,
                       hsbd_error *err) {
    memset(t, 0, sizeof *t);
    t->text = calloc(n, sizeof *t->text);
    t->comments = calloc(n, sizeof *t->comments);
    if (!t->text || !t->comments) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < n && rc == HSBD_OK; ++k)
        rc = read_table(name, src, k, t, err);
    if (rc == HSBD_OK) rc = table_columns(t, err);
    if (rc != HSBD_OK) return rc;
    size_t longest = 0;
    for (size_t k = 0; k < n; ++k) {
        const size_t r = t->text[k].n - t->comments[k] - 1;
        if (r > t->rows) t->rows = r, longest = k;
    }
    t->val = calloc(n * (t->rows ? t->rows : 1) * t->ncol, sizeof *t->val);
    t->abscissa = calloc(t->rows ? t->rows : 1, sizeof *t->abscissa);
    if (!t->val || !t->abscissa) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const int padded = !strcmp(name, "clusters.tsv");
    for (size_t k = 0; k < n && rc == HSBD_OK; ++k) {
        const size_t r = t->text[k].n - t->comments[k] - 1;
        if (r != t->rows && !padded)
            rc = hsbd_error_set(err, HSBD_EINPUT, "merge: %s has %zu rows in '%s' and %zu in '%s'",
                                name, r, src[k].dir, t->rows, src[longest].dir);
        for (size_t i = 0; i < r && rc == HSBD_OK; ++i) {
            rc = parse_row(t, name, src, k, i, err);
            if (k == longest) t->abscissa[i] = t->cell[0];
        }
    }
    /* a size distribution is whole: its fractions add up to 1 (rows lost at its end would
     * pass every other test; the table's 10 digits leave sums within 1e-9 of 1) */
    for (size_t k = 0; k < n && rc == HSBD_OK && padded && t->ncol == 2; ++k) {
        double sum = 0;
        for (size_t i = 0; i < t->rows; ++i)
            sum += t->val[(k * t->rows + i) * t->ncol + 1];
        if (!(fabs(sum - 1) <= 1e-6))
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "merge: the fractions of '%s/%s' add up to %.10g, not 1: the "
                                "table is not whole",
                                src[k].dir, name, sum);
    }
    /* the abscissae agree row by row */
    for (size_t k = 0; k < n && rc == HSBD_OK; ++k) {
        const size_t c = t->comments[k], r = t->text[k].n - c - 1;
        for (size_t i = 0; i < r && rc == HSBD_OK; ++i)
            if (strcmp(t->text[k].line[c + 1 + i], t->abscissa[i]))
                rc = hsbd_error_set(err, HSBD_EINPUT,
                                    "merge: %s row %zu is at %.40s in '%s' and %.40s in '%s'", name,
                                    i + 1, t->text[k].line[c + 1 + i], src[k].dir, t->abscissa[i],
                                    src[longest].dir);
    }
    return rc;
}

static int merge_plain_table(FILE *f, const char *name, const merge_source *src, size_t n,
                             hsbd_error *err) {
    table_set t;
    int rc = load_tables(name, src, n, &t, err);
    double *v = rc == HSBD_OK ? malloc(n * sizeof *v) : NULL;
    if (rc == HSBD_OK && !v) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    if (rc == HSBD_OK) {
        write_comments(f, &t.text[0], n, NULL);
        for (size_t j = 0; j < t.ncol; ++j)
            fprintf(f, "%s%s", j ? "\t" : "", t.names[j]);
        fputc('\n', f);
        for (size_t i = 0; i < t.rows; ++i) {
            fputs(t.abscissa[i], f);
            for (size_t j = 1; j < t.ncol; ++j) {
                const size_t col = t.kind[j] == COLUMN_ERROR ? t.base[j] : j;
                for (size_t k = 0; k < n; ++k)
                    v[k] = t.val[(k * t.rows + i) * t.ncol + col];
                double mean, error;
                mean_and_error(v, n, &mean, &error);
                if (t.kind[j] == COLUMN_ERROR)
                    fprintf(f, "\t%.4g", error);
                else if (t.kind[j] == COLUMN_COUNT)
                    fprintf(f, "\t%.0f", mean * (double)n);
                else
                    fprintf(f, "\t%.10g", mean);
            }
            fputc('\n', f);
        }
    }
    free(v);
    table_set_free(&t, n);
    return rc;
}

/* X_blocks.tsv: one column per replica, the replica's value (second column) of X.tsv. */
static int merge_blocks_table(FILE *f, const char *name, const merge_source *src, size_t n,
                              hsbd_error *err) {
    char base[256];
    snprintf(base, sizeof base, "%.*s.tsv", (int)(strlen(name) - strlen("_blocks.tsv")), name);
    table_set t, b;
    int rc = load_tables(base, src, n, &t, err);
    int brc = load_tables(name, src, n, &b, rc == HSBD_OK ? err : &(hsbd_error){0});
    if (rc == HSBD_OK) rc = brc;
    if (rc == HSBD_OK && t.ncol < 2)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "merge: %s of '%s' has %zu column, no values for %s to hold", base,
                            src[0].dir, t.ncol, name);
    if (rc == HSBD_OK && b.rows != t.rows)
        rc = hsbd_error_set(err, HSBD_EINPUT, "merge: %s of '%s' has %zu rows, %s has %zu", name,
                            src[0].dir, b.rows, base, t.rows);
    if (rc == HSBD_OK) {
        char what[640];
        snprintf(what, sizeof what,
                 "%.100s of %.200s in each replica (the estimates behind the merged errors; their "
                 "covariance gives correlated errors)",
                 t.names[1], base);
        write_comments(f, &b.text[0], n, what);
        fprintf(f, "%s", b.names[0]);
        for (size_t k = 0; k < n; ++k) /* named by the replica (sorted by index) */
            fprintf(f, "\treplica_%ld", src[k].index);
        fputc('\n', f);
        for (size_t i = 0; i < t.rows; ++i) {
            fputs(b.abscissa[i], f);
            for (size_t k = 0; k < n; ++k)
                fprintf(f, "\t%.8g", t.val[(k * t.rows + i) * t.ncol + 1]);
            fputc('\n', f);
        }
    }
    table_set_free(&t, n);
    table_set_free(&b, n);
    return rc;
}

/* ---- summary.json -------------------------------------------------------------------- */

static int timing_key(const char *key) {
    return strstr(key, "wall") || strstr(key, "cpu") || strstr(key, "per_second") ||
           !strcmp(key, "resumes") || !strcmp(key, "threads_used") || !strcmp(key, "stop_reason") ||
           !strcmp(key, "completed") || !strcmp(key, "replicas");
}

static int is_number(const char *v) {
    char *end;
    strtod(v, &end);
    return end != v && (*end == ',' || *end == '\0');
}

/* The next string of a one-line JSON array of strings at *p (after '[' or a string): its
 * text with the quotes, escapes as written, in [*start, *start + *len); 0 at the array's
 * end, and on anything that is not such an array (a summary written by hand). */
static int next_json_string(const char **p, const char **start, size_t *len) {
    const char *q = *p;
    while (*q == ' ' || *q == ',')
        ++q;
    if (*q != '"') return 0;
    *start = q++;
    for (; *q && *q != '"'; ++q)
        if ((unsigned char)*q < 0x20 || (*q == '\\' && !*++q)) return 0;
    if (*q != '"') return 0;
    *len = (size_t)(++q - *start);
    *p = q;
    return 1;
}

/* "warnings": each distinct warning of the replicas once, in the order of the replicas
 * (their time-step warnings are the same; a measured rate may differ in its digits), at
 * most the first 64. */
static void write_warnings(FILE *f, const merge_source *src, size_t n) {
    struct {
        const char *text;
        size_t len;
    } seen[64];
    size_t nseen = 0;
    fprintf(f, "  \"warnings\": [");
    for (size_t r = 0; r < n && nseen < 64; ++r) {
        const char *p = summary_value(&src[r], "warnings"), *w;
        size_t len;
        if (!p || *p++ != '[') continue;
        while (nseen < 64 && next_json_string(&p, &w, &len)) {
            size_t e = 0;
            while (e < nseen && !(seen[e].len == len && !memcmp(seen[e].text, w, len)))
                ++e;
            if (e < nseen) continue;
            fprintf(f, "%s%.*s", nseen ? ", " : "", (int)len, w);
            seen[nseen].text = w, seen[nseen++].len = len;
        }
    }
    fprintf(f, "],\n");
}

/* A JSON array or object that closes on its own line (before a trailing comma); those
 * that go on over lines (contacts per species pair) are the replicas' own. */
static int whole_on_its_line(const char *v) {
    int depth = 0, quoted = 0;
    const char *end = v + value_len(v);
    for (const char *c = v; c < end; ++c) {
        if (quoted && *c == '\\' && c + 1 < end)
            ++c;
        else if (*c == '"')
            quoted = !quoted;
        else if (!quoted && (*c == '[' || *c == '{'))
            ++depth;
        else if (!quoted && (*c == ']' || *c == '}') &&
                 (--depth < 0 || (depth == 0 && c + 1 < end)))
            return 0;
    }
    return depth == 0 && !quoted;
}

static int write_summary(FILE *f, const merge_source *src, size_t n, const char *out,
                         hsbd_error *err) {
    double *v = malloc(n * sizeof *v);
    if (!v) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const merge_source *s0 = &src[0];
    fprintf(f, "{\n");
    for (size_t k = 1; k < s0->params; ++k) {
        char key[64], errkey[80];
        const char *val = json_entry(s0->sum.line[k], 2, key, sizeof key);
        if (!val || timing_key(key)) continue;
        const int nested = *val == '{' || *val == '[';
        if (nested && !strcmp(key, "warnings")) write_warnings(f, src, n);
        if (nested && (!strcmp(key, "warnings") || !whole_on_its_line(val))) continue;
        const size_t len = strlen(key);
        if (len > 4 && !strcmp(key + len - 4, "_err")) {
            snprintf(errkey, sizeof errkey, "%.*s", (int)(len - 4), key);
            if (summary_value(s0, errkey)) continue; /* written with its value */
        }
        int same = 1, numbers = is_number(val);
        for (size_t r = 0; r < n; ++r) {
            const char *vr = summary_value(&src[r], key);
            if (!vr) vr = "null";
            same &= value_len(vr) == value_len(val) && !strncmp(vr, val, (size_t)value_len(val));
            numbers &= is_number(vr);
            v[r] = strtod(vr, NULL);
        }
        if (same) {
            fprintf(f, "  \"%s\": %.*s,\n", key, value_len(val), val);
        } else if (nested) { /* an array or object that differs: the replicas' own */
        } else if (numbers && !strncmp(key, "min_", 4)) { /* the smallest over replicas */
            double least = v[0];
            for (size_t r = 1; r < n; ++r)
                least = fmin(least, v[r]);
            fprintf(f, "  \"%s\": %.10g,\n", key, least);
        } else if (numbers) {
            double mean, error;
            mean_and_error(v, n, &mean, &error);
            fprintf(f, "  \"%s\": %.10g,\n  \"%s_err\": %.4g,\n", key, mean, key, error);
        }
        if (strcmp(key, "model")) continue;
        /* after the model: the ensemble */
        fprintf(f, "  \"completed\": true,\n  \"replicas\": %zu,\n  \"replica_indices\": [", n);
        for (size_t r = 0; r < n; ++r)
            fprintf(f, "%s%ld", r ? ", " : "", src[r].index);
        fprintf(f, "],\n");
    }
    fprintf(f, "%s\n", s0->sum.line[s0->params]);
    for (size_t k = s0->params + 1; k < s0->sum.n; ++k) {
        char key[64];
        const char *line = s0->sum.line[k];
        const char *val = json_entry(line, 6, key, sizeof key);
        const char *comma = val && line[strlen(line) - 1] == ',' ? "," : "";
        if (val && !strcmp(key, "replica"))
            fprintf(f, "      \"replica\": -1%s\n", comma);
        else if (val && !strcmp(key, "replicas"))
            fprintf(f, "      \"replicas\": %zu%s\n", n, comma);
        else if (val && !strcmp(key, "dir")) {
            fprintf(f, "      \"dir\": ");
            hsbd_json_string(f, out);
            fprintf(f, "%s\n", comma);
        } else if (line[0] || k + 1 < s0->sum.n)
            fprintf(f, "%s\n", line);
    }
    free(v);
    return HSBD_OK;
}

/* ---- the merge ------------------------------------------------------------------------ */

static int by_name(const void *a, const void *b) {
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static void free_names(char **names, size_t n) {
    for (size_t k = 0; names && k < n; ++k)
        free(names[k]);
    free(names);
}

/* The tables (X.tsv) of a replica's directory, sorted by name. A file X.part, an output the
 * run was still writing when it stopped, refuses the replica: it did not finish. */
static int list_tables(const char *dir, char ***names, size_t *n, hsbd_error *err) {
    DIR *d = opendir(dir);
    *names = NULL, *n = 0;
    if (!d) return hsbd_error_set(err, HSBD_EINPUT, "merge: cannot read '%s'", dir);
    size_t cap = 16;
    *names = malloc(cap * sizeof **names);
    int rc = *names ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (struct dirent *e; rc == HSBD_OK && (e = readdir(d));) {
        const size_t len = strlen(e->d_name);
        if (len > 5 && !strcmp(e->d_name + len - 5, ".part")) {
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "merge: '%s' holds '%s', an output its run was writing when it "
                                "stopped: the run did not finish; continue it first (hsbd "
                                "resume %s)",
                                dir, e->d_name, dir);
            break;
        }
        if (len < 5 || strcmp(e->d_name + len - 4, ".tsv")) continue;
        if (*n == cap) {
            char **g = realloc(*names, 2 * cap * sizeof **names);
            if (!g) {
                rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
                break;
            }
            *names = g, cap *= 2;
        }
        if (!((*names)[*n] = strdup(e->d_name)))
            rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        else
            *n += 1;
    }
    closedir(d);
    if (rc != HSBD_OK) return free_names(*names, *n), *names = NULL, *n = 0, rc;
    qsort(*names, *n, sizeof **names, by_name);
    return HSBD_OK;
}

/* The tables every replica holds: the same set in all (a table one of them lacks would
 * otherwise drop out of the merge unnoticed). */
static int common_tables(const merge_source *src, size_t n, char ***names, size_t *count,
                         hsbd_error *err) {
    int rc = list_tables(src[0].dir, names, count, err);
    for (size_t k = 1; k < n && rc == HSBD_OK; ++k) {
        char **other;
        size_t m;
        rc = list_tables(src[k].dir, &other, &m, err);
        if (rc != HSBD_OK) break;
        size_t i = 0, j = 0;
        while (i < *count && j < m && !strcmp((*names)[i], other[j]))
            ++i, ++j;
        if (i < *count || j < m) {
            const int missing_in_k = j == m || (i < *count && strcmp((*names)[i], other[j]) < 0);
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "merge: '%s' holds %s but '%s' does not; the replicas of one "
                                "configuration write the same tables",
                                missing_in_k ? src[0].dir : src[k].dir,
                                missing_in_k ? (*names)[i] : other[j],
                                missing_in_k ? src[k].dir : src[0].dir);
        }
        free_names(other, m);
    }
    if (rc != HSBD_OK) free_names(*names, *count), *names = NULL, *count = 0;
    return rc;
}

/* One merged file, made in memory first: nothing is written unless every file merges. */
typedef struct merged_file {
    char name[256];
    char *text;
    size_t len;
} merged_file;

static int make_file(merged_file *m, const char *name, const merge_source *src, size_t n,
                     const char *out, hsbd_error *err) {
    snprintf(m->name, sizeof m->name, "%s", name);
    FILE *f = open_memstream(&m->text, &m->len);
    if (!f) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const size_t len = strlen(name);
    int rc;
    if (!strcmp(name, "summary.json"))
        rc = write_summary(f, src, n, out, err);
    else if (len > 11 && !strcmp(name + len - 11, "_blocks.tsv"))
        rc = merge_blocks_table(f, name, src, n, err);
    else
        rc = merge_plain_table(f, name, src, n, err);
    fclose(f);
    return rc;
}

/* The line that merges `first` and dirs into a new OUT, for messages: "hsbd merge MERGED
 * first a b ..." */
static void merge_line(char *line, size_t len, const char *first, const char *const *dirs,
                       size_t ndirs) {
    int used = snprintf(line, len, "hsbd merge MERGED %s", first);
    for (size_t k = 0; k < ndirs && used >= 0 && (size_t)used < len; ++k)
        used += snprintf(line + used, len - (size_t)used, " %s", dirs[k]);
}

/* The output directory of hsbd merge: a path of usable length, no run directory merged
 * (nor one inside it: --force would clear it first), never a run, a replica or an
 * ensemble (whatever --force says: only an earlier merge's result is replaced), and empty
 * unless force. */
static int check_out(const char *out, const char *const *dirs, size_t ndirs, int force,
                     hsbd_error *err) {
    if (!out[0]) return hsbd_error_set(err, HSBD_EINPUT, "merge: OUT is empty; name a directory");
    if (strlen(out) + sizeof "/summary.json.part" > HSBD_PATH_MAX)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: OUT '%.60s...' is too long; allowed: up to %d characters",
                              out, HSBD_PATH_MAX - (int)sizeof "/summary.json.part");
    for (size_t k = 0; k < ndirs; ++k) {
        const int where = run_path_nesting(out, dirs[k]);
        const char *base = strrchr(dirs[k], '/');
        const int replica_of_out = where > 0 && base && run_is_replica_name(base + 1);
        if (where)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "merge: OUT '%s' %s '%s', one of the runs merged; choose "
                                  "another OUT%s%s%s",
                                  out, where > 0 ? "is or holds" : "lies inside", dirs[k],
                                  replica_of_out ? " (or merge the ensemble there into it: hsbd "
                                                   "merge "
                                                 : "",
                                  replica_of_out ? out : "", replica_of_out ? ")" : "");
    }
    const int ensemble = run_dir_holds_replicas(out);
    if (ensemble || run_dir_holds_run(out)) {
        char line[512];
        merge_line(line, sizeof line, out, dirs, ndirs);
        return hsbd_error_set(
            err, HSBD_EINPUT,
            "merge: OUT '%s' holds %s, which merge never replaces (with or "
            "without --force); if it is an input run, name a new OUT first: "
            "%s",
            out, ensemble ? "an ensemble's replicas" : "a run (its checkpoint or summary.json)",
            line);
    }
    if (!force && !run_dir_is_empty(out))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: OUT '%s' already exists and is not empty; choose another "
                              "OUT, or pass --force to replace an earlier merge's result",
                              out);
    return HSBD_OK;
}

/* The replicas of the ensemble in out (sorted by index): all of 0 .. R-1 when they give
 * run.replicas = R (with R = 0, the ranks of mpirun, as many as are there). */
static int whole_ensemble(const char *out, const merge_source *src, size_t n, hsbd_error *err) {
    const long planned = src[0].planned;
    long missing = -1; /* the first index missing from 0 .. R-1 (R unknown: from those there) */
    for (size_t k = 0; k < (planned > 0 ? (size_t)planned : n) && missing < 0; ++k)
        if (k >= n || src[k].index != (long)k) missing = (long)k;
    if (missing >= 0 && planned <= 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: the ensemble in '%s' lacks replica %ld (it holds replicas "
                              "up to %ld); run it alone first: hsbd run CONFIG --replica %ld "
                              "--out %s/replica-%ld",
                              out, missing, src[n - 1].index, missing, out, missing);
    if (missing < 0 && (planned <= 0 || (long)n == planned)) return HSBD_OK;
    if (missing < 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' holds replica %ld, beyond the ensemble's run.replicas "
                              "= %ld",
                              out, src[n - 1].index, planned);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "merge: the ensemble in '%s' lacks replica %ld of its %ld (it never "
                          "began); run it alone first: hsbd run CONFIG --replica %ld --set "
                          "run.replicas=%ld --out %s/replica-%ld",
                          out, missing, planned, missing, planned, out, missing);
}

/* The merged files into out (made first when prepare), each committed on its own
 * (temporary name, rename); when one fails (a full disk), those already written are
 * removed again, and out itself when the merge made it, so that no partial result is left
 * looking valid. */
static int write_files(const char *out, const merged_file *files, size_t count, int prepare,
                       int force, int existed, hsbd_error *err) {
    int rc = prepare ? hsbd_run_dir_prepare(out, force, err) : HSBD_OK;
    size_t written = 0;
    for (; written < count && rc == HSBD_OK; ++written) {
        hsbd_outfile o;
        rc = hsbd_outfile_open(&o, out, files[written].name, err);
        if (rc != HSBD_OK) break;
        if (fwrite(files[written].text, 1, files[written].len, o.f) != files[written].len) {
            hsbd_outfile_discard(&o);
            rc = hsbd_error_set(err, HSBD_EIO, "merge: cannot write '%s/%s': %s", out,
                                files[written].name, strerror(errno));
            break;
        }
        rc = hsbd_outfile_commit(&o, err);
        if (rc != HSBD_OK) break;
    }
    if (rc == HSBD_OK) return rc;
    for (size_t k = 0; k < written; ++k) {
        char path[HSBD_PATH_MAX + 300];
        snprintf(path, sizeof path, "%s/%s", out, files[k].name);
        remove(path);
    }
    if (prepare && !existed) run_dir_remove(out);
    return rc;
}

int run_merge_into(const char *out, const char *const *dirs, size_t ndirs, int prepare, int force,
                   hsbd_error *err) {
    if (ndirs < 2)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: %zu run directories given; allowed: at least two replicas",
                              ndirs);
    merge_source *src = calloc(ndirs, sizeof *src);
    if (!src) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < ndirs; ++k)
        src[k].lock = -1;
    for (size_t k = 0; k < ndirs && rc == HSBD_OK; ++k) { /* read while no run writes there */
        src[k].dir = dirs[k];
        rc = run_dir_claim(src[k].dir, RUN_DIR_READ, &src[k].lock, err);
        if (rc == HSBD_OK) rc = load_source(&src[k], err);
    }
    if (rc == HSBD_OK) qsort(src, ndirs, sizeof *src, by_index);
    for (size_t k = 1; k < ndirs && rc == HSBD_OK; ++k) {
        if (src[k].index == src[k - 1].index)
            rc = hsbd_error_set(err, HSBD_EINPUT, "merge: '%s' and '%s' are both replica %ld",
                                src[k - 1].dir, src[k].dir, src[k].index);
        if (rc == HSBD_OK) rc = same_build(&src[0], &src[k], err);
        if (rc == HSBD_OK) rc = same_parameters(&src[0], &src[k], err);
        if (rc == HSBD_OK) rc = same_inputs(&src[0], &src[k], err);
    }
    if (rc == HSBD_OK && prepare) rc = check_out(out, dirs, ndirs, force, err);
    if (rc == HSBD_OK && !prepare) rc = whole_ensemble(out, src, ndirs, err);
    char **names = NULL;
    size_t nnames = 0;
    if (rc == HSBD_OK) rc = common_tables(src, ndirs, &names, &nnames, err);
    merged_file *files = rc == HSBD_OK ? calloc(nnames + 1, sizeof *files) : NULL;
    if (rc == HSBD_OK && !files) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t k = 0; k < nnames && rc == HSBD_OK; ++k)
        rc = make_file(&files[k], names[k], src, ndirs, out, err);
    if (rc == HSBD_OK) rc = make_file(&files[nnames], "summary.json", src, ndirs, out, err);
    /* everything was read and checked before the output directory is touched; the
     * summary, which says a result is whole, goes last */
    int out_lock = -1; /* no other process writes in OUT while the merge does */
    struct stat st;
    const int existed = stat(out, &st) == 0; /* else made by the claim, removed on failure */
    if (rc == HSBD_OK && prepare) rc = run_dir_claim(out, RUN_DIR_WRITE_NEW, &out_lock, err);
    if (rc == HSBD_OK) rc = write_files(out, files, nnames + 1, prepare, force, existed, err);
    run_dir_release(out_lock);
    for (size_t k = 0; files && k <= nnames; ++k)
        free(files[k].text);
    free_names(names, nnames);
    free(files);
    for (size_t k = 0; k < ndirs; ++k)
        text_free(&src[k].sum), run_dir_release(src[k].lock);
    free(src);
    return rc;
}

/* The replica-K directories in dir (not links), as "dir/replica-K". */
static int list_replica_dirs(const char *dir, char ***paths, size_t *n, hsbd_error *err) {
    *paths = NULL, *n = 0;
    DIR *d = opendir(dir);
    if (!d)
        return hsbd_error_set(err, HSBD_EINPUT, "merge: cannot read '%s': %s", dir,
                              strerror(errno));
    size_t cap = 0;
    int rc = HSBD_OK;
    for (struct dirent *e; rc == HSBD_OK && (e = readdir(d));) {
        const int replica = run_replica_entry(dir, e->d_name);
        if (!replica) continue;
        char path[HSBD_PATH_MAX + 300];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (replica < 0) {
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "merge: '%s' is not a directory (a symbolic link or a file): an "
                                "ensemble's replicas are directories of its own; merge replicas "
                                "kept elsewhere with hsbd merge OUT DIR...",
                                path);
            break;
        }
        if (*n == cap) {
            char **more = realloc(*paths, (cap = 2 * cap + 8) * sizeof *more);
            if (!more) {
                rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
                break;
            }
            *paths = more;
        }
        if (!((*paths)[*n] = strdup(path)))
            rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        else
            ++*n;
    }
    closedir(d);
    return rc;
}

/* An ensemble's directory holds its replicas and, once merged, the merged files; a run of
 * its own there is not replaced. */
static int no_results_of_its_own(const char *dir, hsbd_error *err) {
    if (run_dir_holds_run(dir))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' holds the results of a run of its own (a checkpoint "
                              "or its summary.json), which merging its replica directories into "
                              "it would replace; merge them elsewhere (hsbd merge OUT %s/replica-0 "
                              "...)",
                              dir, dir);
    return HSBD_OK;
}

/* hsbd merge DIR: the replicas of the ensemble in DIR merged into DIR, as the ensemble
 * does at its end (an ensemble that was stopped, its replicas continued one by one). */
static int merge_ensemble_in_place(const char *dir, hsbd_error *err) {
    char **paths;
    size_t n;
    int rc = list_replica_dirs(dir, &paths, &n, err);
    if (rc == HSBD_OK && n == 0)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "merge: only OUT given, and '%s' holds no replica-K directories of "
                            "an ensemble; allowed: hsbd merge OUT DIR DIR... (at least two "
                            "replicas), or hsbd merge DIR for the ensemble in DIR",
                            dir);
    if (rc == HSBD_OK && n == 1)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "merge: the ensemble in '%s' holds one replica (%s); run the others "
                            "alone first (hsbd run CONFIG --replica K --out %s/replica-K, with the "
                            "ensemble's run.replicas)",
                            dir, paths[0], dir);
    int lock = -1; /* no ensemble or other merge writes in dir meanwhile */
    if (rc == HSBD_OK) rc = run_dir_claim(dir, RUN_DIR_WRITE, &lock, err);
    if (rc == HSBD_OK) rc = no_results_of_its_own(dir, err);
    if (rc == HSBD_OK) rc = run_merge_into(dir, (const char *const *)paths, n, 0, 0, err);
    run_dir_release(lock);
    free_names(paths, n);
    return rc;
}

int hsbd_merge(const char *out, const char *const *dirs, size_t ndirs, int force, hsbd_error *err) {
    hsbd_error_clear(err);
    return ndirs == 0 ? merge_ensemble_in_place(out, err)
                      : run_merge_into(out, dirs, ndirs, 1, force, err);
}
