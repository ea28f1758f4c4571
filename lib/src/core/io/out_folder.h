/* An output folder written whole or not at all (internal): the HTML report of
 * `brdfit compare --html`, the output of `brdfit fit-images`.
 *
 * The folder is built under a registered temporary sibling "DIR.tmp.XXXXXX" (removed by a
 * fatal signal too, temp_registry.h) and renamed into place at the end, so a failed run
 * leaves nothing and an old folder stays whole until the new one replaces it. An existing
 * DIR is replaced only when it holds the marker file (a previous run's folder) or is
 * empty: a typo cannot wipe a user's folder.
 *
 * Use: bf_out_folder_begin, files written at bf_out_folder_path (through bf_outfile),
 * then bf_out_folder_end with the status of the whole, whatever it is. */
#ifndef BRDFIT_OUT_FOLDER_H
#define BRDFIT_OUT_FOLDER_H

#include <stddef.h>

#include "brdfit/error.h"

typedef struct bf_out_folder {
    char *target;       /* the folder as named, trailing slashes removed (malloc'd) */
    char *tmp;          /* the registered temporary sibling being filled (malloc'd) */
    int handle;         /* its temp_registry handle */
    const char *marker; /* the marker file's name (not owned) */
    const char *what;   /* the kind of folder in messages, as given to begin (not owned) */
} bf_out_folder;

/* Whether dir may be written: it does not exist, or is an empty folder, or holds the marker
 * file; and its parent folder is writable. what names the kind of folder in messages
 * ("report", "fit-images output"): "DIR: exists and is not a brdfit WHAT (no MARKER): not
 * replacing it"; "WHAT folder: empty name" (BF_ERR_ARG); "DIR: cannot write in the folder
 * PARENT: REASON". Nothing is created. */
bf_status bf_out_folder_check(const char *dir, const char *marker, const char *what, bf_error *err);

/* Checks (as above), creates the temporary sibling and writes the marker file in it with
 * marker_text (a line saying the folder is replaced by the next run; a newline is added if
 * it has none). marker and what must outlive f. On failure nothing is left behind and f is
 * cleared (bf_out_folder_end on it is harmless and returns its rc). */
bf_status bf_out_folder_begin(bf_out_folder *f, const char *dir, const char *marker, const char *what,
                              const char *marker_text, bf_error *err);

/* A path inside the folder being built: "TMP/name" into buf; BF_ERR_ARG if too long. */
bf_status bf_out_folder_path(const bf_out_folder *f, const char *name, char *buf, size_t size, bf_error *err);

/* rc == BF_OK: renames the folder into place (an old one there, which must still hold the
 * marker or be empty, is exchanged with it in one step where the file system can, else moved
 * aside with fatal signals held off, and removed once the new one is in) and returns its
 * status; otherwise (a failure or cancellation before) removes the temporary and returns rc
 * unchanged. Either way, when the status returned is a failure, err's message, if it names
 * the temporary, is rewritten to name the target ("DIR/index.html", not
 * "DIR.tmp.XXXXXX/index.html"), and f is cleared (frees target and tmp, forgets the
 * registration). */
bf_status bf_out_folder_end(bf_out_folder *f, bf_status rc, bf_error *err);

#endif
