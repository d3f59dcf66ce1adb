#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <dirent.h>
#include <unistd.h>

#include "hsbd/io.h"

int hsbd_outfile_open(hsbd_outfile *o, const char *dir, const char *name, hsbd_error *err) {
    snprintf(o->path, sizeof o->path, "%s/%s", dir, name);
    snprintf(o->tmp, sizeof o->tmp, "%s.part", o->path);
    o->f = fopen(o->tmp, "w");
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

int hsbd_outfile_reopen(hsbd_outfile *o, const char *dir, const char *name, int64_t length,
                        hsbd_error *err) {
    snprintf(o->path, sizeof o->path, "%s/%s", dir, name);
    snprintf(o->tmp, sizeof o->tmp, "%s.part", o->path);
    struct stat st;
    if (stat(o->tmp, &st) != 0 && rename(o->path, o->tmp) != 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "cannot continue '%s': neither it nor '%s' can be opened (%s)",
                              o->path, o->tmp, strerror(errno));
    o->f = fopen(o->tmp, "r+");
    if (!o->f)
        return hsbd_error_set(err, HSBD_EIO, "cannot open '%s': %s", o->tmp, strerror(errno));
    if (fseeko(o->f, 0, SEEK_END) != 0 || ftello(o->f) < length) {
        const long long have = (long long)ftello(o->f);
        fclose(o->f), o->f = NULL;
        return hsbd_error_set(err, HSBD_EINPUT,
                              "cannot continue '%s': it has %lld bytes, the checkpoint counts %lld",
                              o->tmp, have, (long long)length);
    }
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
        "plot.png",        ".hsbd-probe"};
    char base[256];
    snprintf(base, sizeof base, "%s", name);
    const size_t len = strlen(base);
    if (len > 5 && !strcmp(base + len - 5, ".part")) base[len - 5] = '\0';
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
        if (!strcmp(base, names[k])) return 1;
    return 0;
}

/* An earlier run's files are removed (--force); anything else in the directory refuses. */
static int clear_earlier_run(const char *dir, hsbd_error *err) {
    DIR *d = opendir(dir);
    if (!d)
        return hsbd_error_set(err, HSBD_EINPUT, "cannot read output directory '%s': %s", dir,
                              strerror(errno));
    int rc = HSBD_OK;
    for (struct dirent *e; rc == HSBD_OK && (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && !is_run_output(e->d_name))
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "output directory '%s' holds '%s', which is not a file of an "
                                "hsbd run; --force replaces only an earlier run's files: choose "
                                "another --out",
                                dir, e->d_name);
    closedir(d);
    if (rc != HSBD_OK) return rc;
    d = opendir(dir);
    for (struct dirent *e; d && (e = readdir(d));) {
        if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
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
    return probe_writable(dir, err);
}

int hsbd_run_dir_prepare(const char *dir, int force, hsbd_error *err) {
    if (!dir[0])
        return hsbd_error_set(err, HSBD_EINPUT, "no output directory given (use --out DIR)");
    struct stat st;
    if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)) {
        DIR *d = opendir(dir);
        int empty = 1;
        if (d) {
            for (struct dirent *e; (e = readdir(d));)
                if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) empty = 0;
            closedir(d);
        }
        if (!empty && !force)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "output directory '%s' already exists and is not empty; choose "
                                  "another --out, continue it with 'hsbd resume %s', or pass "
                                  "--force to replace the earlier run's files",
                                  dir, dir);
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

int hsbd_read_positions(const char *path, size_t n, double *x, size_t nspecies,
                        const char (*names)[HSBD_SPECIES_NAME], int *species, hsbd_error *err) {
    FILE *f = fopen(path, "r");
    if (!f)
        return hsbd_error_set(err, HSBD_EINPUT, "init.positions: cannot read '%s': %s", path,
                              strerror(errno));
    char line[512];
    size_t count = 0;
    int lineno = 0, rc = HSBD_OK;
    while (fgets(line, sizeof line, f)) {
        ++lineno;
        char *s = line;
        while (*s == ' ' || *s == '\t')
            ++s;
        if (*s == '#' || *s == '\n' || *s == '\r' || *s == '\0') continue;
        char *end;
        const double v = strtod(s, &end);
        char word[HSBD_SPECIES_NAME + 2] = "";
        int used = 0;
        if (nspecies > 0 && end != s) sscanf(end, " %33[A-Za-z0-9_]%n", word, &used);
        end += used;
        while (*end == ' ' || *end == '\t' || *end == '\r' || *end == '\n')
            ++end;
        if (end == s || *end != '\0' || !isfinite(v) || (nspecies > 0 && !word[0])) {
            rc = hsbd_error_set(err, HSBD_EINPUT, "%s:%d: expected %s per line", path, lineno,
                                nspecies ? "a finite position and a species name"
                                         : "one finite number");
            break;
        }
        if (count == n) {
            rc = hsbd_error_set(err, HSBD_EINPUT, "%s:%d: more positions than system.N = %zu", path,
                                lineno, n);
            break;
        }
        if (nspecies > 0) {
            const int k = species_index(word, nspecies, names);
            if (k < 0) {
                rc = hsbd_error_set(err, HSBD_EINPUT,
                                    "%s:%d: unknown species '%s'; allowed: the species.names", path,
                                    lineno, word);
                break;
            }
            species[count] = k;
        }
        x[count++] = v;
    }
    fclose(f);
    if (rc == HSBD_OK && count != n)
        rc = hsbd_error_set(err, HSBD_EINPUT, "%s: %zu positions for system.N = %zu", path, count,
                            n);
    return rc;
}
