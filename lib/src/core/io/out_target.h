/* What an output path names once symbolic links are followed: the file a temporary
 * replaces, or a device, FIFO or standard stream written through. Used by bf_outfile
 * and by the checks made before long work (bf_outputs_check). */
#ifndef BRDFIT_OUT_TARGET_H
#define BRDFIT_OUT_TARGET_H

#include <sys/stat.h>

#include "brdfit/error.h"

typedef enum out_kind {
    OUT_NEW,     /* nothing there yet: a new regular file is created */
    OUT_REGULAR, /* an existing regular file, replaced by a rename */
    OUT_DIRECT   /* anything else (device, FIFO, socket, an open file named through
                    /proc/self/fd or /dev/stdout): written through, never replaced */
} out_kind;

typedef struct out_target {
    out_kind kind;
    char *file;     /* malloc'd: OUT_NEW, OUT_REGULAR: the file, links followed (the
                       temporary goes beside it); OUT_DIRECT: the name to open */
    struct stat st; /* OUT_REGULAR, OUT_DIRECT: the file as open() would reach it */
} out_target;

/* Follows path's links (at most 40) to what an output would write. Errors (BF_ERR_IO,
 * naming path): a folder, a loop, a missing parent folder, lstat/readlink failures;
 * BF_ERR_ARG for an empty name. */
bf_status out_resolve(const char *path, out_target *t, bf_error *err);
void out_target_clear(out_target *t);

/* Whether the output can be written: a replaced or new file needs its folder writable
 * (and an existing file writable, as a plain open would); a written-through one needs
 * write permission. Checked with access(), so nothing is created. BF_ERR_IO naming
 * path on failure. */
bf_status out_writable(const out_target *t, const char *path, bf_error *err);

/* After a rename into place: the folder holding path is synced so that the new entry
 * reaches the disk too (best effort: some file systems cannot sync a folder, and the
 * file itself is synced already). */
void out_sync_folder(const char *path);

/* The folder part of path ("." when it has none) into a malloc'd string; NULL when out
 * of memory. */
char *out_dirname(const char *path);

#endif
