/* One run directory (see rundir.h): its lock, what it holds, and its preparation. */
#include "rundir/rundir.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

/* The files a run (or the tools beside it) writes into a run directory, each with or
 * without its ".part" (an output being written). */
static int is_run_output(const char *name) {
    static const char outputs[] =
        " density.tsv contact.tsv density_blocks.tsv contact_blocks.tsv msd.tsv clusters.tsv"
        " current.tsv gr.tsv fs.tsv sk.tsv log.tsv orientation.tsv local_density.tsv"
        " density_phases.tsv density_x.tsv density_y.tsv density_z.tsv theory.tsv percus.tsv"
        " summary.json trajectory.xyz trajectory.gsd checkpoint.hsbd checkpoint.prev.hsbd"
        " plot.png .hsbd-probe " RUNDIR_LOCK_FILE " ";
    const size_t len = strlen(name),
                 base = len > 5 && !strcmp(name + len - 5, ".part") ? len - 5 : len;
    char word[300]; /* " name " (a name is at most 255 bytes) */
    snprintf(word, sizeof word, " %.*s ", (int)base, name);
    return base > 0 && !strchr(name, ' ') && strstr(outputs, word);
}

int rundir_replica_entry(const char *dir, const char *name) {
    if (strncmp(name, "replica-", 8) || !name[8] ||
        strspn(name + 8, "0123456789") != strlen(name + 8))
        return 0;
    char path[HSBD_PATH_MAX + 300];
    struct stat st;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return lstat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* The first entry of dir that is not an earlier run's file (nor, with replicas, a replica
 * directory) into found (len > 0); 0 when there is none or dir cannot be read. */
static int foreign_entry(const char *dir, int replicas, char *found, size_t len) {
    DIR *d = opendir(dir);
    found[0] = '\0';
    for (struct dirent *e; d && !found[0] && (e = readdir(d));)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") && !is_run_output(e->d_name) &&
            !(replicas && rundir_replica_entry(dir, e->d_name)))
            snprintf(found, len, "%s", e->d_name);
    if (d) closedir(d);
    return found[0] != '\0';
}

int rundir_is_empty(const char *dir) {
    DIR *d = opendir(dir);
    int empty = 1;
    for (struct dirent *e; d && empty && (e = readdir(d));)
        empty = !strcmp(e->d_name, ".") || !strcmp(e->d_name, "..") ||
                !strcmp(e->d_name, RUNDIR_LOCK_FILE);
    if (d) closedir(d);
    return empty;
}

static int holds_file(const char *dir, const char *name) {
    char path[HSBD_PATH_MAX + 300];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

int rundir_holds_checkpoint(const char *dir) {
    return holds_file(dir, "checkpoint.hsbd") || holds_file(dir, "checkpoint.prev.hsbd");
}

int rundir_holds_run(const char *dir) {
    if (rundir_holds_checkpoint(dir)) return 1;
    char path[HSBD_PATH_MAX + 300], line[256];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    FILE *f = holds_file(dir, "summary.json") ? fopen(path, "r") : NULL;
    if (!f) return 0;
    int merged = 0; /* a merge's summary lists the replicas it merged */
    while (!merged && fgets(line, sizeof line, f))
        merged = strstr(line, "\"replica_indices\":") != NULL;
    fclose(f);
    return !merged;
}

int rundir_holds_replicas(const char *dir) {
    DIR *d = opendir(dir);
    int found = 0;
    for (struct dirent *e; d && !found && (e = readdir(d));)
        found = rundir_replica_entry(dir, e->d_name);
    if (d) closedir(d);
    return found;
}

/* ---- the lock ---------------------------------------------------------------------------- */

/* Opens dir's lock file for `use`: its descriptor, -1 when there is none to take (no
 * directory, no lock file yet for a reader or a check, a directory of other files: no lock
 * file is left there), or -2 with err set when the name is no lock file. */
static int open_lock_file(const char *dir, rundir_use use, hsbd_error *err) {
    char path[HSBD_PATH_MAX + 32], other[256];
    snprintf(path, sizeof path, "%s/%s", dir, RUNDIR_LOCK_FILE);
    const int create = use == RUNDIR_WRITE ||
                       (use == RUNDIR_WRITE_NEW && !foreign_entry(dir, 1, other, sizeof other));
    /* NFS grants an exclusive lock only on a file open for writing; O_NONBLOCK: a FIFO
     * must not block the open */
    const int flags = O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK;
    int f =
        open(path, (use == RUNDIR_READ ? O_RDONLY : O_RDWR) | (create ? O_CREAT : 0) | flags, 0666);
    if (f < 0 && errno == EACCES && use != RUNDIR_READ) /* another user's: local locks */
        f = open(path, O_RDONLY | flags);               /* need no write access */
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

int rundir_claim(const char *dir, rundir_use use, int *fd, hsbd_error *err) {
    *fd = -1;
    struct stat st;
    int made;
    if (!dir[0] || (use == RUNDIR_WRITE_NEW && stat(dir, &st) != 0 && rundir_make(dir, &made)))
        return HSBD_OK; /* the directory's own checks say why */
    const int f = open_lock_file(dir, use, err);
    if (f == -2) return err->status;
    if (f < 0) return HSBD_OK;
    if (flock(f, (use == RUNDIR_READ ? LOCK_SH : LOCK_EX) | LOCK_NB) == 0) return *fd = f, HSBD_OK;
    const int busy = errno == EWOULDBLOCK;
    close(f);
    if (!busy) return HSBD_OK; /* no locks on this file system */
    return hsbd_error_set(err, HSBD_EINPUT,
                          "run directory '%s' is in use: another hsbd process (a run, a resume, "
                          "an ensemble or a merge) is %s there; wait until it ends",
                          dir, use == RUNDIR_READ ? "writing" : "writing or reading");
}

void rundir_release(int fd) {
    if (fd >= 0) close(fd); /* closing drops the lock */
}

/* ---- making and preparing ---------------------------------------------------------------- */

int rundir_make(const char *dir, int *made) {
    char buf[HSBD_PATH_MAX];
    snprintf(buf, sizeof buf, "%s", dir);
    *made = 0;
    for (char *p = buf + !!buf[0];; ++p) {
        if (*p && *p != '/') continue;
        const char end = *p;
        *p = '\0';
        if (mkdir(buf, 0777) == 0)
            ++*made;
        else if (errno != EEXIST)
            return -1;
        if (!end) return 0;
        *p = '/';
    }
}

void rundir_unmake(const char *dir, int made) {
    char buf[HSBD_PATH_MAX], lock[HSBD_PATH_MAX + 32];
    snprintf(buf, sizeof buf, "%s", dir);
    for (size_t n = strlen(buf); n > 1 && buf[n - 1] == '/';) /* "/" stays */
        buf[--n] = '\0';
    snprintf(lock, sizeof lock, "%s/%s", buf, RUNDIR_LOCK_FILE);
    if (made > 0) unlink(lock);
    for (int k = 0; k < made && rmdir(buf) == 0; ++k) {
        char *slash = strrchr(buf, '/');
        if (!slash || slash == buf) return;
        while (slash > buf && *slash == '/') /* the parent, without trailing slashes */
            *slash-- = '\0';
    }
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

int rundir_create(const char *dir, hsbd_error *err) {
    if (!dir[0])
        return hsbd_error_set(err, HSBD_EINPUT, "no output directory given (use --out DIR)");
    struct stat st;
    if (stat(dir, &st) == 0 && !S_ISDIR(st.st_mode))
        return hsbd_error_set(err, HSBD_EINPUT, "output path '%s' exists and is not a directory",
                              dir);
    int made;
    if (rundir_make(dir, &made) != 0)
        return hsbd_error_set(err, HSBD_EINPUT, "cannot create output directory '%s': %s", dir,
                              strerror(errno));
    if (stat(dir, &st) != 0) /* mkdir does not follow a dangling link */
        return hsbd_error_set(err, HSBD_EINPUT,
                              "output directory '%s' leads to no directory (a dangling symbolic "
                              "link?): %s; create it or choose another --out",
                              dir, strerror(errno));
    return probe_writable(dir, err);
}

/* --force: an earlier run's files are removed (the lock file stays: this process may hold
 * it); anything else in the directory refuses. */
static int clear_earlier_run(const char *dir, hsbd_error *err) {
    char other[256];
    if (foreign_entry(dir, 0, other, sizeof other))
        return hsbd_error_set(err, HSBD_EINPUT,
                              rundir_replica_entry(dir, other)
                                  ? "output directory '%s' holds '%s', a replica of an ensemble: "
                                    "a single run does not replace an ensemble's results; choose "
                                    "another --out"
                                  : "output directory '%s' holds '%s', which is not a file of an "
                                    "hsbd run; --force replaces only an earlier run's files: "
                                    "choose another --out",
                              dir, other);
    DIR *d = opendir(dir);
    int rc = d ? HSBD_OK
               : hsbd_error_set(err, HSBD_EINPUT, "cannot read output directory '%s': %s", dir,
                                strerror(errno));
    for (struct dirent *e; d && (e = readdir(d));) {
        char path[HSBD_PATH_MAX + 300];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (is_run_output(e->d_name) && strcmp(e->d_name, RUNDIR_LOCK_FILE) && remove(path) != 0 &&
            rc == HSBD_OK)
            rc = hsbd_error_set(err, HSBD_EINPUT, "cannot remove '%s' of the earlier run: %s", path,
                                strerror(errno));
    }
    if (d) closedir(d);
    return rc;
}

int rundir_prepare(const char *dir, int force, hsbd_error *err) {
    struct stat st;
    if (!dir[0] || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode) || rundir_is_empty(dir))
        return rundir_create(dir, err);
    if (force)
        return clear_earlier_run(dir, err) == HSBD_OK ? rundir_create(dir, err) : err->status;
    if (rundir_holds_replicas(dir))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "output directory '%s' already exists and holds an ensemble's "
                              "replicas; choose another --out (nothing replaces an ensemble)",
                              dir);
    const int resumable = rundir_holds_checkpoint(dir);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "output directory '%s' already exists and is not empty; choose another "
                          "--out, %s%s%sor pass --force to replace the earlier run's files",
                          dir, resumable ? "continue it with 'hsbd resume " : "",
                          resumable ? dir : "", resumable ? "', " : "");
}
