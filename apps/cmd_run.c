/* hsbd run, hsbd resume, hsbd merge: a run, an ensemble of replicas (over the ranks of
 * mpirun), its continuation, and the merge of replicas (docs/runs.md, docs/scaling.md). */
#include "cli.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "hsbd/config.h"
#include "hsbd/run.h"
#include "rundir/rundir.h"

static const char *const synopsis_run =
    "hsbd run CONFIG.ini [options]   simulate (see 'hsbd run --help')\n"
    "       hsbd run --defaults [options]   simulate the default configuration\n";
static const char *const synopsis_resume =
    "hsbd resume DIR [--set run.t_total=T] [--threads N] [--quiet]\n"
    "                                       continue a stopped run from its checkpoint\n";
static const char *const synopsis_merge =
    "hsbd merge OUT DIR... [--force]        merge replicas of one configuration\n";

void cmd_run_synopses(FILE *out) {
    fprintf(out, "usage: %s       %s       %s", synopsis_run, synopsis_resume, synopsis_merge);
}

static void run_help(void) {
    printf("usage: hsbd run CONFIG.ini [--set section.key=value]... [--out DIR] [--seed S]\n"
           "                [--replica K] [--threads N] [--force] [--check] [--quiet]\n"
           "       hsbd run --defaults [options]\n"
           "       mpirun -n P hsbd run CONFIG.ini [options]   run.replicas (default P)\n"
           "              replicas spread over the ranks, merged into DIR (docs/scaling.md)\n\n"
           "  --set k=v   override any key (repeatable)\n"
           "  --out DIR   run directory (same as --set output.dir=DIR)\n"
           "  --seed S    random seed (same as --set system.seed=S)\n"
           "  --replica K run replica K of an ensemble alone (same as --set run.replica=K;\n"
           "              join replicas with hsbd merge)\n"
           "  --threads N threads of the run (same as --set run.threads=N; default: the\n"
           "              cores the process may use, under mpirun its rank's share of\n"
           "              them; the same results for every N)\n"
           "  --defaults  no configuration file: every key at its default (runs/defaults);\n"
           "              a file that sets no key is refused\n"
           "  --force     replace an earlier run's files in the run directory (never an\n"
           "              ensemble's: an ensemble's directory must be new or empty)\n"
           "  --check     verify the hard core after every step (slower)\n"
           "  --quiet     no progress (on a terminal one line; otherwise, as in a batch\n"
           "              job's log, a whole line after 10 s, then at intervals doubling\n"
           "              up to 10 minutes: stage, percent, simulated time, rate, ETA)\n\n"
           "Writes density.tsv, contact.tsv, msd.tsv, clusters.tsv, log.tsv, summary.json\n"
           "(and trajectory.xyz, current.tsv when asked) atomically. Exit status: 0 done, 2 bad\n"
           "input, 130 interrupted (results so far written), 1 other errors.\n\n"
           "Configuration keys:\n");
    hsbd_config_write_reference(stdout, 0);
}

/* A --set value is section.key=value: 0, or EXIT_INPUT with a message that shows the line
 * meant ("--set run.t_total 5": --set run.t_total=5) when the value is missing its '='. */
static int set_value_check(const char *cmd, int argc, char **argv, int i) {
    if (strchr(argv[i], '=')) return 0;
    const int next = i + 1 < argc && argv[i + 1][0] != '-';
    fprintf(stderr, "hsbd %s: --set needs section.key=value, not '%.100s'%s%.100s%s%.100s%s\n", cmd,
            argv[i], next ? " (write --set " : "", next ? argv[i] : "", next ? "=" : "",
            next ? argv[i + 1] : "", next ? ")" : "");
    return EXIT_INPUT;
}

/* The whole file (for the run's checkpoints); NULL when it cannot be read. */
static char *read_whole_file(const char *path, size_t *len) {
    FILE *f = fopen(path, "rb");
    if (!f) return NULL;
    size_t cap = 4096, n = 0;
    char *buf = malloc(cap);
    for (size_t got; buf && (got = fread(buf + n, 1, cap - n, f)) > 0;) {
        n += got;
        if (n == cap) {
            char *b = realloc(buf, 2 * cap);
            if (!b) free(buf);
            buf = b, cap *= 2;
        }
    }
    fclose(f);
    if (buf) *len = n;
    return buf;
}

/* ---- hsbd run: what rank 0 reads, checks and shares ----------------------------------- */

/* The checked request of hsbd run as one block of bytes (rank 0 sends it to every rank): the
 * plan, then the configuration file's name and text and the overrides, each NUL-ended. */
typedef struct run_plan {
    int go; /* run; else exit with code (bad input, or --help printed) */
    int code;
    int quiet, force, check;
    hsbd_config cfg;
    size_t name_len, text_len, nsets; /* name_len 0: --defaults */
} run_plan;

/* What a process runs: the plan, and the source kept for the checkpoints (pointing into the
 * block). */
typedef struct run_request {
    run_plan *plan;
    size_t len; /* of the block */
    hsbd_run_source source;
    const char **sets;
} run_request;

/* runs/<config file name without directory and extension> */
static void default_out_dir(const char *config_path, char *out, size_t len) {
    const char *base = strrchr(config_path, '/');
    base = base ? base + 1 : config_path;
    const char *dot = strrchr(base, '.');
    const int n = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
    snprintf(out, len, "runs/%.*s", n, base);
}

/* An override of the command line, applied in order after the file: its flag and its
 * section.key=value ("--out DIR": output.dir=DIR). */
typedef struct run_override {
    const char *flag;
    char text[HSBD_PATH_MAX + 64];
} run_override;

static void override_make(run_override *o, const char *flag, const char *value) {
    const char *key = !strcmp(flag, "--out")       ? "output.dir"
                      : !strcmp(flag, "--replica") ? "run.replica"
                      : !strcmp(flag, "--threads") ? "run.threads"
                                                   : "system.seed";
    o->flag = flag;
    if (!strcmp(flag, "--set"))
        snprintf(o->text, sizeof o->text, "%s", value);
    else
        snprintf(o->text, sizeof o->text, "%s=%s", key, value);
}

/* The block: the plan, the file's name and text, the overrides. */
static run_plan *plan_pack(const run_plan *p, const char *name, const char *text,
                           const run_override *sets, size_t *len) {
    *len = sizeof *p + p->name_len + 1 + p->text_len + 1;
    for (size_t k = 0; k < p->nsets; ++k)
        *len += strlen(sets[k].text) + 1;
    run_plan *block = malloc(*len);
    if (!block) return NULL;
    *block = *p;
    char *at = (char *)(block + 1);
    if (p->name_len) memcpy(at, name, p->name_len);
    at[p->name_len] = '\0', at += p->name_len + 1;
    if (p->text_len) memcpy(at, text, p->text_len);
    at[p->text_len] = '\0', at += p->text_len + 1;
    for (size_t k = 0; k < p->nsets; ++k)
        at = stpcpy(at, sets[k].text) + 1;
    return block;
}

/* The source of the checkpoints from a shared block; 0, or -1 when out of memory. */
static int request_unpack(run_request *q) {
    run_plan *p = q->plan;
    char *at = (char *)(p + 1);
    q->sets = calloc(p->nsets + 1, sizeof *q->sets);
    if (!q->sets) return -1;
    q->source = (hsbd_run_source){.name = p->name_len ? at : NULL,
                                  .text = at + p->name_len + 1,
                                  .text_len = p->text_len,
                                  .sets = q->sets,
                                  .nsets = p->nsets};
    at += p->name_len + 1 + p->text_len + 1;
    for (size_t k = 0; k < p->nsets; ++k, at += strlen(at) + 1)
        q->sets[k] = at;
    return 0;
}

/* The command line of hsbd run into p, the overrides in order into sets; an exit status
 * (-1: --help printed), with its message on stderr. */
static int run_args(int argc, char **argv, run_plan *p, const char **path, run_override *sets) {
    static const char *const value_flags[] = {"--set",     "--out",     "--seed",
                                              "--replica", "--threads", NULL};
    if (cli_asks_help(argc, argv, value_flags)) return run_help(), -1;
    int defaults = 0;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--set") || !strcmp(a, "--out") || !strcmp(a, "--seed") ||
            !strcmp(a, "--replica") || !strcmp(a, "--threads")) {
            const char *v = cli_flag_value("run", argc, argv, &i, stderr);
            if (!v || (!strcmp(a, "--set") && set_value_check("run", argc, argv, i)))
                return EXIT_INPUT;
            if (strlen(v) >= HSBD_PATH_MAX) {
                fprintf(stderr, "hsbd run: %s: the value is longer than %d characters\n", a,
                        HSBD_PATH_MAX - 1);
                return EXIT_INPUT;
            }
            override_make(&sets[p->nsets++], a, v);
        } else if (!strcmp(a, "--defaults")) {
            defaults = 1;
        } else if (!strcmp(a, "--force")) {
            p->force = 1;
        } else if (!strcmp(a, "--check")) {
            p->check = 1;
        } else if (!strcmp(a, "--quiet")) {
            p->quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "hsbd run: unknown option '%.60s' (hsbd run --help)\n", a);
            return EXIT_INPUT;
        } else if (*path) {
            fprintf(stderr, "hsbd run: more than one configuration file ('%.200s', '%.200s')\n",
                    *path, a);
            return EXIT_INPUT;
        } else {
            *path = a;
        }
    }
    if (!*path == !defaults) {
        fprintf(stderr, "hsbd run: %s (hsbd run --help)\n",
                defaults ? "--defaults runs without a configuration file, but one is given"
                         : "no configuration file given; --defaults runs the default "
                           "configuration");
        return EXIT_INPUT;
    }
    return 0;
}

/* The configuration of hsbd run: the file (kept as text for the checkpoints), then the
 * overrides in order; an exit status, with its message on stderr. */
static int run_config(run_plan *p, const char *path, char **text, const run_override *sets) {
    hsbd_error err;
    hsbd_config_defaults(&p->cfg);
    if (path && hsbd_config_load_file(&p->cfg, path, &err) != HSBD_OK)
        return cli_fail(err.status, err.message);
    if (path && !(*text = read_whole_file(path, &p->text_len))) {
        fprintf(stderr, "hsbd run: cannot read '%s' again\n", path);
        return EXIT_INPUT;
    }
    p->name_len = path ? strlen(path) : 0;
    if (!p->cfg.output.dir[0])
        default_out_dir(path ? path : "defaults", p->cfg.output.dir, sizeof p->cfg.output.dir);
    for (size_t k = 0; k < p->nsets; ++k) {
        char origin[64];
        snprintf(origin, sizeof origin, "command line (%s)", sets[k].flag);
        if (hsbd_config_set(&p->cfg, sets[k].text, origin, &err) != HSBD_OK)
            return cli_fail(err.status, err.message);
    }
    return hsbd_config_finalize(&p->cfg, &err) == HSBD_OK ? 0 : cli_fail(err.status, err.message);
}

/* Rank 0: the command line and the configuration read and checked, as the block to share
 * (NULL when out of memory). */
static run_plan *run_read(int argc, char **argv, size_t *len) {
    run_plan *p = calloc(1, sizeof *p);
    run_override *sets = calloc((size_t)argc, sizeof *sets);
    const char *path = NULL;
    char *text = NULL;
    run_plan *block = NULL;
    if (p && sets) {
        p->code = run_args(argc, argv, p, &path, sets);
        if (p->code == 0) p->code = run_config(p, path, &text, sets);
        p->go = p->code == 0;
        if (p->code < 0) p->code = 0;                         /* --help */
        if (!p->go) p->name_len = p->text_len = p->nsets = 0; /* the exit code alone */
        block = plan_pack(p, path, text, sets, len);
    }
    if (!block) fprintf(stderr, "hsbd: out of memory\n");
    free(p), free(sets), free(text);
    return block;
}

/* ---- hsbd run: the run, or an ensemble over the ranks ---------------------------------- */

/* progress on a terminal as one line, in a batch job's log (stderr no terminal) as whole
 * lines; none with --quiet */
static int progress_mode(int quiet) {
    return quiet                   ? HSBD_PROGRESS_NONE
           : isatty(STDERR_FILENO) ? HSBD_PROGRESS_TERMINAL
                                   : HSBD_PROGRESS_LINES;
}

/* A single run (rank 0's) or an ensemble's replicas k = rank, rank + P, ... after rank 0
 * claimed its directory; rank 0 then merges them. Returns this rank's exit code. */
static int run_on_ranks(const ranks *r, run_request *q) {
    const run_plan *p = q->plan;
    const size_t replicas = rundir_ensemble_size(&p->cfg, r->size);
    const hsbd_run_options opt = {.force = p->force,
                                  .check = p->check,
                                  .progress = progress_mode(r->rank != 0 || p->quiet),
                                  .stop = &cli_stop,
                                  .source = &q->source};
    hsbd_error err = {0};
    rundir_ensemble ens = {.lock = -1};
    int status = HSBD_OK, begun = 1;
    ranks_share_threads(r, replicas > 1 ? (size_t)r->rank < replicas : r->rank == 0);
    cli_catch_stop_signals();
    if (replicas > 1 && r->rank == 0) status = rundir_ensemble_begin(&p->cfg, &ens, &err);
    if (replicas > 1) begun = ranks_rank0_value(r, status) == HSBD_OK; /* rank 0's claim */
    if (begun && replicas > 1)
        status = rundir_ensemble_run(&p->cfg, &opt, replicas, r->rank, r->size, &err);
    else if (r->rank == 0 && replicas == 1)
        status = hsbd_run(&p->cfg, &opt, &err);
    status = ranks_gather_failures(r, status, &err); /* the messages printed */
    if (begun && replicas > 1 && r->rank == 0) {
        const int merged = rundir_ensemble_end(&p->cfg, status, &ens, &err);
        if (merged != status) fprintf(stderr, "hsbd: %s\n", err.message);
        status = merged;
    }
    if (status == HSBD_OK && opt.progress)
        fprintf(stderr, "hsbd: results in %s/\n", p->cfg.output.dir);
    return ranks_rank0_value(r, cli_exit_code(status));
}

int cmd_run(int argc, char **argv) {
    ranks r = ranks_begin();
    run_request q = {0};
    if (r.rank == 0) q.plan = run_read(argc, argv, &q.len);
    ranks_share(&r, (void **)&q.plan, &q.len);
    int code = q.plan && q.len >= sizeof *q.plan ? q.plan->code : 1;
    if (code == 0 && q.plan->go)
        code = request_unpack(&q) ? cli_fail(HSBD_ENOMEM, "out of memory") : run_on_ranks(&r, &q);
    free(q.plan), free(q.sets);
    ranks_end(&r);
    return code;
}

/* ---- hsbd resume ---------------------------------------------------------------------- */

static void resume_help(void) {
    printf("usage: hsbd resume DIR [--set run.t_total=T] [--threads N] [--quiet]\n\n"
           "Continues the run in DIR from its newest checkpoint (checkpoint.hsbd, or\n"
           "checkpoint.prev.hsbd when the newest is damaged). The configuration is the run's\n"
           "own, read again from the checkpoint; stream files (trajectory.xyz, current.tsv) are\n"
           "cut back to the checkpoint. The results equal those of a run never stopped.\n"
           "One process writes a run directory at a time: a resume (or run) of a directory\n"
           "another hsbd process is writing is refused. Under mpirun, rank 0 resumes DIR\n"
           "and the other ranks do nothing.\n\n"
           "  --set run.t_total=T  a longer production time: extends the run (also a\n"
           "                       completed one)\n"
           "  --threads N          threads of the run from here on (same as --set\n"
           "                       run.threads=N; the same results for every N)\n"
           "  --quiet              no progress line\n\n"
           "Exit status: 0 done, 2 bad input (no or a damaged checkpoint, a completed run\n"
           "without a longer run.t_total, a directory in use), 129/130/143 stopped by\n"
           "SIGHUP/SIGINT/SIGTERM (a checkpoint and the results so far written), 1 other\n"
           "errors.\n");
}

/* The command line of hsbd resume: DIR and the overrides; an exit status, with its message
 * on stderr. */
static int resume_args(int argc, char **argv, const char **dir, const char **sets, size_t *nsets,
                       int *quiet, char *threads_set, size_t threads_len) {
    for (int i = 2; i < argc; ++i) {
        const int value = i + 1 < argc && argv[i + 1][0] != '-';
        if (!strcmp(argv[i], "--quiet")) {
            *quiet = 1;
        } else if (!strcmp(argv[i], "--threads") && !value) {
            fprintf(stderr, "hsbd resume: --threads needs a value (--threads N)\n");
            return EXIT_INPUT;
        } else if (!strcmp(argv[i], "--threads")) {
            if ((size_t)snprintf(threads_set, threads_len, "run.threads=%s", argv[++i]) >=
                threads_len) {
                fprintf(stderr,
                        "hsbd resume: --threads %.40s...: too long; allowed: 0 <= N <= 1024\n",
                        argv[i]);
                return EXIT_INPUT;
            }
            sets[(*nsets)++] = threads_set;
        } else if (!strcmp(argv[i], "--set") && !value) {
            fprintf(stderr, "hsbd resume: --set needs a value (--set run.t_total=T)\n");
            return EXIT_INPUT;
        } else if (!strcmp(argv[i], "--set")) {
            if (set_value_check("resume", argc, argv, ++i)) return EXIT_INPUT;
            sets[(*nsets)++] = argv[i];
        } else if (argv[i][0] == '-') {
            fprintf(stderr, "hsbd resume: unknown option '%s' (hsbd resume --help)\n", argv[i]);
            return EXIT_INPUT;
        } else if (*dir) {
            fprintf(stderr, "hsbd resume: more than one run directory ('%s', '%s')\n", *dir,
                    argv[i]);
            return EXIT_INPUT;
        } else {
            *dir = argv[i];
        }
    }
    if (*dir) return 0;
    fprintf(stderr, "hsbd resume: no run directory given (hsbd resume --help)\n");
    return EXIT_INPUT;
}

int cmd_resume(int argc, char **argv) {
    static const char *const value_flags[] = {"--set", "--threads", NULL};
    if (ranks_own_rank() > 0) return 0; /* under mpirun, rank 0's */
    if (cli_asks_help(argc, argv, value_flags)) return resume_help(), 0;
    char threads_set[64];
    const char *dir = NULL;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    size_t nsets = 0;
    int quiet = 0;
    int code =
        sets ? resume_args(argc, argv, &dir, sets, &nsets, &quiet, threads_set, sizeof threads_set)
             : cli_fail(HSBD_ENOMEM, "out of memory");
    if (code == 0) {
        const hsbd_run_options opt = {.progress = progress_mode(quiet), .stop = &cli_stop};
        hsbd_error err;
        cli_catch_stop_signals();
        const int rc = hsbd_resume(dir, sets, nsets, &opt, &err);
        code = rc == HSBD_OK ? 0 : cli_fail(rc, err.message);
        if (rc == HSBD_OK && opt.progress) fprintf(stderr, "hsbd: results in %s/\n", dir);
    }
    free(sets);
    return code;
}

/* ---- hsbd merge ----------------------------------------------------------------------- */

static void merge_help(void) {
    printf("usage: hsbd merge OUT DIR... [--force]\n"
           "       hsbd merge DIR   the replicas of the ensemble in DIR (DIR/replica-K) into DIR\n"
           "                        (an ensemble stopped, its replicas continued one by one)\n\n"
           "Merges the run directories of replicas of one configuration (hsbd run CONFIG\n"
           "--replica K, e.g. the tasks of a job array) into OUT: the means over the replicas\n"
           "and errors from their scatter, summed in replica order, so the result equals\n"
           "that of one ensemble run (mpirun) of the same replicas byte for byte.\n"
           "Refused (exit 2, nothing written): fewer than two directories, a run that did\n"
           "not finish, runs that are no replicas, the same replica twice, runs of\n"
           "different configurations (any parameter but run.replica, run.replicas,\n"
           "run.threads and output.dir), of different builds of hsbd (version, git) or of\n"
           "different contents of an input file, replicas that do not hold the same\n"
           "tables, a table cut short or holding a cell that is no number, a file that is\n"
           "no regular file, a directory another hsbd process is writing, and an OUT that\n"
           "holds a run, a replica or an ensemble (with or without --force).\n"
           "Under mpirun, rank 0 merges and the other ranks do nothing.\n\n"
           "  --force  write into an existing, non-empty OUT (an earlier merge's files)\n");
}

/* The command line of hsbd merge: OUT and the directories; an exit status, with its message
 * on stderr. */
static int merge_args(int argc, char **argv, const char **out, const char **dirs, size_t *ndirs,
                      int *force) {
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--force")) {
            *force = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(stderr, "hsbd merge: unknown option '%.60s' (hsbd merge --help)\n", a);
            return EXIT_INPUT;
        } else if (!*out) {
            *out = a;
        } else {
            dirs[(*ndirs)++] = a;
        }
    }
    if (*out) return 0;
    fprintf(stderr, "hsbd merge: no output directory given (hsbd merge OUT DIR...)\n");
    return EXIT_INPUT;
}

int cmd_merge(int argc, char **argv) {
    static const char *const value_flags[] = {NULL};
    if (ranks_own_rank() > 0) return 0; /* under mpirun, rank 0's */
    if (cli_asks_help(argc, argv, value_flags)) return merge_help(), 0;
    const char *out = NULL;
    const char **dirs = calloc((size_t)argc, sizeof *dirs);
    size_t ndirs = 0;
    int force = 0;
    int code = dirs ? merge_args(argc, argv, &out, dirs, &ndirs, &force)
                    : cli_fail(HSBD_ENOMEM, "out of memory");
    hsbd_error err;
    if (code == 0 && rundir_merge(out, dirs, ndirs, force, &err) != HSBD_OK)
        code = cli_fail(err.status, err.message);
    free(dirs);
    return code;
}
