/* hsbd: command-line front end. Subcommands: run, bench, theory, validate, config-doc,
 * version; each takes --help. */
#define _GNU_SOURCE /* sched_getaffinity: the CPUs of an MPI rank */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/stat.h>
#include <unistd.h>

#include "hsbd/bench.h"
#include "hsbd/config.h"
#include "hsbd/io.h"
#include "hsbd/spheres.h"
#include "hsbd/rods.h"
#include "hsbd/run.h"
#include "hsbd/theory.h"
#include "hsbd/validate.h"
#include "rundir/rundir.h"
#include "hsbd_version.h"

#ifdef HSBD_HAVE_MPI
#include <mpi.h>
#include <sched.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

enum { EXIT_INPUT = 2, EXIT_INTERRUPTED = 130 };

#ifdef HSBD_HAVE_MPI
enum { HSBD_WITH_MPI = 1 };
#else
enum { HSBD_WITH_MPI = 0 };
#endif
#ifdef _OPENMP
enum { HSBD_WITH_OPENMP = 1 };
#else
enum { HSBD_WITH_OPENMP = 0 };
#endif

static volatile sig_atomic_t stop_flag = 0;

/* SIGINT, SIGTERM, SIGHUP: the run writes a checkpoint and its results so far, then
 * exits with 128 + the signal's number; a second signal ends it at once. */
static void on_signal(int sig) {
    if (stop_flag) {
        signal(sig, SIG_DFL);
        raise(sig);
    }
    stop_flag = sig;
}

static void catch_stop_signals(void) {
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGHUP, on_signal);
}

static int exit_code_for(int status) {
    switch (status) {
    case HSBD_OK:
        return 0;
    case HSBD_EINPUT:
        return EXIT_INPUT;
    case HSBD_EINTERRUPT:
        return stop_flag ? 128 + (int)stop_flag : EXIT_INTERRUPTED;
    default:
        return 1;
    }
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

static int fail(int status, const char *msg) {
    fprintf(stderr, "hsbd: %s\n", msg);
    return exit_code_for(status);
}

/* One synopsis per subcommand: `hsbd --help` prints them all, `hsbd CMD --help` its own
 * with the options. */
static const char *const synopsis_run =
    "hsbd run CONFIG.ini [options]   simulate (see 'hsbd run --help')\n"
    "       hsbd run --defaults [options]   simulate the default configuration\n";
static const char *const synopsis_resume =
    "hsbd resume DIR [--set run.t_total=T] [--threads N] [--quiet]\n"
    "                                       continue a stopped run from its checkpoint\n";
static const char *const synopsis_merge =
    "hsbd merge OUT DIR... [--force]        merge replicas of one configuration\n";
static const char *const synopsis_bench =
    "hsbd bench [--seconds S] [--case NAME] [--list] [--threads]\n"
    "                                       throughput, with the free-particle bound\n";
static const char *const synopsis_percus =
    "hsbd theory percus --sigma S --rho R --amplitude U0 [--gamma G]\n"
    "                      [--wavelength W] [--points M] --out FILE|-\n"
    "                                       exact equilibrium profile (x rho rho2)\n";
static const char *const synopsis_tonks =
    "hsbd theory tonks --sigma S --rho R [--gamma G] [--D D]\n"
    "                                       closed forms of the homogeneous fluid\n";
static const char *const synopsis_box =
    "hsbd theory box --N N --L L --sigma S [--force F] [--stiffness K]\n"
    "                      [--center C] [--amplitude U0] [--wavelength W] [--bin W]\n"
    "                      [--points M] --out FILE|-\n"
    "                                       exact profile between hard walls\n";
static const char *const synopsis_washboard =
    "hsbd theory washboard --amplitude U0 [--wavelength W] [--D D] [--kT kT]\n"
    "                      [--force F | --force-min A --force-max B --forces K]\n"
    "                      [--rocking F1] [--tol T] --out FILE|-\n"
    "                                       one particle in a tilted cosine: <v>, D_eff\n";
static const char *const synopsis_validate =
    "hsbd validate [--quick] [--dt-scan] [--sticky] [--out DIR] [--case TEXT]\n"
    "                     [--jobs N] [--seed-offset K] [--list]\n"
    "                                       simulations against exact theory\n";

static void usage(FILE *out) {
    fprintf(out,
            "usage: %s       %s       %s       %s       %s       %s       %s       %s       %s",
            synopsis_run, synopsis_resume, synopsis_merge, synopsis_bench, synopsis_percus,
            synopsis_tonks, synopsis_box, synopsis_washboard, synopsis_validate);
    fprintf(out, "       hsbd config-doc                 print the configuration reference "
                 "(Markdown)\n"
                 "       hsbd version\n"
                 "Every subcommand takes --help.\n");
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
           "  --force     write into an existing, non-empty run directory\n"
           "  --check     verify the hard core after every step (slower)\n"
           "  --quiet     no progress line\n\n"
           "Writes density.tsv, contact.tsv, msd.tsv, clusters.tsv, summary.json (and\n"
           "trajectory.xyz, current.tsv when asked) atomically. Exit status: 0 done, 2 bad\n"
           "input, 130 interrupted (results so far written), 1 other errors.\n\n"
           "Configuration keys:\n");
    hsbd_config_write_reference(stdout, 0);
}

static int is_help(const char *arg) {
    return !strcmp(arg, "--help") || !strcmp(arg, "-h");
}

/* --help or -h anywhere after the subcommand but as the value of one of the flags listed
 * in value_flags (NULL-terminated): it wins over any other argument. */
static int asks_help(int argc, char **argv, const char *const *value_flags) {
    for (int i = 2; i < argc; ++i) {
        if (is_help(argv[i])) return 1;
        for (const char *const *f = value_flags; *f; ++f)
            if (!strcmp(argv[i], *f)) {
                ++i; /* its value, whatever it is */
                break;
            }
    }
    return 0;
}

/* The value of the flag argv[*i], advancing *i; NULL after a message when nothing follows
 * or the next argument is itself a flag (a value starting with "--" is read as a flag:
 * write ./--name for such a file). */
static const char *flag_value(const char *cmd, int argc, char **argv, int *i, FILE *msg) {
    const char *flag = argv[*i];
    if (*i + 1 >= argc) {
        fprintf(msg, "hsbd %s: %s needs a value (nothing follows it)\n", cmd, flag);
        return NULL;
    }
    if (!strncmp(argv[*i + 1], "--", 2)) {
        fprintf(msg, "hsbd %s: %s needs a value, but the next argument '%.60s' is a flag\n", cmd,
                flag, argv[*i + 1]);
        return NULL;
    }
    return argv[++*i];
}

/* runs/<config file name without directory and extension> */
static void default_out_dir(const char *config_path, char *out, size_t len) {
    const char *base = strrchr(config_path, '/');
    base = base ? base + 1 : config_path;
    const char *dot = strrchr(base, '.');
    const int n = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
    snprintf(out, len, "runs/%.*s", n, base);
}

/* ---- ensembles of replicas over MPI ranks (docs/scaling.md) ----------------------------- */

/* status of a rank that stopped because another rank failed (that one prints why) */
enum { HSBD_ESILENT = -1 };

#ifdef HSBD_HAVE_MPI
/* started by mpirun (OpenMPI or a PMI launcher): only then is MPI initialised, so a
 * plain run never pays for it */
static int launched_by_mpi(void) {
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
}
#endif

typedef struct ranks {
    int rank, size, mpi;
} ranks;

static ranks ranks_begin(void) {
    ranks r = {0, 1, 0};
#ifdef HSBD_HAVE_MPI
    if (launched_by_mpi() && MPI_Init(NULL, NULL) == MPI_SUCCESS) {
        r.mpi = 1;
        MPI_Comm_rank(MPI_COMM_WORLD, &r.rank);
        MPI_Comm_size(MPI_COMM_WORLD, &r.size);
    }
#endif
    return r;
}

#ifdef HSBD_HAVE_MPI
/* Waits for a non-blocking collective, sleeping between polls (50 us, doubled up to 20 ms): a rank
 * that waits for the others (its replicas done, or its work left to another rank) would otherwise
 * spin in the library's progress loop for as long as their work takes. `started` is the status of
 * the call that started it. */
static void wait_asleep(int started, MPI_Request *req) {
    int done = started != MPI_SUCCESS;
    struct timespec pause = {0, 50 * 1000}; /* doubled up to 20 ms: a quick agreement */
    while (!done && MPI_Test(req, &done, MPI_STATUS_IGNORE) == MPI_SUCCESS && !done) {
        nanosleep(&pause, NULL); /* waits little, a long one costs no CPU */
        if (pause.tv_nsec < 20 * 1000 * 1000) pause.tv_nsec *= 2;
    }
}
#endif

/* Every rank waits for the others (asleep) before MPI_Finalize. */
static void ranks_end(const ranks *r) {
#ifdef HSBD_HAVE_MPI
    if (!r->mpi) return;
    MPI_Request all_done;
    wait_asleep(MPI_Ibarrier(MPI_COMM_WORLD, &all_done), &all_done);
    MPI_Finalize();
#else
    (void)r;
#endif
}

/* The largest (or, with largest 0, the smallest) of the ranks' values: a collective,
 * waited for asleep; the value itself without MPI. */
static int ranks_reduce(const ranks *r, int value, int largest) {
    int reduced = value;
#ifdef HSBD_HAVE_MPI
    MPI_Request done;
    if (r->mpi)
        wait_asleep(MPI_Iallreduce(&value, &reduced, 1, MPI_INT, largest ? MPI_MAX : MPI_MIN,
                                   MPI_COMM_WORLD, &done),
                    &done);
#else
    (void)r, (void)largest;
#endif
    return reduced;
}

/* The worst status over the ranks (every rank calls it at the same point); a rank that
 * itself succeeded gets HSBD_ESILENT with the status in err. */
static int ranks_agree(const ranks *r, int rc, hsbd_error *err) {
    const int worst = ranks_reduce(r, rc, 1);
    if (worst == HSBD_OK || rc != HSBD_OK) return rc;
    err->status = worst;
    return HSBD_ESILENT;
}

#ifdef HSBD_HAVE_MPI
/* A 64-bit FNV-1a hash of text (0 for none). */
static uint64_t text_key(const char *text) {
    uint64_t key = UINT64_C(14695981039346656037);
    for (const char *c = text; c && *c; ++c)
        key = (key ^ (unsigned char)*c) * UINT64_C(1099511628211);
    return text && *text ? key : 0;
}

/* The key of a directory, the same however it is spelled: its path resolved (symbolic
 * links, . and ..; a part not there yet through its nearest existing parent). */
static uint64_t dir_key(const char *dir) {
    char resolved[PATH_MAX];
    return text_key(realpath(dir, resolved) ? resolved : dir);
}

/* Each rank's key, gathered over MPI_COMM_WORLD (a collective, waited for asleep); NULL
 * when out of memory, after the message (the job is aborted). */
static uint64_t *gather_keys(const ranks *r, uint64_t key) {
    uint64_t *keys = malloc((size_t)r->size * sizeof *keys);
    if (!keys) {
        fprintf(stderr, "hsbd: out of memory\n");
        MPI_Abort(MPI_COMM_WORLD, 1);
        return NULL;
    }
    for (int k = 0; k < r->size; ++k) /* what a failed gather leaves */
        keys[k] = k == r->rank ? key : 0;
    MPI_Request gathered;
    wait_asleep(
        MPI_Iallgather(&key, 1, MPI_UINT64_T, keys, 1, MPI_UINT64_T, MPI_COMM_WORLD, &gathered),
        &gathered);
    return keys;
}
#endif

/* A verdict over the ranks (every rank calls it at the same point, with its exit code
 * and what it would print): each distinct message is printed once, by the lowest rank
 * that has it (ranks above 0 name themselves), and every rank gets the worst exit code. */
static int ranks_report(const ranks *r, int code, const char *said) {
    int print = 1, worst = code;
#ifdef HSBD_HAVE_MPI
    if (r->mpi) {
        const uint64_t key = text_key(said);
        uint64_t *keys = gather_keys(r, key);
        for (int k = 0; keys && k < r->rank && print; ++k)
            print = keys[k] != key;
        free(keys);
        worst = ranks_reduce(r, code, 1);
    }
#endif
    if (print && said && *said && r->rank > 0) /* one write: no other rank's line inside */
        fprintf(stderr, "hsbd: rank %d of mpirun:\n%s", r->rank, said);
    else if (print && said && *said)
        fputs(said, stderr);
    return worst;
}

/* The messages of a command's input checks: under mpirun kept and printed once over the
 * ranks (ranks_report), else written to stderr at once. */
typedef struct input_messages {
    FILE *f;
    char *text;
    size_t len;
} input_messages;

static FILE *input_messages_open(const ranks *r, input_messages *m) {
    *m = (input_messages){0};
    if (r->mpi) m->f = open_memstream(&m->text, &m->len);
    return m->f ? m->f : stderr;
}

/* The worst exit code over the ranks, the messages printed (a collective). */
static int input_messages_report(const ranks *r, input_messages *m, int code) {
    if (m->f) fclose(m->f);
    code = ranks_report(r, code, m->text);
    free(m->text);
    return code;
}

/* The lowest rank whose flag is set, or -1 (a collective). */
static int ranks_lowest(const ranks *r, int flag) {
    const int lowest = ranks_reduce(r, flag ? r->rank : INT_MAX, 0);
    return lowest == INT_MAX ? -1 : lowest;
}

/* Under mpirun, --help asked on any rank: printed by the lowest that asked, and every rank
 * stops (1); else 0. A collective. */
static int ranks_help(const ranks *r, int asked, void (*help)(void)) {
    const int first = ranks_lowest(r, asked);
    if (first == r->rank) help();
    return first >= 0;
}

/* The end of a command on every rank: its status (HSBD_ESILENT: another rank's failure,
 * in err->status) and message, as an exit code; the messages printed once over the ranks
 * and every rank given the worst code. A collective. */
static int ranks_outcome(const ranks *r, int rc, const hsbd_error *err) {
    input_messages said;
    FILE *msg = input_messages_open(r, &said);
    if (rc != HSBD_OK && err->message[0]) fprintf(msg, "hsbd: %s\n", err->message);
    return input_messages_report(r, &said, exit_code_for(rc == HSBD_ESILENT ? err->status : rc));
}

/* The lowest rank given the same directory as this one (its own rank when none below
 * is): under mpirun one process resumes or merges into a directory, while ranks given
 * directories of their own (a job step with one per task) all work. *others: how many
 * ranks above leave their directory to this one. Paths are compared resolved (symbolic
 * links, . and ..), as a 64-bit FNV-1a hash. A collective. */
static int first_rank_for(const ranks *r, const char *dir, int *others) {
    *others = 0;
#ifdef HSBD_HAVE_MPI
    if (!r->mpi) return r->rank;
    const uint64_t key = dir_key(dir);
    uint64_t *keys = gather_keys(r, key);
    int first = r->rank;
    for (int k = 0; keys && k < r->size; ++k) {
        if (keys[k] == key && k < first) first = k;
        *others += keys[k] == key && k > r->rank;
    }
    free(keys);
    if (first != r->rank) *others = 0;
    return first;
#else
    (void)dir;
    return r->rank;
#endif
}

/* One line from the rank that works in dir, when other ranks were given it too. */
static void say_others_wait(const char *cmd, const ranks *r, int others, const char *dir) {
    if (others > 0)
        fprintf(stderr, "hsbd %s: %d other rank%s of mpirun given '%s' leave%s it to rank %d\n",
                cmd, others, others > 1 ? "s" : "", dir, others > 1 ? "" : "s", r->rank);
}

/* The threads each working rank takes when neither run.threads nor OMP_NUM_THREADS sets
 * them: the CPUs it may use divided by the most working ranks of its node that may use one
 * of them, so that ranks and threads do not oversubscribe the node (ranks bound to cores
 * keep theirs; unbound ones, or ranks bound to a socket, split their CPUs), while ranks
 * that only wait (working 0) leave their CPUs to the others. A collective over
 * MPI_COMM_WORLD; 0 when unknown (no MPI, or no CPU masks). */
static int rank_threads_share(const ranks *r, int working) {
#if defined(HSBD_HAVE_MPI) && defined(__linux__) && defined(CPU_COUNT)
    if (!r->mpi) return 0;
    cpu_set_t own;
    const int known = sched_getaffinity(0, sizeof own, &own) == 0;
    if (!known) CPU_ZERO(&own); /* it still takes part in the collective */
    MPI_Comm node;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node) !=
        MPI_SUCCESS)
        return 0;
    int mine[CPU_SETSIZE], ranks_on[CPU_SETSIZE]; /* ranks of the node that may use each CPU */
    for (int c = 0; c < CPU_SETSIZE; ++c)
        mine[c] = working && CPU_ISSET(c, &own) ? 1 : 0;
    const int summed =
        MPI_Allreduce(mine, ranks_on, CPU_SETSIZE, MPI_INT, MPI_SUM, node) == MPI_SUCCESS;
    MPI_Comm_free(&node);
    int sharing = 0; /* the most ranks on any of this rank's CPUs */
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (mine[c] && ranks_on[c] > sharing) sharing = ranks_on[c];
    if (!known || !summed || sharing < 1) return 0;
    const int cpus = CPU_COUNT(&own);
    return cpus / sharing > 1 ? cpus / sharing : 1;
#else
    (void)r, (void)working;
    return 0;
#endif
}

/* Under mpirun, the default thread count (run.threads 0) becomes the rank's share of its
 * node's CPUs (rank_threads_share) unless OMP_NUM_THREADS sets it; run.threads stays 0 in
 * the parameters, as in one process. A collective. */
static void share_rank_threads(const ranks *r, int working) {
    const int share = rank_threads_share(r, working);
#ifdef _OPENMP
    if (share > 0 && !getenv("OMP_NUM_THREADS")) omp_set_num_threads(share);
#else
    (void)share; /* one thread anyway */
#endif
}

/* A single run (under mpirun, one per directory the ranks were given), or run.replicas
 * replicas spread over the ranks (replica k on rank k mod P, each in DIR/replica-k; every
 * rank given the same configuration) and merged by rank 0 in replica order. */
static int run_ensemble_or_single(const ranks *ranks_of_run, hsbd_config *cfg,
                                  hsbd_run_options *opt, int quiet, hsbd_error *err) {
    const ranks r = *ranks_of_run;
    const size_t replicas = rundir_ensemble_size(cfg, r.size);
    int rc = HSBD_OK;
    if (replicas == 1) { /* ranks given the same directory leave it to the lowest */
        int others;
        const int first = first_rank_for(&r, cfg->output.dir, &others);
        share_rank_threads(&r, first == r.rank);
        if (!quiet) say_others_wait("run", &r, others, cfg->output.dir);
        if (first == r.rank) rc = hsbd_run(cfg, opt, err);
        if (first != r.rank) opt->progress = 0; /* no "results in" from it */
    } else {
        if (r.rank > 0) opt->progress = 0;
        share_rank_threads(&r, (size_t)r.rank < replicas); /* a collective */
        rundir_ensemble claim = {.lock = -1};              /* rank 0's */
        if (r.rank == 0) rc = rundir_ensemble_begin(cfg, &claim, err);
        rc = ranks_agree(&r, rc, err);
        if (rc == HSBD_OK) { /* on every rank or on none: each meets the second agreement */
            rc = rundir_ensemble_run(cfg, opt, replicas, r.rank, r.size, err);
            rc = ranks_agree(&r, rc, err);
        }
        /* merged, or the directory made for nothing removed; its lock released */
        if (r.rank == 0) {
            const int status = rc == HSBD_ESILENT ? err->status : rc;
            const int done = rundir_ensemble_end(cfg, status, &claim, err);
            if (rc != HSBD_ESILENT || done != status) rc = done;
        }
    }
    return rc;
}

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
           "is or holds one of the directories merged.\n"
           "Under mpirun, ranks given the same OUT leave it to the lowest of them.\n\n"
           "  --force  write into an existing, non-empty OUT (an earlier result's files)\n");
}

/* The command line of hsbd merge: OUT and the directories; an exit status, with the
 * message written to msg. */
static int merge_args(int argc, char **argv, FILE *msg, const char **out, const char **dirs,
                      size_t *ndirs, int *force) {
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--force")) {
            *force = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(msg, "hsbd merge: unknown option '%.60s' (hsbd merge --help)\n", a);
            return EXIT_INPUT;
        } else if (!*out) {
            *out = a;
        } else {
            dirs[(*ndirs)++] = a;
        }
    }
    if (!*out) {
        fprintf(msg, "hsbd merge: no output directory given (hsbd merge OUT DIR...)\n");
        return EXIT_INPUT;
    }
    return 0;
}

static int cmd_merge(const ranks *r, int argc, char **argv) {
    static const char *const value_flags[] = {NULL};
    if (ranks_help(r, asks_help(argc, argv, value_flags), merge_help)) return 0;
    const char *out = NULL;
    const char **dirs = calloc((size_t)argc, sizeof *dirs);
    size_t ndirs = 0;
    int force = 0;
    input_messages said;
    FILE *msg = input_messages_open(r, &said);
    int code = dirs ? merge_args(argc, argv, msg, &out, dirs, &ndirs, &force)
                    : (fprintf(msg, "hsbd: out of memory\n"), 1);
    code = input_messages_report(r, &said, code);
    if (code == 0) { /* under mpirun, one process merges into each OUT */
        int others;
        const int first = first_rank_for(r, out, &others);
        say_others_wait("merge", r, others, out);
        hsbd_error err = {0}; /* a rank that did no work has no message */
        const int rc = first == r->rank ? rundir_merge(out, dirs, ndirs, force, &err) : HSBD_OK;
        code = ranks_outcome(r, rc, &err);
    }
    free(dirs);
    return code;
}

/* One override from the command line, applied in order after the file. */
typedef struct run_override {
    const char *flag, *value;
} run_override;

/* What `hsbd run` is asked to do: the configuration with its overrides applied, the
 * options, and the source kept for the checkpoints. */
typedef struct run_request {
    const char *config_path;
    int quiet; /* --quiet */
    hsbd_config cfg;
    hsbd_run_options opt;
    hsbd_run_source source;
    char (*sets)[HSBD_PATH_MAX + 64];
    const char **set_list;
} run_request;

static void run_request_free(run_request *q) {
    if (q->config_path) free((char *)q->source.text);
    free(q->sets), free(q->set_list);
}

/* A path that names the standard input (/dev/stdin, /dev/fd/0, /proc/self/fd/0). */
static int names_standard_input(const char *path) {
    return !strcmp(path, "/dev/stdin") || !strcmp(path, "/dev/fd/0") ||
           !strcmp(path, "/proc/self/fd/0");
}

/* The command line and the configuration read into q (nranks: of mpirun, 1 without); an
 * exit status, with the message written to msg. */
/* A --set value is section.key=value: 0, or EXIT_INPUT with a message that shows the line
 * meant ("--set run.t_total 5": --set run.t_total=5) when the value is missing its '='. */
static int set_value_check(const char *cmd, int argc, char **argv, int i, FILE *msg) {
    if (strchr(argv[i], '=')) return 0;
    const int next = i + 1 < argc && argv[i + 1][0] != '-';
    fprintf(msg, "hsbd %s: --set needs section.key=value, not '%.100s'%s%.100s%s%.100s%s\n", cmd,
            argv[i], next ? " (write --set " : "", next ? argv[i] : "", next ? "=" : "",
            next ? argv[i + 1] : "", next ? ")" : "");
    return EXIT_INPUT;
}

static int run_request_read(int argc, char **argv, int nranks, FILE *msg, run_request *q) {
    int defaults = 0, noverrides = 0;
    run_override *overrides = calloc((size_t)argc, sizeof *overrides);
    q->opt = (hsbd_run_options){.progress = isatty(STDERR_FILENO), .stop = &stop_flag};
    q->sets = calloc((size_t)argc, sizeof *q->sets);
    q->set_list = calloc((size_t)argc, sizeof *q->set_list);
    if (!overrides || !q->sets || !q->set_list)
        return free(overrides), fprintf(msg, "hsbd: out of memory\n"), 1;
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i];
        if (!strcmp(a, "--set") || !strcmp(a, "--out") || !strcmp(a, "--seed") ||
            !strcmp(a, "--replica") || !strcmp(a, "--threads")) {
            const char *v = flag_value("run", argc, argv, &i, msg);
            if (!v || (!strcmp(a, "--set") && set_value_check("run", argc, argv, i, msg)))
                return free(overrides), EXIT_INPUT;
            overrides[noverrides++] = (run_override){a, v};
        } else if (!strcmp(a, "--defaults")) {
            defaults = 1;
        } else if (!strcmp(a, "--force")) {
            q->opt.force = 1;
        } else if (!strcmp(a, "--check")) {
            q->opt.check = 1;
        } else if (!strcmp(a, "--quiet")) {
            q->quiet = 1;
        } else if (a[0] == '-' && a[1] != '\0') {
            fprintf(msg, "hsbd run: unknown option '%.60s' (hsbd run --help)\n", a);
            return free(overrides), EXIT_INPUT;
        } else if (q->config_path) {
            fprintf(msg, "hsbd run: more than one configuration file ('%.200s', '%.200s')\n",
                    q->config_path, a);
            return free(overrides), EXIT_INPUT;
        } else {
            q->config_path = a;
        }
    }
    if (!q->config_path == !defaults) {
        fprintf(msg, "hsbd run: %s (hsbd run --help)\n",
                defaults ? "--defaults runs without a configuration file, but one is given"
                         : "no configuration file given; --defaults runs the default "
                           "configuration");
        return free(overrides), EXIT_INPUT;
    }
    const char *config_path = q->config_path;
    q->config_path = NULL; /* set again once its text is read */
    if (config_path && nranks > 1 && names_standard_input(config_path)) {
        fprintf(msg,
                "hsbd run: the configuration file '%s' is the standard input, which mpirun "
                "gives to rank 0 only; give every rank a file it can read\n",
                config_path);
        return free(overrides), EXIT_INPUT;
    }
    hsbd_error err;
    hsbd_config_defaults(&q->cfg);
    if (config_path && hsbd_config_load_file(&q->cfg, config_path, &err) != HSBD_OK)
        return free(overrides), fprintf(msg, "hsbd: %s\n", err.message), exit_code_for(err.status);
    /* the source of the configuration goes into the checkpoints (hsbd resume) */
    q->source = (hsbd_run_source){.name = config_path, .text = "", .text_len = 0};
    if (config_path) {
        q->source.text = read_whole_file(config_path, &q->source.text_len);
        if (!q->source.text) {
            fprintf(msg, "hsbd run: cannot read '%s' again\n", config_path);
            return free(overrides), EXIT_INPUT;
        }
        q->config_path = config_path;
    }
    q->source.sets = q->set_list;
    q->opt.source = &q->source;
    if (!q->cfg.output.dir[0])
        default_out_dir(config_path ? config_path : "defaults", q->cfg.output.dir,
                        sizeof q->cfg.output.dir);
    for (int k = 0; k < noverrides; ++k) {
        const run_override *o = &overrides[k];
        char buf[HSBD_PATH_MAX + 64], origin[64];
        if (!strcmp(o->flag, "--set"))
            snprintf(buf, sizeof buf, "%s", o->value);
        else
            snprintf(buf, sizeof buf, "%s=%s",
                     !strcmp(o->flag, "--out")       ? "output.dir"
                     : !strcmp(o->flag, "--replica") ? "run.replica"
                     : !strcmp(o->flag, "--threads") ? "run.threads"
                                                     : "system.seed",
                     o->value);
        snprintf(origin, sizeof origin, "command line (%s)", o->flag);
        if (strlen(o->value) >= HSBD_PATH_MAX) {
            fprintf(msg, "hsbd run: %s: the value is longer than %d characters\n", o->flag,
                    HSBD_PATH_MAX - 1);
            return free(overrides), EXIT_INPUT;
        }
        snprintf(q->sets[q->source.nsets], sizeof q->sets[0], "%s", buf);
        q->set_list[q->source.nsets] = q->sets[q->source.nsets];
        q->source.nsets += 1;
        if (hsbd_config_set(&q->cfg, buf, origin, &err) != HSBD_OK)
            return free(overrides), fprintf(msg, "hsbd: %s\n", err.message),
                   exit_code_for(err.status);
    }
    free(overrides);
    if (hsbd_config_finalize(&q->cfg, &err) != HSBD_OK)
        return fprintf(msg, "hsbd: %s\n", err.message), exit_code_for(err.status);
    if (q->quiet) q->opt.progress = 0;
    return 0;
}

#ifdef HSBD_HAVE_MPI
/* A key of the configuration that is the same on ranks given the same one: its parameters
 * (JSON) with output.dir resolved and without run.threads, which changes no result; 0 when
 * out of memory. */
static uint64_t config_key(const hsbd_config *cfg) {
    hsbd_config *same = malloc(sizeof *same);
    char *text = NULL;
    size_t len = 0;
    FILE *f = same ? open_memstream(&text, &len) : NULL;
    if (f) {
        *same = *cfg;
        same->run.threads = 0;
        char resolved[PATH_MAX];
        if (realpath(cfg->output.dir, resolved) && strlen(resolved) < sizeof same->output.dir)
            memcpy(same->output.dir, resolved, strlen(resolved) + 1);
        hsbd_config_write_json(same, f, 0);
        fclose(f);
    }
    const uint64_t key = text_key(text);
    free(text), free(same);
    return key;
}
#endif

/* Under mpirun, ranks that must be given the same configuration and are not: the ranks of
 * an ensemble (all of them), or ranks given the same output directory for a single run
 * (the lowest runs it for all). EXIT_INPUT after rank 0's message, else 0. A collective. */
static int ranks_same_config(const ranks *r, const hsbd_config *cfg, int ensemble) {
#ifdef HSBD_HAVE_MPI
    if (!r->mpi) return 0;
    uint64_t *dirs = gather_keys(r, ensemble ? 1 : dir_key(cfg->output.dir));
    uint64_t *keys = gather_keys(r, config_key(cfg));
    int a = 0, b = 0; /* the first pair of ranks that should agree and do not */
    for (int k = 1; dirs && keys && k < r->size && !b; ++k)
        for (int j = 0; j < k && !b; ++j)
            if (dirs[j] == dirs[k] && (keys[j] != keys[k] || !keys[k])) a = j, b = k;
    free(dirs), free(keys);
    if (b && r->rank == 0)
        fprintf(stderr, "hsbd run: ranks %d and %d of mpirun were given %s\n", a, b,
                ensemble ? "different configurations for one ensemble (only run.threads may "
                           "differ: the same configuration file and --set, --out, --seed, "
                           "--replica on every rank)"
                         : "the same output directory for different single runs (one rank "
                           "runs each directory: give each run its own --out)");
    return b ? EXIT_INPUT : 0;
#else
    (void)r, (void)cfg, (void)ensemble;
    return 0;
#endif
}

static int cmd_run(const ranks *r, int argc, char **argv) {
    static const char *const value_flags[] = {"--set",     "--out",     "--seed",
                                              "--replica", "--threads", NULL};
    /* under mpirun every rank reads the input; a message is printed once however many ranks
     * meet it, and a rank that meets none does not start a run the others cannot join */
    if (ranks_help(r, asks_help(argc, argv, value_flags), run_help)) return 0;
    input_messages said;
    FILE *msg = input_messages_open(r, &said);
    run_request q = {0};
    int code = input_messages_report(r, &said, run_request_read(argc, argv, r->size, msg, &q));
    /* an ensemble on any rank: the same configuration on all; single runs: on the ranks
     * given one directory */
    if (code == 0)
        code = ranks_same_config(r, &q.cfg,
                                 ranks_lowest(r, rundir_ensemble_size(&q.cfg, r->size) > 1) >= 0);
    if (code == 0) {
        hsbd_error err = {0}; /* a rank that did no work has no message */
        catch_stop_signals();
        const int rc = run_ensemble_or_single(r, &q.cfg, &q.opt, q.quiet, &err);
        if (rc == HSBD_OK && q.opt.progress)
            fprintf(stderr, "hsbd: results in %s/\n", q.cfg.output.dir);
        code = ranks_outcome(r, rc, &err);
    }
    run_request_free(&q);
    return code;
}

static void resume_help(void) {
    printf("usage: hsbd resume DIR [--set run.t_total=T] [--threads N] [--quiet]\n\n"
           "Continues the run in DIR from its newest checkpoint (checkpoint.hsbd, or\n"
           "checkpoint.prev.hsbd when the newest is damaged). The configuration is the run's\n"
           "own, read again from the checkpoint; stream files (trajectory.xyz, current.tsv) are\n"
           "cut back to the checkpoint. The results equal those of a run never stopped.\n"
           "One process writes a run directory at a time: a resume (or run) of a directory\n"
           "another hsbd process is writing is refused. Under mpirun, ranks given the same\n"
           "DIR leave it to the lowest of them; ranks given their own DIR each resume it.\n\n"
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

/* The command line of hsbd resume: DIR and the overrides; an exit status, with the message
 * written to msg. */
static int resume_args(int argc, char **argv, FILE *msg, const char **dir, const char **sets,
                       size_t *nsets, int *quiet, char *threads_set, size_t threads_len) {
    for (int i = 2; i < argc; ++i) {
        if (!strcmp(argv[i], "--quiet")) {
            *quiet = 1;
        } else if (!strcmp(argv[i], "--threads")) {
            if (i + 1 >= argc || argv[i + 1][0] == '-') {
                fprintf(msg, "hsbd resume: --threads needs a value (--threads N)\n");
                return EXIT_INPUT;
            }
            if ((size_t)snprintf(threads_set, threads_len, "run.threads=%s", argv[++i]) >=
                threads_len) {
                fprintf(msg, "hsbd resume: --threads %.40s...: too long; allowed: 0 <= N <= 1024\n",
                        argv[i]);
                return EXIT_INPUT;
            }
            sets[(*nsets)++] = threads_set;
        } else if (!strcmp(argv[i], "--set")) {
            if (i + 1 >= argc || argv[i + 1][0] == '-') {
                fprintf(msg, "hsbd resume: --set needs a value (--set run.t_total=T)\n");
                return EXIT_INPUT;
            }
            if (set_value_check("resume", argc, argv, ++i, msg)) return EXIT_INPUT;
            sets[(*nsets)++] = argv[i];
        } else if (argv[i][0] == '-') {
            fprintf(msg, "hsbd resume: unknown option '%s' (hsbd resume --help)\n", argv[i]);
            return EXIT_INPUT;
        } else if (*dir) {
            fprintf(msg, "hsbd resume: more than one run directory ('%s', '%s')\n", *dir, argv[i]);
            return EXIT_INPUT;
        } else {
            *dir = argv[i];
        }
    }
    if (!*dir) {
        fprintf(msg, "hsbd resume: no run directory given (hsbd resume --help)\n");
        return EXIT_INPUT;
    }
    return 0;
}

static int cmd_resume(const ranks *r, int argc, char **argv) {
    static const char *const value_flags[] = {"--set", "--threads", NULL};
    if (ranks_help(r, asks_help(argc, argv, value_flags), resume_help)) return 0;
    char threads_set[64];
    const char *dir = NULL;
    const char **sets = calloc((size_t)argc, sizeof *sets);
    size_t nsets = 0;
    hsbd_run_options opt = {.progress = isatty(STDERR_FILENO), .stop = &stop_flag};
    int quiet = 0;
    input_messages said;
    FILE *msg = input_messages_open(r, &said);
    int code = sets ? resume_args(argc, argv, msg, &dir, sets, &nsets, &quiet, threads_set,
                                  sizeof threads_set)
                    : (fprintf(msg, "hsbd: out of memory\n"), 1);
    code = input_messages_report(r, &said, code);
    if (quiet) opt.progress = 0;
    if (code == 0) { /* under mpirun, one process resumes each directory */
        int others;
        const int first = first_rank_for(r, dir, &others);
        share_rank_threads(r, first == r->rank);
        if (!quiet) say_others_wait("resume", r, others, dir);
        hsbd_error err = {0}; /* a rank that did no work has no message */
        catch_stop_signals();
        const int rc = first == r->rank ? hsbd_resume(dir, sets, nsets, &opt, &err) : HSBD_OK;
        if (rc == HSBD_OK && first == r->rank && opt.progress)
            fprintf(stderr, "hsbd: results in %s/\n", dir);
        code = ranks_outcome(r, rc, &err);
    }
    free(sets);
    return code;
}

static int cmd_bench(int argc, char **argv) {
    double seconds = 2.0;
    int threads = 0;
    const char *only = NULL;
    for (int i = 2; i < argc; ++i) {
        if (is_help(argv[i])) {
            printf("usage: %s\n"
                   "  --seconds S   measuring time per case and variant (default 2; 0 < S < "
                   "3600)\n"
                   "  --case NAME   only this case\n"
                   "  --list        print the names of the cases and exit\n"
                   "  --threads     rods: one thread against all the process may use (wall\n"
                   "                clock) instead of the one-core tables\n",
                   synopsis_bench);
            return 0;
        }
        if (!strcmp(argv[i], "--list")) {
            hsbd_bench_list(stdout);
            return 0;
        }
        if (!strcmp(argv[i], "--threads")) {
            threads = 1;
            continue;
        }
        if (!strcmp(argv[i], "--seconds")) {
            const char *v = flag_value("bench", argc, argv, &i, stderr);
            if (!v) return EXIT_INPUT;
            char *end;
            seconds = strtod(v, &end);
            if (end == v || *end || !(seconds > 0 && seconds < 3600)) {
                fprintf(stderr, "hsbd bench: --seconds = '%.60s'; allowed: 0 < S < 3600\n", v);
                return EXIT_INPUT;
            }
        } else if (!strcmp(argv[i], "--case")) {
            if (!(only = flag_value("bench", argc, argv, &i, stderr))) return EXIT_INPUT;
        } else {
            fprintf(stderr, "hsbd bench: unknown option '%.60s' (hsbd bench --help)\n", argv[i]);
            return EXIT_INPUT;
        }
    }
    if (only && !hsbd_bench_has_case(only)) {
        fprintf(stderr,
                "hsbd bench: --case: no case named '%.60s' (hsbd bench --list names them)\n", only);
        return EXIT_INPUT;
    }
    if (threads)
        hsbd_bench_threads(only, seconds, stdout);
    else
        hsbd_bench_run(only, seconds, stdout);
    return 0;
}

/* ---- theory ------------------------------------------------------------------------ */

typedef struct num_flag {
    const char *name;
    double *value;
    double min, max;
    int open_min, open_max;
    int required;
    const char *doc;
    int seen;
} num_flag;

/* "-inf", "inf" for the tables' 1e300 bounds, else %g */
static const char *bound_text(double v, char *buf, size_t len) {
    if (fabs(v) >= 1e300) return v < 0 ? "-inf" : "inf";
    snprintf(buf, len, "%g", v);
    return buf;
}

/* "lo <= name < hi" of a flag */
static void flag_range(const num_flag *f, char *buf, size_t len) {
    char lo[32], hi[32];
    snprintf(buf, len, "%s %s %s %s %s", bound_text(f->min, lo, sizeof lo),
             f->open_min ? "<" : "<=", f->name + 2,
             f->open_max ? "<" : "<=", bound_text(f->max, hi, sizeof hi));
}

/* "  --name  doc (allowed: range; required)" per flag, after the synopsis */
static void num_flags_help(const char *synopsis, const char *about, const num_flag *flags,
                           size_t nflags, int has_out) {
    printf("usage: %s\n%s\n", synopsis, about);
    for (size_t k = 0; k < nflags; ++k) {
        const num_flag *f = &flags[k];
        char range[96];
        flag_range(f, range, sizeof range);
        printf("  %-13s %s; allowed: %s%s\n", f->name, f->doc, range,
               f->required ? " (required)" : "");
    }
    if (has_out)
        printf("  %-13s output file, written atomically, or - for standard output (required)\n",
               "--out");
}

/* Parse "--name value" pairs into the table (and --out into *out_path when given); 0, -1
 * after --help (help printed), or an exit status. */
static int parse_num_flags(const char *cmd, int argc, char **argv, num_flag *flags, size_t nflags,
                           const char **out_path) {
    for (int i = 3; i < argc; ++i) {
        if (is_help(argv[i])) return -1;
        if (out_path && !strcmp(argv[i], "--out")) {
            if (!(*out_path = flag_value(cmd, argc, argv, &i, stderr))) return EXIT_INPUT;
            continue;
        }
        num_flag *f = NULL;
        for (size_t k = 0; k < nflags; ++k)
            if (!strcmp(argv[i], flags[k].name)) f = &flags[k];
        if (!f) {
            fprintf(stderr, "hsbd %s: unknown option '%.60s' (hsbd %s --help)\n", cmd, argv[i],
                    cmd);
            return EXIT_INPUT;
        }
        const char *text = flag_value(cmd, argc, argv, &i, stderr);
        if (!text) return EXIT_INPUT;
        char *end;
        const double v = strtod(text, &end);
        const int low_ok = f->open_min ? v > f->min : v >= f->min;
        const int high_ok = f->open_max ? v < f->max : v <= f->max;
        if (end == text || *end || !isfinite(v) || !low_ok || !high_ok) {
            char range[96];
            flag_range(f, range, sizeof range);
            fprintf(stderr, "hsbd %s: %s = '%.60s'; allowed: %s\n", cmd, f->name, text, range);
            return EXIT_INPUT;
        }
        *f->value = v;
        f->seen = 1;
    }
    for (size_t k = 0; k < nflags; ++k)
        if (flags[k].required && !flags[k].seen) {
            fprintf(stderr, "hsbd %s: %s is required (hsbd %s --help)\n", cmd, flags[k].name, cmd);
            return EXIT_INPUT;
        }
    if (out_path && !*out_path) {
        fprintf(stderr, "hsbd %s: --out FILE (or - for standard output) is required\n", cmd);
        return EXIT_INPUT;
    }
    return 0;
}

/* --out FILE (written atomically) or - (standard output), opened before the work so that
 * an unusable location is a bad input (exit 2) found at once */
static int open_theory_output(const char *cmd, const char *out, hsbd_outfile *o, FILE **f) {
    *f = stdout;
    if (!strcmp(out, "-")) return 0;
    struct stat st;
    const size_t len = strlen(out);
    const char *why = NULL;
    if (len == 0 || out[len - 1] == '/' || (stat(out, &st) == 0 && S_ISDIR(st.st_mode)))
        why = "it names a directory; allowed: a file name";
    else if (len >= HSBD_PATH_MAX)
        why = "the path is too long";
    char dir[HSBD_PATH_MAX], name[HSBD_PATH_MAX];
    const char *slash = strrchr(out, '/');
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - out) : 1, slash ? out : ".");
    snprintf(name, sizeof name, "%s", slash ? slash + 1 : out);
    hsbd_error err;
    if (!why && hsbd_outfile_open(o, slash == out ? "" : dir, name, &err) != HSBD_OK)
        why = strerror(errno);
    if (why) {
        fprintf(stderr, "hsbd %s: --out '%.200s': cannot write there: %s\n", cmd, out, why);
        return EXIT_INPUT;
    }
    *f = o->f;
    return 0;
}

/* Commit the theory output (a write error is exit 1), or discard it when rc != 0. */
static int close_theory_output(hsbd_outfile *o, FILE *f, int rc) {
    hsbd_error err;
    if (f == stdout) return rc;
    if (rc != 0) {
        hsbd_outfile_discard(o);
        return rc;
    }
    return hsbd_outfile_commit(o, &err) == HSBD_OK ? 0 : fail(err.status, err.message);
}

/* N rods between hard walls at 0 and L in cosine + tilt + harmonic fields: the exact
 * canonical profile (src/theory/box.c), bin averages. */
static int cmd_theory_box(int argc, char **argv) {
    double n = 0, length = 0, sigma = 0, u0 = 0, wavelength = 1, force = 0, stiffness = 0,
           center = NAN, bin = 0.01, points = 0;
    const char *out = NULL;
    num_flag flags[] = {
        {"--N", &n, 1, 1e7, 0, 0, 1, "number of rods (whole)", 0},
        {"--L", &length, 0, 1e300, 1, 1, 1, "distance between the walls", 0},
        {"--sigma", &sigma, 0, 1e300, 0, 1, 1, "rod length (N sigma < L)", 0},
        {"--amplitude", &u0, -1e6, 1e6, 0, 0, 0, "cosine amplitude U0 in kT (default 0)", 0},
        {"--wavelength", &wavelength, 0, 1e300, 1, 1, 0, "cosine wavelength (default 1)", 0},
        {"--force", &force, -1e6, 1e6, 0, 0, 0, "constant force in kT/length (default 0)", 0},
        {"--stiffness", &stiffness, 0, 1e6, 0, 0, 0, "harmonic trap stiffness (default 0)", 0},
        {"--center", &center, -1e300, 1e300, 0, 0, 0, "harmonic trap centre (default L/2)", 0},
        {"--bin", &bin, 0, 1e300, 1, 1, 0, "bin width of the profile (default 0.01)", 0},
        {"--points", &points, 16, 1e8, 0, 0, 0,
         "grid points (whole; default min(1e5, max(2000, 2e7/N)))", 0},
    };
    const size_t nflags = sizeof flags / sizeof flags[0];
    const int rc = parse_num_flags("theory box", argc, argv, flags, nflags, &out);
    if (rc < 0)
        num_flags_help(synopsis_box,
                       "The exact canonical density profile of N hard rods between hard walls "
                       "at 0 and L\nin cosine, tilt and harmonic fields, as bin averages "
                       "(columns x rho rho2; docs/theory.md).",
                       flags, nflags, 1);
    if (rc) return rc < 0 ? 0 : rc;
    if (n != floor(n) || points != floor(points) || !(n * sigma < length)) {
        fprintf(stderr, "hsbd theory box: need whole --N and --points, and N sigma < L\n");
        return EXIT_INPUT;
    }
    hsbd_outfile o = {0};
    FILE *f;
    if (open_theory_output("theory box", out, &o, &f)) return EXIT_INPUT;
    hsbd_field field = {0};
    if (u0 != 0) hsbd_field_add(&field, hsbd_field_cosine(u0, wavelength));
    if (force != 0) hsbd_field_add(&field, hsbd_field_tilt(force));
    if (stiffness > 0)
        hsbd_field_add(&field,
                       hsbd_field_harmonic(stiffness, isnan(center) ? 0.5 * length : center, 0.0));
    if (points == 0) points = fmin(1e5, fmax(2000, 2e7 / n)); /* memory N x points doubles */
    hsbd_box_params p = {.n = (size_t)n,
                         .length = length,
                         .sigma = sigma,
                         .field = &field,
                         .points = (size_t)points};
    hsbd_box_result r;
    hsbd_error err;
    const int st = hsbd_box_solve(&p, bin, &r, &err);
    if (st != HSBD_OK) return close_theory_output(&o, f, fail(st, err.message));
    fprintf(f,
            "# hsbd %s (git %s): N hard rods between hard walls, exact canonical profile "
            "(docs/theory.md), bin averages\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    fprintf(f,
            "# N = %zu\n# L = %.17g\n# sigma = %.17g\n# amplitude = %.17g\n# wavelength = %.17g\n"
            "# force = %.17g\n# stiffness = %.17g\n# center = %.17g\n# points = %zu\n"
            "# wall_left = %.12g\n# wall_right = %.12g\n",
            p.n, length, sigma, u0, wavelength, force, stiffness,
            isnan(center) ? 0.5 * length : center, p.points, r.wall_left, r.wall_right);
    fprintf(f, "x\trho\trho2\n");
    for (size_t k = 0; k < r.nbins; ++k)
        fprintf(f, "%.10g\t%.12g\t%.12g\n", (k + 0.5) * bin, r.rho[k], r.rho2[k]);
    hsbd_box_result_free(&r);
    return close_theory_output(&o, f, 0);
}

static int cmd_theory_percus(int argc, char **argv) {
    double sigma = 0, rho = 0, u0 = 0, gamma = 0, wavelength = 1, points = 2000;
    const char *out = NULL;
    num_flag flags[] = {
        {"--sigma", &sigma, 0, 1e300, 0, 1, 1, "rod length", 0},
        {"--rho", &rho, 0, 1e300, 1, 1, 1, "mean density (rho sigma < 1)", 0},
        {"--amplitude", &u0, 0, 1e6, 0, 0, 1, "cosine amplitude U0 in kT", 0},
        {"--gamma", &gamma, 0, 1e12, 0, 0, 0, "Baxter stickiness (default 0: hard rods)", 0},
        {"--wavelength", &wavelength, 0, 1e300, 1, 1, 0, "cosine wavelength (default 1)", 0},
        {"--points", &points, 16, 1e8, 0, 0, 0, "grid points per wavelength (whole; default 2000)",
         0},
    };
    const size_t nflags = sizeof flags / sizeof flags[0];
    const int rc = parse_num_flags("theory percus", argc, argv, flags, nflags, &out);
    if (rc < 0)
        num_flags_help(synopsis_percus,
                       "The exact equilibrium profile of hard rods on a line in the cosine field "
                       "(Percus,\nAntonov Eqs. 20-23; sticky rods with --gamma, Eqs. 34), "
                       "columns x rho rho2.",
                       flags, nflags, 1);
    if (rc) return rc < 0 ? 0 : rc;
    if (!(rho * sigma < 1)) {
        fprintf(stderr,
                "hsbd theory percus: --rho %g with --sigma %g: need rho*sigma < 1 (no "
                "room); allowed: rho < %g\n",
                rho, sigma, 1 / sigma);
        return EXIT_INPUT;
    }
    if (points != floor(points)) {
        fprintf(stderr, "hsbd theory percus: --points must be a whole number\n");
        return EXIT_INPUT;
    }
    hsbd_outfile o = {0};
    FILE *f;
    if (open_theory_output("theory percus", out, &o, &f)) return EXIT_INPUT;
    hsbd_percus_params p = {.sigma = sigma,
                            .rho_mean = rho,
                            .amplitude = u0,
                            .wavelength = wavelength,
                            .gamma = gamma,
                            .points = (size_t)points};
    hsbd_percus_result r;
    hsbd_error err;
    const int st = hsbd_percus_solve(&p, &r, &err);
    if (st != HSBD_OK) return close_theory_output(&o, f, fail(st, err.message));
    fprintf(f, "# hsbd %s (git %s): Percus exact equilibrium profile%s\n", HSBD_VERSION_STRING,
            HSBD_GIT_COMMIT, gamma > 0 ? " (sticky, Antonov Eqs. 34)" : " (Antonov Eqs. 20-23)");
    fprintf(f,
            "# sigma = %.17g\n# rho_mean = %.17g\n# amplitude = %.17g\n# wavelength = %.17g\n"
            "# gamma = %.17g\n# points = %zu\n# beta_mu = %.15g\n# iterations = %d\n"
            "# residual = %.3g\n",
            sigma, rho, u0, wavelength, gamma, p.points, r.beta_mu, r.iterations, r.residual);
    if (gamma > 0) fprintf(f, "# rho2 is not available for gamma > 0 (nan)\n");
    fprintf(f, "x\trho\trho2\n");
    for (size_t j = 0; j < r.m; ++j)
        fprintf(f, "%.10g\t%.12g\t%.12g\n", r.x[j], r.rho[j], r.rho2[j]);
    hsbd_percus_result_free(&r);
    return close_theory_output(&o, f, 0);
}

/* One overdamped particle in U0/2 cos(2 pi x / lambda) - F x: the exact mean velocity
 * (Stratonovich) and D_eff (Reimann et al. 2001) at one tilt or over a grid of tilts, and
 * the adiabatically rocked drift for F(t) = F + F1 cos(omega t) (src/theory/washboard.c). */
static int cmd_theory_washboard(int argc, char **argv) {
    double u0 = 0, wavelength = 1, d = 1, kT = 1, force = NAN, fmin = NAN, fmax = NAN, nforces = 0,
           rocking = 0, tol = 1e-10;
    const char *out = NULL;
    num_flag flags[] = {
        {"--amplitude", &u0, -1e4, 1e4, 0, 0, 1, "cosine amplitude U0 (energy)", 0},
        {"--wavelength", &wavelength, 0, 1e300, 1, 1, 0, "wavelength lambda (default 1)", 0},
        {"--D", &d, 0, 1e300, 1, 1, 0, "diffusion coefficient (default 1)", 0},
        {"--kT", &kT, 0, 1e300, 1, 1, 0, "thermal energy (default 1)", 0},
        {"--force", &force, -1e6, 1e6, 0, 0, 0, "tilt F (energy/length); or a grid:", 0},
        {"--force-min", &fmin, -1e6, 1e6, 0, 0, 0, "first tilt of the grid", 0},
        {"--force-max", &fmax, -1e6, 1e6, 0, 0, 0, "last tilt of the grid", 0},
        {"--forces", &nforces, 2, 1e5, 0, 0, 0, "tilts in the grid (whole)", 0},
        {"--rocking", &rocking, 0, 1e6, 0, 0, 0,
         "F1: add the adiabatic drift of F(t) = F + F1 cos(omega t) (default 0: none)", 0},
        {"--tol", &tol, 1e-14, 1e-2, 0, 0, 0, "relative accuracy (default 1e-10)", 0},
    };
    const size_t nflags = sizeof flags / sizeof flags[0];
    const int rc = parse_num_flags("theory washboard", argc, argv, flags, nflags, &out);
    if (rc < 0)
        num_flags_help(synopsis_washboard,
                       "One overdamped Brownian particle in U(x) = (U0/2) cos(2 pi x / lambda) - "
                       "F x: the exact\nmean velocity (Stratonovich) and effective diffusion "
                       "coefficient D_eff (Reimann et al.,\nPRL 87, 010602 (2001)); columns force "
                       "velocity d_eff rel_error [velocity_rocking]\n(docs/theory.md). Critical "
                       "tilt: pi U0 / lambda.",
                       flags, nflags, 1);
    if (rc) return rc < 0 ? 0 : rc;
    const int grid = !isnan(fmin) || !isnan(fmax) || nforces > 0;
    if (grid == !isnan(force) || (grid && (isnan(fmin) || isnan(fmax) || nforces == 0)) ||
        nforces != floor(nforces) || (grid && !(fmax > fmin))) {
        fprintf(stderr, "hsbd theory washboard: give --force F, or --force-min A --force-max B "
                        "--forces K with A < B and K whole (not both)\n");
        return EXIT_INPUT;
    }
    hsbd_outfile o = {0};
    FILE *f;
    if (open_theory_output("theory washboard", out, &o, &f)) return EXIT_INPUT;
    hsbd_field field = {0};
    hsbd_field_add(&field, hsbd_field_cosine(u0, wavelength));
    hsbd_washboard_params p = {
        .diffusion = d, .kT = kT, .period = wavelength, .field = &field, .tol = tol};
    const size_t nf = grid ? (size_t)nforces : 1;
    fprintf(f,
            "# hsbd %s (git %s): one particle in a tilted cosine, exact stationary drift and "
            "D_eff (docs/theory.md)\n# amplitude = %.17g\n# wavelength = %.17g\n# D = %.17g\n"
            "# kT = %.17g\n# critical_force = %.17g\n# rocking = %.17g\n",
            HSBD_VERSION_STRING, HSBD_GIT_COMMIT, u0, wavelength, d, kT,
            3.141592653589793 * fabs(u0) / wavelength, rocking);
    fprintf(f, "force\tvelocity\td_eff\trel_error%s\n", rocking > 0 ? "\tvelocity_rocking" : "");
    for (size_t k = 0; k < nf; ++k) {
        p.force = grid ? fmin + (fmax - fmin) * (double)k / (double)(nf - 1) : force;
        hsbd_washboard_result r;
        hsbd_error err;
        int st = hsbd_washboard_solve(&p, &r, &err);
        if (st != HSBD_OK) return close_theory_output(&o, f, fail(st, err.message));
        fprintf(f, "%.10g\t%.15g\t%.15g\t%.3g", p.force, r.velocity, r.diffusion_eff, r.error);
        hsbd_washboard_result_free(&r);
        if (rocking > 0) {
            hsbd_washboard_rocking_result rr;
            st = hsbd_washboard_rocking(&p, p.force, rocking, &rr, &err);
            if (st != HSBD_OK) return close_theory_output(&o, f, fail(st, err.message));
            fprintf(f, "\t%.15g", rr.velocity);
        }
        fputc('\n', f);
    }
    return close_theory_output(&o, f, 0);
}

static int cmd_theory_tonks(int argc, char **argv) {
    double sigma = 0, rho = 0, gamma = 0, d = 1;
    num_flag flags[] = {
        {"--sigma", &sigma, 0, 1e300, 0, 1, 1, "rod length", 0},
        {"--rho", &rho, 0, 1e300, 1, 1, 1, "density (rho sigma < 1)", 0},
        {"--gamma", &gamma, 0, 1e12, 0, 0, 0, "Baxter stickiness (default 0)", 0},
        {"--D", &d, 0, 1e300, 1, 1, 0, "diffusion coefficient (default 1)", 0},
    };
    const size_t nflags = sizeof flags / sizeof flags[0];
    const int rc = parse_num_flags("theory tonks", argc, argv, flags, nflags, NULL);
    if (rc < 0)
        num_flags_help(synopsis_tonks,
                       "Closed forms of the homogeneous hard-rod fluid (Tonks gas; sticky with "
                       "--gamma):\npressure, chemical potential, contact density and the "
                       "single-file MSD\nprefactor, on standard output.",
                       flags, nflags, 0);
    if (rc) return rc < 0 ? 0 : rc;
    if (!(rho * sigma < 1)) {
        fprintf(stderr, "hsbd theory tonks: need rho*sigma < 1; allowed: rho < %g\n", 1 / sigma);
        return EXIT_INPUT;
    }
    const double pi = 3.141592653589793;
    printf("# homogeneous hard rods, sigma = %g, rho = %g (packing %g), kT = 1\n", sigma, rho,
           rho * sigma);
    printf("beta_P = %.15g\n", hsbd_tonks_pressure(rho, sigma));
    printf("beta_mu = %.15g\n", hsbd_tonks_beta_mu(rho, sigma));
    printf("contact_density = %.15g\n", hsbd_tonks_contact(rho, sigma));
    printf("g_contact = %.15g\n", 1.0 / (1.0 - rho * sigma));
    printf("single_file_msd_prefactor = %.15g   # MSD -> prefactor * sqrt(t), D = %g\n",
           (1 - rho * sigma) / rho * sqrt(4 * d / pi), d);
    if (gamma > 0) {
        printf("sticky_gamma = %g\n", gamma);
        printf("sticky_beta_P = %.15g\n", hsbd_sticky_pressure(rho, sigma, gamma));
        printf("sticky_beta_mu = %.15g\n", hsbd_sticky_beta_mu(rho, sigma, gamma));
    }
    return 0;
}

static void validate_help(void) {
    printf("usage: %s\n"
           "Simulations of the validation grid against exact theory; prints the table and\n"
           "writes DIR/validation.tsv and DIR/validation.md (docs/validation.md).\n"
           "  --quick          15 short cases in about 4 minutes on 2 cores: three Percus\n"
           "                   cases, one sticky, Tonks, single file, and nine of hard\n"
           "                   spheres and disks (without --quick: the whole grid, far longer)\n"
           "  --list           print the names of the cases, run nothing\n"
           "  --dt-scan        add the time-step convergence cases\n"
           "  --sticky         the paper's sticky contact rule instead of reflect\n"
           "  --out DIR        run directory of the cases (default runs/validate)\n"
           "  --case TEXT      only the cases whose name contains TEXT\n"
           "  --jobs N         simulations in parallel (default 2; 1 <= N <= 64)\n"
           "  --seed-offset K  added to every seed: the same grid with other noise (0 <= K "
           "<= 1000000)\n"
           "Exit status: 0 every case passes, 1 a case fails, 2 bad input.\n",
           synopsis_validate);
}

/* a whole number in [lo, hi] from a flag's value; -1 after a message otherwise */
static long whole_flag(const char *cmd, const char *flag, const char *text, long lo, long hi) {
    char *end;
    errno = 0;
    const long v = strtol(text, &end, 10);
    if (end == text || *end || errno == ERANGE || v < lo || v > hi) {
        fprintf(stderr, "hsbd %s: %s = '%.60s'; allowed: %ld <= %s <= %ld (whole)\n", cmd, flag,
                text, lo, flag + 2, hi);
        return -1;
    }
    return v;
}

static int cmd_validate(int argc, char **argv) {
    hsbd_validate_options opt = {.out_dir = "runs/validate", .jobs = 2};
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i], *v = NULL;
        const int takes_value = !strcmp(a, "--out") || !strcmp(a, "--case") ||
                                !strcmp(a, "--jobs") || !strcmp(a, "--seed-offset");
        if (takes_value && !(v = flag_value("validate", argc, argv, &i, stderr))) return EXIT_INPUT;
        long w = 0;
        if (is_help(a)) {
            validate_help();
            return 0;
        } else if (!strcmp(a, "--quick")) {
            opt.quick = 1;
        } else if (!strcmp(a, "--list")) {
            opt.list = 1;
        } else if (!strcmp(a, "--dt-scan")) {
            opt.dt_scan = 1;
        } else if (!strcmp(a, "--sticky")) {
            opt.sticky = 1;
        } else if (!strcmp(a, "--out")) {
            opt.out_dir = v;
        } else if (!strcmp(a, "--case")) {
            opt.only = v;
        } else if (!strcmp(a, "--jobs")) {
            if ((w = whole_flag("validate", a, v, 1, 64)) < 0) return EXIT_INPUT;
            opt.jobs = (int)w;
        } else if (!strcmp(a, "--seed-offset")) {
            if ((w = whole_flag("validate", a, v, 0, 1000000)) < 0) return EXIT_INPUT;
            opt.seed_offset = (unsigned)w;
        } else {
            fprintf(stderr, "hsbd validate: unknown option '%.60s' (hsbd validate --help)\n", a);
            return EXIT_INPUT;
        }
    }
    hsbd_error err;
    const int rc = hsbd_validate(&opt, stdout, &err);
    if (rc != HSBD_OK) return fail(rc, err.message);
    printf("all cases pass; table in %s/validation.md\n", opt.out_dir);
    return 0;
}

static int cmd_theory(int argc, char **argv) {
    if (argc >= 3 && !strcmp(argv[2], "percus")) return cmd_theory_percus(argc, argv);
    if (argc >= 3 && !strcmp(argv[2], "tonks")) return cmd_theory_tonks(argc, argv);
    if (argc >= 3 && !strcmp(argv[2], "box")) return cmd_theory_box(argc, argv);
    if (argc >= 3 && !strcmp(argv[2], "washboard")) return cmd_theory_washboard(argc, argv);
    if (argc >= 3 && is_help(argv[2])) {
        printf("usage: %s       %s       %s       %s", synopsis_percus, synopsis_tonks,
               synopsis_box, synopsis_washboard);
        return 0;
    }
    if (argc >= 3)
        fprintf(stderr,
                "hsbd theory: unknown theory '%.60s'; allowed: percus, tonks, box, washboard "
                "(hsbd theory --help)\n",
                argv[2]);
    else
        fprintf(stderr, "hsbd theory: which theory? allowed: percus, tonks, box, "
                        "washboard (hsbd theory --help)\n");
    return EXIT_INPUT;
}

/* The command line's first checks: a command, and no argument with a control character
 * (messages quote arguments: one line each). 0, or EXIT_INPUT after the message to msg. */
static int command_line_check(int argc, char **argv, FILE *msg) {
    const char *cmd = argc > 1 ? argv[1] : NULL;
    for (int i = 1; i < argc; ++i)
        for (const char *p = argv[i]; *p; ++p)
            if (((unsigned char)*p < 0x20 && *p != '\t') || *p == 0x7f) {
                const int after_flag = i > 1 && !strncmp(argv[i - 1], "--", 2);
                fprintf(msg,
                        "hsbd: argument %d%s%s%s has a control character (0x%02x at "
                        "position %d); allowed: text\n",
                        i, after_flag ? " (the value of " : "", after_flag ? argv[i - 1] : "",
                        after_flag ? ")" : "", (unsigned)(unsigned char)*p, (int)(p - argv[i]) + 1);
                return EXIT_INPUT;
            }
    static const char *const known[] = {"run",      "resume",     "merge",   "bench",     "theory",
                                        "validate", "config-doc", "version", "--version", "help",
                                        "--help",   "-h",         NULL};
    for (const char *const *k = known; cmd && *k; ++k)
        if (!strcmp(cmd, *k)) return 0;
    if (cmd) fprintf(msg, "hsbd: unknown command '%s'\n", cmd);
    usage(msg);
    return EXIT_INPUT;
}

/* The commands that run on the ranks of mpirun together; the others (bench, theory,
 * validate, ...) run in each process on its own, once the ranks agreed on the command
 * line. */
static int mpi_command(const char *cmd) {
    return !strcmp(cmd, "run") || !strcmp(cmd, "resume") || !strcmp(cmd, "merge");
}

/* Under mpirun, ranks given different commands: EXIT_INPUT after rank 0's message, else 0.
 * A collective. */
static int ranks_same_command(const ranks *r, const char *cmd) {
#ifdef HSBD_HAVE_MPI
    if (!r->mpi) return 0;
    uint64_t *keys = gather_keys(r, text_key(cmd));
    int b = 0; /* the first rank given another command than rank 0 */
    for (int k = 1; keys && k < r->size && !b; ++k)
        if (keys[k] != keys[0]) b = k;
    free(keys);
    if (b && r->rank == 0)
        fprintf(stderr,
                "hsbd: ranks 0 and %d of mpirun were given different commands (every rank runs "
                "the same hsbd run, resume or merge)\n",
                b);
    return b ? EXIT_INPUT : 0;
#else
    (void)r, (void)cmd;
    return 0;
#endif
}

static int cmd_config_doc(int argc, char **argv) {
    if (argc > 2 && is_help(argv[2])) {
        printf("usage: hsbd config-doc\nPrints the configuration reference (Markdown, the "
               "text of docs/config.md).\n");
        return 0;
    }
    if (argc > 2) {
        fprintf(stderr, "hsbd config-doc: unexpected argument '%.60s'\n", argv[2]);
        return EXIT_INPUT;
    }
    hsbd_config_write_reference(stdout, 1);
    return 0;
}

/* A checked command line's command (the ranks given to those that run on all of them). */
static int run_command(const ranks *r, int argc, char **argv) {
    const char *cmd = argv[1];
    if (!strcmp(cmd, "run")) return cmd_run(r, argc, argv);
    if (!strcmp(cmd, "resume")) return cmd_resume(r, argc, argv);
    if (!strcmp(cmd, "merge")) return cmd_merge(r, argc, argv);
    if (!strcmp(cmd, "bench")) return cmd_bench(argc, argv);
    if (!strcmp(cmd, "theory")) return cmd_theory(argc, argv);
    if (!strcmp(cmd, "validate")) return cmd_validate(argc, argv);
    if (!strcmp(cmd, "config-doc")) return cmd_config_doc(argc, argv);
    if (!strcmp(cmd, "version") || !strcmp(cmd, "--version")) {
        printf("hsbd %s (git %s)\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
        printf("built with:%s%s\n", HSBD_WITH_MPI ? " mpi (replicas over mpirun ranks)" : " no mpi",
               HSBD_WITH_OPENMP ? ", openmp (threads)" : ", no openmp");
        return 0;
    }
    usage(stdout); /* help, --help, -h */
    return 0;
}

/* GNU-style "--name=value" as "--name" "value" (users type --threads=2, --out=DIR,
 * --set=key=value); every other argument as it is. A new array (freed at exit), or NULL. */
static char **split_gnu_options(int argc, char **argv, int *out_argc) {
    char **out = malloc((2 * (size_t)argc + 1) * sizeof *out);
    if (!out) return NULL;
    int n = 0;
    for (int i = 0; i < argc; ++i) {
        const char *eq = i > 0 && !strncmp(argv[i], "--", 2) ? strchr(argv[i], '=') : NULL;
        const char *p = argv[i] + 2;
        while (eq && p < eq && (isalnum((unsigned char)*p) || *p == '-'))
            ++p;
        if (eq && p == eq && eq > argv[i] + 2) {
            *(char *)eq = '\0'; /* argv's strings are the program's to change */
            out[n++] = argv[i];
            out[n++] = (char *)eq + 1;
        } else {
            out[n++] = argv[i];
        }
    }
    out[n] = NULL;
    *out_argc = n;
    return out;
}

int main(int argc, char **argv) {
    /* under mpirun every rank takes part in MPI until the ranks agree on the command line:
     * one refused on any rank stops all, its message printed once, and so do different
     * commands where one of them is run, resume or merge (which wait for each other);
     * the other commands then run in each process on its own */
    char **split = split_gnu_options(argc, argv, &argc);
    if (!split) {
        fprintf(stderr, "hsbd: out of memory\n");
        return EXIT_FAILURE;
    }
    argv = split;
    ranks r = ranks_begin();
    input_messages said;
    FILE *msg = input_messages_open(&r, &said);
    int code = input_messages_report(&r, &said, command_line_check(argc, argv, msg));
    if (code == 0 && ranks_lowest(&r, mpi_command(argv[1])) >= 0)
        code = ranks_same_command(&r, argv[1]);
    if (code == 0 && !mpi_command(argv[1])) {
        ranks_end(&r);
        r = (ranks){0, 1, 0};
    }
    if (code == 0) code = run_command(&r, argc, argv);
    ranks_end(&r);
    free(split);
    return code;
}
