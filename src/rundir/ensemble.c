/* Ensembles of replicas (see rundir.h, docs/scaling.md): replica k runs the whole
 * configuration into DIR/replica-k with its own noise (run.replica = k); the process that
 * began the ensemble holds DIR's lock and merges the replicas into DIR at the end. */
#include "rundir/rundir.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

size_t rundir_ensemble_size(const hsbd_config *cfg, int ranks) {
    if (cfg->run.replica >= 0) return 1; /* one replica, run alone */
    if (cfg->run.replicas > 0) return (size_t)cfg->run.replicas;
    return ranks > 1 ? (size_t)ranks : 1;
}

/* An ensemble's directory must hold nothing: an ensemble replaces no earlier results. */
static int refuse_earlier(const char *dir, hsbd_error *err) {
    if (rundir_holds_run(dir) && !rundir_holds_replicas(dir))
        return hsbd_error_set(err, HSBD_EINPUT,
                              "output directory '%s' holds a single run (its checkpoint or "
                              "summary.json), which an ensemble never replaces (with or without "
                              "--force); choose another --out",
                              dir);
    return hsbd_error_set(err, HSBD_EINPUT,
                          "output directory '%s' already exists and is not empty; an ensemble "
                          "replaces no earlier results (with or without --force): remove them or "
                          "choose another --out, or continue an interrupted ensemble replica by "
                          "replica (hsbd resume %s/replica-K, then hsbd merge %s)",
                          dir, dir, dir);
}

int rundir_ensemble_begin(const hsbd_config *cfg, rundir_ensemble *e, hsbd_error *err) {
    hsbd_error_clear(err);
    *e = (rundir_ensemble){.lock = -1};
    const char *dir = cfg->output.dir;
    struct stat st;
    int made = 0;
    if (!dir[0] || (stat(dir, &st) != 0 && rundir_make(dir, &made) != 0))
        return rundir_create(dir, err); /* its message */
    int rc = rundir_claim(dir, RUNDIR_WRITE_NEW, &e->lock, err);
    e->made = rc == HSBD_OK ? made : 0; /* a directory another process claimed is not ours */
    if (rc == HSBD_OK && !rundir_is_empty(dir)) rc = refuse_earlier(dir, err);
    if (rc == HSBD_OK) rc = rundir_create(dir, err); /* a file, a dangling link, no access */
    return rc == HSBD_OK ? rc : rundir_ensemble_end(cfg, rc, e, err);
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

/* Replica k of cfg, run into DIR/replica-k. */
static int run_replica(const hsbd_config *cfg, const hsbd_run_options *opt, size_t k,
                       hsbd_config *one, hsbd_error *err) {
    *one = *cfg;
    one->run.replica = (int64_t)k;
    const int n =
        snprintf(one->output.dir, sizeof one->output.dir, "%s/replica-%zu", cfg->output.dir, k);
    if (n < 0 || (size_t)n >= sizeof one->output.dir)
        return hsbd_error_set(err, HSBD_EINPUT, "output.dir '%.200s...': too long for its replicas",
                              cfg->output.dir);
    replica_source rs;
    if (replica_source_make(&rs, opt->source, k) != 0)
        return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    hsbd_run_options o = *opt;
    o.source = &rs.source;
    o.quiet_warnings |= k > 0; /* the same warnings replica by replica: printed once */
    const int rc = hsbd_run(one, &o, err);
    free(rs.sets);
    return rc;
}

int rundir_ensemble_run(const hsbd_config *cfg, const hsbd_run_options *opt, size_t replicas,
                        int rank, int ranks, hsbd_error *err) {
    hsbd_error_clear(err);
    hsbd_config *one = malloc(sizeof *one);
    int rc = one ? HSBD_OK : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    for (size_t k = (size_t)rank; k < replicas && rc == HSBD_OK; k += (size_t)ranks)
        rc = run_replica(cfg, opt, k, one, err);
    free(one);
    return rc;
}

int rundir_ensemble_end(const hsbd_config *cfg, int status, rundir_ensemble *e, hsbd_error *err) {
    const char *dir = cfg->output.dir;
    if (status == HSBD_OK) status = rundir_merge_ensemble(dir, err);
    if (status != HSBD_OK && e->made && rundir_is_empty(dir)) rundir_unmake(dir, e->made);
    rundir_release(e->lock);
    *e = (rundir_ensemble){.lock = -1};
    return status;
}
