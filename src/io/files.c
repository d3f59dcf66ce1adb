#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <dirent.h>
#include <unistd.h>

#include "core/input.h"
#include "hsbd/io.h"
#include "io/files.h"

int hsbd_outfile_open(hsbd_outfile *o, const char *dir, const char *name, hsbd_error *err) {
    snprintf(o->path, sizeof o->path, "%s/%s", dir, name);
    snprintf(o->tmp, sizeof o->tmp, "%s.part", o->path);
    o->f = fopen(o->tmp, "w+"); /* read too: the GSD index moves */
    if (!o->f)
        return hsbd_error_set(err, HSBD_EIO, "cannot write '%s': %s", o->tmp, strerror(errno));
    return HSBD_OK;
}

int hsbd_outfile_commit(hsbd_outfile *o, hsbd_error *err) {
    if (!o->f) return HSBD_OK;
    int bad = fflush(o->f) != 0 || ferror(o->f);
    if (!bad) fsync(fileno(o->f));
    bad |= fclose(o->f) != 0;
    o->f = NULL;
    if (bad) {
        remove(o->tmp);
        return hsbd_error_set(err, HSBD_EIO, "writing '%s' failed: %s", o->path, strerror(errno));
    }
    if (rename(o->tmp, o->path) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", o->tmp, o->path,
                              strerror(errno));
    return HSBD_OK;
}

int hsbd_outfile_can_reopen(const char *dir, const char *name, int64_t length, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 64], tmp[HSBD_PATH_MAX + 72];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    snprintf(tmp, sizeof tmp, "%s.part", path);
    struct stat st;
    const char *found = stat(tmp, &st) == 0 ? tmp : stat(path, &st) == 0 ? path : NULL;
    if (!found)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "cannot continue '%s': neither it nor '%s' can be opened (%s)", path,
                              tmp, strerror(errno));
    if (!S_ISREG(st.st_mode) || access(found, R_OK | W_OK) != 0)
        return hsbd_error_set(err, HSBD_EINPUT, "cannot continue '%s': not a writable file", found);
    if (st.st_size < length)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "cannot continue '%s': it has %lld bytes, the checkpoint counts %lld",
                              found, (long long)st.st_size, (long long)length);
    return HSBD_OK;
}

int hsbd_outfile_reopen(hsbd_outfile *o, const char *dir, const char *name, int64_t length,
                        hsbd_error *err) {
    if (hsbd_outfile_can_reopen(dir, name, length, err) != HSBD_OK) return err->status;
    snprintf(o->path, sizeof o->path, "%s/%s", dir, name);
    snprintf(o->tmp, sizeof o->tmp, "%s.part", o->path);
    struct stat st;
    if (stat(o->tmp, &st) != 0 && rename(o->path, o->tmp) != 0)
        return hsbd_error_set(err, HSBD_EIO, "cannot rename '%s' to '%s': %s", o->path, o->tmp,
                              strerror(errno));
    o->f = fopen(o->tmp, "r+");
    if (!o->f)
        return hsbd_error_set(err, HSBD_EIO, "cannot open '%s': %s", o->tmp, strerror(errno));
    if (ftruncate(fileno(o->f), (off_t)length) != 0 || fseeko(o->f, length, SEEK_SET) != 0) {
        fclose(o->f), o->f = NULL;
        return hsbd_error_set(err, HSBD_EIO, "cannot cut '%s' back to %lld bytes: %s", o->tmp,
                              (long long)length, strerror(errno));
    }
    return HSBD_OK;
}

void hsbd_outfile_discard(hsbd_outfile *o) {
    if (!o->f) return;
    fclose(o->f);
    o->f = NULL;
    remove(o->tmp);
}

static int mkdir_parents(char *path) {
    for (char *p = path + 1; *p; ++p) {
        if (*p != '/') continue;
        *p = '\0';
        const int rc = mkdir(path, 0777);
        *p = '/';
        if (rc != 0 && errno != EEXIST) return -1;
    }
    return mkdir(path, 0777) != 0 && errno != EEXIST ? -1 : 0;
}

/* The files a run (or the tools beside it) writes into a run directory. */
static int is_run_output(const char *name) {
    static const char *const names[] = {
        "density.tsv",     "contact.tsv",          "density_blocks.tsv", "contact_blocks.tsv",
        "msd.tsv",         "clusters.tsv",         "current.tsv",        "gr.tsv",
        "fs.tsv",          "summary.json",         "trajectory.xyz",     "trajectory.gsd",
        "checkpoint.hsbd", "checkpoint.prev.hsbd", "theory.tsv",         "percus.tsv",
        "plot.png",        ".hsbd-probe",          "density_phases.tsv", "density_x.tsv",
        "density_y.tsv",   "density_z.tsv",        RUN_LOCK_FILE};
    char base[256];
    snprintf(base, sizeof base, "%s", name);
    const size_t len = strlen(base);
    if (len > 5 && !strcmp(base + len - 5, ".part")) base[len - 5] = '\0';
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
        if (!strcmp(base, names[k])) return 1;
    return 0;
}

size_t run_path_bare(const char *path, char *out, size_t len) {
    size_t n = strlen(path);
    while (n > 1 && path[n - 1] == '/')
        --n;
    snprintf(out, len, "%.*s", (int)n, path);
    return n;
}

/* path resolved (symbolic links, . and ..) into out (PATH_MAX); a path that does not exist
 * yet is its nearest existing parent resolved, with the rest appended. NULL if none. */
static char *resolve_path(const char *path, char *out) {
    char head[PATH_MAX];
    if (run_path_bare(path, head, sizeof head) >= sizeof head) return NULL;
    if (realpath(head, out)) return out;
    char *slash = strrchr(head, '/');
    char parent[PATH_MAX];
    if (!slash)
        snprintf(parent, sizeof parent, ".");
    else if (slash == head)
        snprintf(parent, sizeof parent, "/");
    else
        snprintf(parent, sizeof parent, "%.*s", (int)(slash - head), head);
    char resolved[PATH_MAX];
    if (!resolve_path(parent, resolved)) return NULL;
    const char *rest = slash ? slash + 1 : head;
    if (!strcmp(rest, ".")) /* not there yet, so no link: its parent, or that one's */
        return strcpy(out, resolved);
    if (!strcmp(rest, "..")) {
        char *up = strrchr(resolved, '/');
        if (up) up[up == resolved ? 1 : 0] = '\0';
        return strcpy(out, resolved);
    }
    const size_t rl = strlen(resolved);
    if (snprintf(out, PATH_MAX, "%s%s%s", resolved, resolved[rl - 1] == '/' ? "" : "/", rest) >=
        PATH_MAX)
        return NULL;
    return out;
}

int hsbd_path_resolve(const char *path, char *out) {
    return resolve_path(path, out) ? 0 : -1;
}

int run_dir_holds(const char *dir, const char *name) {
    char path[HSBD_PATH_MAX + 300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* Is path b the directory a or inside it (1), or a inside b (-1), or neither (0)? Paths
 * resolved; a path not there yet is resolved through its nearest existing parent. */
int run_path_nesting(const char *a, const char *b) {
    char ra[PATH_MAX], rb[PATH_MAX];
    if (!resolve_path(a, ra) || !resolve_path(b, rb)) return 0;
    const size_t la = strlen(ra), lb = strlen(rb);
    if (!strcmp(ra, rb)) return 1;
    if (la < lb && !strncmp(ra, rb, la) && (ra[la - 1] == '/' || rb[la] == '/')) return 1;
    if (lb < la && !strncmp(ra, rb, lb) && (rb[lb - 1] == '/' || ra[lb] == '/')) return -1;
    return 0;
}

int run_dir_is_empty(const char *dir) {
    DIR *d = opendir(dir);
    int empty = 1;
    for (struct dirent *e; d && (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && strcmp(e->d_name, RUN_LOCK_FILE))
            empty = 0;
    if (d) closedir(d);
    return empty;
}

int run_is_replica_name(const char *name) {
    if (strncmp(name, "replica-", 8) || !name[8]) return 0;
    for (const char *p = name + 8; *p; ++p)
        if (*p < '0' || *p > '9') return 0;
    return 1;
}

int run_dir_holds_checkpoint(const char *dir) {
    return run_dir_holds(dir, "checkpoint.hsbd") || run_dir_holds(dir, "checkpoint.prev.hsbd");
}

int run_dir_holds_run(const char *dir) {
    if (run_dir_holds_checkpoint(dir)) return 1;
    char path[HSBD_PATH_MAX + 300], line[256];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    FILE *f = run_dir_holds(dir, "summary.json") ? fopen(path, "r") : NULL;
    if (!f) return 0;
    int merged = 0;
    while (!merged && fgets(line, sizeof line, f))
        merged = strstr(line, "\"replica_indices\":") != NULL;
    fclose(f);
    return !merged;
}

int run_replica_entry(const char *dir, const char *name) {
    if (!run_is_replica_name(name)) return 0;
    char path[HSBD_PATH_MAX + 300];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return lstat(path, &st) == 0 && S_ISDIR(st.st_mode) ? 1 : -1;
}

int run_dir_holds_replicas(const char *dir) {
    DIR *d = opendir(dir);
    int found = 0;
    for (struct dirent *e; d && !found && (e = readdir(d));)
        found = run_replica_entry(dir, e->d_name) > 0;
    if (d) closedir(d);
    return found;
}

DIR *run_dir_open(const char *dir, hsbd_error *err) {
    DIR *d = opendir(dir);
    if (!d)
        hsbd_error_set(err, HSBD_EINPUT, "cannot read output directory '%s': %s", dir,
                       strerror(errno));
    return d;
}

int run_dir_check_earlier(const char *dir, int replica_dirs, hsbd_error *err) {
    DIR *d = run_dir_open(dir, err);
    if (!d) return err->status;
    int rc = HSBD_OK;
    for (struct dirent *e; rc == HSBD_OK && (e = readdir(d));) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") || is_run_output(e->d_name))
            continue;
        const int replica = run_replica_entry(dir, e->d_name) > 0;
        if (replica && replica_dirs) continue;
        if (replica)
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "output directory '%s' holds '%s', a replica of an ensemble: "
                                "a single run does not replace an ensemble's results; choose "
                                "another --out (an ensemble's --force replaces them)",
                                dir, e->d_name);
        else
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "output directory '%s' holds '%s', which is not a file of an "
                                "hsbd run; --force replaces only an earlier run's files: choose "
                                "another --out",
                                dir, e->d_name);
    }
    closedir(d);
    return rc;
}

/* An earlier run's files are removed (--force); anything else in the directory refuses. */
static int clear_earlier_run(const char *dir, hsbd_error *err) {
    int rc = run_dir_check_earlier(dir, 0, err);
    if (rc != HSBD_OK) return rc;
    DIR *d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));) {
        /* the lock stays: this process may hold it, and a new file would be another lock */
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") ||
            !strcmp(e->d_name, RUN_LOCK_FILE))
            continue;
        char path[HSBD_PATH_MAX + 300];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (remove(path) != 0 && rc == HSBD_OK)
            rc = hsbd_error_set(err, HSBD_EINPUT, "cannot remove '%s' of the earlier run: %s", path,
                                strerror(errno));
    }
    if (d) closedir(d);
    return rc;
}

/* A file can be created, written and synced in dir (before any dynamics). */
static int probe_writable(const char *dir, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/.hsbd-probe", dir);
    FILE *f = fopen(path, "w");
    int ok = f && fputc('h', f) != EOF && fflush(f) == 0 && fsync(fileno(f)) == 0;
    const int saved = errno;
    if (f) ok &= fclose(f) == 0;
    remove(path);
    return ok ? HSBD_OK
              : hsbd_error_set(err, HSBD_EINPUT,
                               "output directory '%s' is not writable: %s; choose another --out",
                               dir, strerror(saved ? saved : errno));
}

int hsbd_dir_create(const char *dir, hsbd_error *err) {
    if (!dir[0])
        return hsbd_error_set(err, HSBD_EINPUT, "no output directory given (use --out DIR)");
    struct stat st;
    if (stat(dir, &st) == 0 && !S_ISDIR(st.st_mode))
        return hsbd_error_set(err, HSBD_EINPUT, "output path '%s' exists and is not a directory",
                              dir);
    char buf[HSBD_PATH_MAX];
    snprintf(buf, sizeof buf, "%s", dir);
    if (mkdir_parents(buf) != 0)
        return hsbd_error_set(err, HSBD_EINPUT, "cannot create output directory '%s': %s", dir,
                              strerror(errno));
    char bare[HSBD_PATH_MAX], target[HSBD_PATH_MAX];
    run_path_bare(dir, bare, sizeof bare); /* readlink takes no trailing slash */
    const ssize_t len = readlink(bare, target, sizeof target - 1);
    if (len >= 0 && stat(dir, &st) != 0) /* mkdir does not follow a link */
        return hsbd_error_set(err, HSBD_EINPUT,
                              "output directory '%s' is a symbolic link to '%.*s', which leads "
                              "to no directory; create it or choose another --out",
                              dir, (int)len, target);
    return probe_writable(dir, err);
}

/* Opens dir's lock file for `use`: its descriptor, -1 when there is none to take (no
 * directory, no lock file yet for a reader or a check, a directory of foreign files, which
 * the caller's checks refuse: no lock file is left there), or -2 with err set when the
 * name is taken by something that is no lock file (a link, a FIFO, a directory). */
static int open_lock_file(const char *dir, run_dir_use use, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, RUN_LOCK_FILE);
    hsbd_error ignored;
    const int create =
        use == RUN_DIR_WRITE ||
        (use == RUN_DIR_WRITE_NEW &&
         (run_dir_is_empty(dir) || run_dir_check_earlier(dir, 1, &ignored) == HSBD_OK));
    /* NFS grants an exclusive lock only on a file open for writing; O_NONBLOCK: a FIFO
     * must not block the open */
    const int flags = O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK;
    int f = open(path, (use == RUN_DIR_READ ? O_RDONLY : O_RDWR) | (create ? O_CREAT : 0) | flags,
                 0666);
    if (f < 0 && errno == EACCES && use != RUN_DIR_READ) /* another user's: local locks */
        f = open(path, O_RDONLY | flags);                /* need no write access */
    if (f < 0 && errno != ELOOP && errno != EISDIR && errno != ENXIO) return -1; /* none */
    struct stat st;
    if (f >= 0 && fstat(f, &st) == 0 && S_ISREG(st.st_mode)) return f;
    if (f >= 0) close(f);
    hsbd_error_set(err, HSBD_EINPUT,
                   "'%s' is not the lock file of a run directory (a link or another kind of "
                   "file): remove it, or choose another directory",
                   path);
    return -2;
}

int run_dir_claim(const char *dir, run_dir_use use, int *fd, hsbd_error *err) {
    *fd = -1;
    if (!dir[0]) return HSBD_OK;
    struct stat st;
    if (use == RUN_DIR_WRITE_NEW && stat(dir, &st) != 0) {
        char buf[HSBD_PATH_MAX];
        snprintf(buf, sizeof buf, "%s", dir);
        if (mkdir_parents(buf) != 0) return HSBD_OK; /* hsbd_dir_create says why */
    }
    const int f = open_lock_file(dir, use, err);
    if (f == -2) return err->status;
    if (f < 0) return HSBD_OK;
    if (flock(f, (use == RUN_DIR_READ ? LOCK_SH : LOCK_EX) | LOCK_NB) == 0) return *fd = f, HSBD_OK;
    const int busy = errno == EWOULDBLOCK;
    close(f);
    if (!busy) return HSBD_OK; /* no locks on this file system */
    return hsbd_error_set(err, HSBD_EINPUT,
                          "run directory '%s' is in use: another hsbd process (a run, a resume, "
                          "an ensemble or a merge) is %s there; wait until it ends",
                          dir, use == RUN_DIR_READ ? "writing" : "writing or reading");
}

void run_dir_release(int fd) {
    if (fd >= 0) close(fd); /* closing drops the lock */
}

int run_dir_make(const char *dir, int *made) {
    char buf[HSBD_PATH_MAX];
    snprintf(buf, sizeof buf, "%s", dir);
    *made = 0;
    for (char *p = buf + 1; *p; ++p) { /* the parents, counted from the first one made */
        if (*p != '/') continue;
        *p = '\0';
        if (mkdir(buf, 0777) == 0)
            ++*made;
        else if (errno != EEXIST)
            return -1;
        *p = '/';
    }
    if (mkdir(buf, 0777) == 0) return ++*made, 0;
    return errno == EEXIST ? 0 : -1;
}

void run_dir_unmake(const char *dir, int made) {
    char buf[HSBD_PATH_MAX];
    snprintf(buf, sizeof buf, "%s", dir);
    for (int k = 0; k < made; ++k) {
        if (k == 0 ? run_dir_remove(buf) != 0 : rmdir(buf) != 0) return; /* not empty */
        char *slash = strrchr(buf, '/');
        while (slash && slash > buf && slash[1] == '\0') { /* trailing slashes */
            *slash = '\0';
            slash = strrchr(buf, '/');
        }
        if (!slash || slash == buf) return;
        *slash = '\0';
    }
}

int run_dir_remove(const char *dir) {
    char path[HSBD_PATH_MAX + 32];
    snprintf(path, sizeof path, "%s/%s", dir, RUN_LOCK_FILE);
    unlink(path);
    return rmdir(dir);
}

int hsbd_run_dir_prepare(const char *dir, int force, hsbd_error *err) {
    if (!dir[0])
        return hsbd_error_set(err, HSBD_EINPUT, "no output directory given (use --out DIR)");
    struct stat st;
    if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)) {
        const int empty = run_dir_is_empty(dir);
        if (!empty && !force && run_dir_holds_replicas(dir))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "output directory '%s' already exists and holds an ensemble's "
                                  "replicas; choose another --out, or pass --force to an "
                                  "ensemble to replace them",
                                  dir);
        const int resumable = !empty && !force && run_dir_holds_checkpoint(dir);
        if (!empty && !force)
            return hsbd_error_set(
                err, HSBD_EINPUT,
                "output directory '%s' already exists and is not empty; choose another --out, "
                "%s%s%sor pass --force to replace the earlier run's files",
                dir, resumable ? "continue it with 'hsbd resume " : "", resumable ? dir : "",
                resumable ? "', " : "");
        if (!empty && clear_earlier_run(dir, err) != HSBD_OK) return err->status;
    }
    return hsbd_dir_create(dir, err);
}

/* species name -> index, or -1 */
static int species_index(const char *word, size_t nspecies,
                         const char (*names)[HSBD_SPECIES_NAME]) {
    for (size_t k = 0; k < nspecies; ++k)
        if (!strcmp(word, names[k])) return (int)k;
    return -1;
}

/* one rod as read: its position (0 for L on a ring), length and line */
typedef struct read_rod {
    double x, sigma;
    long line;
} read_rod;

static int compare_rods(const void *a, const void *b) {
    const double xa = ((const read_rod *)a)->x, xb = ((const read_rod *)b)->x;
    return (xa > xb) - (xa < xb);
}

static int is_blank_char(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/* One line "x" or "x name" into *x and *sp; HSBD_EINPUT naming the line otherwise. */
static int parse_position_line(const hsbd_lines *in, const hsbd_config *cfg, double *x, int *sp,
                               hsbd_error *err) {
    const size_t ns = cfg->species.n;
    const char *s = in->text;
    while (is_blank_char(*s))
        ++s;
    const size_t len = hsbd_scan_decimal(s, x);
    const char *e = s + len;
    char word[HSBD_SPECIES_NAME + 1] = "";
    size_t wl = 0;
    if (len > 0 && ns > 0 && is_blank_char(*e)) {
        while (is_blank_char(*e))
            ++e;
        while (*e && !is_blank_char(*e) && wl < HSBD_SPECIES_NAME)
            word[wl++] = *e++;
        word[wl] = '\0';
    }
    while (is_blank_char(*e))
        ++e;
    if (len == 0 || *e != '\0' || !isfinite(*x) || (ns > 0 && !wl))
        return hsbd_error_set(err, HSBD_EINPUT, "%s:%ld: expected %s per line, got '%.40s'",
                              in->name, in->number,
                              ns ? "a finite position and a species name" : "one finite number", s);
    *sp = 0;
    if (ns > 0 && (*sp = species_index(word, ns, cfg->species.name)) < 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:%ld: unknown species '%.40s'; allowed: the species.names",
                              in->name, in->number, word);
    return HSBD_OK;
}

/* the rod inside the ring [0, L] (L is 0 again) or between the walls */
static int check_position(const hsbd_lines *in, const hsbd_config *cfg, double x, double sigma,
                          hsbd_error *err) {
    const double L = cfg->system.length, half = 0.5 * sigma;
    if (cfg->system.boundary == HSBD_BOUNDARY_WALLS) {
        if (x < half * (1 - 1e-12) || x > L - half * (1 - 1e-12))
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: x = %.17g is outside the walls: allowed sigma/2 = %g "
                                  "<= x <= L - sigma/2 = %g",
                                  in->name, in->number, x, half, L - half);
    } else if (!(x >= 0 && x <= L)) {
        return hsbd_error_set(err, HSBD_EINPUT,
                              "%s:%ld: x = %.17g is outside the ring; allowed: 0 <= x <= L = %g "
                              "(positions are not wrapped)",
                              in->name, in->number, x, L);
    }
    return HSBD_OK;
}

/* No two rods closer than their contact distance (on a ring also across x = 0 = L). */
static int check_overlaps(const char *name, const hsbd_config *cfg, read_rod *r, size_t n,
                          hsbd_error *err) {
    const double L = cfg->system.length;
    const int ring = cfg->system.boundary != HSBD_BOUNDARY_WALLS;
    const double tol = 1e-12 * (cfg->system.sigma > 0 ? cfg->system.sigma : 1.0);
    qsort(r, n, sizeof *r, compare_rods);
    for (size_t i = 0; n > 1 && i < (ring ? n : n - 1); ++i) {
        const size_t j = i + 1 < n ? i + 1 : 0;
        const double next = i + 1 < n ? r[j].x : r[0].x + L;
        const double contact = 0.5 * (r[i].sigma + r[j].sigma);
        if (next - r[i].x - contact < -tol)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s:%ld: the rod at x = %.17g and the one at line %ld (x = "
                                  "%.17g) overlap: distance %.17g < contact distance %g; allowed: "
                                  "no overlaps",
                                  name, r[i].line, r[i].x, r[j].line, r[j].x, next - r[i].x,
                                  contact);
    }
    return HSBD_OK;
}

int hsbd_read_positions_stream(FILE *f, const char *name, const hsbd_config *cfg, double *x,
                               int *species, hsbd_error *err) {
    hsbd_error_clear(err);
    const size_t n = (size_t)cfg->system.n;
    read_rod *rods = malloc((n ? n : 1) * sizeof *rods);
    if (!rods) return hsbd_error_set(err, HSBD_ENOMEM, "%s: out of memory for N = %zu", name, n);
    hsbd_lines in;
    hsbd_lines_init(&in, f, name);
    size_t count = 0;
    int got, rc = HSBD_OK;
    while (rc == HSBD_OK && (got = hsbd_lines_next(&in, err)) > 0) {
        const char *s = in.text;
        while (is_blank_char(*s))
            ++s;
        if (*s == '#' || *s == '\0') continue;
        if (count == n) {
            rc = hsbd_error_set(err, HSBD_EINPUT, "%s:%ld: more positions than system.N = %zu",
                                name, in.number, n);
            break;
        }
        double v;
        int sp = 0;
        if ((rc = parse_position_line(&in, cfg, &v, &sp, err)) != HSBD_OK) break;
        const double sigma = cfg->species.n ? cfg->species.sigma[sp] : cfg->system.sigma;
        if ((rc = check_position(&in, cfg, v, sigma, err)) != HSBD_OK) break;
        if (species) species[count] = sp;
        x[count] = v;
        const int ring = cfg->system.boundary != HSBD_BOUNDARY_WALLS;
        rods[count++] = (read_rod){ring && v == cfg->system.length ? 0 : v, sigma, in.number};
    }
    if (rc == HSBD_OK && got < 0) rc = err->status;
    hsbd_lines_free(&in);
    if (rc == HSBD_OK && count != n)
        rc = hsbd_error_set(err, HSBD_EINPUT, "%s: %zu positions for system.N = %zu", name, count,
                            n);
    if (rc == HSBD_OK && cfg->system.hard_core) rc = check_overlaps(name, cfg, rods, n, err);
    free(rods);
    return rc;
}

int hsbd_read_positions(const hsbd_config *cfg, double *x, int *species, hsbd_error *err) {
    const char *path = cfg->init.positions;
    FILE *f = hsbd_input_open(path, "init.positions file", err);
    if (!f) return err->status;
    const int rc = hsbd_read_positions_stream(f, path, cfg, x, species, err);
    fclose(f);
    return rc;
}
