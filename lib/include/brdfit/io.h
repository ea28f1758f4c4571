/* Reading and writing the files the commands exchange: numeric CSV tables, parameter
 * files (JSON), and output files that appear only when complete.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_IO_H
#define BRDFIT_IO_H

#include <stddef.h>
#include <stdio.h>

#include "brdfit/formats.h"
#include "brdfit/error.h"
#include "brdfit/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- CSV: a header row, then numeric rows; '#' comment lines and blank lines are
 * skipped. Fields may be quoted (RFC 4180: "a,b", "say ""hi"""), within one line;
 * header names are any text, numbers too ("400" nm), unless the whole row is numbers
 * (a file without a header); at most BF_CSV_MAX_COLUMNS. Errors name the file, the
 * line and the column. */
typedef struct bf_csv {
    size_t nrows, ncols;
    char **names; /* ncols header names */
    double *data; /* nrows * ncols, row-major */
    size_t *line; /* source line number of each row (for later error messages) */
} bf_csv;

BF_API bf_status bf_csv_read(const char *path, bf_csv **out, bf_error *err);
BF_API void bf_csv_free(bf_csv *t);
BF_API int bf_csv_column(const bf_csv *t, const char *name); /* -1 if absent */

/* ---- Parameter files: {"model": "walter", "options": {"fresnel": "schlick"},
 * "channels": 3, "params": {"rho_d": [..C..], "alpha": 0.1, ...}}. Every parameter of
 * the configured model must be given, with one value per channel for colour
 * parameters, inside its bounds. Other top-level keys are ignored, so a fit result can
 * stand in for a parameter file. On success *model and *x (malloc'd, length
 * bf_model_nvalues) belong to the caller. */
BF_API bf_status bf_params_read(const char *path, bf_model **model, double **x, bf_error *err);
/* The same from text in memory (a fit's bf_fit_result_json); name stands for the file
 * in messages ("name:LINE: problem"; NULL: "parameters"). *x is freed with bf_free. */
BF_API bf_status bf_params_parse(const char *text, const char *name, bf_model **model, double **x, bf_error *err);

/* ---- Outputs that survive failures. bf_outfile_open resolves path: a regular file
 * (symbolic links followed: the file a link points to is replaced, the link stays) is
 * written to a new temporary "<file>.tmp.XXXXXX" beside it; bf_outfile_commit checks
 * every write (the first error's cause is kept), fsyncs, closes and renames it into
 * place, so the old file stays whole until the new one is complete, keeping its mode
 * (and owner where allowed; a new file gets 0666 less the umask). Anything that is not
 * a regular file (a device such as /dev/null, a FIFO, /dev/stdout) is opened and
 * written through, never replaced; what a failed write-through wrote cannot be taken
 * back. A folder, an empty name, a missing or unwritable folder or an existing file
 * without write permission fail at open (BF_ERR_ARG for the empty name, else
 * BF_ERR_IO, naming path). path NULL or "-": standard output. Temporaries are
 * registered so that bf_remove_temporaries_on_signals (brdfit/tool.h) can remove them. */
struct bf_out_sink;
/* Frozen (docs/api.md): declared by the caller, opened by bf_outfile_open. */
typedef struct bf_outfile {
    FILE *fp;
    char *path;               /* as given (messages); NULL for standard output */
    char *target;             /* the file replaced, links followed; NULL: written through */
    char *tmp;                /* the temporary beside target */
    struct bf_out_sink *sink; /* the descriptor under fp and the first write error */
    int handle;               /* the temporary's registration */
} bf_outfile;

BF_API bf_status bf_outfile_open(bf_outfile *o, const char *path, bf_error *err);
BF_API bf_status bf_outfile_commit(bf_outfile *o, bf_error *err); /* closes; renames into place */
BF_API void bf_outfile_abort(bf_outfile *o);                      /* closes; removes the temporary */

/* Whether bf_outfile_open(path) could write (nothing is created: access() on the
 * folder and the file), so a command can fail before long work. */
BF_API bf_status bf_outfile_check(const char *path, bf_error *err);

/* Shortest decimal text that reads back as exactly v ("%.17g" at most). buf >= 32. */
BF_API const char *bf_format_double(double v, char *buf, size_t size);

/* Opens an input for reading: a file, or standard input for "-" (read whole on the first
 * open and kept, so that it can be opened again: every reader takes "-"). NULL with errno
 * set when it cannot; a device (/dev/zero, a terminal: some never end) is refused with
 * ENODEV. bf_input_error(errno) says why, for a message. */
BF_API FILE *bf_input_open(const char *path);
BF_API const char *bf_input_error(int e);

#ifdef __cplusplus
}
#endif
#endif
