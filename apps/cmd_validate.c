/* hsbd validate: simulations of the validation grid against exact theory
 * (docs/validation.md). */
#include "cli.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "hsbd/validate.h"

static const char *const synopsis_validate =
    "hsbd validate [--quick] [--dt-scan] [--sticky] [--out DIR] [--case TEXT]\n"
    "                     [--jobs N] [--seed-offset K] [--list]\n"
    "                                       simulations against exact theory\n";

void cmd_validate_synopsis(FILE *out) {
    fprintf(out, "       %s", synopsis_validate);
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
static long whole_flag(const char *flag, const char *text, long lo, long hi) {
    char *end;
    errno = 0;
    const long v = strtol(text, &end, 10);
    if (end != text && !*end && errno != ERANGE && v >= lo && v <= hi) return v;
    fprintf(stderr, "hsbd validate: %s = '%.60s'; allowed: %ld <= %s <= %ld (whole)\n", flag, text,
            lo, flag + 2, hi);
    return -1;
}

/* One option of the command line into opt (v: its value, for those that take one); 0, 1
 * after --help, or an exit status. */
static int validate_option(const char *a, const char *v, hsbd_validate_options *opt) {
    if (cli_is_help(a)) return validate_help(), 1;
    if (!strcmp(a, "--jobs") || !strcmp(a, "--seed-offset")) {
        const int jobs = !strcmp(a, "--jobs");
        const long w = whole_flag(a, v, jobs ? 1 : 0, jobs ? 64 : 1000000);
        if (w < 0) return EXIT_INPUT;
        if (jobs)
            opt->jobs = (int)w;
        else
            opt->seed_offset = (unsigned)w;
    } else if (!strcmp(a, "--quick")) {
        opt->quick = 1;
    } else if (!strcmp(a, "--list")) {
        opt->list = 1;
    } else if (!strcmp(a, "--dt-scan")) {
        opt->dt_scan = 1;
    } else if (!strcmp(a, "--sticky")) {
        opt->sticky = 1;
    } else if (!strcmp(a, "--out")) {
        opt->out_dir = v;
    } else if (!strcmp(a, "--case")) {
        opt->only = v;
    } else {
        fprintf(stderr, "hsbd validate: unknown option '%.60s' (hsbd validate --help)\n", a);
        return EXIT_INPUT;
    }
    return 0;
}

int cmd_validate(int argc, char **argv) {
    hsbd_validate_options opt = {.out_dir = "runs/validate", .jobs = 2};
    for (int i = 2; i < argc; ++i) {
        const char *a = argv[i], *v = NULL;
        const int takes_value = !strcmp(a, "--out") || !strcmp(a, "--case") ||
                                !strcmp(a, "--jobs") || !strcmp(a, "--seed-offset");
        if (takes_value && !(v = cli_flag_value("validate", argc, argv, &i, stderr)))
            return EXIT_INPUT;
        const int rc = validate_option(a, v, &opt);
        if (rc) return rc == 1 ? 0 : rc;
    }
    hsbd_error err;
    const int rc = hsbd_validate(&opt, stdout, &err);
    if (rc != HSBD_OK) return cli_fail(rc, err.message);
    printf("all cases pass; table in %s/validation.md\n", opt.out_dir);
    return 0;
}
