/* hsbd: the command line. Commands: run, resume, merge (apps/cmd_run.c), bench, theory,
 * validate, config-doc, version; each takes --help. Here: the dispatch, GNU-style
 * --name=value options, the help, and what the commands share (cli.h). */
#include "cli.h"

#include <ctype.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/config.h"
#include "hsbd_version.h"

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

/* ---- shared by the commands (cli.h) ------------------------------------------------------ */

volatile sig_atomic_t cli_stop = 0;

static void on_signal(int sig) {
    if (cli_stop) {
        signal(sig, SIG_DFL);
        raise(sig);
    }
    cli_stop = sig;
}

void cli_catch_stop_signals(void) {
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    signal(SIGHUP, on_signal);
}

int cli_exit_code(int status) {
    switch (status) {
    case HSBD_OK:
        return 0;
    case HSBD_EINPUT:
        return EXIT_INPUT;
    case HSBD_EINTERRUPT:
        return cli_stop ? 128 + (int)cli_stop : EXIT_INTERRUPTED;
    default:
        return 1;
    }
}

int cli_fail(int status, const char *msg) {
    fprintf(stderr, "hsbd: %s\n", msg);
    return cli_exit_code(status);
}

int cli_is_help(const char *arg) {
    return !strcmp(arg, "--help") || !strcmp(arg, "-h");
}

int cli_asks_help(int argc, char **argv, const char *const *value_flags) {
    for (int i = 2; i < argc; ++i) {
        if (cli_is_help(argv[i])) return 1;
        for (const char *const *f = value_flags; *f; ++f)
            if (!strcmp(argv[i], *f)) {
                ++i; /* its value, whatever it is */
                break;
            }
    }
    return 0;
}

const char *cli_flag_value(const char *cmd, int argc, char **argv, int *i, FILE *msg) {
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

/* ---- the front ---------------------------------------------------------------------------- */

static void usage(FILE *out) {
    cmd_run_synopses(out);
    cmd_bench_synopsis(out);
    cmd_theory_synopses(out);
    cmd_validate_synopsis(out);
    fprintf(out, "       hsbd config-doc                 print the configuration reference "
                 "(Markdown)\n"
                 "       hsbd version\n"
                 "Every subcommand takes --help.\n");
}

static int cmd_config_doc(int argc, char **argv) {
    if (argc > 2 && cli_is_help(argv[2])) {
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

static int cmd_version(int argc, char **argv) {
    (void)argc, (void)argv;
    printf("hsbd %s (git %s)\n", HSBD_VERSION_STRING, HSBD_GIT_COMMIT);
    printf("built with:%s%s\n", HSBD_WITH_MPI ? " mpi (replicas over mpirun ranks)" : " no mpi",
           HSBD_WITH_OPENMP ? ", openmp (threads)" : ", no openmp");
    return 0;
}

static int cmd_help(int argc, char **argv) {
    (void)argc, (void)argv;
    usage(stdout);
    return 0;
}

static const struct command {
    const char *name;
    int (*run)(int argc, char **argv);
} commands[] = {
    {"run", cmd_run},
    {"resume", cmd_resume},
    {"merge", cmd_merge},
    {"bench", cmd_bench},
    {"theory", cmd_theory},
    {"validate", cmd_validate},
    {"config-doc", cmd_config_doc},
    {"version", cmd_version},
    {"--version", cmd_version},
    {"help", cmd_help},
    {"--help", cmd_help},
    {"-h", cmd_help},
};

/* The command of the command line, after its first checks: a known command, and no argument
 * with a control character (messages quote arguments: one line each); NULL after the
 * message to msg otherwise. */
static const struct command *command_of(int argc, char **argv, FILE *msg) {
    for (int i = 1; i < argc; ++i)
        for (const char *p = argv[i]; *p; ++p)
            if (((unsigned char)*p < 0x20 && *p != '\t') || *p == 0x7f) {
                const int after_flag = i > 1 && !strncmp(argv[i - 1], "--", 2);
                fprintf(msg,
                        "hsbd: argument %d%s%s%s has a control character (0x%02x at "
                        "position %d); allowed: text\n",
                        i, after_flag ? " (the value of " : "", after_flag ? argv[i - 1] : "",
                        after_flag ? ")" : "", (unsigned)(unsigned char)*p, (int)(p - argv[i]) + 1);
                return NULL;
            }
    for (size_t k = 0; argc > 1 && k < sizeof commands / sizeof commands[0]; ++k)
        if (!strcmp(argv[1], commands[k].name)) return &commands[k];
    if (argc > 1) fprintf(msg, "hsbd: unknown command '%s'\n", argv[1]);
    usage(msg);
    return NULL;
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
    char **split = split_gnu_options(argc, argv, &argc);
    if (!split) {
        fprintf(stderr, "hsbd: out of memory\n");
        return EXIT_FAILURE;
    }
    /* under mpirun every rank meets the same command line: rank 0 says what is wrong */
    FILE *quiet = ranks_own_rank() > 0 ? fopen("/dev/null", "w") : NULL;
    const struct command *cmd = command_of(argc, split, quiet ? quiet : stderr);
    if (quiet) fclose(quiet);
    const int code = cmd ? cmd->run(argc, split) : EXIT_INPUT;
    free(split);
    return code;
}
