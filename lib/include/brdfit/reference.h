/* Published fits read beside brdfit's own: reference files, and a reference's error on a
 * material in exactly the terms of a fit's (brdfit compare --reference).
 *
 * A reference file is one of
 *  - a reference set: {"source": "Ngan, Durand & Matusik 2005 (EGSR)", "table":
 *    "ngan_ward", "materials": {"blue-acrylic": PARAMETER FILE, ...}}, each entry an
 *    ordinary parameter file (brdfit/io.h: model, options, channels, params);
 *  - a parameter file (a fit's result too): one reference for the material named by the
 *    file's stem, its source the file's "source" if it is a string (else the file as
 *    named), its table the file's "table" if it is a string (else none);
 *  - a directory: every "*.json" in it, in byte order of the names, each either of the
 *    above (folders inside it are not entered).
 * A reference's parameters may lie outside brdfit's bounds for the family: a published
 * fit is what it is, so it is read (finite values only) and the entries outside are
 * named in bf_reference.outside.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_REFERENCE_H
#define BRDFIT_REFERENCE_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/metrics.h"
#include "brdfit/model.h"
#include "brdfit/options.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

#define BF_REFERENCE_OUTSIDE_LEN 256

/* One published fit. Frozen (docs/api.md): an array element of bf_reference_set. */
typedef struct bf_reference {
    char *file;      /* the file it was read from, as named (owned) */
    int line;        /* the line its entry starts on (1 for a parameter file) */
    char *source;    /* who published it (owned) */
    char *table;     /* which of their tables (owned; NULL: none) */
    char *material;  /* the material it is a fit of (owned) */
    bf_model *model; /* its model, with its own channel count (owned) */
    double *x;       /* bf_model_nvalues(model) values (owned) */
    /* The entries outside the family's bounds, ", "-separated ("alpha, rho_s[2]"; cut
     * with "..." when long); "" when every entry is inside. */
    char outside[BF_REFERENCE_OUTSIDE_LEN];
} bf_reference;

/* References in the order read: files in the order given, a directory's files by name,
 * a set's materials in the file's order. Made by the library (docs/api.md). */
typedef struct bf_reference_set {
    int n;
    bf_reference *refs; /* n (owned) */
} bf_reference_set;

/* An empty set (BF_ERR_NOMEM only). */
BF_API bf_status bf_reference_set_new(bf_reference_set **out, bf_error *err);
/* Frees s and what it holds (NULL allowed). */
BF_API void bf_reference_set_free(bf_reference_set *s);

/* Reads the file or directory at path into s (appended). A bad file is a one-line error
 * naming the file, the line and the problem (BF_ERR_PARSE, BF_ERR_RANGE; BF_ERR_IO when
 * it cannot be read; an empty directory or one without "*.json" is BF_ERR_ARG); s then
 * holds what it held before. */
BF_API bf_status bf_reference_read(bf_reference_set *s, const char *path, bf_error *err);
/* The same for text in memory; name stands for the file (in messages and .file, and its
 * stem names a parameter file's material; NULL: "references"). */
BF_API bf_status bf_reference_parse(bf_reference_set *s, const char *text, const char *name, bf_error *err);

/* The material name of a data file, as references name materials: its name without
 * folders and without its last extension ("data/blue-acrylic.binary": "blue-acrylic").
 * Returns buf. */
BF_API const char *bf_reference_material(const char *data, char *buf, size_t size);
/* 1 when r is a fit of material (a name as bf_reference_material gives) with the model
 * spec (any spelling: compared as canonical specs, channel counts aside). */
BF_API int bf_reference_matches(const bf_reference *r, const char *material, const char *spec);

/* What a fit is judged by, at r's parameters on samples s, with the fitting options o
 * (any task but BF_TASK_READ) as bf_fit(s, spec, o) judges its own solution: *cost the
 * objective it minimises, 1/2 sum rho(r_i^2) over the residuals of its form, weights
 * (the samples', solid-angle and scene weights) and robust loss (its solution's
 * final_cost); *metrics what its result reports (rmse, rmse_log, ... over the scene's
 * directions as the scene weighs them when there is one; k counts the free entries).
 * Parameters outside the bounds are evaluated as they are (a NaN or infinite cost is
 * possible). BF_ERR_ARG when r's channel count is not the samples'. */
BF_API bf_status bf_reference_evaluate(const bf_reference *r, bf_samples *s, const bf_options *o, double *cost,
                                       bf_metrics *metrics, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
