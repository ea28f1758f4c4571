/* The child process that fits an MPI worker's items (batch_fitter.h).
 *
 * Decisions:
 *  - fork, not a new program, and one child for many items: it reads the materials and
 *    keeps one as the worker did before there was a child, and its heap stays warm
 *    between items. A child per item cost about 50 ms each in page faults (every fit's
 *    workspace touched fresh), a quarter of a small item; this costs a socket round trip.
 *  - The library's thread pool is fork-safe (lib/src/parallel.c); the child never calls
 *    MPI and leaves with _exit, so neither MPI's nor stdio's exit handlers run twice.
 *  - Rows come back as batch_row_pack bytes (bit-exact doubles) over a Unix socket
 *    (send with MSG_NOSIGNAL: a dead child is an error to handle, not a SIGPIPE).
 *  - The child dies with its parent (PR_SET_PDEATHSIG): a rank that mpirun ends takes
 *    its fit along instead of leaving it running unowned.
 *  - It raises its own oom_score_adj: when memory runs out, the kernel kills the fit (one
 *    item, handed out again) rather than the rank that holds the job together.
 *  - Its name is "brdfit:ITEM" while it fits ITEM (ps, top, pgrep -x). */
#include "batch_fitter.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/prctl.h>
#endif

/* All n bytes of buf sent; 0 or -1. */
static int send_all(int fd, const void *buf, size_t n)
{
    const char *p = buf;
    while (n > 0) {
        const ssize_t w = send(fd, p, n, MSG_NOSIGNAL);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        p += w, n -= (size_t)w;
    }
    return 0;
}

/* Exactly n bytes into buf: 1; 0 at the end of the stream (the other side closed, even
 * part-way); -1 a read error. */
static int read_all(int fd, void *buf, size_t n)
{
    char *p = buf;
    while (n > 0) {
        const ssize_t r = read(fd, p, n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return r == 0 ? 0 : -1;
        p += r, n -= (size_t)r;
    }
    return 1;
}

/* The child: items in, rows out, until the socket closes. */
static void child_main(const batch_fitter *f, int fd, pid_t parent)
{
#ifdef __linux__
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) /* the parent died before the line above */
        _exit(1);
    const int oom = open("/proc/self/oom_score_adj", O_WRONLY | O_CLOEXEC);
    if (oom >= 0) {
        (void)!write(oom, "500", 3); /* best effort: only a preference for the killer */
        close(oom);
    }
#else
    (void)parent;
#endif
    int32_t item;
    while (read_all(fd, &item, sizeof item) == 1) {
#ifdef __linux__
        char name[16];
        snprintf(name, sizeof name, "brdfit:%d", (int)item);
        prctl(PR_SET_NAME, name);
#endif
        batch_row row;
        int held = -1;
        memset(&row, 0, sizeof row);
        f->fit(f->ctx, item, &row, &held);
        unsigned char *buf;
        size_t len;
        bf_error err;
        if (batch_row_pack(&row, &buf, &len, &err) != BF_OK)
            _exit(3);
        const int32_t h = held;
        const uint64_t n = len;
        if (send_all(fd, &h, sizeof h) < 0 || send_all(fd, &n, sizeof n) < 0 || send_all(fd, buf, len) < 0)
            _exit(4);
        free(buf);
        batch_row_clear(&row);
#ifdef __linux__
        prctl(PR_SET_NAME, "brdfit:idle");
#endif
    }
    _exit(0);
}

void batch_fitter_init(batch_fitter *f, batch_fit_fn fit, void *ctx)
{
    f->fit = fit, f->ctx = ctx, f->pid = 0, f->fd = -1;
}

/* A child started; 0, or -1 with why. */
static int start(batch_fitter *f, char *why, size_t n)
{
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) < 0) {
        snprintf(why, n, "no socket for its process: %s", strerror(errno));
        return -1;
    }
    const pid_t parent = getpid(), pid = fork();
    if (pid < 0) {
        snprintf(why, n, "its process could not be started: %s", strerror(errno));
        close(sv[0]), close(sv[1]);
        return -1;
    }
    if (pid == 0) {
        close(sv[0]);
        child_main(f, sv[1], parent);
    }
    close(sv[1]);
    f->pid = pid, f->fd = sv[0];
    return 0;
}

/* Why the child with wait status st gave no row. */
static void explain(int st, char *why, size_t n)
{
    if (WIFSIGNALED(st)) {
        const int sig = WTERMSIG(st);
        snprintf(why, n, "killed by signal %d (%s)%s", sig, strsignal(sig),
                 sig == SIGKILL ? ": a kill, or the kernel out of memory" : "");
    } else if (WIFEXITED(st) && WEXITSTATUS(st) != 0) {
        snprintf(why, n, "its process exited with status %d before sending its result", WEXITSTATUS(st));
    } else {
        snprintf(why, n, "its process sent a result that could not be read");
    }
}

/* The child gone or unusable: waited for (killed first unless it closed its end: eof),
 * forgotten, why filled. */
static void lose(batch_fitter *f, int eof, char *why, size_t n)
{
    if (!eof)
        kill(f->pid, SIGKILL);
    int st = 0;
    while (waitpid(f->pid, &st, 0) < 0 && errno == EINTR)
        ;
    close(f->fd);
    f->pid = 0, f->fd = -1;
    explain(eof ? st : 0, why, n);
}

int batch_fitter_run(batch_fitter *f, int item, batch_row *row, int *held, char *why, size_t n)
{
    memset(row, 0, sizeof *row);
    *held = -1;
    if (!f->pid && start(f, why, n) < 0)
        return -1;
    const int32_t it = item;
    int32_t h;
    uint64_t len;
    unsigned char *buf = NULL;
    int r = send_all(f->fd, &it, sizeof it) < 0 ? 0 : read_all(f->fd, &h, sizeof h);
    if (r == 1)
        r = read_all(f->fd, &len, sizeof len);
    if (r == 1 && (len > ((uint64_t)1 << 30) || !(buf = malloc(len ? len : 1))))
        r = -1;
    if (r == 1)
        r = read_all(f->fd, buf, len);
    bf_error err;
    if (r == 1 && batch_row_unpack(buf, len, row, &err) != BF_OK)
        r = -1;
    free(buf);
    if (r != 1) {
        memset(row, 0, sizeof *row);
        lose(f, r == 0, why, n);
        return -1;
    }
    *held = h;
    return 0;
}

void batch_fitter_clear(batch_fitter *f)
{
    if (!f->pid)
        return;
    close(f->fd); /* the child reads the end of its stream and exits */
    int st;
    while (waitpid(f->pid, &st, 0) < 0 && errno == EINTR)
        ;
    f->pid = 0, f->fd = -1;
}
