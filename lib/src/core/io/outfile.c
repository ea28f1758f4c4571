/* Output files that appear only when complete (io.h), and exact decimal formatting.
 *
 * A regular file (new, or reached through symbolic links) is written to a registered
 * temporary beside it, every write checked through a stdio cookie that keeps the first
 * error's errno (so the message says "No space left on device", not just "error"),
 * fsynced, closed, renamed over the target and the folder synced: the old file stays
 * whole until the new one is complete, and keeps its mode and, where allowed, its owner.
 * Anything else (a device, FIFO, /dev/stdout) cannot be replaced: it is opened and
 * written through. */
#define _GNU_SOURCE /* fopencookie */
#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/tool.h"

#include "io/out_target.h"
#include "io/temp_registry.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The descriptor under an outfile's FILE and the first error a write met. */
struct bf_out_sink {
    int fd;
    int err;
};

static ssize_t sink_write(void *cookie, const char *buf, size_t n)
{
    struct bf_out_sink *k = cookie;
    size_t done = 0;
    while (done < n) {
        ssize_t w = write(k->fd, buf + done, n - done);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0) {
            if (!k->err)
                k->err = w < 0 ? errno : EIO;
            /* Short: stdio marks the stream in error. Never negative (fopencookie(3):
             * glibc would take -1 as a huge count and read past the caller's buffer). */
            return (ssize_t)done;
        }
        done += (size_t)w;
    }
    return (ssize_t)n;
}

static int sink_close(void *cookie)
{
    struct bf_out_sink *k = cookie;
    int r = close(k->fd);
    if (r != 0 && !k->err)
        k->err = errno;
    return r;
}

static void reset(bf_outfile *o)
{
    free(o->path);
    free(o->target);
    free(o->tmp);
    free(o->sink);
    memset(o, 0, sizeof *o);
    o->handle = -1;
}

/* Opens the temporary (or, written through, the file itself) for t. */
static int open_fd(bf_outfile *o, out_target *t)
{
    if (t->kind == OUT_DIRECT)
        /* O_APPEND: a file reached through /dev/stdout keeps what was written there. */
        return open(t->file, O_WRONLY | O_NOCTTY | O_APPEND | O_CLOEXEC);
    /* A new file gets the mode a plain create would (0666 less the umask); a replaced
     * one is created no more open than it was, then given its exact mode and owner. */
    mode_t mode = t->kind == OUT_REGULAR ? t->st.st_mode & 0777 : 0666;
    int fd = bf_temp_create(t->file, 0, mode, &o->tmp, &o->handle);
    if (fd >= 0 && t->kind == OUT_REGULAR) {
        if ((t->st.st_uid != geteuid() || t->st.st_gid != getegid()) && fchown(fd, t->st.st_uid, t->st.st_gid) != 0) {
            /* Not allowed (not root): the file becomes ours, as any rewrite would. */
        }
        if (fchmod(fd, mode) != 0) {
            int e = errno;
            close(fd);
            unlink(o->tmp);
            bf_temp_forget(o->handle);
            o->handle = -1;
            errno = e;
            return -1;
        }
    }
    o->target = t->file;
    t->file = NULL;
    return fd;
}

bf_status bf_outfile_open(bf_outfile *o, const char *path, bf_error *err)
{
    memset(o, 0, sizeof *o);
    o->handle = -1;
    if (!path || strcmp(path, "-") == 0) {
        o->fp = stdout;
        return BF_OK;
    }
    out_target t;
    bf_status rc = out_resolve(path, &t, err);
    if (rc == BF_OK && (rc = out_writable(&t, path, err)) != BF_OK)
        out_target_clear(&t);
    if (rc != BF_OK)
        return rc;
    o->path = strdup(path);
    o->sink = calloc(1, sizeof *o->sink);
    if (!o->path || !o->sink) {
        out_target_clear(&t);
        reset(o);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    int direct = t.kind == OUT_DIRECT;
    int fd = open_fd(o, &t);
    int e = errno;
    out_target_clear(&t);
    if (fd < 0) {
        reset(o);
        return bf_fail(err, BF_ERR_IO,
                       direct ? "%s: cannot open: %s" : "%s: cannot create a temporary file beside it: %s", path,
                       strerror(e));
    }
    o->sink->fd = fd;
    static const cookie_io_functions_t io = {.write = sink_write, .close = sink_close};
    if (!(o->fp = fopencookie(o->sink, "w", io))) {
        close(fd);
        bf_outfile_abort(o);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    return BF_OK;
}

bf_status bf_outfile_commit(bf_outfile *o, bf_error *err)
{
    if (!o->sink) {
        if (fflush(o->fp) != 0 || ferror(o->fp))
            return bf_fail(err, BF_ERR_IO, "standard output: write error: %s", strerror(errno));
        return BF_OK;
    }
    struct bf_out_sink *k = o->sink;
    const char *what = "write error";
    int e = 0;
    if (fflush(o->fp) != 0 || ferror(o->fp))
        e = k->err ? k->err : EIO;
    /* The data on the disk before the name points at it. A written-through device or
     * FIFO has nothing to sync (EINVAL). */
    if (!e && fsync(k->fd) != 0 && (o->tmp || (errno != EINVAL && errno != EROFS)))
        e = errno;
    if (fclose(o->fp) != 0 && !e)
        e = k->err ? k->err : EIO;
    o->fp = NULL;
    if (!e && o->tmp && rename(o->tmp, o->target) != 0) {
        e = errno;
        what = "cannot move into place";
    }
    if (o->tmp) {
        if (e)
            unlink(o->tmp);
        else
            out_sync_folder(o->target);
        bf_temp_forget(o->handle);
    }
    bf_status rc = e ? bf_fail(err, BF_ERR_IO, "%s: %s: %s", o->path, what, strerror(e)) : BF_OK;
    reset(o);
    return rc;
}

void bf_outfile_abort(bf_outfile *o)
{
    if (o->sink) {
        if (o->fp)
            fclose(o->fp);
        if (o->tmp) {
            unlink(o->tmp);
            bf_temp_forget(o->handle);
        }
    }
    reset(o);
}

bf_status bf_outfile_check(const char *path, bf_error *err)
{
    if (!path || !strcmp(path, "-"))
        return BF_OK;
    out_target t;
    bf_status rc = out_resolve(path, &t, err);
    if (rc == BF_OK)
        rc = out_writable(&t, path, err);
    out_target_clear(&t);
    return rc;
}

const char *bf_format_double(double v, char *buf, size_t size)
{
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, size, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return buf;
}

void bf_csv_put_text(FILE *fp, const char *s)
{
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, fp);
        return;
    }
    fputc('"', fp);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', fp);
        fputc(*s, fp);
    }
    fputc('"', fp);
}

void bf_csv_put_list(FILE *fp, const char *items, size_t stride, int n)
{
    /* Quoted as a whole when any item needs it, so the field reads back as one. */
    int quote = 0;
    for (int i = 0; i < n; i++)
        quote |= strpbrk(items + (size_t)i * stride, ",\"\r\n") != NULL;
    fputc(',', fp);
    if (quote)
        fputc('"', fp);
    for (int i = 0; i < n; i++) {
        if (i)
            fputs("; ", fp);
        for (const char *s = items + (size_t)i * stride; *s; s++) {
            if (*s == '"' && quote)
                fputc('"', fp);
            fputc(*s, fp);
        }
    }
    if (quote)
        fputc('"', fp);
}

void bf_csv_put_number(FILE *fp, double v)
{
    char buf[40];
    fputc(',', fp);
    if (isfinite(v))
        fputs(bf_format_double(v, buf, sizeof buf), fp);
}
