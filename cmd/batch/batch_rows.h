/* One work item of brdfit batch as a row of the results database (batch_db.h), and the
 * conversions between a row and the comparison table (brdfit/compare.h) that compare's
 * writers read: a finished fit becomes a row, a row becomes the fit again. */
#ifndef BRDFIT_BATCH_ROWS_H
#define BRDFIT_BATCH_ROWS_H

#include <stddef.h>

#include "brdfit/compare.h"
#include "brdfit/error.h"

typedef struct batch_row {
    int item, material, model;
    int pending;            /* 1: not run yet (the other fields are empty) */
    bf_compare_state state; /* OK, FAILED or ERROR */
    char message[512];      /* ERROR: why */
    size_t samples;
    int channels;
    bf_metrics metrics;
    double cv, work;
    /* JSON texts (malloc'd, NULL when absent): the canonical spec is plain text;
     * warning_kinds the kinds of the warnings, by name, in their order (NULL in a row
     * stored before kinds were: batch_rows.c reads those from the texts). */
    char *spec, *params, *stderr_, *warnings, *options, *warning_kinds;
    const char *version; /* the tool's, as written (borrowed) */
    double seconds;      /* wall time of the fit: a timing, it decides nothing */
} batch_row;

/* Fills r from fit j of c's material 0 (after bf_compare_run) for item `item`:
 * malloc'd texts. BF_ERR_NOMEM. */
bf_status batch_row_from_fit(batch_row *r, const bf_compare *c, int j, bf_error *err);
void batch_row_clear(batch_row *r);

/* The fit of row r into f, its result rebuilt into res (model from the canonical spec
 * and channels, parameters, standard errors, warnings), f->result = res when the fit
 * ran. BF_ERR_PARSE for a row that cannot be read back. */
bf_status batch_row_to_fit(const batch_row *r, bf_compare_fit *f, bf_fit_result *res, bf_error *err);

/* A row as bytes and back, for sending a finished item from an MPI worker to the
 * coordinator (cmd/batch_mpi.c): every field the database stores, doubles as their bit
 * patterns (bit-exact, so the coordinator writes what a one-process run would), the
 * texts with their lengths (absent ones apart from empty ones). Processes of one job
 * share one architecture, so the bytes are in its order. batch_row_pack: a malloc'd
 * buffer in *buf, its size in *len (BF_ERR_NOMEM). batch_row_unpack: r from the bytes,
 * its texts malloc'd (clear it with batch_row_clear); BF_ERR_PARSE for bytes that are
 * not a packed row. */
bf_status batch_row_pack(const batch_row *r, unsigned char **buf, size_t *len, bf_error *err);
bf_status batch_row_unpack(const unsigned char *buf, size_t len, batch_row *r, bf_error *err);

#endif
