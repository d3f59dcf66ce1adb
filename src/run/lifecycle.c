/* The run lifecycle (see run.h). */
#include "run/run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/progress.h"
#include "hsbd/observe.h"
#include "hsbd_version.h"
#include "io/tables.h"
#include "run/checkpoint.h"

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

static void leave_equilibration(run *r) {
    if (r->model.equilibration_dt) r->model.equilibration_dt(r, 0);
    r->stage = RUN_PRODUCING;
    if (r->steps_done == 0 && r->replicas_started == 0) { /* production begins */
        if (r->cfg->sample.blocking == HSBD_BLOCKS_REPLICAS && r->model.start_replica)
            r->replicas_started = 1;
        if (r->model.start_production) r->model.start_production(r);
    } else if (r->model.replica_ready) { /* a replica's equilibration ended */
        r->model.replica_ready(r);
    }
}

/* When the next checkpoint is due: every output.checkpoint_every of simulated time, or
 * (0, the default) every HSBD_CHECKPOINT_WALL seconds of wall time. Taking one never
 * changes the results, so either rule is safe. */
typedef struct checkpoint_clock {
    int enabled;
    uint64_t every_steps; /* > 0: by simulated time */
    uint64_t steps_since;
    double wall_last;
} checkpoint_clock;

static int checkpoint_due(checkpoint_clock *c, int at_poll) {
    if (!c->enabled) return 0;
    if (c->every_steps) return c->steps_since >= c->every_steps;
    return at_poll && hsbd_wall_seconds() - c->wall_last >= HSBD_CHECKPOINT_WALL;
}

static int take_checkpoint(run *r, checkpoint_clock *c, hsbd_error *err) {
    c->steps_since = 0;
    c->wall_last = hsbd_wall_seconds();
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

/* The loop: equilibration, then production with its operations, replicas and
 * checkpoints, until done, stopped or failed. Resumable: it continues from whatever
 * stage and counters the run holds (a fresh run or one loaded from a checkpoint). */
static int run_loop(run *r, hsbd_error *err) {
    const hsbd_config *cfg = r->cfg;
    const uint64_t nprod = hsbd_config_steps(cfg), nequil = hsbd_config_equil_steps(cfg);
    checkpoint_clock ck = {.enabled = r->model.save != NULL && cfg->output.checkpoints,
                           .every_steps = run_every(cfg, cfg->output.checkpoint_every),
                           .wall_last = hsbd_wall_seconds()};
    hsbd_progress pr;
    int shown = -1;
    stage_clock clock = {hsbd_wall_seconds(), cpu_seconds()};
    int rc = HSBD_OK;
    for (uint64_t iter = 0; rc == HSBD_OK && r->stage != RUN_DONE; ++iter) {
        if (shown != r->stage) { /* a progress line per stage */
            if (shown >= 0) hsbd_progress_end(&pr);
            hsbd_progress_start(&pr, r->opt->progress,
                                r->stage == RUN_PRODUCING ? "running" : "equilibrating",
                                r->model.particles);
            shown = r->stage;
        }
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
            rc = r->model.start_replica(r, r->replicas_started, err);
            r->replicas_started += 1;
            enter_equilibration(r);
            continue;
        }
        rc = r->model.step(r, err);
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
            hsbd_progress_update(&pr, equilibrating ? r->stage_steps : r->steps_done,
                                 equilibrating ? nequil : nprod);
            if ((rc = r->model.check(r, 0, err)) != HSBD_OK) break;
        }
        if (checkpoint_due(&ck, poll) && (rc = take_checkpoint(r, &ck, err)) != HSBD_OK) break;
        if (poll && stop_requested(r)) break;
    }
    account(r, &clock);
    if (shown >= 0) hsbd_progress_end(&pr);
    if (rc == HSBD_OK && r->stage == RUN_DONE) rc = r->model.check(r, 0, err);
    r->completed = rc == HSBD_OK && r->stage == RUN_DONE;
    /* a stopped or finished run leaves a checkpoint to continue or extend from */
    if (rc == HSBD_OK && ck.enabled) rc = take_checkpoint(r, &ck, err);
    return rc;
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
}

/* Final tables, streams and summary.json. Every file is committed on its own: one that
 * fails to write (a full disk) leaves the others and is named in the message. */
static int finish(run *r, int run_rc, hsbd_error *err) {
    const char *reason = run_rc == HSBD_OK ? (r->completed ? "completed" : "interrupted") : "error";
    hsbd_error werr;
    hsbd_error_clear(&werr);
    int rc = r->model.write_tables(r, &werr);
    for (size_t k = 0; k < r->nstreams && rc == HSBD_OK; ++k)
        rc = hsbd_outfile_commit(&r->streams[k].file, &werr);
    if (rc == HSBD_OK) {
        hsbd_outfile o;
        rc = hsbd_outfile_open(&o, r->cfg->output.dir, "summary.json", &werr);
        if (rc == HSBD_OK) {
            run_write_summary_head(r, o.f, reason);
            r->model.write_summary(r, o.f);
            fprintf(o.f, "  \"parameters\": ");
            hsbd_config_write_json(r->cfg, o.f, 2);
            fprintf(o.f, "\n}\n");
            rc = hsbd_outfile_commit(&o, &werr);
        }
    }
    if (run_rc != HSBD_OK) return run_rc; /* the run's own error message stays in err */
    return hsbd_run_outcome(r->cfg, rc, &werr, r->completed, r->steps_done, err);
}

static void release(run *r) {
    for (size_t k = 0; k < r->nstreams; ++k)
        hsbd_outfile_discard(&r->streams[k].file);
    if (r->model.release) r->model.release(r);
}

static int open_streams(run *r, hsbd_error *err) {
    for (size_t k = 0; k < r->nstreams; ++k) {
        run_stream *s = &r->streams[k];
        if (hsbd_outfile_open(&s->file, r->cfg->output.dir, s->name, err) != HSBD_OK)
            return err->status;
        if (s->header) s->header(r, s->file.f);
    }
    return HSBD_OK;
}

int hsbd_run(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err) {
    hsbd_error_clear(err);
    run r = {.cfg = cfg, .opt = opt};
    /* everything that can refuse the input happens before the directory is touched */
    int rc = cfg->system.model == HSBD_MODEL_SPHERES ? run_spheres_build(&r, err)
                                                     : run_rods_build(&r, err);
    if (rc == HSBD_OK) rc = hsbd_run_dir_prepare(cfg->output.dir, opt->force, err);
    if (rc == HSBD_OK) rc = open_streams(&r, err);
    if (rc == HSBD_OK) {
        enter_equilibration(&r);
        rc = finish(&r, run_loop(&r, err), err);
    }
    release(&r);
    return rc;
}

int hsbd_run_rods(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err) {
    return hsbd_run(cfg, opt, err);
}

int hsbd_run_spheres(const hsbd_config *cfg, const hsbd_run_options *opt, hsbd_error *err) {
    return hsbd_run(cfg, opt, err);
}
