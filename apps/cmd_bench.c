/* hsbd bench: the throughput of the engines (bench/README.md). */
#include "cli.h"

#include <stdlib.h>
#include <string.h>

#include "hsbd/bench.h"

static const char *const synopsis_bench =
    "hsbd bench [--seconds S] [--case NAME] [--list] [--threads]\n"
    "                                       throughput, with the free-particle bound\n";

void cmd_bench_synopsis(FILE *out) {
    fprintf(out, "       %s", synopsis_bench);
}

static void bench_help(void) {
    printf("usage: %s\n"
           "  --seconds S   measuring time per case and variant (default 2; 0 < S < 3600)\n"
           "  --case NAME   only this case\n"
           "  --list        print the names of the cases and exit\n"
           "  --threads     rods: one thread against all the process may use (wall\n"
           "                clock) instead of the one-core tables\n",
           synopsis_bench);
}

/* --seconds S: 0, or EXIT_INPUT after a message */
static int seconds_value(const char *v, double *seconds) {
    char *end;
    *seconds = strtod(v, &end);
    if (end != v && !*end && *seconds > 0 && *seconds < 3600) return 0;
    fprintf(stderr, "hsbd bench: --seconds = '%.60s'; allowed: 0 < S < 3600\n", v);
    return EXIT_INPUT;
}

int cmd_bench(int argc, char **argv) {
    double seconds = 2.0;
    int threads = 0;
    const char *only = NULL, *v;
    for (int i = 2; i < argc; ++i) {
        if (cli_is_help(argv[i])) return bench_help(), 0;
        if (!strcmp(argv[i], "--list")) return hsbd_bench_list(stdout), 0;
        if (!strcmp(argv[i], "--threads")) {
            threads = 1;
        } else if (!strcmp(argv[i], "--seconds")) {
            if (!(v = cli_flag_value("bench", argc, argv, &i, stderr)) ||
                seconds_value(v, &seconds))
                return EXIT_INPUT;
        } else if (!strcmp(argv[i], "--case")) {
            if (!(only = cli_flag_value("bench", argc, argv, &i, stderr))) return EXIT_INPUT;
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
