/* brdfit batch across MPI processes (batch_mpi.h).
 *
 * Decisions:
 *  - Only the coordinator touches SQLite: one writer, the same per-item transactions and
 *    resumability as one process, and workers need no access to the database's folder.
 *  - Items are handed out one at a time, on request (dynamic): a worker asks with its
 *    last result, so a slow item never holds up the others. Largest material first (by
 *    weight: its data file's size), ties in manifest order, so the long items start
 *    early and the last ones are short. A worker that holds a material gets that
 *    material's next item while there is one, so it does not read it again.
 *  - Results do not depend on which worker fits an item, nor on the thread count
 *    (fit.h): each item is fitted alone as in a --shard run, whose rows equal the
 *    one-process run's. Rows travel as batch_row_pack bytes, doubles bit for bit.
 *  - Waiting is MPI_Iprobe and a 1 ms sleep, not a blocking receive: Open MPI's blocking
 *    calls spin on a core, and the coordinator would take one from the workers.
 *  - A worker's items are fitted by a child process of it (batch_fitter.h), which reads
 *    the materials and lives on between items: when it dies (a crash, the out-of-memory
 *    killer, a kill) the worker reports the item lost, starts a fresh one at its next
 *    item and goes on. The coordinator hands a lost item out again, first of all (to
 *    the worker that holds its material if one does); lost twice, it becomes an error
 *    row with the reason, which --redo failed reruns. Twice, because a fit that died
 *    for want of memory may pass on a less loaded machine, and one that crashes crashes
 *    every time.
 *  - A rank that dies ends the job (Open MPI 4 has no fault-tolerant MPI: mpirun kills
 *    the others when a process exits abnormally), and so does the death of the launcher
 *    (PR_SET_PDEATHSIG below); the database keeps what was written and the same command
 *    resumes, the items in flight being pending still. A worker rank itself only passes
 *    messages, which is why the fitting is what runs apart. */
#include "batch_mpi.h"

#include <mpi.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __linux__
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>
#endif

enum { TAG_ASK = 1, TAG_ITEM, TAG_STOP, TAG_LOST };
enum { MAX_LOSSES = 2 }; /* an item lost this often is an error */

static int started;

void batch_mpi_start(int *rank, int *size)
{
    *rank = 0, *size = 1;
    /* Set by Open MPI's mpirun, by PMIx (srun --mpi=pmix, Open MPI 5) and by PMI-1/2
     * launchers (srun, MPICH's hydra): without them this is a plain command, and MPI's
     * singleton start (a daemon in Open MPI 4) is not wanted. */
    if (!getenv("OMPI_COMM_WORLD_SIZE") && !getenv("PMIX_RANK") && !getenv("PMI_SIZE"))
        return;
#ifdef __linux__
    /* A rank whose launcher dies (mpirun, or the orted or slurmstepd under it, killed
     * with SIGKILL) is killed too: Open MPI 4's ranks would otherwise go on as orphans,
     * and the orphaned coordinator would keep the database (its flock) from the rerun. */
    const pid_t parent = getppid();
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent)
        raise(SIGKILL);
#endif
    int provided;
    /* Only the main thread calls MPI; the solver's threads never do. */
    MPI_Init_thread(NULL, NULL, MPI_THREAD_FUNNELED, &provided);
    started = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
}

void batch_mpi_end(void)
{
    if (started)
        MPI_Finalize();
    started = 0;
}

void batch_mpi_share(int *status, char hash[17])
{
    MPI_Bcast(status, 1, MPI_INT, 0, MPI_COMM_WORLD);
    MPI_Bcast(hash, 17, MPI_CHAR, 0, MPI_COMM_WORLD);
}

int batch_mpi_all(int ok)
{
    int all;
    ok = !!ok;
    MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    return all;
}

/* Waits (without spinning) for a message from source (MPI_ANY_SOURCE: any) and receives
 * it: a malloc'd buffer in *buf (NULL when empty), its size in *len, its tag and source
 * returned in *tag and *from. */
static void receive(int source, unsigned char **buf, int *len, int *tag, int *from)
{
    MPI_Status st;
    int flag = 0;
    const struct timespec ms = {0, 1000000};
    for (;;) {
        MPI_Iprobe(source, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st);
        if (flag)
            break;
        nanosleep(&ms, NULL);
    }
    MPI_Get_count(&st, MPI_BYTE, len);
    *buf = *len > 0 ? malloc((size_t)*len) : NULL;
    if (*len > 0 && !*buf) {
        fprintf(stderr, "brdfit batch: out of memory for a %d-byte message\n", *len);
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    MPI_Recv(*buf, *len, MPI_BYTE, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    *tag = st.MPI_TAG, *from = st.MPI_SOURCE;
}

/* ---- The coordinator ------------------------------------------------------------------- */

typedef struct queue {
    const int *items; /* ascending */
    int n, nmodels;
    int *order;         /* materials with items, heaviest first */
    int norder, next;   /* order[next]: the first that may have items left */
    int *from, *to;     /* per material: its items' range in items (from == to: none) */
    int *retry, nretry; /* lost items to hand out again, before any other */
} queue;

static const double *sort_weight;

static int heavier_first(const void *a, const void *b)
{
    const int i = *(const int *)a, j = *(const int *)b;
    const double wi = sort_weight[i], wj = sort_weight[j];
    return wi > wj ? -1 : wi < wj ? 1 : (i > j) - (i < j);
}

static int queue_init(queue *q, const int *items, int n, int nmodels, const double *weight, int nmaterials)
{
    memset(q, 0, sizeof *q);
    q->items = items, q->n = n, q->nmodels = nmodels;
    q->order = malloc(((size_t)nmaterials + 1) * sizeof *q->order);
    q->from = calloc((size_t)nmaterials + 1, sizeof *q->from);
    q->to = calloc((size_t)nmaterials + 1, sizeof *q->to);
    q->retry = malloc(((size_t)n + 1) * sizeof *q->retry); /* each item is lost at most once before it is an error */
    if (!q->order || !q->from || !q->to || !q->retry)
        return -1;
    for (int k = 0; k < n;) {
        const int i = items[k] / nmodels;
        q->from[i] = k;
        while (k < n && items[k] / nmodels == i)
            k++;
        q->to[i] = k;
        q->order[q->norder++] = i;
    }
    sort_weight = weight;
    qsort(q->order, (size_t)q->norder, sizeof *q->order, heavier_first);
    return 0;
}

static void queue_clear(queue *q)
{
    free(q->order);
    free(q->from);
    free(q->to);
    free(q->retry);
}

/* The next item for a worker that holds material `held` (-1: none), or -1: a lost one
 * first (held's if there is one), then held's next, then the heaviest material's. */
static int queue_take(queue *q, int held)
{
    if (q->nretry > 0) {
        int k = q->nretry - 1;
        for (int j = 0; j < q->nretry; j++)
            if (q->retry[j] / q->nmodels == held)
                k = j;
        const int item = q->retry[k];
        memmove(q->retry + k, q->retry + k + 1, (size_t)(q->nretry - k - 1) * sizeof *q->retry);
        q->nretry--;
        return item;
    }
    if (held >= 0 && q->from[held] < q->to[held])
        return q->items[q->from[held]++];
    while (q->next < q->norder && q->from[q->order[q->next]] == q->to[q->order[q->next]])
        q->next++;
    if (q->next == q->norder)
        return -1;
    const int i = q->order[q->next];
    return q->items[q->from[i]++];
}

void batch_mpi_coordinate(const int *items, int n, int nmodels, const double *weight, int nmaterials,
                          const batch_mpi_callbacks *cb, const volatile sig_atomic_t *stop)
{
    queue q;
    int size;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    int *given = malloc(((size_t)size + 1) * sizeof *given);                     /* per rank: its item in flight */
    unsigned char *losses = calloc((size_t)nmaterials * (size_t)nmodels + 1, 1); /* per item */
    if (!given || !losses || queue_init(&q, items, n, nmodels, weight, nmaterials) < 0) {
        fprintf(stderr, "brdfit batch: out of memory for the work queue\n");
        MPI_Abort(MPI_COMM_WORLD, 1);
    }
    for (int active = size - 1; active > 0;) {
        unsigned char *buf;
        int len, tag, from;
        receive(MPI_ANY_SOURCE, &buf, &len, &tag, &from);
        int64_t held = -1;
        if (len >= (int)sizeof held)
            memcpy(&held, buf, sizeof held);
        if (tag == TAG_LOST) { /* [held][why]: the process fitting given[from] died */
            const int item = given[from];
            char why[512];
            const size_t wn = len > (int)sizeof held ? (size_t)len - sizeof held : 0;
            snprintf(why, sizeof why, "%.*s", (int)(wn < sizeof why ? wn : sizeof why - 1),
                     wn ? (const char *)buf + sizeof held : "");
            const int again = ++losses[item] < MAX_LOSSES;
            if (again)
                q.retry[q.nretry++] = item;
            cb->lost(cb->ctx, item, from, why, again);
        } else if (len > (int)sizeof held) { /* a result: [held][row] */
            batch_row row;
            bf_error err;
            if (batch_row_unpack(buf + sizeof held, (size_t)len - sizeof held, &row, &err) != BF_OK) {
                fprintf(stderr, "brdfit batch: from rank %d: %s\n", from, err.msg);
                MPI_Abort(MPI_COMM_WORLD, 1);
            }
            cb->done(cb->ctx, &row);
            batch_row_clear(&row);
        }
        free(buf);
        const int item = *stop ? -1 : queue_take(&q, held >= 0 && held < nmaterials ? (int)held : -1);
        given[from] = item;
        if (item < 0) {
            MPI_Send(NULL, 0, MPI_BYTE, from, TAG_STOP, MPI_COMM_WORLD);
            active--;
        } else {
            MPI_Send(&item, 1, MPI_INT, from, TAG_ITEM, MPI_COMM_WORLD);
        }
    }
    queue_clear(&q);
    free(given);
    free(losses);
}

/* ---- A worker -------------------------------------------------------------------------- */

/* Sends [held][bytes] to the coordinator with tag. */
static void send_held(int64_t held, const void *bytes, size_t n, int tag)
{
    unsigned char *buf;
    if (n > (size_t)INT32_MAX - sizeof held || !(buf = malloc(n + sizeof held))) {
        fprintf(stderr, "brdfit batch: out of memory for a %zu-byte message\n", n);
        MPI_Abort(MPI_COMM_WORLD, 1);
        return;
    }
    memcpy(buf, &held, sizeof held);
    if (n)
        memcpy(buf + sizeof held, bytes, n);
    MPI_Send(buf, (int)(n + sizeof held), MPI_BYTE, 0, tag, MPI_COMM_WORLD);
    free(buf);
}

void batch_mpi_work(int (*fit)(void *ctx, int item, batch_row *row, int *held, char *why, size_t n), void *ctx)
{
    int held = -1;
    send_held(-1, NULL, 0, TAG_ASK);
    for (;;) {
        unsigned char *buf, *packed;
        int len, tag, from, item = -1;
        receive(0, &buf, &len, &tag, &from);
        if (tag == TAG_ITEM && len == (int)sizeof item)
            memcpy(&item, buf, sizeof item);
        free(buf);
        if (tag != TAG_ITEM)
            return;
        batch_row row;
        char why[512] = "";
        if (fit(ctx, item, &row, &held, why, sizeof why) < 0) {
            send_held(held, why, strlen(why), TAG_LOST);
            continue;
        }
        size_t n;
        bf_error err;
        if (batch_row_pack(&row, &packed, &n, &err) != BF_OK) {
            fprintf(stderr, "brdfit batch: item %d: %s\n", item, "out of memory for its result");
            MPI_Abort(MPI_COMM_WORLD, 1);
        }
        send_held(held, packed, n, TAG_ASK);
        free(packed);
        batch_row_clear(&row);
    }
}
