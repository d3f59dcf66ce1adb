/* Merges of replicas (see rundir.h, docs/scaling.md): the run directories of replicas of one
 * configuration become one result whose means are the replicas' means and whose errors come
 * from their scatter (the standard error of the mean over the replicas). Every sum runs over
 * the replicas in the order of their index, so the bytes depend only on the set of replicas.
 *
 * Everything is read line by line, as hsbd writes it. A table X.tsv merges row by row: the
 * first column must agree (cluster-size distributions are padded with zeros), a column `c_err`
 * beside a column `c` gets the scatter of `c`, `origins` (counts) are summed, every other
 * column is averaged; X_blocks.tsv gets one column per replica, its value of X. summary.json:
 * a line `  "key": value,` all replicas share is kept (a value over several lines is the
 * replicas' own), a number that differs becomes the mean and `key_err` (the least for min_*),
 * the warnings are listed each once, timings and how each replica ran are left out; the
 * parameters, compared line by line, are copied with the ensemble's run.replica,
 * run.replicas and output.dir. */
#include "rundir/rundir.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/input.h"
#include "hsbd/io.h"
#include "io/tables.h"

/* ---- files as lines ------------------------------------------------------------------- */

typedef struct lines {
    char *buf;
    char **line;
    size_t n;
    int cut; /* the last line has no newline: the file was cut short */
} lines;

static void lines_free(lines *t) {
    free(t->buf), free(t->line);
    *t = (lines){0};
}

/* dir/name as lines without their newlines; HSBD_EINPUT for a file that cannot be read or is
 * no regular file (a FIFO would block the merge). */
static int lines_read(const char *dir, const char *name, lines *t, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    *t = (lines){0};
    const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    struct stat st;
    if (fd < 0 || fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        const int e = fd < 0 ? errno : 0;
        if (fd >= 0) close(fd);
        return hsbd_error_set(err, HSBD_EINPUT, "merge: cannot read '%s': %s", path,
                              e ? strerror(e) : "not a regular file");
    }
    size_t len = 0, size = (size_t)st.st_size, count = 1;
    t->buf = malloc(size + 1);
    for (ssize_t got = 1; t->buf && len < size && got > 0; len += got > 0 ? (size_t)got : 0)
        got = read(fd, t->buf + len, size - len);
    close(fd);
    if (!t->buf) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory reading '%s'", path);
    t->buf[len] = '\0';
    t->cut = len < size || (len > 0 && t->buf[len - 1] != '\n');
    for (size_t k = 0; k < len; ++k)
        count += t->buf[k] == '\n';
    if (!(t->line = malloc(count * sizeof *t->line))) {
        lines_free(t);
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory reading '%s'", path);
    }
    for (char *p = t->buf, *nl; *p; p = nl + 1) {
        t->line[t->n++] = p;
        if (!(nl = strchr(p, '\n'))) break;
        *nl = '\0';
    }
    return HSBD_OK;
}

/* ---- the replicas' summaries ------------------------------------------------------------ */

typedef struct replica {
    const char *dir;
    int lock;            /* its shared lock, or -1 */
    long index, planned; /* run.replica, run.replicas */
    lines sum;           /* summary.json */
    size_t params;       /* its line `  "parameters": {` */
    char **param;        /* "section.key = value" of each parameter replicas share */
    size_t nparam;
} replica;

/* A line `<indent>"key": value`: the key into key (64 bytes) and the value; NULL if none. */
static const char *entry(const char *line, size_t indent, char *key) {
    if (strspn(line, " ") != indent || line[indent] != '"') return NULL;
    const char *q = strchr(line + indent + 1, '"');
    if (!q || strncmp(q, "\": ", 3)) return NULL;
    snprintf(key, 64, "%.*s", (int)(q - line - indent - 1), line + indent + 1);
    return q + 3;
}

/* a value's length without its trailing comma */
static int value_len(const char *v) {
    const size_t len = strlen(v);
    return (int)(len && v[len - 1] == ',' ? len - 1 : len);
}

/* The value of a top-level key of s's summary, NULL if absent. */
static const char *summary_value(const replica *s, const char *key) {
    char k[64];
    for (size_t i = 1; i < s->params; ++i) {
        const char *v = entry(s->sum.line[i], 2, k);
        if (v && !strcmp(k, key)) return v;
    }
    return NULL;
}

/* A whole number, then a comma or the end, into *v. */
static int whole_value(const char *text, long *v) {
    char *end;
    errno = 0;
    *v = strtol(text, &end, 10);
    return (text[0] == '-' || (text[0] >= '0' && text[0] <= '9')) && errno == 0 &&
           (*end == ',' || !*end);
}

/* The parameters (the lines after s->params) as "section.key = value", but for those of the
 * replica's own (index, count, directory) and its threads (no result depends on them): 0, -1
 * out of memory, -2 when run.replica is no whole number. */
static int flatten_parameters(replica *s) {
    char section[64] = "", key[64];
    if (!(s->param = calloc(s->sum.n, sizeof *s->param))) return -1;
    for (size_t i = s->params + 1; i < s->sum.n; ++i) {
        const char *v = entry(s->sum.line[i], 4, key);
        if (v) snprintf(section, sizeof section, "%s", key);
        if (v || !(v = entry(s->sum.line[i], 6, key))) continue;
        if (!strcmp(key, "replica") && !whole_value(v, &s->index)) return -2;
        if (!strcmp(key, "replicas")) whole_value(v, &s->planned);
        if (!strcmp(key, "replica") || !strcmp(key, "replicas") || !strcmp(key, "dir") ||
            !strcmp(key, "threads"))
            continue;
        const size_t len = strlen(section) + strlen(key) + strlen(v) + 8;
        if (!(s->param[s->nparam] = malloc(len))) return -1;
        snprintf(s->param[s->nparam++], len, "%s.%s = %.*s", section, key, value_len(v), v);
    }
    return 0;
}

static int load_replica(replica *s, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 32], key[64];
    snprintf(path, sizeof path, "%s/summary.json", s->dir);
    if (access(path, F_OK) != 0 && rundir_holds_checkpoint(s->dir))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: the run in '%s' did not finish (a checkpoint, no "
                              "summary.json: it was stopped); continue it first (hsbd resume %s)",
                              s->dir, s->dir);
    if (access(path, F_OK) != 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' holds no readable summary.json: not a run directory "
                              "of hsbd",
                              s->dir);
    int rc = lines_read(s->dir, "summary.json", &s->sum, err);
    if (rc == HSBD_OK && s->sum.cut)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "merge: '%s/summary.json' ends inside a line: the file was cut short",
                            s->dir);
    for (s->params = 0; rc == HSBD_OK && s->params < s->sum.n; ++s->params) {
        const char *v = entry(s->sum.line[s->params], 2, key);
        if (v && !strcmp(key, "parameters")) break;
    }
    s->index = LONG_MIN;
    const int flat = rc == HSBD_OK && s->params < s->sum.n ? flatten_parameters(s) : 0;
    const char *done = summary_value(s, "completed");
    if (rc != HSBD_OK) return rc;
    if (flat == -1) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    if (flat == -2 || s->index == LONG_MIN)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s/summary.json' gives no run.replica as a whole number in "
                              "its parameters: not a run of this hsbd, or edited or damaged",
                              s->dir);
    if (!done || strncmp(done, "true", 4))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: the run in '%s' did not complete; continue it first (hsbd "
                              "resume %s)",
                              s->dir, s->dir);
    if (s->index < 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' is no replica of an ensemble (run.replica = -1); run "
                              "replicas with hsbd run CONFIG --replica K",
                              s->dir);
    return HSBD_OK;
}

static int by_index(const void *a, const void *b) {
    const long x = ((const replica *)a)->index, y = ((const replica *)b)->index;
    return (x > y) - (x < y);
}

static void free_replica(replica *s) {
    for (size_t k = 0; k < s->nparam; ++k)
        free(s->param[k]);
    free(s->param);
    lines_free(&s->sum);
    rundir_release(s->lock);
}

/* The same build of hsbd (another may give other results; the merged files name one) and
 * the same contents of the input files (the parameters name a file, not what it held). */
static int same_run(const replica *a, const replica *b, hsbd_error *err) {
    static const char *const keys[] = {"version", "git", "input_checksums"};
    for (size_t k = 0; k < 3; ++k) {
        const char *va = summary_value(a, keys[k]), *vb = summary_value(b, keys[k]);
        va = va ? va : "none", vb = vb ? vb : "none";
        const int la = value_len(va), lb = value_len(vb);
        if (la == lb && !strncmp(va, vb, (size_t)la)) continue;
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' and '%s' differ in %s (%.*s in the first, %.*s in "
                              "the second); only runs of one build of hsbd and the same "
                              "contents of their input files can be merged",
                              a->dir, b->dir, keys[k], la > 300 ? 300 : la, va, lb > 300 ? 300 : lb,
                              vb);
    }
    return HSBD_OK;
}

/* the length of the name section.key of a flattened parameter */
static int name_len(const char *p) {
    const char *eq = strstr(p, " = ");
    return eq ? (int)(eq - p) : (int)strlen(p);
}

static int same_name(const char *p, const char *q) {
    return name_len(p) == name_len(q) && !strncmp(p, q, (size_t)name_len(p));
}

/* The same configuration: every parameter but the replica's own. The message names the
 * first that differs. */
static int same_parameters(const replica *a, const replica *b, hsbd_error *err) {
    size_t i = 0;
    while (i < a->nparam && i < b->nparam && !strcmp(a->param[i], b->param[i]))
        ++i;
    if (i == a->nparam && i == b->nparam) return HSBD_OK;
    const char *end = "(the end of the parameters)";
    const char *pa = i < a->nparam ? a->param[i] : end, *pb = i < b->nparam ? b->param[i] : end;
    if (!same_name(pa, pb))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' and '%s' are not replicas of one configuration: their "
                              "parameters differ at %.*s in the first and %.*s in the second; "
                              "only runs of the same configuration (apart from run.replica) can "
                              "be merged",
                              a->dir, b->dir, name_len(pa), pa, name_len(pb), pb);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "merge: '%s' and '%s' are not replicas of one configuration: %.300s in "
                          "the first, %.200s in the second; only runs of the same configuration "
                          "(apart from run.replica) can be merged",
                          a->dir, b->dir, pa, pb + name_len(pb) + 3);
}

/* ---- tables ----------------------------------------------------------------------------- */

/* mean and standard error of the mean of v[0..n-1], summed in order */
static void mean_and_error(const double *v, size_t n, double *mean, double *err) {
    double s = 0, q = 0;
    for (size_t k = 0; k < n; ++k)
        s += v[k];
    const double m = s / (double)n;
    for (size_t k = 0; k < n; ++k)
        q += (v[k] - m) * (v[k] - m);
    *mean = m;
    *err = n > 1 ? sqrt(q / ((double)n * (double)(n - 1))) : NAN;
}

static size_t comment_lines(const lines *t) {
    size_t c = 0;
    while (c < t->n && t->line[c][0] == '#')
        ++c;
    return c;
}

/* The line of column names, the rows after it: the header's last line, "# " and names
 * between tabs (or, in tables written before the names became a comment, the first line
 * after the header). */
static size_t names_line(const lines *t) {
    const size_t c = comment_lines(t);
    const char *last = c ? t->line[c - 1] : "";
    return !strncmp(last, "# ", 2) && strchr(last, '\t') && !strstr(last, " = ") ? c - 1 : c;
}

/* the names of that line, without its "# " */
static char *names_text(const lines *t, size_t line) {
    char *s = t->line[line];
    return s[0] == '#' ? s + 2 : s;
}

/* The header of a merged table: the first line's description (or `what`), then the
 * configuration lines with the ensemble's run.replica and run.replicas. */
static void write_comments(FILE *f, const lines *t, size_t nreplicas, const char *what) {
    const char *colon = strstr(t->line[0], "): ");
    if (what && colon)
        fprintf(f, "%.*s): %s\n", (int)(colon - t->line[0]), t->line[0], what);
    else
        fprintf(f,
                "%s; merged over %zu replicas: means of the replicas' values, errors from "
                "their scatter\n",
                t->line[0], nreplicas);
    for (size_t k = 1; k < names_line(t); ++k) {
        if (!strncmp(t->line[k], "# run.replica = ", 16))
            fprintf(f, "# run.replica = -1\n");
        else if (!strncmp(t->line[k], "# run.replicas = ", 17))
            fprintf(f, "# run.replicas = %zu\n", nreplicas);
        else
            fprintf(f, "%s\n", t->line[k]);
    }
}

/* One table of every replica, its values as numbers. */
typedef struct table {
    lines *text;
    size_t *head;         /* [replica]: its line of column names */
    size_t rows, longest; /* rows of the longest, that replica */
    size_t ncol;
    char **name; /* [ncol]: the columns */
    double *val; /* [replica][row][column], zero-padded */
} table;

static void table_free(table *t, size_t n) {
    for (size_t k = 0; t->text && k < n; ++k)
        lines_free(&t->text[k]);
    free(t->text), free(t->head), free(t->name), free(t->val);
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

/* Row i of replica k's table into t->val: ncol cells (cut at their tabs: the line is then
 * its first cell, the abscissa), each after the first a number. */
static int parse_row(table *t, const char *name, const char *dir, size_t k, size_t i,
                     hsbd_error *err) {
    const size_t line = t->head[k] + 1 + i;
    size_t j = 0;
    for (char *cell = t->text[k].line[line], *tab; cell; ++j, cell = tab ? tab + 1 : NULL) {
        if ((tab = strchr(cell, '\t'))) *tab = '\0';
        if (j > 0 && j < t->ncol && !table_number(cell, &t->val[(k * t->rows + i) * t->ncol + j]))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "merge: '%s/%s' line %zu, column %s: '%.40s' is not a number",
                                  dir, name, line + 1, t->name[j], cell);
    }
    if (j != t->ncol)
        return hsbd_error_set(err, HSBD_EINPUT, "merge: '%s/%s' line %zu has %zu columns, not %zu",
                              dir, name, line + 1, j, t->ncol);
    return HSBD_OK;
}

/* Replica k's table `name`, whole: comments, a line of columns, every line ended (its header
 * is that of the others: the parameters agree). */
static int read_table(const char *name, const replica *src, size_t k, table *t, hsbd_error *err) {
    const lines *tx = &t->text[k];
    int rc = lines_read(src[k].dir, name, &t->text[k], err);
    t->head[k] = names_line(tx);
    if (rc == HSBD_OK && (t->head[k] == 0 || t->head[k] >= tx->n))
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "merge: '%s/%s' is not a table of hsbd (no header or no columns)",
                            src[k].dir, name);
    if (rc == HSBD_OK && tx->cut)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "merge: '%s/%s' ends inside line %zu: the file was cut short",
                            src[k].dir, name, tx->n);
    if (rc == HSBD_OK && tx->n - t->head[k] - 1 > t->rows)
        t->rows = tx->n - t->head[k] - 1, t->longest = k;
    return rc;
}

/* The columns from replica 0's line of names (cut at its tabs). */
static int table_columns(table *t, size_t n, hsbd_error *err) {
    char *p = names_text(&t->text[0], t->head[0]);
    t->ncol = 1;
    for (const char *c = p; (c = strchr(c, '\t')); ++c)
        ++t->ncol;
    t->name = calloc(t->ncol, sizeof *t->name);
    t->val = calloc(n * t->ncol * (t->rows ? t->rows : 1), sizeof *t->val);
    if (!t->name || !t->val) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t j = 0; j < t->ncol; ++j, ++p) {
        t->name[j] = p;
        if ((p = strchr(p, '\t'))) *p = '\0';
    }
    return HSBD_OK;
}

/* Table `name` of every replica into t: the same rows in all (the parameters agree), but
 * size distributions, padded with zeros where a replica saw no cluster that large. */
static int load_table(const char *name, const replica *src, size_t n, table *t, hsbd_error *err) {
    *t = (table){.text = calloc(n, sizeof *t->text), .head = calloc(n, sizeof *t->head)};
    if (!t->text || !t->head) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < n && rc == HSBD_OK; ++k)
        rc = read_table(name, src, k, t, err);
    if (rc == HSBD_OK) rc = table_columns(t, n, err);
    const int padded = !strcmp(name, "clusters.tsv");
    for (size_t k = 0; k < n && rc == HSBD_OK; ++k) {
        const size_t rows = t->text[k].n - t->head[k] - 1;
        if (rows != t->rows && !padded)
            rc = hsbd_error_set(err, HSBD_EINPUT, "merge: %s has %zu rows in '%s' and %zu in '%s'",
                                name, rows, src[k].dir, t->rows, src[t->longest].dir);
        for (size_t i = 0; i < rows && rc == HSBD_OK; ++i)
            rc = parse_row(t, name, src[k].dir, k, i, err);
    }
    return rc;
}

/* the abscissa of row i */
static const char *abscissa(const table *t, size_t i) {
    return t->text[t->longest].line[t->head[t->longest] + 1 + i];
}

/* the column j's value column when it is c_err beside a column c (its scatter), else 0 */
static size_t error_of(const table *t, size_t j) {
    const size_t len = strlen(t->name[j]);
    for (size_t b = 1; len > 4 && !strcmp(t->name[j] + len - 4, "_err") && b < t->ncol; ++b)
        if (strlen(t->name[b]) == len - 4 && !strncmp(t->name[b], t->name[j], len - 4)) return b;
    return 0;
}

static int merge_plain_table(FILE *f, const char *name, const replica *src, size_t n,
                             hsbd_error *err) {
    table t;
    int rc = load_table(name, src, n, &t, err);
    double *v = malloc(n * sizeof *v);
    if (rc == HSBD_OK && !v) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    if (rc == HSBD_OK) {
        write_comments(f, &t.text[0], n, NULL);
        for (size_t j = 0; j < t.ncol; ++j)
            fprintf(f, "%s%s", j ? "\t" : "# ", t.name[j]);
        for (size_t i = 0; i < t.rows; ++i) {
            fprintf(f, "\n%s", abscissa(&t, i));
            for (size_t j = 1; j < t.ncol; ++j) {
                const size_t base = error_of(&t, j), col = base ? base : j;
                for (size_t k = 0; k < n; ++k)
                    v[k] = t.val[(k * t.rows + i) * t.ncol + col];
                double mean, error;
                mean_and_error(v, n, &mean, &error);
                if (base)
                    fprintf(f, "\t%.4g", error);
                else if (!strcmp(t.name[j], "origins"))
                    fprintf(f, "\t%.0f", mean * (double)n);
                else
                    fprintf(f, "\t%.10g", mean);
            }
        }
        fputc('\n', f);
    }
    free(v);
    table_free(&t, n);
    return rc;
}

/* X_blocks.tsv: one column per replica (named by its index), its value of X (the second
 * column of X.tsv), under the header of replica 0's X_blocks.tsv. */
static int merge_blocks_table(FILE *f, const char *name, const replica *src, size_t n,
                              hsbd_error *err) {
    char base[256], what[640];
    snprintf(base, sizeof base, "%.*s.tsv", (int)(strlen(name) - strlen("_blocks.tsv")), name);
    table t;
    lines b = {0};
    int rc = load_table(base, src, n, &t, err);
    if (rc == HSBD_OK) rc = lines_read(src[0].dir, name, &b, err);
    if (rc == HSBD_OK && (t.ncol < 2 || !names_line(&b) || names_line(&b) >= b.n))
        rc = hsbd_error_set(err, HSBD_EINPUT, "merge: '%s/%s' or its %s is not a table of hsbd",
                            src[0].dir, name, base);
    if (rc == HSBD_OK) {
        snprintf(what, sizeof what,
                 "%.100s of %.200s in each replica (the estimates behind the merged errors; their "
                 "covariance gives correlated errors)",
                 t.name[1], base);
        write_comments(f, &b, n, what);
        const char *columns = names_text(&b, names_line(&b));
        fprintf(f, "# %.*s", (int)strcspn(columns, "\t"), columns);
        for (size_t k = 0; k < n; ++k)
            fprintf(f, "\treplica_%ld", src[k].index);
        for (size_t i = 0; i < t.rows; ++i) {
            fprintf(f, "\n%s", abscissa(&t, i));
            for (size_t k = 0; k < n; ++k)
                fprintf(f, "\t%.8g", t.val[(k * t.rows + i) * t.ncol + 1]);
        }
        fputc('\n', f);
    }
    lines_free(&b);
    table_free(&t, n);
    return rc;
}

/* ---- summary.json ----------------------------------------------------------------------- */

/* timings and how each replica ran: not the ensemble's */
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

/* a value whole on its line: no object or array that goes on over lines */
static int one_line(const char *v) {
    if (!value_len(v)) return 0;
    const char last = v[value_len(v) - 1];
    return (v[0] != '[' || last == ']') && (v[0] != '{' || last == '}');
}

/* "warnings": each distinct text of the replicas once, in the order of the replicas (hsbd
 * writes them on one line, ["text", "text"]: no string holds `", "`, whose quote would be
 * escaped); a line of another form is left out. */
static void write_warnings(FILE *f, const replica *src, size_t n) {
    const char *seen[64];
    int len[64];
    size_t nseen = 0;
    fprintf(f, "  \"warnings\": [");
    for (size_t r = 0; r < n; ++r) {
        const char *v = summary_value(&src[r], "warnings");
        const int vl = v ? value_len(v) : 0;
        if (vl < 2 || strncmp(v, "[", 1) || v[vl - 1] != ']' || (vl > 2 && v[vl - 2] != '"'))
            continue;
        for (const char *w = v + 1, *end = v + vl - 1; w < end && *w == '"' && nseen < 64;) {
            const char *sep = strstr(w, "\", \"");
            const char *stop = sep && sep < end ? sep + 1 : end;
            size_t e = 0;
            while (e < nseen && !(len[e] == stop - w && !strncmp(seen[e], w, (size_t)len[e])))
                ++e;
            if (e == nseen) {
                fprintf(f, "%s%.*s", nseen ? ", " : "", (int)(stop - w), w);
                seen[nseen] = w, len[nseen++] = (int)(stop - w);
            }
            w = stop + 2;
        }
    }
    fprintf(f, "],\n");
}

/* A top-level value of the merge: shared by all replicas (kept), or numbers (mean and
 * error, the least for min_*), or the replicas' own (left out). */
static void write_merged_value(FILE *f, const char *key, const char *val, const replica *src,
                               size_t n, double *v) {
    int same = 1, numbers = 1;
    for (size_t r = 0; r < n; ++r) {
        const char *vr = summary_value(&src[r], key);
        vr = vr ? vr : "null";
        same &= value_len(vr) == value_len(val) && !strncmp(vr, val, (size_t)value_len(val));
        numbers &= is_number(vr);
        v[r] = strtod(vr, NULL);
    }
    double mean = v[0], error;
    if (same && one_line(val)) {
        fprintf(f, "  \"%s\": %.*s,\n", key, value_len(val), val);
    } else if (numbers && !strncmp(key, "min_", 4)) {
        for (size_t r = 1; r < n; ++r)
            mean = fmin(mean, v[r]);
        fprintf(f, "  \"%s\": %.10g,\n", key, mean);
    } else if (numbers) {
        mean_and_error(v, n, &mean, &error);
        fprintf(f, "  \"%s\": %.10g,\n  \"%s_err\": %.4g,\n", key, mean, key, error);
    }
}

static int write_summary(FILE *f, const replica *src, size_t n, const char *out, hsbd_error *err) {
    double *v = malloc(n * sizeof *v);
    if (!v) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const replica *s0 = &src[0];
    char key[64] = "", base[64];
    fprintf(f, "{\n");
    for (size_t k = 1; k < s0->params; ++k) {
        const char *val = entry(s0->sum.line[k], 2, key);
        const size_t len = val ? strlen(key) : 0;
        snprintf(base, sizeof base, "%.*s", (int)(len > 4 ? len - 4 : 0), key);
        if (!val || timing_key(key) ||
            (len > 4 && !strcmp(key + len - 4, "_err") &&
             summary_value(s0, base))) /* written with its value */
            continue;
        if (!strcmp(key, "warnings"))
            write_warnings(f, src, n);
        else
            write_merged_value(f, key, val, src, n, v);
        if (strcmp(key, "model")) continue;
        fprintf(f, "  \"completed\": true,\n  \"replicas\": %zu,\n  \"replica_indices\": [", n);
        for (size_t r = 0; r < n; ++r)
            fprintf(f, "%s%ld", r ? ", " : "", src[r].index);
        fprintf(f, "],\n");
    }
    for (size_t k = s0->params; k < s0->sum.n; ++k) { /* the parameters, the ensemble's */
        const char *line = s0->sum.line[k], *val = entry(line, 6, key);
        const char *comma = val && val[value_len(val)] == ',' ? "," : "";
        if (val && !strcmp(key, "replica"))
            fprintf(f, "      \"replica\": -1%s\n", comma);
        else if (val && !strcmp(key, "replicas"))
            fprintf(f, "      \"replicas\": %zu%s\n", n, comma);
        else if (val && !strcmp(key, "dir"))
            fprintf(f, "      \"dir\": "), hsbd_json_string(f, out), fprintf(f, "%s\n", comma);
        else
            fprintf(f, "%s\n", line);
    }
    free(v);
    return HSBD_OK;
}

/* ---- the merge -------------------------------------------------------------------------- */

static int by_name(const void *a, const void *b) {
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static void free_names(char **names, size_t n) {
    for (size_t k = 0; names && k < n; ++k)
        free(names[k]);
    free(names);
}

/* The entries of dir that keep() takes (1) or skips (0), sorted by name (as "dir/name" with
 * paths); one it refuses (-1, err set) ends the list. */
static int list_entries(const char *dir, int (*keep)(const char *, const char *, hsbd_error *),
                        int paths, char ***names, size_t *n, hsbd_error *err) {
    DIR *d = opendir(dir);
    size_t cap = 0;
    *names = NULL, *n = 0;
    int rc =
        d ? HSBD_OK
          : hsbd_error_set(err, HSBD_EINPUT, "merge: cannot read '%s': %s", dir, strerror(errno));
    for (struct dirent *e; rc == HSBD_OK && (e = readdir(d));) {
        const int take = keep(dir, e->d_name, err);
        if (take < 0) rc = err->status;
        if (take <= 0) continue;
        char **more = *n < cap ? *names : realloc(*names, (cap = 2 * cap + 16) * sizeof *more);
        const size_t len = strlen(dir) + strlen(e->d_name) + 2;
        if (more) *names = more;
        if (more && ((*names)[*n] = malloc(len)))
            snprintf((*names)[*n], len, "%s%s%s", paths ? dir : "", paths ? "/" : "", e->d_name);
        if (!more || !(*names)[*n])
            rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        else
            ++*n;
    }
    if (d) closedir(d);
    if (rc != HSBD_OK) return free_names(*names, *n), *names = NULL, *n = 0, rc;
    if (*n) qsort(*names, *n, sizeof **names, by_name);
    return HSBD_OK;
}

static int ends_with(const char *s, const char *end) {
    const size_t ls = strlen(s), le = strlen(end);
    return ls > le && !strcmp(s + ls - le, end);
}

/* X.tsv; X.part, an output its run was still writing when it stopped, refuses the run */
static int table_entry(const char *dir, const char *name, hsbd_error *err) {
    if (ends_with(name, ".part"))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' holds '%s', an output its run was writing when it "
                              "stopped: the run did not finish; continue it first (hsbd resume "
                              "%s)",
                              dir, name, dir),
               -1;
    return ends_with(name, ".tsv");
}

/* The tables every replica holds: the same set in all (a table one of them lacks would
 * otherwise drop out of the merge unnoticed). */
static int common_tables(const replica *src, size_t n, char ***names, size_t *count,
                         hsbd_error *err) {
    int rc = list_entries(src[0].dir, table_entry, 0, names, count, err);
    for (size_t k = 1; k < n && rc == HSBD_OK; ++k) {
        char **other;
        size_t m, i = 0;
        if ((rc = list_entries(src[k].dir, table_entry, 0, &other, &m, err)) != HSBD_OK) break;
        while (i < *count && i < m && !strcmp((*names)[i], other[i]))
            ++i;
        if (i < *count || i < m) {
            const int lacks = i == m || (i < *count && strcmp((*names)[i], other[i]) < 0);
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "merge: '%s' holds %s but '%s' does not; the replicas of one "
                                "configuration write the same tables",
                                lacks ? src[0].dir : src[k].dir, lacks ? (*names)[i] : other[i],
                                lacks ? src[k].dir : src[0].dir);
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

static int make_file(merged_file *m, const char *name, const replica *src, size_t n,
                     const char *out, hsbd_error *err) {
    snprintf(m->name, sizeof m->name, "%s", name);
    FILE *f = open_memstream(&m->text, &m->len);
    if (!f) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const int rc = !strcmp(name, "summary.json")    ? write_summary(f, src, n, out, err)
                   : ends_with(name, "_blocks.tsv") ? merge_blocks_table(f, name, src, n, err)
                                                    : merge_plain_table(f, name, src, n, err);
    fclose(f);
    return rc;
}

/* The output directory of hsbd merge: a path of usable length, never a run, a replica or an
 * ensemble (only an earlier merge's result is replaced; one that holds anything else is
 * refused by its preparation), and empty unless force. */
static int check_out(const char *out, const char *const *dirs, size_t ndirs, int force,
                     hsbd_error *err) {
    if (!out[0]) return hsbd_error_set(err, HSBD_EINPUT, "merge: OUT is empty; name a directory");
    if (strlen(out) + sizeof "/summary.json.part" > HSBD_PATH_MAX)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: OUT '%.60s...' is too long; allowed: up to %d characters",
                              out, HSBD_PATH_MAX - (int)sizeof "/summary.json.part");
    const int ensemble = rundir_holds_replicas(out);
    if (ensemble || rundir_holds_run(out)) {
        char line[512];
        int used = snprintf(line, sizeof line, "hsbd merge MERGED %s", out);
        for (size_t k = 0; k < ndirs && used >= 0 && (size_t)used < sizeof line; ++k)
            used += snprintf(line + used, sizeof line - (size_t)used, " %s", dirs[k]);
        return hsbd_error_set(
            err, HSBD_EINPUT,
            "merge: OUT '%s' holds %s, which merge never replaces (with or "
            "without --force); if it is an input run, name a new OUT first: "
            "%s%s%s",
            out, ensemble ? "an ensemble's replicas" : "a run (its checkpoint or summary.json)",
            line, ensemble ? "; or merge its replicas into it: hsbd merge " : "",
            ensemble ? out : "");
    }
    if (!force && !rundir_is_empty(out))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: OUT '%s' already exists and is not empty; choose another "
                              "OUT, or pass --force to replace an earlier merge's result",
                              out);
    return HSBD_OK;
}

/* The replicas of the ensemble in out (sorted by index): all of 0 .. R-1 when they give
 * run.replicas = R, else (R = 0: as many as mpirun had ranks) 0 .. the highest there. */
static int whole_ensemble(const char *out, const replica *src, size_t n, hsbd_error *err) {
    const long planned = src[0].planned > 0 ? src[0].planned : src[n - 1].index + 1;
    long missing = 0; /* the first index missing from 0 .. R-1 */
    while (missing < planned && (size_t)missing < n && src[missing].index == missing)
        ++missing;
    if (missing == planned && (long)n == planned) return HSBD_OK;
    if (missing == planned)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' holds replica %ld, beyond the ensemble's run.replicas "
                              "= %ld",
                              out, src[n - 1].index, planned);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "merge: the ensemble in '%s' lacks replica %ld of its %ld (it never "
                          "began); run it alone first: hsbd run CONFIG --replica %ld --set "
                          "run.replicas=%ld --out %s/replica-%ld",
                          out, missing, planned, missing, src[0].planned, out, missing);
}

/* The merged files into out (made first when prepare), each committed on its own; when one
 * fails (a full disk) those written are removed again, and out when the merge made it: no
 * partial result is left looking valid. */
static int write_files(const char *out, const merged_file *files, size_t count, int prepare,
                       int force, int existed, hsbd_error *err) {
    int rc = prepare ? rundir_prepare(out, force, err) : HSBD_OK;
    size_t written = 0;
    for (; written < count && rc == HSBD_OK; ++written) {
        hsbd_outfile o;
        rc = hsbd_outfile_open(&o, out, files[written].name, err);
        if (rc == HSBD_OK &&
            fwrite(files[written].text, 1, files[written].len, o.f) != files[written].len) {
            hsbd_outfile_discard(&o);
            rc = hsbd_error_set(err, HSBD_EIO, "merge: cannot write '%s/%s': %s", out,
                                files[written].name, strerror(errno));
        }
        if (rc == HSBD_OK) rc = hsbd_outfile_commit(&o, err);
    }
    for (size_t k = 0; rc != HSBD_OK && k + 1 < written; ++k) {
        char path[HSBD_PATH_MAX + 300];
        snprintf(path, sizeof path, "%s/%s", out, files[k].name);
        remove(path);
    }
    if (rc != HSBD_OK && prepare && !existed) rundir_unmake(out, 1);
    return rc;
}

/* The merge of dirs into out: everything is read and checked before out is touched; the
 * summary, which says a result is whole, goes last. */
static int merge_into(const char *out, const char *const *dirs, size_t ndirs, int prepare,
                      int force, hsbd_error *err) {
    if (ndirs < 2)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: %zu run directories given; allowed: at least two replicas",
                              ndirs);
    replica *src = calloc(ndirs, sizeof *src);
    if (!src) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = 0; k < ndirs; ++k)
        src[k] = (replica){.dir = dirs[k], .lock = -1};
    for (size_t k = 0; k < ndirs && rc == HSBD_OK; ++k) { /* read while no run writes there */
        rc = rundir_claim(src[k].dir, RUNDIR_READ, &src[k].lock, err);
        if (rc == HSBD_OK) rc = load_replica(&src[k], err);
    }
    if (rc == HSBD_OK) qsort(src, ndirs, sizeof *src, by_index);
    for (size_t k = 1; k < ndirs && rc == HSBD_OK; ++k) {
        if (src[k].index == src[k - 1].index)
            rc = hsbd_error_set(err, HSBD_EINPUT, "merge: '%s' and '%s' are both replica %ld",
                                src[k - 1].dir, src[k].dir, src[k].index);
        if (rc == HSBD_OK) rc = same_run(&src[0], &src[k], err);
        if (rc == HSBD_OK) rc = same_parameters(&src[0], &src[k], err);
    }
    if (rc == HSBD_OK)
        rc = prepare ? check_out(out, dirs, ndirs, force, err)
                     : whole_ensemble(out, src, ndirs, err);
    char **names = NULL;
    size_t nnames = 0;
    if (rc == HSBD_OK) rc = common_tables(src, ndirs, &names, &nnames, err);
    merged_file *files = rc == HSBD_OK ? calloc(nnames + 1, sizeof *files) : NULL;
    if (rc == HSBD_OK && !files) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t k = 0; k < nnames && rc == HSBD_OK; ++k)
        rc = make_file(&files[k], names[k], src, ndirs, out, err);
    if (rc == HSBD_OK) rc = make_file(&files[nnames], "summary.json", src, ndirs, out, err);
    int out_lock = -1; /* no other process writes in OUT while the merge does */
    struct stat st;
    const int existed = stat(out, &st) == 0; /* else made by the claim, removed on failure */
    if (rc == HSBD_OK && prepare) rc = rundir_claim(out, RUNDIR_WRITE_NEW, &out_lock, err);
    if (rc == HSBD_OK) rc = write_files(out, files, nnames + 1, prepare, force, existed, err);
    rundir_release(out_lock);
    for (size_t k = 0; files && k <= nnames; ++k)
        free(files[k].text);
    free(files);
    free_names(names, nnames);
    for (size_t k = 0; k < ndirs; ++k)
        free_replica(&src[k]);
    free(src);
    return rc;
}

/* a replica-K directory of an ensemble (a link or a file of that name is none) */
static int replica_dir_entry(const char *dir, const char *name, hsbd_error *err) {
    (void)err;
    return rundir_replica_entry(dir, name);
}

/* The checks of an ensemble's directory before its replicas merge into it. */
static int ensemble_dir(const char *dir, size_t n, hsbd_error *err) {
    if (n < 2)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: only OUT given, and '%s' holds %zu replica-K directories of "
                              "an ensemble; allowed: hsbd merge DIR for an ensemble of at least "
                              "two replicas (run the others alone first: hsbd run CONFIG "
                              "--replica K --out %s/replica-K), or hsbd merge OUT DIR DIR...",
                              dir, n, dir);
    if (rundir_holds_run(dir))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "merge: '%s' holds the results of a run of its own (a checkpoint "
                              "or its summary.json), which merging its replica directories into "
                              "it would replace; merge them elsewhere (hsbd merge OUT "
                              "%s/replica-0 ...)",
                              dir, dir);
    return HSBD_OK;
}

int rundir_merge_ensemble(const char *dir, hsbd_error *err) {
    char **names;
    size_t n;
    int rc = list_entries(dir, replica_dir_entry, 1, &names, &n, err);
    if (rc == HSBD_OK) rc = ensemble_dir(dir, n, err);
    if (rc == HSBD_OK) rc = merge_into(dir, (const char *const *)names, n, 0, 0, err);
    free_names(names, n);
    return rc;
}

int rundir_merge(const char *out, const char *const *dirs, size_t ndirs, int force,
                 hsbd_error *err) {
    hsbd_error_clear(err);
    if (ndirs > 0) return merge_into(out, dirs, ndirs, 1, force, err);
    int lock = -1; /* an ensemble's directory: no ensemble or other merge writes there meanwhile */
    int rc = rundir_holds_replicas(out) ? rundir_claim(out, RUNDIR_WRITE, &lock, err) : HSBD_OK;
    if (rc == HSBD_OK) rc = rundir_merge_ensemble(out, err);
    rundir_release(lock);
    return rc;
}
