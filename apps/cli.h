/* What the commands of the hsbd command line share (apps/): exit codes, the stop signals,
 * flags, the synopses of `hsbd --help`, and the ranks of mpirun (apps/mpi.c). */
#ifndef HSBD_APPS_CLI_H
#define HSBD_APPS_CLI_H

#include <signal.h>
#include <stdio.h>

#include "hsbd/error.h"

enum { EXIT_INPUT = 2, EXIT_INTERRUPTED = 130 };

/* Set by SIGINT, SIGTERM or SIGHUP (to its number) once cli_catch_stop_signals ran: a run
 * then writes a checkpoint and its results so far; a second signal ends it at once. */
extern volatile sig_atomic_t cli_stop;
void cli_catch_stop_signals(void);
/* The exit status of a library status: 0, 2 bad input, 128 + the signal when stopped, 1. */
int cli_exit_code(int status);
/* "hsbd: msg" on stderr; the exit status of status. */
int cli_fail(int status, const char *msg);
int cli_is_help(const char *arg);
/* --help or -h after the command, but as the value of one of value_flags (NULL-ended). */
int cli_asks_help(int argc, char **argv, const char *const *value_flags);
/* The value of the flag argv[*i], advancing *i; NULL after a message to msg when nothing
 * follows or the next argument is itself a flag (write ./--name for such a file). */
const char *cli_flag_value(const char *cmd, int argc, char **argv, int *i, FILE *msg);

/* The commands: argv[1] is the command's name. Each returns its exit status. */
int cmd_run(int argc, char **argv);
int cmd_resume(int argc, char **argv);
int cmd_merge(int argc, char **argv);
int cmd_bench(int argc, char **argv);
int cmd_theory(int argc, char **argv);
int cmd_validate(int argc, char **argv);
/* The synopses of `hsbd --help`. */
void cmd_run_synopses(FILE *out);
void cmd_bench_synopsis(FILE *out);
void cmd_theory_synopses(FILE *out);
void cmd_validate_synopsis(FILE *out);

/* ---- the ranks of mpirun (apps/mpi.c; docs/scaling.md) ------------------------------------
 * Only `hsbd run` takes part in MPI: rank 0 reads and checks the input and shares it, the
 * replicas of an ensemble are spread over the ranks, and rank 0 merges them. */
typedef struct ranks {
    int rank, size;
    int mpi; /* MPI was initialised (started by mpirun) */
} ranks;

/* This process's rank of mpirun from the launcher's environment, without MPI (0 when not
 * started by mpirun): `hsbd resume` and `hsbd merge` run on rank 0 only. */
int ranks_own_rank(void);
/* MPI initialised when started by mpirun (so plain runs never pay for it): this process's
 * rank and the number of ranks; {0, 1} otherwise. */
ranks ranks_begin(void);
/* Every rank waits (asleep) for the others, then leaves MPI. */
void ranks_end(const ranks *r);
/* Rank 0's *len bytes at *buf to every rank (the others get a new buffer, or NULL when out
 * of memory: their job is aborted). A collective. */
void ranks_share(const ranks *r, void **buf, size_t *len);
/* After a command on every rank, with its status and message: rank 0 prints each distinct
 * message of a failure once (naming ranks above 0) and returns the worst status over the
 * ranks; the others print nothing and return their own. A collective. */
int ranks_gather_failures(const ranks *r, int status, hsbd_error *err);
/* Rank 0's value, given to every rank. A collective. */
int ranks_rank0_value(const ranks *r, int value);
/* The default thread count of a rank that works (or waits: working 0) under mpirun: its
 * share of its node's CPUs, unless run.threads or OMP_NUM_THREADS set it. A collective. */
void ranks_share_threads(const ranks *r, int working);

#endif
