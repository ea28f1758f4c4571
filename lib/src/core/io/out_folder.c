/* Output folders written whole or not at all (out_folder.h).
 *
 * Decisions:
 *  - The folder is built under a registered temporary sibling (DIR.tmp.XXXXXX, removed
 *    by a fatal signal too) and renamed into place at the end: a failed run leaves no
 *    folder and no partial one, and an old folder stays whole until the new one
 *    replaces it.
 *  - An existing DIR is replaced only when it holds the marker file (a previous run's
 *    folder) or is empty; anything else is refused, so a typo cannot wipe a user's
 *    folder. It is checked again just before the rename.
 *  - Messages about files in the folder being built name them as the folder will have
 *    them. */
#define _GNU_SOURCE /* renameat2 */
#include "io/out_folder.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "brdfit/io.h"
#include "io/out_target.h"
#include "io/temp_registry.h"

/* The longest folder name taken (without trailing slashes). */
enum { TARGET_MAX = 4000 };

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *f)
{
    (void)st;
    (void)flag;
    (void)f;
    return remove(path);
}

static void remove_tree(const char *path)
{
    nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* 1: DIR may be replaced (it holds the marker, or is empty); 0: it may not; -1: not there. */
static int replaceable(const char *dir, const char *marker)
{
    struct stat st;
    if (lstat(dir, &st) != 0)
        return errno == ENOENT ? -1 : 0;
    if (!S_ISDIR(st.st_mode))
        return 0;
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", dir, marker) < (int)sizeof path && access(path, F_OK) == 0)
        return 1;
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    struct dirent *e;
    int empty = 1;
    while (empty && (e = readdir(d)))
        empty = !strcmp(e->d_name, ".") || !strcmp(e->d_name, "..");
    closedir(d);
    return empty;
}

bf_status bf_out_folder_check(const char *dir, const char *marker, const char *what, bf_error *err)
{
    if (!what)
        what = "output";
    if (!dir || !*dir)
        return bf_fail(err, BF_ERR_ARG, "%s folder: empty name", what);
    if (!marker || !*marker)
        return bf_fail(err, BF_ERR_ARG, "%s: no marker file named", dir);
    if (replaceable(dir, marker) == 0)
        return bf_fail(err, BF_ERR_IO, "%s: exists and is not a brdfit %s (no %s): not replacing it", dir, what,
                       marker);
    /* The folder is built beside DIR and renamed there: the parent must take it. */
    size_t len = strlen(dir);
    while (len > 1 && dir[len - 1] == '/')
        len--;
    char *target = strndup(dir, len), *parent = target ? out_dirname(target) : NULL;
    bf_status rc = BF_OK;
    if (!parent)
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
    else if (access(parent, W_OK | X_OK) != 0)
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot write in the folder %s: %s", dir, parent, strerror(errno));
    free(target);
    free(parent);
    return rc;
}

static void clear(bf_out_folder *f)
{
    *f = (bf_out_folder){.handle = -1};
}

bf_status bf_out_folder_begin(bf_out_folder *f, const char *dir, const char *marker, const char *what,
                              const char *marker_text, bf_error *err)
{
    clear(f);
    if (!what)
        what = "output";
    bf_status rc = bf_out_folder_check(dir, marker, what, err);
    if (rc != BF_OK)
        return rc;
    size_t len = strlen(dir);
    while (len > 1 && dir[len - 1] == '/')
        len--;
    if (len >= TARGET_MAX)
        return bf_fail(err, BF_ERR_ARG, "%s: path too long", dir);
    f->target = strndup(dir, len);
    if (!f->target)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
    /* Registered, so a fatal signal removes it with whatever it holds. */
    if (bf_temp_create(f->target, 1, 0777, &f->tmp, &f->handle) < 0) {
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot create the %s folder: %s", f->target, what, strerror(errno));
        free(f->target);
        clear(f);
        return rc;
    }
    f->marker = marker;
    f->what = what;

    char path[4200];
    bf_outfile mk;
    if ((rc = bf_out_folder_path(f, marker, path, sizeof path, err)) == BF_OK &&
        (rc = bf_outfile_open(&mk, path, err)) == BF_OK) {
        const char *text = marker_text ? marker_text : "";
        size_t n = strlen(text);
        fputs(text, mk.fp);
        if (!n || text[n - 1] != '\n')
            fputc('\n', mk.fp);
        rc = bf_outfile_commit(&mk, err);
    }
    return rc == BF_OK ? BF_OK : bf_out_folder_end(f, rc, err);
}

bf_status bf_out_folder_path(const bf_out_folder *f, const char *name, char *buf, size_t size, bf_error *err)
{
    if (!f || !f->tmp || !name)
        return bf_fail(err, BF_ERR_ARG, "output folder: not begun");
    int n = snprintf(buf, size, "%s/%s", f->tmp, name);
    if (n < 0 || (size_t)n >= size)
        return bf_fail(err, BF_ERR_ARG, "%s: path too long", f->tmp);
    return BF_OK;
}

/* Puts the finished folder tmp at target. An old folder there is exchanged with it in one
 * step where the file system can (RENAME_EXCHANGE: the old one is then at tmp, still
 * registered, and removed by the caller); otherwise it is moved aside to a registered
 * temporary and the new one renamed in, with fatal signals held off between the two
 * renames so that target is never left missing. *aside: where the old folder went. */
static bf_status swap_in(const char *tmp, const char *target, const char *what, int had, char **aside,
                         int *aside_handle, bf_error *err)
{
    *aside = NULL;
    if (had != 1)
        return rename(tmp, target) == 0
                   ? BF_OK
                   : bf_fail(err, BF_ERR_IO, "%s: cannot rename the %s into place: %s", target, what, strerror(errno));
    if (renameat2(AT_FDCWD, tmp, AT_FDCWD, target, RENAME_EXCHANGE) == 0)
        return BF_OK;
    if (bf_temp_create(target, 1, 0700, aside, aside_handle) < 0)
        return bf_fail(err, BF_ERR_IO, "%s: cannot move the previous %s aside: %s", target, what, strerror(errno));
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    bf_status rc = BF_OK;
    if (rename(target, *aside) != 0)
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot move the previous %s aside: %s", target, what, strerror(errno));
    else if (rename(tmp, target) != 0) {
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot rename the %s into place: %s", target, what, strerror(errno));
        if (rename(*aside, target) != 0) {
            /* The old folder stays at *aside; the message above stands. */
        }
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc != BF_OK) {
        rmdir(*aside);
        bf_temp_forget(*aside_handle);
        free(*aside);
        *aside = NULL;
    }
    return rc;
}

/* A message about a file in the folder being built names it as the folder will have it:
 * "DIR/index.html", not "DIR.tmp.XXXXXX/index.html". */
static void name_target(bf_error *err, const char *tmp, const char *target)
{
    char *at = err ? strstr(err->msg, tmp) : NULL;
    if (!at)
        return;
    char rest[sizeof err->msg];
    snprintf(rest, sizeof rest, "%s", at + strlen(tmp));
    snprintf(at, sizeof err->msg - (size_t)(at - err->msg), "%s%s", target, rest);
}

bf_status bf_out_folder_end(bf_out_folder *f, bf_status rc, bf_error *err)
{
    if (!f->tmp) { /* never begun, or begun and failed (cleared) */
        free(f->target);
        clear(f);
        return rc;
    }
    const char *what = f->what ? f->what : "output";
    /* Into place; an old folder is removed only once the new one is in. */
    int had = rc == BF_OK ? replaceable(f->target, f->marker) : -1;
    if (rc == BF_OK && had == 0)
        rc = bf_fail(err, BF_ERR_IO, "%s: appeared while the %s was written and is not a brdfit %s", f->target, what,
                     what);
    char *aside = NULL;
    int aside_handle = -1;
    if (rc == BF_OK && (rc = swap_in(f->tmp, f->target, what, had, &aside, &aside_handle, err)) == BF_OK)
        out_sync_folder(f->target);
    if (rc != BF_OK || had == 1)
        remove_tree(f->tmp); /* the failed folder, or the old one exchanged out */
    if (rc != BF_OK)
        name_target(err, f->tmp, f->target);
    bf_temp_forget(f->handle);
    free(f->tmp);
    free(f->target);
    clear(f);
    if (aside) {
        remove_tree(aside);
        bf_temp_forget(aside_handle);
        free(aside);
    }
    return rc;
}
