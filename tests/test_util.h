/* Minimal assertion helpers: every CHECK can fail, and failures are counted, printed
 * with file and line, and turned into a non-zero exit status. */
#ifndef HSBD_TEST_UTIL_H
#define HSBD_TEST_UTIL_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int test_failures = 0;
static int test_checks = 0;

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        ++test_checks;                                                                             \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "%s:%d: CHECK(%s) failed: ", __FILE__, __LINE__, #cond);               \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fputc('\n', stderr);                                                                   \
            ++test_failures;                                                                       \
        }                                                                                          \
    } while (0)

#define CHECK_CLOSE(a, b, tol)                                                                     \
    CHECK(fabs((double)(a) - (double)(b)) <= (tol), "%s = %.17g, %s = %.17g, |diff| = %.3g > %g",  \
          #a, (double)(a), #b, (double)(b), fabs((double)(a) - (double)(b)), (double)(tol))

static inline int test_finish(const char *name) {
    printf("%s: %d checks, %d failed\n", name, test_checks, test_failures);
    return test_failures ? 1 : 0;
}

#endif
