/* The ranks of mpirun (see cli.h, docs/scaling.md). Only the CLI talks to MPI, and only
 * `hsbd run`: rank 0 shares the checked input, every rank reports its end to rank 0. */
#define _GNU_SOURCE /* sched_getaffinity: the CPUs of a rank */
#include "cli.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#ifdef HSBD_HAVE_MPI
#include <mpi.h>
#include <sched.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

int ranks_own_rank(void) {
    static const char *const names[] = {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"};
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k)
        if (getenv(names[k])) return atoi(getenv(names[k]));
    return 0;
}

ranks ranks_begin(void) {
    ranks r = {0, 1, 0};
#ifdef HSBD_HAVE_MPI
    const int launched =
        getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMI_SIZE") || getenv("PMIX_RANK");
    if (launched && MPI_Init(NULL, NULL) == MPI_SUCCESS) {
        r.mpi = 1;
        MPI_Comm_rank(MPI_COMM_WORLD, &r.rank);
        MPI_Comm_size(MPI_COMM_WORLD, &r.size);
    }
#endif
    return r;
}

#ifdef HSBD_HAVE_MPI
/* Waits for a non-blocking collective (`started`: the status of the call that started it),
 * asleep between polls (50 us, doubled up to 20 ms): a rank that waits for the others would
 * otherwise spin in the library's progress loop for as long as their replicas take. */
static void wait_asleep(int started, MPI_Request *req) {
    int done = started != MPI_SUCCESS;
    struct timespec pause = {0, 50 * 1000};
    while (!done && MPI_Test(req, &done, MPI_STATUS_IGNORE) == MPI_SUCCESS && !done) {
        nanosleep(&pause, NULL);
        if (pause.tv_nsec < 20 * 1000 * 1000) pause.tv_nsec *= 2;
    }
}
#endif

void ranks_end(const ranks *r) {
#ifdef HSBD_HAVE_MPI
    if (!r->mpi) return;
    MPI_Request all_done;
    wait_asleep(MPI_Ibarrier(MPI_COMM_WORLD, &all_done), &all_done);
    MPI_Finalize();
#else
    (void)r;
#endif
}

void ranks_share(const ranks *r, void **buf, size_t *len) {
#ifdef HSBD_HAVE_MPI
    if (!r->mpi) return;
    uint64_t n = *len;
    MPI_Request req;
    wait_asleep(MPI_Ibcast(&n, 1, MPI_UINT64_T, 0, MPI_COMM_WORLD, &req), &req);
    if (r->rank > 0 && !(*buf = malloc(n ? n : 1))) {
        fprintf(stderr, "hsbd: rank %d of mpirun: out of memory\n", r->rank);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    *len = n;
    wait_asleep(MPI_Ibcast(*buf, (int)n, MPI_BYTE, 0, MPI_COMM_WORLD, &req), &req);
#else
    (void)r, (void)buf, (void)len;
#endif
}

/* The failures of every rank (all ranks' errors at rank 0), or NULL: its own alone. */
static hsbd_error *gather_errors(const ranks *r, const hsbd_error *own) {
    hsbd_error *all = NULL;
#ifdef HSBD_HAVE_MPI
    if (!r->mpi || r->size < 2) return NULL;
    all = r->rank == 0 ? calloc((size_t)r->size, sizeof *all) : NULL;
    if (r->rank == 0 && !all) MPI_Abort(MPI_COMM_WORLD, 1);
    MPI_Request req;
    wait_asleep(MPI_Igather(own, sizeof *own, MPI_BYTE, all, sizeof *own, MPI_BYTE, 0,
                            MPI_COMM_WORLD, &req),
                &req);
#else
    (void)r, (void)own;
#endif
    return all;
}

int ranks_gather_failures(const ranks *r, int status, hsbd_error *err) {
    err->status = status;
    hsbd_error *all = gather_errors(r, err);
    if (r->rank > 0) return status;
    const int n = all ? r->size : 1;
    const hsbd_error *e = all ? all : err;
    int worst = 0;
    for (int k = 0; k < n; ++k) {
        if (e[k].status == HSBD_OK) continue;
        if (cli_exit_code(e[k].status) > cli_exit_code(e[worst].status)) worst = k;
        int said = 0;
        for (int j = 0; j < k && !said; ++j)
            said = e[j].status != HSBD_OK && !strcmp(e[j].message, e[k].message);
        if (said || !e[k].message[0]) continue;
        if (k > 0)
            fprintf(stderr, "hsbd: rank %d of mpirun: %s\n", k, e[k].message);
        else
            fprintf(stderr, "hsbd: %s\n", e[k].message);
    }
    status = e[worst].status;
    free(all);
    return status;
}

int ranks_rank0_value(const ranks *r, int value) {
#ifdef HSBD_HAVE_MPI
    MPI_Request req;
    if (r->mpi) wait_asleep(MPI_Ibcast(&value, 1, MPI_INT, 0, MPI_COMM_WORLD, &req), &req);
#else
    (void)r;
#endif
    return value;
}

/* The threads of a working rank: the CPUs it may use divided by the most working ranks of its
 * node that may use one of them (ranks bound to cores keep theirs; unbound ones, or ranks
 * bound to a socket, split their CPUs; waiting ranks count for nothing). 0: unknown. */
static int threads_share(const ranks *r, int working) {
#if defined(HSBD_HAVE_MPI) && defined(__linux__) && defined(CPU_COUNT)
    if (!r->mpi) return 0;
    cpu_set_t own;
    const int known = sched_getaffinity(0, sizeof own, &own) == 0;
    if (!known) CPU_ZERO(&own); /* it still takes part in the collective */
    MPI_Comm node;
    if (MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node) !=
        MPI_SUCCESS)
        return 0;
    int mine[CPU_SETSIZE], ranks_on[CPU_SETSIZE], sharing = 0;
    for (int c = 0; c < CPU_SETSIZE; ++c)
        mine[c] = working && CPU_ISSET(c, &own);
    const int summed =
        MPI_Allreduce(mine, ranks_on, CPU_SETSIZE, MPI_INT, MPI_SUM, node) == MPI_SUCCESS;
    MPI_Comm_free(&node);
    for (int c = 0; c < CPU_SETSIZE; ++c)
        if (mine[c] && ranks_on[c] > sharing) sharing = ranks_on[c];
    if (!known || !summed || sharing < 1) return 0;
    return CPU_COUNT(&own) / sharing > 1 ? CPU_COUNT(&own) / sharing : 1;
#else
    (void)r, (void)working;
    return 0;
#endif
}

void ranks_share_threads(const ranks *r, int working) {
    const int share = threads_share(r, working);
#ifdef _OPENMP
    if (share > 0 && !getenv("OMP_NUM_THREADS")) omp_set_num_threads(share);
#else
    (void)share; /* one thread anyway */
#endif
}
