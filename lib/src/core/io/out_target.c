/* Output paths resolved to what they name (out_target.h). */
#include "io/out_target.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>
#include <sys/vfs.h>
#include <unistd.h>

#ifndef PROC_SUPER_MAGIC
#define PROC_SUPER_MAGIC 0x9fa0
#endif

char *out_dirname(const char *path)
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        return strdup(".");
    while (slash > path && slash[-1] == '/')
        slash--;
    size_t n = slash == path ? 1 : (size_t)(slash - path); /* "/x" -> "/" */
    char *d = malloc(n + 1);
    if (d) {
        memcpy(d, path, n);
        d[n] = '\0';
    }
    return d;
}

void out_sync_folder(const char *path)
{
    char *dir = out_dirname(path);
    int fd = dir ? open(dir, O_RDONLY | O_DIRECTORY | O_CLOEXEC) : -1;
    if (fd >= 0) {
        if (fsync(fd) != 0) {
            /* ignored, see above */
        }
        close(fd);
    }
    free(dir);
}

/* A link in /proc (/proc/self/fd/N, which /dev/stdout and /dev/fd/N lead to) names an
 * open file, not a path: it is written through, whatever it reaches. */
static int in_procfs(const char *link)
{
    char *dir = out_dirname(link);
    struct statfs fs;
    int yes = dir && statfs(dir, &fs) == 0 && fs.f_type == PROC_SUPER_MAGIC;
    free(dir);
    return yes;
}

/* The link's target as a path usable from here: absolute as read, or relative to the
 * folder holding the link. NULL with errno set. */
static char *follow(const char *link)
{
    char text[PATH_MAX];
    ssize_t n = readlink(link, text, sizeof text);
    if (n < 0)
        return NULL;
    if ((size_t)n >= sizeof text) {
        errno = ENAMETOOLONG;
        return NULL;
    }
    text[n] = '\0';
    if (text[0] == '/')
        return strdup(text);
    char *dir = out_dirname(link);
    char *next = dir ? malloc(strlen(dir) + (size_t)n + 2) : NULL;
    if (next)
        strcat(strcat(strcpy(next, dir), "/"), text);
    else
        errno = ENOMEM;
    free(dir);
    return next;
}

static bf_status io_fail(bf_error *err, const char *path, const char *file, int e)
{
    if (file && strcmp(file, path))
        return bf_fail(err, BF_ERR_IO, "%s (-> %s): cannot write: %s", path, file, strerror(e));
    return bf_fail(err, BF_ERR_IO, "%s: cannot write: %s", path, strerror(e));
}

/* file does not exist: BF_OK when its folder does (a new file may be made there). */
static bf_status new_file(const char *path, const char *file, bf_error *err)
{
    char *dir = out_dirname(file);
    if (!dir)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    struct stat st;
    int e = stat(dir, &st) != 0 ? errno : S_ISDIR(st.st_mode) ? 0 : ENOTDIR;
    bf_status rc = e ? bf_fail(err, BF_ERR_IO, "%s: cannot write in the folder %s: %s", path, dir, strerror(e)) : BF_OK;
    free(dir);
    return rc;
}

bf_status out_resolve(const char *path, out_target *t, bf_error *err)
{
    memset(t, 0, sizeof *t);
    if (!path || !*path)
        return bf_fail(err, BF_ERR_ARG, "an output file name is empty");
    char *cur = strdup(path);
    if (!cur)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    for (int hops = 0;; hops++) {
        struct stat lst;
        if (hops > 40) {
            free(cur);
            return io_fail(err, path, NULL, ELOOP);
        }
        if (lstat(cur, &lst) != 0) {
            int e = errno;
            if (e == ENOENT) {
                /* A new file: its folder must exist. */
                bf_status rc = new_file(path, cur, err);
                if (rc == BF_OK) {
                    t->kind = OUT_NEW;
                    t->file = cur;
                } else {
                    free(cur);
                }
                return rc;
            }
            io_fail(err, path, cur, e);
            free(cur);
            return BF_ERR_IO;
        }
        if (S_ISLNK(lst.st_mode)) {
            if (in_procfs(cur)) {
                /* Written through by this very name; stat reaches the open file. */
                int e = stat(cur, &t->st) != 0 ? errno : S_ISDIR(t->st.st_mode) ? EISDIR : 0;
                if (e) {
                    io_fail(err, path, NULL, e);
                    free(cur);
                    return BF_ERR_IO;
                }
                t->kind = OUT_DIRECT;
                t->file = cur;
                return BF_OK;
            }
            char *next = follow(cur);
            if (!next) {
                int e = errno;
                io_fail(err, path, cur, e);
                free(cur);
                return BF_ERR_IO;
            }
            free(cur);
            cur = next;
            continue;
        }
        if (S_ISDIR(lst.st_mode)) {
            bf_fail(err, BF_ERR_IO, "%s: is a folder, not a file", path);
            free(cur);
            return BF_ERR_IO;
        }
        t->kind = S_ISREG(lst.st_mode) ? OUT_REGULAR : OUT_DIRECT;
        t->file = cur;
        t->st = lst;
        return BF_OK;
    }
}

void out_target_clear(out_target *t)
{
    free(t->file);
    t->file = NULL;
}

bf_status out_writable(const out_target *t, const char *path, bf_error *err)
{
    if (t->kind != OUT_NEW && access(t->file, W_OK) != 0)
        return io_fail(err, path, t->file, errno);
    if (t->kind == OUT_DIRECT)
        return BF_OK;
    /* The temporary is created in the folder and renamed there. */
    char *dir = out_dirname(t->file);
    if (!dir)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    bf_status rc = BF_OK;
    if (access(dir, W_OK | X_OK) != 0) {
        int e = errno;
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot write in the folder %s: %s", path, dir, strerror(e));
    }
    free(dir);
    return rc;
}
