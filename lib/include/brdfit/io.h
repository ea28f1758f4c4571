/* Reading and writing the files the commands exchange: numeric CSV tables, parameter
 * files (JSON), and output files that appear only when complete. */
#ifndef BRDFIT_IO_H
#define BRDFIT_IO_H

#include <stddef.h>
#include <stdio.h>

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
    char **names;   /* ncols header names */
    double *data;   /* nrows * ncols, row-major */
    size_t *line;   /* source line number of each row (for later error messages) */
} bf_csv;

int bf_csv_read(const char *path, bf_csv **out, bf_error *err);
void bf_csv_free(bf_csv *t);
int bf_csv_column(const bf_csv *t, const char *name); /* -1 if absent */

/* ---- Parameter files: {"model": "walter", "options": {"fresnel": "schlick"},
 * "channels": 3, "params": {"rho_d": [..C..], "alpha": 0.1, ...}}. Every parameter of
 * the configured model must be given, with one value per channel for colour
 * parameters, inside its bounds. Other top-level keys are ignored, so a fit result can
 * stand in for a parameter file. On success *model and *x (malloc'd, length
 * bf_model_nfree) belong to the caller. */
int bf_params_read(const char *path, bf_model **model, double **x, bf_error *err);

/* ---- Output written to a temporary file beside the target and renamed into place by
 * bf_outfile_commit, so a failed run leaves no partial file. path NULL or "-": stdout. */
typedef struct bf_outfile {
    FILE *fp;
    char *path, *tmp; /* NULL for stdout */
} bf_outfile;

int bf_outfile_open(bf_outfile *o, const char *path, bf_error *err);
int bf_outfile_commit(bf_outfile *o, bf_error *err); /* closes; renames into place */
void bf_outfile_abort(bf_outfile *o);                /* closes; removes the temporary */

/* Shortest decimal text that reads back as exactly v ("%.17g" at most). buf >= 32. */
const char *bf_format_double(double v, char *buf, size_t size);

/* CSV fields for the table writers: text quoted when it holds a comma, quote or line
 * break (RFC 4180); a number as ",v" (bf_format_double), or "," alone when not finite. */
void bf_csv_put_text(FILE *fp, const char *s);
void bf_csv_put_number(FILE *fp, double v);
/* n strings, each stride bytes apart from items on (a char [n][stride] array), as ",s"
 * with s the strings joined by "; " (quoted as bf_csv_put_text): one field for a list
 * such as a fit's warnings. */
void bf_csv_put_list(FILE *fp, const char *items, size_t stride, int n);

#ifdef __cplusplus
}
#endif
#endif
