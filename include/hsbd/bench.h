/* Throughput benchmarks of the engines against the free-particle bound (hsbd bench,
 * make bench; bench/RESULTS.md). */
#ifndef HSBD_BENCH_H
#define HSBD_BENCH_H

#include "hsbd/export.h"
#include <stdio.h>

/* The names of the cases, one per line. */
HSBD_API void hsbd_bench_list(FILE *out);
/* Is there a case of this name? */
HSBD_API int hsbd_bench_has_case(const char *name);
/* Runs every case (or only the named one), `seconds` per case and variant, printing a
 * table to out. */
HSBD_API void hsbd_bench_run(const char *only, double seconds, FILE *out);
/* The rods cases of N >= 10^4 on one thread and on all the process may use (wall clock). */
HSBD_API void hsbd_bench_threads(const char *only, double seconds, FILE *out);

#endif
