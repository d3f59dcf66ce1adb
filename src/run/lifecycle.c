/* The run lifecycle (see run.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "run/run.h"

#include <errno.h>
#include <stdarg.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/progress.h"
#include "core/threads.h"
#include "hsbd/observe.h"
#include "hsbd_version.h"
#include "io/tables.h"
#include "run/checkpoint.h"
#include "rundir/rundir.h"

int run_add_op(run *r, const char *name, uint64_t every, run_action act, void *ctx,
               hsbd_error *err) {
    if (r->nops == RUN_MAX_OPS)
        return hsbd_error_set(err, HSBD_ENOMEM, "run: too many operations (%s)", name);
    r->ops[r->nops++] = (run_op){name, every, act, ctx};
    return HSBD_OK;
}

run_stream *run_add_stream(run *r, const char *name, hsbd_error *err) {
    if (r->nstreams == RUN_MAX_STREAMS) {
        hsbd_error_set(err, HSBD_ENOMEM, "run: too many streams (%s)", name);
        return NULL;
    }
    run_stream *s = &r->streams[r->nstreams++];
    memset(s, 0, sizeof *s);
    s->name = name;
    return s;
}

int run_stream_check(const run_stream *s, hsbd_error *err) {
    if (!ferror(s->file.f)) return HSBD_OK;
    return hsbd_error_set(err, HSBD_EIO, "writing '%s' failed: %s", s->file.tmp, strerror(errno));
}

uint64_t run_every(const hsbd_config *cfg, double period) {
    return period > 0 ? (uint64_t)fmax(1.0, round(period / cfg->run.dt)) : 0;
}

static double cpu_seconds(void) {
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int stop_requested(const run *r) {
    return r->opt->stop && *r->opt->stop;
}

/* sample.blocking = replicas: does a new replica begin before production step k (each
 * error block after the first is one replica, with its own initial state and
 * equilibration)? */
static int replica_due(const run *r) {
    const hsbd_config *cfg = r->cfg;
    const uint64_t k = r->steps_done, every = (uint64_t)cfg->sample.every;
    if (cfg->sample.blocking != HSBD_BLOCKS_REPLICAS || !r->model.start_replica || k == 0 ||
        k % every != 0)
        return 0;
    const uint64_t total = hsbd_config_steps(cfg) / every, done = k / every;
    const size_t nb = (size_t)cfg->sample.blocks;
    const size_t block = hsbd_blocks_block_of(done, nb, total);
    return done < total && block != hsbd_blocks_block_of(done - 1, nb, total) &&
           r->replicas_started <= block;
}

void run_warn(run *r, const char *format, ...) {
    if (r->nwarnings == RUN_MAX_WARNINGS) return;
    va_list ap;
    va_start(ap, format);
    vsnprintf(r->warnings[r->nwarnings++], HSBD_WARNING_LEN, format, ap);
    va_end(ap);
}

void run_write_warnings(const run *r, FILE *f, const char (*more)[HSBD_WARNING_LEN], int nmore) {
    fprintf(f, "  \"warnings\": [");
    for (int k = 0; k < nmore + r->nwarnings; ++k) {
        fputs(k ? ", " : "", f);
        hsbd_json_string(f, k < nmore ? more[k] : r->warnings[k - nmore]);
    }
    fprintf(f, "],\n");
}

/* the warnings of the build on stderr (hsbd_run's and hsbd_sim's start) */
void run_warn_start(const run *r) {
    if (r->opt->quiet_warnings) return;
    for (int k = 0; k < r->nwarnings; ++k)
        fprintf(stderr, "hsbd: warning: %s\n", r->warnings[k]);
    if (r->model.warn_start) r->model.warn_start(r);
}

const hsbd_frame *run_frame(run *r) {
    if (!r->frame_valid) r->model.frame(r, &r->frame);
    r->frame_valid = 1;
    return &r->frame;
}

static int run_ops(run *r, hsbd_error *err) {
    for (size_t i = 0; i < r->nops; ++i) {
        const run_op *op = &r->ops[i];
        if (!op->every || r->steps_done % op->every != 0) continue;
        const int rc = op->act(r, op->ctx, err);
        if (rc != HSBD_OK) return rc;
    }
    return HSBD_OK;
}

static void enter_equilibration(run *r) {
    r->stage = RUN_EQUILIBRATING;
    r->stage_steps = 0;
    if (r->model.equilibration_dt) r->model.equilibration_dt(r, 1);
}

void run_begin(run *r) {
    enter_equilibration(r);
}

static void leave_equilibration(run *r) {
    if (r->model.equilibration_dt) r->model.equilibration_dt(r, 0);
    r->stage = RUN_PRODUCING;
    if (r->steps_done == 0 && r->replicas_started == 0) { /* production begins */
        if (r->cfg->sample.blocking == HSBD_BLOCKS_REPLICAS && r->model.start_replica)
            r->replicas_started = 1;
        if (r->model.start_production) r->model.start_production(r);
        run_observers_start_production(r);
    } else { /* a replica's equilibration ended */
        if (r->model.replica_ready) r->model.replica_ready(r);
        run_observers_replica_ready(r);
    }
}

/* When the next checkpoint is due: every output.checkpoint_every of simulated time, or
 * (0, the default) every output.checkpoint_wall seconds of wall time; the first one, by
 * either rule, after a tenth of checkpoint_wall at the latest, so that a run killed early
 * (kill -9, a lost node) leaves something to resume. Taking one never changes the results,
 * so every rule is safe. */
typedef struct checkpoint_clock {
    int enabled;
    uint64_t every_steps; /* > 0: by simulated time */
    uint64_t steps_since;
    double wall_last, wall_every;
    int taken; /* one was taken by this process */
} checkpoint_clock;

static int checkpoint_due(checkpoint_clock *c, int at_poll) {
    if (!c->enabled) return 0;
    const double waited = at_poll ? hsbd_wall_seconds() - c->wall_last : 0;
    if (!c->taken && waited >= 0.1 * c->wall_every) return 1;
    if (c->every_steps) return c->steps_since >= c->every_steps;
    return waited >= c->wall_every;
}

static int take_checkpoint(run *r, checkpoint_clock *c, hsbd_error *err) {
    c->steps_since = 0;
    c->wall_last = hsbd_wall_seconds();
    c->taken = 1;
    return run_checkpoint_write(r, err);
}

/* Wall and CPU time since the last call go to the stage they were spent in. */
typedef struct stage_clock {
    double wall, cpu;
} stage_clock;

static void account(run *r, stage_clock *t) {
    const double w = hsbd_wall_seconds(), c = cpu_seconds();
    const int eq = r->stage == RUN_EQUILIBRATING;
    *(eq ? &r->wall_equil : &r->wall_prod) += w - t->wall;
    *(eq ? &r->cpu_equil : &r->cpu_prod) += c - t->cpu;
    t->wall = w, t->cpu = c;
}

/* The run's progress now: its stage, the steps of the whole run (of `total`), the stage's
 * simulated time. */
static void report(const run *r, hsbd_progress *pr, uint64_t total, int when) {
    const hsbd_config *cfg = r->cfg;
    const int eq = r->stage == RUN_EQUILIBRATING;
    hsbd_progress_update(pr,
                         r->stage == RUN_DONE ? "done"
                         : eq                 ? "equilibrating"
                                              : "production",
                         r->equil_done + r->steps_done, total,
                         eq ? (double)r->stage_steps * hsbd_config_dt_equil(cfg)
                            : (double)r->steps_done * cfg->run.dt,
                         eq ? cfg->run.t_equil : cfg->run.t_total, when);
}

/* The loop: equilibration, then production with its operations, replicas and
 * checkpoints, until done, stopped, failed or `budget` steps are taken. Resumable: it
 * continues from whatever stage and counters the run holds (a fresh run, one loaded from
 * a checkpoint, one advanced step by step through hsbd_sim). */
static int run_loop(run *r, uint64_t budget, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const uint64_t nprod = hsbd_config_steps(cfg), nequil = hsbd_config_equil_steps(cfg);
    checkpoint_clock ck = {.enabled = r->model.save != NULL && cfg->output.checkpoints,
                           .every_steps = run_every(cfg, cfg->output.checkpoint_every),
                           .wall_last = hsbd_wall_seconds(),
                           .wall_every = cfg->output.checkpoint_wall};
    /* progress over the whole run: every equilibration (one per replica block) and the
     * production */
    const uint64_t equilibrations =
        cfg->sample.blocking == HSBD_BLOCKS_REPLICAS ? (uint64_t)cfg->sample.blocks : 1;
    const uint64_t total = nequil * equilibrations + nprod;
    char label[48] = "";
    if (cfg->run.replica >= 0)
        snprintf(label, sizeof label, "replica %lld: ", (long long)cfg->run.replica);
    hsbd_progress pr;
    hsbd_progress_start(&pr, r->opt->progress, label, r->model.particles,
                        r->equil_done + r->steps_done);
    report(r, &pr, total, HSBD_PROGRESS_START);
    stage_clock clock = {hsbd_wall_seconds(), cpu_seconds()};
    int rc = HSBD_OK;
    for (uint64_t iter = 0, taken = 0; rc == HSBD_OK && r->stage != RUN_DONE; ++iter) {
        const int equilibrating = r->stage == RUN_EQUILIBRATING;
        if (equilibrating && r->stage_steps == nequil) {
            account(r, &clock);
            leave_equilibration(r);
            continue;
        }
        if (!equilibrating && r->steps_done == nprod) {
            account(r, &clock);
            r->stage = RUN_DONE;
            break;
        }
        if (!equilibrating && replica_due(r)) {
            account(r, &clock);
            rc = run_observers_end_replica(r, err);
            if (rc == HSBD_OK) rc = r->model.start_replica(r, r->replicas_started, err);
            r->frame_valid = 0;
            if (rc == HSBD_OK) run_observers_start_replica(r);
            r->replicas_started += 1;
            enter_equilibration(r);
            continue;
        }
        if (taken++ == budget) break;
        rc = r->model.step(r, err);
        r->frame_valid = 0;
        if (rc != HSBD_OK) break;
        if (equilibrating)
            r->stage_steps += 1, r->equil_done += 1;
        else
            r->steps_done += 1;
        ck.steps_since += 1;
        if (r->opt->check && (rc = r->model.check(r, 1, err)) != HSBD_OK) break;
        if (!equilibrating && (rc = run_ops(r, err)) != HSBD_OK) break;
        const int poll = (iter & 255) == 0;
        if (poll) {
            account(r, &clock);
            report(r, &pr, total, HSBD_PROGRESS_POLL);
            if ((rc = r->model.check(r, 0, err)) != HSBD_OK) break;
        }
        if (checkpoint_due(&ck, poll) && (rc = take_checkpoint(r, &ck, err)) != HSBD_OK) break;
        if (poll && stop_requested(r)) break;
    }
    account(r, &clock);
    if (r->stage == RUN_DONE) report(r, &pr, total, HSBD_PROGRESS_END);
    hsbd_progress_end(&pr);
    if (rc == HSBD_OK && r->stage == RUN_DONE) rc = r->model.check(r, 0, err);
    r->completed = rc == HSBD_OK && r->stage == RUN_DONE;
    /* a stopped or finished run leaves a checkpoint to continue or extend from */
    if (rc == HSBD_OK && ck.enabled) rc = take_checkpoint(r, &ck, err);
    return rc;
}

int run_advance(run *r, uint64_t steps, hsbd_error *err) {
    return run_loop(r, steps, err);
}

void run_write_summary_head(const run *r, FILE *f, const char *stop_reason) {
    const hsbd_config *cfg = r->cfg;
    fprintf(f, "{\n  \"program\": \"hsbd\",\n  \"version\": \"%s\",\n  \"git\": \"%s\",\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    fprintf(f, "  \"model\": \"%s\",\n  \"seed\": %llu,\n", r->model.name,
            (unsigned long long)cfg->system.seed);
    fprintf(f, "  \"completed\": %s,\n  \"stop_reason\": \"%s\",\n",
            r->completed ? "true" : "false", stop_reason);
    fprintf(f, "  \"steps\": %llu,\n  \"steps_planned\": %llu,\n  \"equilibration_steps\": %llu,\n",
            (unsigned long long)r->steps_done, (unsigned long long)hsbd_config_steps(cfg),
            (unsigned long long)r->equil_done);
    fprintf(f, "  \"resumes\": %llu,\n", (unsigned long long)r->resumes);
    /* the threads of the process that wrote this (run.threads, or the default's value) */
    fprintf(f, "  \"threads_used\": %d,\n", run_threads(cfg));
    if (!r->ninputs) return;
    fprintf(f, "  \"input_checksums\": {"); /* of the input files read, as read (CRC-64) */
    for (size_t k = 0; k < r->ninputs; ++k) {
        fprintf(f, "%s", k ? ", " : "");
        hsbd_json_string(f, r->inputs[k].path);
        fprintf(f, ": \"%016llx\"", (unsigned long long)r->inputs[k].crc);
    }
    fprintf(f, "},\n");
}

void run_write_summary(run *r, FILE *f, const char *stop_reason) {
    run_write_summary_head(r, f, stop_reason);
    r->model.write_summary(r, f);
    run_observers_write_summary(r, f);
    fprintf(f, "  \"parameters\": ");
    hsbd_config_write_json(r->cfg, f, 2);
    fprintf(f, "\n}\n");
}

/* Final tables, streams and summary.json. Every file is committed on its own: one that
 * fails to write (a full disk) leaves the others and is named in the message. */
static int finish(run *r, int run_rc, hsbd_error *err) {
    if (r->extends_finished && !r->completed) /* the finished run's results stay */
        return run_rc != HSBD_OK
                   ? run_rc
                   : hsbd_error_set(err, HSBD_EINTERRUPT,
                                    "the extension stopped at step %llu of %llu; the finished "
                                    "run's results in '%s' stay as they were (hsbd resume %s "
                                    "goes on with the extension)",
                                    (unsigned long long)r->steps_done,
                                    (unsigned long long)hsbd_config_steps(r->cfg),
                                    r->cfg->output.dir, r->cfg->output.dir);
    const char *reason = run_rc == HSBD_OK ? (r->completed ? "completed" : "interrupted") : "error";
    hsbd_error werr;
    hsbd_error_clear(&werr);
    int rc = r->model.write_tables ? r->model.write_tables(r, &werr) : HSBD_OK;
    if (rc == HSBD_OK) rc = run_observers_write_tables(r, &werr);
    for (size_t k = 0; k < r->nstreams && rc == HSBD_OK; ++k)
        rc = hsbd_outfile_commit(&r->streams[k].file, &werr);
    if (rc == HSBD_OK) {
        hsbd_outfile o;
        rc = hsbd_outfile_open(&o, r->cfg->output.dir, "summary.json", &werr);
        if (rc == HSBD_OK) {
            run_write_summary(r, o.f, reason);
            rc = hsbd_outfile_commit(&o, &werr);
        }
    }
    if (run_rc != HSBD_OK) return run_rc; /* the run's own error message stays in err */
    return hsbd_run_outcome(r->cfg, rc, &werr, r->completed, r->steps_done, err);
}

/* Stream files still open here belong to a run that failed: once its dynamics began they
 * stay (under their temporary names) for a resume to cut back and continue. */
static void release(run *r) {
    for (size_t k = 0; k < r->nstreams; ++k) {
        hsbd_outfile *o = &r->streams[k].file;
        if (r->started && o->f)
            fclose(o->f), o->f = NULL;
        else
            hsbd_outfile_discard(o);
        hsbd_gsd_free(&r->streams[k].gsd);
    }
    run_observers_free(r);
    if (r->model.release) r->model.release(r);
}

static int open_streams(run *r, hsbd_error *err) {
    for (size_t k = 0; k < r->nstreams; ++k) {
        run_stream *s = &r->streams[k];
        if (hsbd_outfile_open(&s->file, r->cfg->output.dir, s->name, err) != HSBD_OK)
            return err->status;
        if (s->header) s->header(r, s->file.f);
        if (s->is_gsd && hsbd_gsd_start(&s->gsd, s->file.f, s->file.tmp, err) != HSBD_OK)
            return err->status;
    }
    return HSBD_OK;
}

int run_threads(const hsbd_config *cfg) {
    return cfg->run.threads > 0 ? (int)cfg->run.threads : hsbd_threads_available();
}

size_t run_input_files(const hsbd_config *cfg, const char *key[3], const char *path[3]) {
    size_t n = 0;
    if (cfg->field.type & HSBD_FIELD_TABLE) /* both models */
        key[n] = "field.table", path[n++] = cfg->field.table;
    if (cfg->pair.type == HSBD_PAIR_TABLE) /* rods: finalisation refuses it for spheres */
        key[n] = "pair.table", path[n++] = cfg->pair.table;
    if (cfg->init.positions[0]) /* species, sizes */
        key[n] = "init.positions", path[n++] = cfg->init.positions;
    return n;
}

/* The input files a run reads while it is built, with their checksums. */
static void record_inputs(run *r) {
    const char *key[3], *path[3];
    const size_t n = run_input_files(r->cfg, key, path);
    r->ninputs = 0;
    for (size_t k = 0; k < n; ++k) {
        run_input *in = &r->inputs[r->ninputs];
        snprintf(in->path, sizeof in->path, "%s", path[k]);
        if (run_file_crc(path[k], &in->crc) == 0) r->ninputs += 1;
    }
    if (!getcwd(r->cwd, sizeof r->cwd)) r->cwd[0] = '\0';
}

int hsbd_run(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err) {
    hsbd_error_clear(err);
    run r = {.cfg = cfg, .opt = opt, .source = opt->source};
    /* everything that can refuse the input happens before the directory is touched */
    int rc = run_build(&r, err);
    int lock = -1; /* claimed before its checks: no other run writes there meanwhile */
    if (rc == HSBD_OK) rc = rundir_claim(cfg->output.dir, RUNDIR_WRITE_NEW, &lock, err);
    if (rc == HSBD_OK) rc = rundir_prepare(cfg->output.dir, opt->force, err);
    if (rc == HSBD_OK) rc = open_streams(&r, err);
    if (rc == HSBD_OK) run_warn_start(&r);
    if (rc == HSBD_OK) {
        record_inputs(&r);
        r.started = 1;
        run_begin(&r);
        rc = finish(&r, run_loop(&r, UINT64_MAX, err), err);
    }
    release(&r);
    rundir_release(lock);
    return rc;
}

/* ---- resume ---- */

/* The configuration again from its source: the file's text (read from the checkpoint's
 * copy in memory under the file's name, which messages then give), the overrides in order,
 * then the resume's own (the user's run.t_total and the two keys an extension keeps) and
 * the run directory. */
static int config_from_source(const run_source_copy *src, const char *const *sets, size_t nsets,
                              const char *dir, hsbd_config *cfg, hsbd_error *err) {
    hsbd_config_defaults(cfg);
    int rc = HSBD_OK;
    if (src->has_file) {
        FILE *f = src->text_len ? fmemopen(src->text, src->text_len, "r") : NULL;
        if (!f)
            return hsbd_error_set(err, HSBD_EIO,
                                  "resume: cannot read the copy of '%.200s' the checkpoint "
                                  "holds: %s",
                                  src->name, src->text_len ? strerror(errno) : "it is empty");
        rc = hsbd_config_load_stream(cfg, f, src->name, err);
        fclose(f);
        if (rc != HSBD_OK) return rc;
    }
    for (size_t k = 0; k < src->nsets && rc == HSBD_OK; ++k)
        rc = hsbd_config_set(cfg, src->sets[k], "the run's command line", err);
    for (size_t k = 0; k < nsets && rc == HSBD_OK; ++k) /* checked by load_checkpoint */
        rc = hsbd_config_set(cfg, sets[k], "hsbd resume --set", err);
    char out[HSBD_PATH_MAX + 16];
    snprintf(out, sizeof out, "output.dir=%s", dir);
    if (rc == HSBD_OK) rc = hsbd_config_set(cfg, out, "hsbd resume", err);
    return rc == HSBD_OK ? hsbd_config_finalize(cfg, err) : rc;
}

/* The input files must hold the bytes the run started with. */
static int check_inputs(const run_source_copy *src, hsbd_error *err) {
    for (size_t k = 0; k < src->ninputs; ++k) {
        uint64_t crc;
        if (run_file_crc(src->inputs[k].path, &crc) != 0)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "resume: the run read '%s' (from '%s'), which cannot be "
                                  "read now",
                                  src->inputs[k].path, src->cwd);
        if (crc != src->inputs[k].crc)
            return hsbd_error_set(err, HSBD_EINPUT,
                                  "resume: '%s' changed since the run started; a resumed run "
                                  "must read the same input",
                                  src->inputs[k].path);
    }
    return HSBD_OK;
}

/* Every stream file cut back to its length at the checkpoint and open for appending;
 * all are checked first, so a refusal leaves every file as it was. */
static int reopen_streams(run *r, hsbd_error *err) {
    for (size_t k = 0; k < r->nstreams; ++k)
        if (hsbd_outfile_can_reopen(r->cfg->output.dir, r->streams[k].name, r->streams[k].committed,
                                    err) != HSBD_OK)
            return err->status;
    for (size_t k = 0; k < r->nstreams; ++k) {
        run_stream *s = &r->streams[k];
        if (hsbd_outfile_reopen(&s->file, r->cfg->output.dir, s->name, s->committed, err) !=
            HSBD_OK)
            return err->status;
        if (s->is_gsd &&
            hsbd_gsd_continue(&s->gsd, s->file.f, s->file.tmp, s->committed, err) != HSBD_OK)
            return err->status;
    }
    return HSBD_OK;
}

/* The source a resumed run keeps for its own checkpoints: the stored one with the
 * resume's overrides appended (an extension stays extended). */
enum { RUN_MAX_RESUME_SETS = 8 };
typedef struct resumed_source {
    run_source_copy copy;
    char added[RUN_MAX_RESUME_SETS + 2][HSBD_PATH_MAX + 64]; /* the resume's overrides */
    const char **sets;
    hsbd_run_source source;
} resumed_source;

static int keep_source(resumed_source *rs, const char *const *sets, size_t nsets) {
    const run_source_copy *c = &rs->copy;
    rs->sets = calloc(c->nsets + nsets + 1, sizeof *rs->sets);
    if (!rs->sets) return -1;
    for (size_t k = 0; k < c->nsets; ++k)
        rs->sets[k] = c->sets[k];
    for (size_t k = 0; k < nsets; ++k) {
        snprintf(rs->added[k], sizeof rs->added[k], "%s", sets[k]);
        rs->sets[c->nsets + k] = rs->added[k];
    }
    rs->source = (hsbd_run_source){.name = c->has_file ? c->name : NULL,
                                   .text = c->text,
                                   .text_len = c->text_len,
                                   .sets = rs->sets,
                                   .nsets = c->nsets + nsets};
    return 0;
}

/* Whether a --set names key (spaces around it allowed, as for hsbd run). */
static int set_names(const char *set, const char *key) {
    const char *eq = strchr(set, '=');
    if (!eq) return 0;
    while (*set == ' ' || *set == '\t')
        ++set;
    size_t len = (size_t)(eq - set);
    while (len > 0 && (set[len - 1] == ' ' || set[len - 1] == '\t'))
        --len;
    return len == strlen(key) && !strncmp(set, key, len);
}

/* Build the run of a checkpoint: configuration, model (without an initial state), then
 * the state, the accumulators and the lifecycle's counters. */
static int load_checkpoint(run *r, hsbd_config *cfg, resumed_source *rs, const char *dir,
                           const char *const *sets, size_t nsets, hsbd_error *err) {
    run_checkpoint_data ck;
    int rc = run_checkpoint_read(dir, &ck, err);
    if (rc != HSBD_OK) return rc;
    hsbd_reader rd;
    hsbd_reader_init(&rd, ck.data, ck.len);
    run_source_copy src = {0};
    if (run_checkpoint_read_source(&rd, &src) != 0)
        rc = hsbd_error_set(err, rd.oom ? HSBD_ENOMEM : HSBD_EINPUT, "%s: %s", ck.path, rd.why);
    if (rc == HSBD_OK && strcmp(src.git, HSBD_GIT_COMMIT))
        fprintf(stderr,
                "hsbd: warning: the checkpoint was written by hsbd %s (git %s), this is git %s: "
                "the continued run is exact only with the same binary\n",
                src.version, src.git, HSBD_GIT_COMMIT);
    char here[HSBD_PATH_MAX] = "";
    if (!getcwd(here, sizeof here)) here[0] = '\0';
    /* relative paths of the configuration are those of the run's start */
    char absdir[HSBD_PATH_MAX + 2];
    if (rc == HSBD_OK && !realpath(dir, absdir))
        rc = hsbd_error_set(err, HSBD_EINPUT, "resume: '%s': %s", dir, strerror(errno));
    if (rc == HSBD_OK && src.cwd[0] && chdir(src.cwd) != 0)
        rc = hsbd_error_set(err, HSBD_EINPUT, "resume: the run started in '%s', which is gone: %s",
                            src.cwd, strerror(errno));
    /* an extension keeps the lag grid of the MSD and the intervals of the trajectory and
     * of log.tsv, which by default follow run.t_total: their values of the run as it was
     * go first */
    char kept[3][HSBD_PATH_MAX + 64];
    const char *ext[RUN_MAX_RESUME_SETS + 3] = {0};
    size_t next = 0;
    double planned_t = 0; /* with --set: the run's own run.t_total, and its steps */
    uint64_t planned_steps = 0;
    if (rc == HSBD_OK && nsets > RUN_MAX_RESUME_SETS)
        rc = hsbd_error_set(err, HSBD_EINPUT, "resume: too many --set");
    for (size_t k = 0; k < nsets && rc == HSBD_OK; ++k) /* the two kept keys are not the user's */
        if (!set_names(sets[k], "run.t_total") && !set_names(sets[k], "run.threads"))
            rc = hsbd_error_set(err, HSBD_EINPUT,
                                "resume: --set %s: a resumed run keeps its configuration; "
                                "allowed: --set run.t_total=T (a longer run), --set "
                                "run.threads=N (--threads N)",
                                sets[k]);
    int extends = 0; /* a run.t_total given (the threads change no result) */
    for (size_t k = 0; k < nsets; ++k)
        extends |= set_names(sets[k], "run.t_total");
    if (rc == HSBD_OK && extends) {
        hsbd_config *old = malloc(sizeof *old);
        rc = old ? config_from_source(&src, NULL, 0, absdir, old, err)
                 : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        if (rc == HSBD_OK) {
            snprintf(kept[0], sizeof kept[0], "sample.msd_max_lag=%.17g", old->sample.msd_max_lag);
            snprintf(kept[1], sizeof kept[1], "output.trajectory_every=%.17g",
                     old->output.trajectory_every);
            snprintf(kept[2], sizeof kept[2], "output.log_every=%.17g", old->output.log_every);
            ext[next++] = kept[0], ext[next++] = kept[1], ext[next++] = kept[2];
            planned_t = old->run.t_total, planned_steps = hsbd_config_steps(old);
            if (old->sample.blocking == HSBD_BLOCKS_REPLICAS)
                rc = hsbd_error_set(err, HSBD_EINPUT,
                                    "resume: a run with sample.blocking = replicas cannot be "
                                    "extended (its replicas have their length); start a longer "
                                    "run");
        }
        free(old);
    }
    for (size_t k = 0; k < nsets; ++k)
        ext[next++] = sets[k];
    if (rc == HSBD_OK) rc = config_from_source(&src, ext, next, absdir, cfg, err);
    if (rc == HSBD_OK && extends && hsbd_config_steps(cfg) < planned_steps)
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "resume: --set run.t_total=%g is shorter than the run's own %g; "
                            "allowed: run.t_total >= %g (a run is continued or extended, never "
                            "cut)",
                            cfg->run.t_total, planned_t, planned_t);
    if (rc == HSBD_OK && strcmp(src.model, run_model_name(cfg)))
        rc = hsbd_error_set(err, HSBD_EINPUT, "%s: a checkpoint of model %s", ck.path, src.model);
    if (rc == HSBD_OK) rc = check_inputs(&src, err);
    if (rc == HSBD_OK) {
        r->cfg = cfg;
        r->resuming = 1;
        rc = run_build(r, err);
    }
    if (here[0] && chdir(here) != 0 && rc == HSBD_OK)
        rc = hsbd_error_set(err, HSBD_EIO, "resume: cannot return to '%s'", here);
    if (rc == HSBD_OK && !r->model.load)
        rc = hsbd_error_set(err, HSBD_EINPUT, "%s: the %s model cannot be resumed", ck.path,
                            r->model.name);
    if (rc == HSBD_OK &&
        (run_checkpoint_load_run(r, &rd) != 0 || r->model.load(r, &rd) != 0 ||
         run_observers_load(r, &rd) != 0 || hsbd_get_tag(&rd, "end") != 0 || rd.pos != rd.len))
        rc = hsbd_error_set(err, rd.oom ? HSBD_ENOMEM : HSBD_EINPUT, "%s: %s", ck.path,
                            rd.bad ? rd.why : "data after the end");
    r->frame_valid = 0; /* the state loaded */
    if (rc == HSBD_OK) {
        r->newest_unusable = ck.fell_back;
        snprintf(r->cwd, sizeof r->cwd, "%s", src.cwd);
        r->ninputs = src.ninputs;
        memcpy(r->inputs, src.inputs, sizeof src.inputs);
        rs->copy = src;
        if (keep_source(rs, ext, next) != 0) rc = hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
        r->source = &rs->source;
    } else {
        run_source_copy_free(&src);
    }
    run_checkpoint_data_free(&ck);
    return rc;
}

/* What load_checkpoint built, released. */
static void unload(run *r, hsbd_config *cfg, resumed_source *rs) {
    if (r->cfg) release(r);
    run_source_copy_free(&rs->copy);
    free(rs->sets);
    free(cfg);
}

int run_checkpoint_try_load(const char *dir, hsbd_error *err) {
    hsbd_error_clear(err);
    hsbd_config *cfg = malloc(sizeof *cfg);
    if (!cfg) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    const hsbd_run_options opt = {0};
    run r = {.opt = &opt};
    resumed_source rs = {0};
    const int rc = load_checkpoint(&r, cfg, &rs, dir, NULL, 0, err);
    unload(&r, cfg, &rs);
    return rc;
}

/* The time of steps + 1 steps of dt in the fewest digits that give steps + 1 steps again
 * (run.t_total / run.dt is rounded: %g alone may print the run's own time). */
static void one_step_longer(uint64_t steps, double dt, char *out, size_t len) {
    const double t = (double)(steps + 1) * dt;
    for (int digits = 6; digits <= 17; ++digits) {
        snprintf(out, len, "%.*g", digits, t);
        if (llround(strtod(out, NULL) / dt) == (long long)(steps + 1)) return;
    }
}

/* What dir's summary.json says: a completed run, and one of `steps` steps (summary.json,
 * written last, says the run's results are all committed; a run stopped after its final
 * checkpoint but before its results, e.g. by kill -9, has none or an old one: resuming it
 * writes them). */
static void summary_says(const char *dir, uint64_t steps, int *completed, int *of_steps) {
    char path[HSBD_PATH_MAX + 16], line[256], want[64];
    snprintf(path, sizeof path, "%s/summary.json", dir);
    snprintf(want, sizeof want, "  \"steps\": %llu,", (unsigned long long)steps);
    FILE *f = fopen(path, "r");
    *completed = *of_steps = 0; /* an extension's results: the summary of its own steps */
    while (f && fgets(line, sizeof line, f)) {
        *completed |= strstr(line, "\"completed\": true") != NULL;
        *of_steps |= strncmp(line, want, strlen(want)) == 0;
    }
    if (f) fclose(f);
}

static int results_written(const char *dir, uint64_t steps) {
    int completed, of_steps;
    summary_says(dir, steps, &completed, &of_steps);
    return completed && of_steps;
}

static int summary_says_completed(const char *dir) {
    int completed, of_steps;
    summary_says(dir, 0, &completed, &of_steps);
    return completed;
}

/* A finished run whose extension stopped before its first checkpoint: its streams are
 * under their temporary names, perhaps longer; back to the finished run's bytes and names
 * (a warning names what cannot be restored, which is then left as it is). */
static void restore_streams(run *r, const char *dir) {
    int moved = 0;
    for (size_t k = 0; k < r->nstreams; ++k) {
        char path[HSBD_PATH_MAX + 80];
        snprintf(path, sizeof path, "%s/%s", dir, r->streams[k].name);
        moved |= access(path, F_OK) != 0;
    }
    hsbd_error why;
    int rc = moved ? reopen_streams(r, &why) : HSBD_OK;
    for (size_t k = 0; k < r->nstreams && moved && rc == HSBD_OK; ++k)
        rc = hsbd_outfile_commit(&r->streams[k].file, &why);
    if (rc != HSBD_OK)
        fprintf(stderr, "hsbd: warning: the finished run's stream files stay as they are: %s\n",
                why.message);
}

/* A directory without a checkpoint: in use by a run that has not reached its first
 * checkpoint, an ensemble's, whose replicas hold them, or one whose run stopped before its
 * first; said in err instead of "no usable checkpoint". */
static void why_no_checkpoint(const char *dir, hsbd_error *err) {
    int probe;
    hsbd_error busy;
    hsbd_error_clear(&busy);
    if (rundir_claim(dir, RUNDIR_CHECK, &probe, &busy) != HSBD_OK) {
        hsbd_error_set(err, busy.status, "resume: %s (it has no checkpoint yet)", busy.message);
        return;
    }
    rundir_release(probe);
    if (rundir_holds_replicas(dir))
        hsbd_error_set(err, HSBD_EINPUT,
                       "resume: '%s' is an ensemble's directory, whose replicas hold the "
                       "checkpoints: continue each that stopped (hsbd resume %s/replica-K), "
                       "then merge them into it (hsbd merge %s)",
                       dir, dir, dir);
    else if (access(dir, F_OK) != 0)
        hsbd_error_set(err, HSBD_EINPUT, "resume: '%s': %s", dir, strerror(errno));
    else
        hsbd_error_set(err, HSBD_EINPUT,
                       "resume: '%s' holds no checkpoint: its run stopped before its first one, "
                       "due after a tenth of output.checkpoint_wall (1 minute by default) or "
                       "one output.checkpoint_every, whichever came first; nothing there can be "
                       "continued: run it again (hsbd run CONFIG --out %s --force)",
                       dir, dir);
}

int hsbd_resume(const char *dir, const char *const *sets, size_t nsets, const hsbd_run_options *opt,
                hsbd_error *err) {
    hsbd_error_clear(err);
    hsbd_config *cfg = malloc(sizeof *cfg);
    if (!cfg) return hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    run r = {.opt = opt};
    resumed_source rs = {0};
    int lock = -1; /* a second resume of the same run is refused, not raced (a directory
                    * without checkpoints gets no lock file: the load refuses it) */
    int rc = rundir_holds_checkpoint(dir) ? rundir_claim(dir, RUNDIR_WRITE, &lock, err) : HSBD_OK;
    const int had_checkpoint = lock >= 0;
    if (rc == HSBD_OK) rc = load_checkpoint(&r, cfg, &rs, dir, sets, nsets, err);
    if (rc == HSBD_EINPUT && !had_checkpoint && !rundir_holds_checkpoint(dir))
        why_no_checkpoint(dir, err);
    /* a run's first checkpoint may have landed between the test above and the load: a run
     * still going holds the directory, so the claim refuses this resume; one that ended in
     * between may have written newer checkpoints, so the newest is read again */
    if (rc == HSBD_OK && lock < 0) {
        rc = rundir_claim(dir, RUNDIR_WRITE, &lock, err);
        unload(&r, cfg, &rs);
        r = (run){.opt = opt};
        rs = (resumed_source){0};
        cfg = malloc(sizeof *cfg);
        if (rc == HSBD_OK)
            rc = cfg ? load_checkpoint(&r, cfg, &rs, dir, sets, nsets, err)
                     : hsbd_error_set(err, HSBD_ENOMEM, "out of memory");
    }
    /* from here on the stream files are the stopped run's: kept whatever happens (release()
     * removes the files of a run that never started) */
    r.started = 1;
    if (rc == HSBD_OK && r.stage == RUN_DONE && r.steps_done == hsbd_config_steps(cfg) &&
        results_written(dir, r.steps_done)) {
        restore_streams(&r, dir);
        char longer[32];
        one_step_longer(r.steps_done, cfg->run.dt, longer, sizeof longer);
        rc = hsbd_error_set(err, HSBD_EINPUT,
                            "resume: the run in '%s' is complete (%llu of %llu steps); to "
                            "extend it: --set run.t_total=T with T >= %s (a step more at least)",
                            dir, (unsigned long long)r.steps_done,
                            (unsigned long long)hsbd_config_steps(cfg), longer);
    }
    if (rc == HSBD_OK && r.stage == RUN_DONE) /* extended, or its results unwritten */
        r.stage = RUN_PRODUCING;
    r.extends_finished = rc == HSBD_OK && summary_says_completed(dir);
    if (rc == HSBD_OK) rc = reopen_streams(&r, err);
    if (rc == HSBD_OK) {
        r.resumes += 1;
        rc = finish(&r, run_loop(&r, UINT64_MAX, err), err);
    }
    unload(&r, cfg, &rs);
    rundir_release(lock);
    return rc;
}

int hsbd_run_rods(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err) {
    return hsbd_run(cfg, opt, err);
}

int hsbd_run_spheres(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err) {
    return hsbd_run(cfg, opt, err);
}
