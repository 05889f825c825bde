/* mpi.c - the program's MPI layer: render and bake share their work among
 * the ranks of an MPI launch (mpirun, srun); seabake(1), PARALLEL RUNS WITH
 * MPI.  The library knows nothing of it.
 *
 * MPI is initialised only when the environment shows an MPI launcher
 * (OMPI_COMM_WORLD_SIZE from OpenMPI's mpirun, PMIX_RANK from a PMIx
 * launcher such as srun --mpi=pmix, PMI_RANK from PMI-1/2 launchers): a
 * plain `seabake` never calls MPI_Init, so it starts as fast as a build
 * without MPI and prints nothing of MPI's.  Without HAVE_MPI (configure
 * --without-mpi) every call is that of one rank, rank 0 of 1, and a launch
 * of more than one rank is refused rather than run N times over the same
 * files.
 *
 * Errors: MPI's default handler (MPI_ERRORS_ARE_FATAL) stays, so a failed
 * MPI call aborts the whole job; seabake's own failures are agreed between
 * the ranks (sea_cli_mpi_agree) and reported once, by rank 0. */
#ifdef HAVE_CONFIG_H
#include <config.h>
#endif

#include <assert.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifdef HAVE_MPI
#include <mpi.h>
#endif

#include "cli.h"

#ifdef HAVE_MPI
/* Point-to-point messages go in pieces of at most this many bytes: MPI's
 * counts are int, and a level of a large bake holds more than 2^31 bytes. */
static const size_t MPI_CHUNK_BYTES = (size_t)1 << 30;
#endif

/* The process's place in the launch: set once by sea_cli_mpi_init (as the
 * signal state of progress.c, process-wide by nature). */
static int mpi_rank = 0, mpi_size = 1;
#ifdef HAVE_MPI
static int mpi_on = 0; /* MPI_Init was called */
#endif

#ifndef HAVE_MPI
/* The size of the launch the environment announces, 0 when none. */
static long launch_size(void)
{
    static const char *const SIZE_VARS[] = {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"};
    for (size_t i = 0; i < SEA_CLI_COUNT(SIZE_VARS); i++) {
        const char *v = getenv(SIZE_VARS[i]);
        if (v != NULL && *v != '\0')
            return strtol(v, NULL, 10);
    }
    return 0;
}
#endif

#ifdef HAVE_MPI
static bool launched(void)
{
    static const char *const VARS[] = {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"};
    for (size_t i = 0; i < SEA_CLI_COUNT(VARS); i++)
        if (getenv(VARS[i]) != NULL)
            return true;
    return false;
}
#endif

sea_status sea_cli_mpi_init(int *argc, char ***argv, sea_error *err)
{
#ifdef HAVE_MPI
    if (!launched())
        return SEA_OK;
    /* Only the main thread calls MPI; OpenMP threads never do. */
    int provided = 0;
    MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided);
    mpi_on = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &mpi_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &mpi_size);
    (void)err;
    return SEA_OK;
#else
    (void)argc;
    (void)argv;
    const long n = launch_size();
    if (n > 1) {
        /* one message for the job: only the launch's rank 0 reports it */
        const char *r = getenv("OMPI_COMM_WORLD_RANK");
        if (r == NULL)
            r = getenv("PMI_RANK");
        mpi_rank = r != NULL ? (int)strtol(r, NULL, 10) : 0;
        return sea_fail(err, SEA_ERR_DOMAIN,
                        "launched as one of %ld MPI ranks, but this seabake was built without "
                        "MPI (configure --with-mpi): every rank would write the same files "
                        "(allowed: one process, or mpirun -np 1)",
                        n);
    }
    return SEA_OK;
#endif
}

void sea_cli_mpi_finalize(void)
{
#ifdef HAVE_MPI
    if (mpi_on) {
        /* Every rank has cleaned up and reported before any leaves: a
         * launcher that stops the job at the first non-zero exit must not
         * cut rank 0's removal of a temporary directory short. */
        MPI_Barrier(MPI_COMM_WORLD);
        MPI_Finalize();
        mpi_on = 0;
    }
#endif
}

int sea_cli_mpi_rank(void)
{
    return mpi_rank;
}

int sea_cli_mpi_size(void)
{
    return mpi_size;
}

sea_status sea_cli_mpi_agree(sea_status st, long key, long *failed_key, sea_error *err)
{
    if (failed_key != NULL)
        *failed_key = st != SEA_OK ? key : LONG_MAX;
#ifdef HAVE_MPI
    if (mpi_size == 1)
        return st;
    /* the failing rank with the smallest key, ties to the lowest rank */
    struct {
        long key;
        int rank;
    } mine = {st != SEA_OK ? key : LONG_MAX, mpi_rank}, first;
    MPI_Allreduce(&mine, &first, 1, MPI_LONG_INT, MPI_MINLOC, MPI_COMM_WORLD);
    if (failed_key != NULL)
        *failed_key = first.key;
    if (first.key == LONG_MAX)
        return SEA_OK;
    /* its status and message to every rank (sea_error is plain bytes) */
    int code = (int)st;
    sea_error e;
    if (mpi_rank == first.rank && err != NULL)
        e = *err;
    else
        memset(&e, 0, sizeof e);
    MPI_Bcast(&code, 1, MPI_INT, first.rank, MPI_COMM_WORLD);
    MPI_Bcast(&e, (int)sizeof e, MPI_BYTE, first.rank, MPI_COMM_WORLD);
    if (err != NULL)
        *err = e;
    return (sea_status)code;
#else
    (void)key;
    (void)err;
    return st;
#endif
}

void sea_cli_mpi_minmax(double *lo, double *hi)
{
#ifdef HAVE_MPI
    if (mpi_size > 1) {
        MPI_Allreduce(MPI_IN_PLACE, lo, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
        MPI_Allreduce(MPI_IN_PLACE, hi, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
    }
#else
    (void)lo;
    (void)hi;
#endif
}

void sea_cli_mpi_sum(size_t *v)
{
#ifdef HAVE_MPI
    if (mpi_size > 1) {
        unsigned long long x = *v;
        MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, MPI_COMM_WORLD);
        *v = (size_t)x;
    }
#else
    (void)v;
#endif
}

int sea_cli_mpi_frame_owner(long first, long f)
{
    return (int)((f - first) % sea_cli_mpi_size());
}

size_t sea_cli_mpi_rows(size_t n, size_t block, int k, int size, size_t *rows)
{
    const size_t nb = (n + block - 1) / block;
    size_t m = 0;
    for (size_t b = (size_t)k; b < nb; b += (size_t)size)
        for (size_t j = b * block; j < b * block + block && j < n; j++) {
            if (rows != NULL)
                rows[m] = j;
            m++;
        }
    return m;
}

void sea_cli_mpi_bcast(void *buf, size_t bytes, int root)
{
#ifdef HAVE_MPI
    unsigned char *p = buf;
    for (size_t done = 0; mpi_size > 1 && done < bytes; done += MPI_CHUNK_BYTES) {
        const size_t n = bytes - done < MPI_CHUNK_BYTES ? bytes - done : MPI_CHUNK_BYTES;
        MPI_Bcast(p + done, (int)n, MPI_BYTE, root, MPI_COMM_WORLD);
    }
#else
    (void)buf;
    (void)bytes;
    (void)root;
#endif
}

void sea_cli_mpi_send(const void *buf, size_t bytes, int dest, int tag)
{
#ifdef HAVE_MPI
    const unsigned char *p = buf;
    size_t done = 0;
    do {
        const size_t n = bytes - done < MPI_CHUNK_BYTES ? bytes - done : MPI_CHUNK_BYTES;
        MPI_Send(p + done, (int)n, MPI_BYTE, dest, tag, MPI_COMM_WORLD);
        done += n;
    } while (done < bytes);
#else
    (void)buf;
    (void)bytes;
    (void)dest;
    (void)tag;
    assert(!"sea_cli_mpi_send with one rank"); /* no one to send to */
#endif
}

void sea_cli_mpi_queue_init(sea_cli_mpi_queue *q)
{
    memset(q, 0, sizeof *q);
}

sea_status sea_cli_mpi_queue_send(sea_cli_mpi_queue *q, void *buf, size_t bytes, int dest,
                                  int tag, sea_error *err)
{
#ifdef HAVE_MPI
    const size_t pieces = bytes / MPI_CHUNK_BYTES + 1;
    if (q->n + pieces > q->cap) {
        const size_t cap = 2 * (q->n + pieces);
        void **bufs = realloc(q->bufs, cap * sizeof *bufs);
        if (bufs != NULL)
            q->bufs = bufs;
        MPI_Request *req = bufs ? realloc(q->requests, cap * sizeof *req) : NULL;
        if (req == NULL) {
            free(buf);
            return sea_fail(err, SEA_ERR_NOMEM, "out of memory for the sends to rank %d", dest);
        }
        q->requests = req;
        q->cap = cap;
    }
    MPI_Request *req = q->requests;
    const unsigned char *p = buf;
    size_t done = 0;
    do {
        const size_t n = bytes - done < MPI_CHUNK_BYTES ? bytes - done : MPI_CHUNK_BYTES;
        q->bufs[q->n] = done == 0 ? buf : NULL;
        MPI_Isend(p + done, (int)n, MPI_BYTE, dest, tag, MPI_COMM_WORLD, &req[q->n]);
        q->n++;
        done += n;
    } while (done < bytes);
    return SEA_OK;
#else
    (void)q;
    (void)bytes;
    (void)dest;
    (void)tag;
    (void)err;
    free(buf);
    assert(!"sea_cli_mpi_queue_send with one rank"); /* no one to send to */
    return SEA_OK;
#endif
}

void sea_cli_mpi_queue_wait(sea_cli_mpi_queue *q)
{
#ifdef HAVE_MPI
    if (q->n > 0)
        MPI_Waitall((int)q->n, q->requests, MPI_STATUSES_IGNORE);
#endif
    for (size_t i = 0; i < q->n; i++)
        free(q->bufs[i]);
    q->n = 0;
}

void sea_cli_mpi_queue_free(sea_cli_mpi_queue *q)
{
    sea_cli_mpi_queue_wait(q);
    free(q->bufs);
    free(q->requests);
    memset(q, 0, sizeof *q);
}

void sea_cli_mpi_abort(const sea_error *err)
{
    fprintf(stderr, "seabake: error: %s (rank %d of %d: the job is aborted)\n",
            err != NULL && err->msg[0] ? err->msg : "internal error", mpi_rank, mpi_size);
#ifdef HAVE_MPI
    MPI_Abort(MPI_COMM_WORLD, SEA_CLI_EXIT_RUNTIME);
#endif
    exit(SEA_CLI_EXIT_RUNTIME);
}

void sea_cli_mpi_drop(size_t bytes, int source, int tag)
{
#ifdef HAVE_MPI
    const size_t n = bytes < MPI_CHUNK_BYTES ? bytes : MPI_CHUNK_BYTES;
    void *scratch = malloc(n + 1);
    if (scratch == NULL) {
        /* the last resort: unmatched messages would hang the job */
        sea_error e;
        snprintf(e.msg, sizeof e.msg, "out of memory for a message of rank %d", source);
        sea_cli_mpi_abort(&e);
    }
    size_t done = 0;
    do {
        const size_t k = bytes - done < n ? bytes - done : n;
        MPI_Recv(scratch, (int)k, MPI_BYTE, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        done += k;
    } while (done < bytes);
    free(scratch);
#else
    (void)bytes;
    (void)source;
    (void)tag;
    assert(!"sea_cli_mpi_drop with one rank"); /* no one to receive from */
#endif
}

void sea_cli_mpi_recv(void *buf, size_t bytes, int source, int tag)
{
#ifdef HAVE_MPI
    unsigned char *p = buf;
    size_t done = 0;
    do {
        const size_t n = bytes - done < MPI_CHUNK_BYTES ? bytes - done : MPI_CHUNK_BYTES;
        MPI_Recv(p + done, (int)n, MPI_BYTE, source, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        done += n;
    } while (done < bytes);
#else
    (void)buf;
    (void)bytes;
    (void)source;
    (void)tag;
    assert(!"sea_cli_mpi_recv with one rank"); /* no one to receive from */
#endif
}
