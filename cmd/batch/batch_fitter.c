/* The child process that fits brdfit batch's items, for the one process or an MPI worker
 * (batch_fitter.h).
 *
 * Decisions:
 *  - fork, not a new program, and one child for many calls: it reads the materials and
 *    keeps one between calls, and its heap stays warm. A child per item cost about 50 ms
 *    an item in page faults (every fit's workspace touched afresh), a quarter of a small
 *    item; this costs a socket round trip.
 *  - The child closes every descriptor but its socket and stdio: it must not hold the
 *    results database or its flock (a rerun after the parent is killed would find the
 *    database busy until the child is gone), nor MPI's sockets.
 *  - The child has a process group of its own, so a terminal's ^C reaches the parent
 *    only, which passes SIGINT on once: the child then starts no new fit and sends the
 *    rows of the running ones (a second ^C ends the parent, and the child with it).
 *  - The library's thread pool is fork-safe (lib/src/core/base/parallel.c); the child never calls
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
#include <dirent.h>
#include <poll.h>
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

enum { ROW = 1, END = 2 };    /* the child's frames: [kind][held], then a row's bytes */
enum { MAX_ITEMS = 1 << 20 }; /* a call's items: one material's models */

struct batch_fitter_out {
    int fd;
    int held; /* as the last row said (-1 before any) */
};

void batch_fitter_emit(batch_fitter_out *out, const batch_row *row, int held)
{
    unsigned char *buf;
    size_t len;
    bf_error err;
    if (batch_row_pack(row, &buf, &len, &err) != BF_OK)
        _exit(3);
    const int32_t head[2] = {ROW, held};
    out->held = held;
    const uint64_t n = len;
    if (send_all(out->fd, head, sizeof head) < 0 || send_all(out->fd, &n, sizeof n) < 0 ||
        send_all(out->fd, buf, len) < 0)
        _exit(4);
    free(buf);
}

/* Every descriptor but 0, 1, 2 and keep closed (the decisions above). */
static void close_others(int keep)
{
    DIR *d = opendir("/proc/self/fd");
    if (!d)
        return;
    int fds[1024], n = 0;
    for (struct dirent *e; (e = readdir(d)) && n < 1024;) {
        const int fd = atoi(e->d_name);
        if (fd > 2 && fd != keep && fd != dirfd(d))
            fds[n++] = fd;
    }
    closedir(d);
    for (int k = 0; k < n; k++)
        close(fds[k]);
}

/* The child: calls in, rows out, until the socket closes. */
static void child_main(const batch_fitter *f, int fd, pid_t parent)
{
    close_others(fd);
    setpgid(0, 0);
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
    int32_t n;
    batch_fitter_out out = {fd, -1};
    while (read_all(fd, &n, sizeof n) == 1 && n >= 1 && n <= MAX_ITEMS) {
        int32_t *items32 = malloc((size_t)n * sizeof *items32);
        int *items = malloc((size_t)n * sizeof *items);
        if (!items32 || !items || read_all(fd, items32, (size_t)n * sizeof *items32) != 1)
            _exit(5);
        for (int k = 0; k < n; k++)
            items[k] = items32[k];
#ifdef __linux__
        char name[16];
        snprintf(name, sizeof name, "brdfit:%d%s", items[0], n > 1 ? "+" : "");
        prctl(PR_SET_NAME, name);
#endif
        f->fit(f->ctx, items, n, &out);
        free(items32);
        free(items);
        const int32_t end[2] = {END, out.held};
        if (send_all(fd, end, sizeof end) < 0)
            _exit(4);
#ifdef __linux__
        prctl(PR_SET_NAME, "brdfit:idle");
#endif
    }
    _exit(0);
}

void batch_fitter_init(batch_fitter *f, batch_fit_fn fit, void *ctx)
{
    memset(f, 0, sizeof *f);
    f->fit = fit, f->ctx = ctx, f->fd = -1;
}

/* A child started; 0, or -1 with why. */
static int start(batch_fitter *f, char *why, size_t n)
{
    int sv[2];
    if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) < 0) {
        snprintf(why, n, "no socket for its process: %s", strerror(errno));
        return -1;
    }
    fflush(NULL); /* nothing buffered is written twice */
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
    f->pid = pid, f->fd = sv[0], f->forwarded = 0;
    return 0;
}

/* Why the child with wait status st gave no (complete) answer. */
static void explain(int st, char *why, size_t n)
{
    if (WIFSIGNALED(st)) {
        const int sig = WTERMSIG(st);
        snprintf(why, n, "killed by signal %d (%s)%s", sig, strsignal(sig),
                 sig == SIGKILL ? ": a kill, or the kernel out of memory" : "");
    } else if (WIFEXITED(st) && WEXITSTATUS(st) != 0) {
        snprintf(why, n, "its process exited with status %d before sending its results", WEXITSTATUS(st));
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

/* Waits until the child has something to say, passing SIGINT on when the parent's flag
 * is set (a fifth of a second at most between looks). */
static void await(batch_fitter *f)
{
    struct pollfd p = {.fd = f->fd, .events = POLLIN};
    for (;;) {
        if (f->interrupt && *f->interrupt && !f->forwarded) {
            kill(f->pid, SIGINT);
            f->forwarded = 1;
        }
        if (poll(&p, 1, 200) > 0)
            return;
    }
}

int batch_fitter_run(batch_fitter *f, const int *items, int n, const batch_sink *sink, int *held, char *why,
                     size_t whylen)
{
    *held = -1;
    if (n < 1 || n > MAX_ITEMS) {
        snprintf(why, whylen, "%d items in one call", n);
        return -1;
    }
    if (!f->pid && start(f, why, whylen) < 0)
        return -1;
    int32_t *msg = malloc(((size_t)n + 1) * sizeof *msg);
    if (!msg) {
        snprintf(why, whylen, "out of memory");
        return -1;
    }
    msg[0] = n;
    for (int k = 0; k < n; k++)
        msg[k + 1] = items[k];
    int r = send_all(f->fd, msg, ((size_t)n + 1) * sizeof *msg) < 0 ? 0 : 1;
    free(msg);
    while (r == 1) {
        int32_t head[2];
        await(f);
        if ((r = read_all(f->fd, head, sizeof head)) != 1)
            break;
        if (head[0] == END) {
            *held = head[1];
            return 0;
        }
        uint64_t len;
        unsigned char *buf = NULL;
        batch_row row;
        bf_error err;
        if (head[0] != ROW || (r = read_all(f->fd, &len, sizeof len)) != 1)
            break;
        if (len > ((uint64_t)1 << 30) || !(buf = malloc(len ? len : 1)))
            r = -1;
        if (r == 1)
            r = read_all(f->fd, buf, len);
        if (r == 1 && batch_row_unpack(buf, len, &row, &err) != BF_OK)
            r = -1;
        free(buf);
        if (r == 1) {
            sink->got(sink->user, &row);
            batch_row_clear(&row);
        }
    }
    lose(f, r == 0, why, whylen);
    return -1;
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
