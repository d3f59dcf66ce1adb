/* Ensembles of replicas (see hsbd/run.h, docs/scaling.md): the replicas' noise keys, their
 * run directories DIR/replica-k, and the replicas a process runs. The merge of their
 * results is src/run/merge.c. */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hsbd/io.h"
#include "io/files.h"
#include "run/run.h"

/* Replica k's Philox key: the seed moved by k steps of the golden-ratio Weyl sequence
 * (replica 0, and a run that is no replica, keep the seed itself). */
uint64_t run_noise_seed(const hsbd_config *cfg) {
    const uint64_t k = cfg->run.replica > 0 ? (uint64_t)cfg->run.replica : 0;
    return cfg->system.seed + k * UINT64_C(0x9E3779B97F4A7C15);
}

size_t hsbd_ensemble_size(const hsbd_config *cfg, int ranks) {
    if (cfg->run.replica >= 0) return 1; /* one replica, run alone */
    if (cfg->run.replicas > 0) return (size_t)cfg->run.replicas;
    return ranks > 1 ? (size_t)ranks : 1;
}

int run_replica_dir(const char *dir, size_t k, char *out, size_t len, hsbd_error *err) {
    const int n = snprintf(out, len, "%s/replica-%zu", dir, k);
    if (n < 0 || (size_t)n >= len)
        return hsbd_error_set(err, HSBD_EINPUT, "output.dir '%.200s...': too long for its replicas",
                              dir);
    return HSBD_OK;
}

/* No process writes in dir (a run or a resume of it): HSBD_OK, else HSBD_EINPUT naming it. */
static int not_in_use(const char *dir, hsbd_error *err) {
    int lock;
    const int rc = run_dir_claim(dir, RUN_DIR_CHECK, &lock, err);
    run_dir_release(lock);
    return rc;
}

/* Each entry replica-K of an earlier ensemble in dir: a directory of its own (not a
 * symbolic link, which --force would follow out of dir) holding only a run's files. With
 * remove, they are then removed; without, only checked. */
static int earlier_replicas(const char *dir, int remove, hsbd_error *err) {
    DIR *d = run_dir_open(dir, err);
    if (!d) return err->status;
    int rc = HSBD_OK;
    for (struct dirent *e; rc == HSBD_OK && (e = readdir(d));) {
        if (!run_is_replica_name(e->d_name)) continue;
        char sub[HSBD_PATH_MAX + 300];
        snprintf(sub, sizeof sub, "%s/%s", dir, e->d_name);
        struct stat st;
        if (lstat(sub, &st) != 0 || S_ISREG(st.st_mode)) continue; /* a file: checked below */
        if (!S_ISDIR(st.st_mode))
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "output directory '%s' holds '%s', which is not a replica's "
                                "directory (a link or special file); --force replaces only an "
                                "earlier run's files: choose another --out",
                                dir, e->d_name);
        else if (!remove)
            rc = not_in_use(sub, err) == HSBD_OK ? run_dir_check_earlier(sub, 0, err) : err->status;
        else if (hsbd_run_dir_prepare(sub, 1, err) != HSBD_OK)
            rc = err->status;
        else if (run_dir_remove(sub) != 0)
            rc = hsbd_error_set(err, HSBD_EINPUT, "cannot remove '%s' of the earlier run: %s", sub,
                                strerror(errno));
    }
    closedir(d);
    return rc;
}

/* DIR.earlier: where --force sets an earlier ensemble aside until the new one is done */
static int earlier_path(const char *dir, char *out, size_t len) {
    const size_t n = run_path_bare(dir, out, len);
    return n + sizeof ".earlier" <= len ? (strcat(out, ".earlier"), 0) : -1;
}

/* An input file of the configuration inside dir would go with dir's earlier files, and a
 * working directory inside dir with them (the replicas record it for their resumes). */
static int input_inside(const hsbd_config *cfg, const char *dir, hsbd_error *err) {
    const char *key[3], *path[3];
    const size_t n = run_input_files(cfg, key, path);
    for (size_t k = 0; k < n; ++k)
        if (run_path_nesting(dir, path[k]) > 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "%s '%s' lies inside the output directory '%s', whose earlier "
                                  "files --force replaces; copy it elsewhere first",
                                  key[k], path[k], dir);
    char here[PATH_MAX];
    if (getcwd(here, sizeof here) && run_path_nesting(dir, here) > 0)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "the working directory '%s' lies inside the output directory '%s', "
                              "whose earlier files --force sets aside and removes; start the "
                              "ensemble from another directory",
                              here, dir);
    return HSBD_OK;
}

static void finish_dir(const char *dir, int status, hsbd_ensemble_claim *claim);

/* Makes DIR (when missing) and claims it: claim->created counts the levels made here, kept
 * only once the claim holds (a DIR another process claimed first is not this run's). */
static int make_and_claim(const char *dir, hsbd_ensemble_claim *claim, hsbd_error *err) {
    int made = 0;
    if (run_dir_make(dir, &made) != 0) return HSBD_OK; /* hsbd_run_dir_prepare says why */
    const int rc = run_dir_claim(dir, RUN_DIR_WRITE_NEW, &claim->lock, err);
    claim->created = rc == HSBD_OK ? made : 0;
    return rc;
}

/* An empty or missing DIR: claimed (made when missing), then checked as a run directory. */
static int prepare_new(const char *dir, int force, hsbd_ensemble_claim *claim, hsbd_error *err) {
    struct stat st;
    const int file = dir[0] && stat(dir, &st) == 0 && !S_ISDIR(st.st_mode);
    int rc = file || !dir[0] ? HSBD_OK /* the check below refuses it */
                             : make_and_claim(dir, claim, err);
    if (rc == HSBD_OK) rc = hsbd_run_dir_prepare(dir, force, err);
    if (rc != HSBD_OK) finish_dir(dir, rc, claim);
    return rc;
}

/* The directory --force sets aside for DIR: DIR itself, or the one it names when it is a
 * symbolic link (a link to scratch space keeps pointing to the new results there; moving
 * the link would set the link aside and put the new results beside it) or ends in . or ..
 * (DIR/. cannot be renamed). */
static int aside_target(const char *dir, char *target, hsbd_error *err) {
    char bare[HSBD_PATH_MAX];
    run_path_bare(dir, bare, sizeof bare); /* a trailing slash would follow the link */
    const char *last = strrchr(bare, '/') ? strrchr(bare, '/') + 1 : bare;
    struct stat st;
    char resolved[PATH_MAX];
    if (strcmp(last, ".") && strcmp(last, "..") && (lstat(bare, &st) != 0 || !S_ISLNK(st.st_mode)))
        return snprintf(target, HSBD_PATH_MAX, "%s", dir), HSBD_OK;
    if (hsbd_path_resolve(bare, resolved) != 0 || strlen(resolved) >= HSBD_PATH_MAX)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "output directory '%s' cannot be resolved to a directory within "
                              "%d characters (a link that cannot be followed, or a long target)",
                              dir, HSBD_PATH_MAX - 1);
    memcpy(target, resolved, strlen(resolved) + 1); /* fits: checked above */
    return HSBD_OK;
}

/* The new DIR keeps the mode and group of the one set aside (a group's scratch space with
 * its setgid bit stays shared), the owner's access kept. Best effort, and only on the
 * directory just made: opened without following a link and checked to hold this run's
 * lock file (another user of a shared parent could have put something else in its place);
 * without the group (not a member) the mode stays as made (a chmod by a non-member would
 * drop a setgid bit inherited from the parent). */
static void keep_mode_and_group(const char *dir, const char *aside, int lock) {
    struct stat old, held, found;
    if (lock < 0 || stat(aside, &old) != 0 || fstat(lock, &held) != 0) return;
    const int d = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
    if (d < 0) return;
    if (fstatat(d, RUN_LOCK_FILE, &found, AT_SYMLINK_NOFOLLOW) == 0 &&
        found.st_dev == held.st_dev && found.st_ino == held.st_ino &&
        fchown(d, (uid_t)-1, old.st_gid) == 0)
        fchmod(d, (old.st_mode & 07777u) | S_IRWXU);
    close(d);
}

/* --force over earlier results in dir (checked to be a run's or an ensemble's, with no
 * process writing in it or in a replica-K): they are set aside as DIR.earlier, not removed
 * (the new ensemble may still fail on a replica's input), and a new DIR is claimed. */
static int set_earlier_aside(const hsbd_config *cfg, hsbd_ensemble_claim *claim, hsbd_error *err) {
    const char *dir = claim->dir;
    char aside[HSBD_PATH_MAX + 16];
    struct stat st;
    int rc = aside_target(cfg->output.dir, claim->dir, err);
    if (rc == HSBD_OK) rc = run_dir_claim(dir, RUN_DIR_WRITE_NEW, &claim->aside_lock, err);
    if (rc == HSBD_OK) rc = input_inside(cfg, dir, err);
    if (rc == HSBD_OK) rc = earlier_replicas(dir, 0, err); /* and their writers */
    if (rc == HSBD_OK) rc = run_dir_check_earlier(dir, 1, err);
    if (rc == HSBD_OK && earlier_path(dir, aside, sizeof aside))
        rc = hsbd_error_set(err, HSBD_EINPUT, "output.dir '%.200s...' is too long", dir);
    if (rc == HSBD_OK && lstat(aside, &st) == 0)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "'%s' exists (earlier results set aside by a --force that did not "
                            "finish); remove or rename it before replacing '%s'",
                            aside, dir);
    if (rc == HSBD_OK && rename(dir, aside) != 0)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "cannot set the earlier results in '%s' aside as '%s': %s; remove "
                            "them yourself or choose another --out",
                            dir, aside, strerror(errno));
    if (rc != HSBD_OK) {
        run_dir_release(claim->aside_lock);
        claim->aside_lock = -1;
        return rc;
    }
    claim->set_aside = 1;
    rc = make_and_claim(dir, claim, err);
    if (rc == HSBD_OK && claim->created) keep_mode_and_group(dir, aside, claim->lock);
    return rc == HSBD_OK ? rc : hsbd_ensemble_finish(cfg, rc, claim, err);
}

int hsbd_ensemble_prepare(const hsbd_config *cfg, int force, hsbd_ensemble_claim *claim,
                          hsbd_error *err) {
    hsbd_error_clear(err);
    *claim = (hsbd_ensemble_claim){.lock = -1, .aside_lock = -1};
    const char *dir = cfg->output.dir;
    struct stat st;
    if (dir[0] && stat(dir, &st) != 0 && errno != ENOENT)
        return hsbd_run_dir_prepare(dir, force, err); /* its message */
    if (!dir[0] || stat(dir, &st) != 0 || !S_ISDIR(st.st_mode) || run_dir_is_empty(dir))
        return prepare_new(dir, force, claim, err);
    if (!force)
        return hsbd_error_set(err, HSBD_EINPUT,
                              "output directory '%s' already exists and is not empty; choose "
                              "another --out, pass --force to replace the earlier files, or "
                              "continue an interrupted ensemble replica by replica (hsbd "
                              "resume %s/replica-K, then hsbd merge %s)",
                              dir, dir, dir);
    if (run_dir_holds_run(dir))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "output directory '%s' holds a single run (its checkpoint or "
                              "summary.json): an ensemble's --force replaces only an earlier "
                              "ensemble's results, never a run's; choose another --out",
                              dir);
    return set_earlier_aside(cfg, claim, err);
}

/* The end of an ensemble in dir that did not set earlier results aside: a directory it made
 * goes again when it failed before any replica began (the replicas make theirs once their
 * input is accepted); the lock goes. */
static void finish_dir(const char *dir, int status, hsbd_ensemble_claim *claim) {
    if (status != HSBD_OK && claim->created && run_dir_is_empty(dir))
        run_dir_unmake(dir, claim->created);
    run_dir_release(claim->lock);
    claim->lock = -1;
    claim->created = 0;
}

/* The earlier results set aside in `aside`, after the ensemble in dir: removed when it
 * succeeded; when it failed, back in dir if no replica began, else left (err's message
 * says which). Returns status, or an error when they cannot be removed. */
static int finish_aside(const char *dir, const char *aside, int status, int created,
                        hsbd_error *err) {
    struct stat st;
    const size_t len = strlen(err->message);
    char *more = err->message + len;
    const size_t room = sizeof err->message - len;
    if (status == HSBD_OK) { /* replaced: the earlier files go */
        hsbd_error e;
        hsbd_error_clear(&e);
        if (earlier_replicas(aside, 1, &e) == HSBD_OK &&
            hsbd_run_dir_prepare(aside, 1, &e) == HSBD_OK) {
            if (run_dir_remove(aside) == 0) return HSBD_OK;
            hsbd_error_set(&e, HSBD_EIO, "%s", strerror(errno));
        }
        return hsbd_error_set(err, HSBD_EIO,
                              "the new ensemble in '%s' is complete, but the earlier one set "
                              "aside as '%s' could not be removed: %s",
                              dir, aside, e.message);
    }
    int restored = 0; /* a dir made here (not one another process claimed) and still empty */
    if (stat(dir, &st) != 0 || (created && run_dir_is_empty(dir))) {
        if (created) run_dir_remove(dir);
        restored = rename(aside, dir) == 0;
    }
    snprintf(more, room, "%s%s '%s'", len ? "; " : "",
             restored ? "the earlier results are back in" : "the earlier results were set aside as",
             restored ? dir : aside);
    return status;
}

int hsbd_ensemble_finish(const hsbd_config *cfg, int status, hsbd_ensemble_claim *claim,
                         hsbd_error *err) {
    char aside[HSBD_PATH_MAX + 16];
    if (!claim->set_aside) {
        finish_dir(cfg->output.dir, status, claim);
        return status;
    }
    const char *dir = claim->dir;
    /* the locks are held until the end (another process may still make dir between its
     * removal and the rename back: the restore then fails, and the message says so) */
    const int rc = earlier_path(dir, aside, sizeof aside)
                       ? status
                       : finish_aside(dir, aside, status, claim->created, err);
    run_dir_release(claim->lock);
    run_dir_release(claim->aside_lock);
    *claim = (hsbd_ensemble_claim){.lock = -1, .aside_lock = -1};
    return rc;
}

/* The source of replica k's checkpoints: the run's own with run.replica=k appended, so
 * that `hsbd resume DIR/replica-k` continues that replica. */
typedef struct replica_source {
    hsbd_run_source source;
    const char **sets;
    char replica_set[64];
} replica_source;

static int replica_source_make(replica_source *rs, const hsbd_run_source *src, size_t k) {
    const size_t n = src ? src->nsets : 0;
    rs->sets = calloc(n + 1, sizeof *rs->sets);
    if (!rs->sets) return -1;
    for (size_t j = 0; j < n; ++j)
        rs->sets[j] = src->sets[j];
    snprintf(rs->replica_set, sizeof rs->replica_set, "run.replica=%zu", k);
    rs->sets[n] = rs->replica_set;
    rs->source = src ? *src : (hsbd_run_source){.text = "", .text_len = 0};
    rs->source.sets = rs->sets;
    rs->source.nsets = n + 1;
    return 0;
}

int hsbd_ensemble_run(const hsbd_config *cfg, const hsbd_run_options *opt, size_t replicas,
                      int rank, int ranks, hsbd_error *err) {
    hsbd_error_clear(err);
    hsbd_config *one = malloc(sizeof *one);
    if (!one) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    int rc = HSBD_OK;
    for (size_t k = (size_t)rank; k < replicas && rc == HSBD_OK; k += (size_t)ranks) {
        *one = *cfg;
        one->run.replica = (int64_t)k;
        rc = run_replica_dir(cfg->output.dir, k, one->output.dir, sizeof one->output.dir, err);
        if (rc != HSBD_OK) break;
        replica_source rs;
        if (replica_source_make(&rs, opt->source, k) != 0) {
            rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
            break;
        }
        hsbd_run_options o = *opt;
        o.source = &rs.source;
        o.quiet_warnings |= k > 0; /* the same warnings replica by replica: printed once */
        rc = hsbd_run(one, &o, err);
        free(rs.sets);
    }
    free(one);
    return rc;
}

int hsbd_ensemble_merge(const hsbd_config *cfg, size_t replicas, hsbd_error *err) {
    hsbd_error_clear(err);
    char(*paths)[HSBD_PATH_MAX + 32] = calloc(replicas, sizeof *paths);
    const char **dirs = calloc(replicas, sizeof *dirs);
    int rc = paths && dirs ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t k = 0; k < replicas && rc == HSBD_OK; ++k) {
        rc = run_replica_dir(cfg->output.dir, k, paths[k], sizeof paths[k], err);
        dirs[k] = paths[k];
    }
    if (rc == HSBD_OK) rc = run_merge_into(cfg->output.dir, dirs, replicas, 0, 0, err);
    free(paths), free(dirs);
    return rc;
}
