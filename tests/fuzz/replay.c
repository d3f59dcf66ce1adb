/* Replays fuzz inputs through a harness's LLVMFuzzerTestOneInput without libFuzzer, so
 * that the corpora run under CTest in every build (optimised, and AddressSanitizer +
 * UBSan): a crash found once stays fixed. Usage: replay_<target> MAX_SECONDS PATH...
 * (files, or directories whose files are read in name order). Fails when an input takes
 * more than MAX_SECONDS of CPU time; prints how many inputs ran and the slowest. */
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

typedef struct replay_stats {
    size_t inputs;
    double slowest, max_seconds;
    char slowest_name[1024];
    int failed;
} replay_stats;

static void replay_file(const char *path, replay_stats *st) {
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "replay: cannot read '%s'\n", path);
        st->failed = 1;
        return;
    }
    size_t cap = 4096, len = 0;
    uint8_t *data = malloc(cap);
    for (size_t got; data && (got = fread(data + len, 1, cap - len, f)) > 0;) {
        len += got;
        if (len == cap) {
            uint8_t *bigger = realloc(data, cap *= 2);
            if (!bigger) free(data);
            data = bigger;
        }
    }
    fclose(f);
    if (!data) {
        fprintf(stderr, "replay: out of memory for '%s'\n", path);
        st->failed = 1;
        return;
    }
    const clock_t start = clock();
    LLVMFuzzerTestOneInput(data, len);
    const double seconds = (double)(clock() - start) / CLOCKS_PER_SEC;
    free(data);
    st->inputs++;
    if (seconds > st->slowest) {
        st->slowest = seconds;
        snprintf(st->slowest_name, sizeof st->slowest_name, "%s", path);
    }
    if (seconds > st->max_seconds) {
        fprintf(stderr, "replay: '%s' took %.2f s of CPU time; allowed: %g s\n", path, seconds,
                st->max_seconds);
        st->failed = 1;
    }
}

static int by_name(const struct dirent **a, const struct dirent **b) {
    return strcmp((*a)->d_name, (*b)->d_name);
}

static void replay_path(const char *path, replay_stats *st) {
    struct stat info;
    if (stat(path, &info) != 0 || !S_ISDIR(info.st_mode)) {
        replay_file(path, st);
        return;
    }
    struct dirent **names;
    const int n = scandir(path, &names, NULL, by_name);
    if (n < 0) {
        fprintf(stderr, "replay: cannot list '%s'\n", path);
        st->failed = 1;
        return;
    }
    for (int k = 0; k < n; ++k) {
        char file[4096];
        snprintf(file, sizeof file, "%s/%s", path, names[k]->d_name);
        if (names[k]->d_name[0] != '.' && stat(file, &info) == 0 && S_ISREG(info.st_mode))
            replay_file(file, st);
        free(names[k]);
    }
    free(names);
}

int main(int argc, char **argv) {
    if (argc < 3) {
        fprintf(stderr, "usage: %s MAX_SECONDS PATH...\n", argv[0]);
        return 2;
    }
    replay_stats st = {.max_seconds = atof(argv[1])};
    for (int k = 2; k < argc; ++k)
        replay_path(argv[k], &st);
    printf("replay: %zu inputs, slowest %.3f s (%s)\n", st.inputs, st.slowest,
           st.inputs ? st.slowest_name : "-");
    if (st.inputs == 0) {
        fprintf(stderr, "replay: no inputs\n");
        return 1;
    }
    return st.failed;
}
