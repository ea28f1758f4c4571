/* Regression baselines: a JSON file listing data files, fit settings and the expected
 * parameters and metrics with tolerances; checking fit results against it, rewriting it
 * with new results, and a JUnit XML report for CI systems.
 *
 * The caller runs the fits (options are brdfit fit's, parsed by the command); this
 * layer only reads the baseline, compares bf_fit_results with it and writes files.
 *
 * {"brdfit_baseline": 1,
 *  "tolerance": {"params": {"rel": 1e-6, "abs": 1e-9}, "metrics": {"rel": 1e-6, "abs": 1e-12}},
 *  "cases": [{"name": "cayman-walter", "data": "../cornell/cayman.brdf", "model": "walter",
 *             "options": ["--rgb", "--seed", "1"],
 *             "tolerance": {"params": {"alpha": {"rel": 1e-4}}},
 *             "expected": {"ok": true, "params": {"alpha": 0.12, ...}, "metrics": {"rmse": ...}}}]}
 *
 * A value passes when |got - expected| <= abs + rel |expected|. Tolerances resolve from
 * the most general to the most specific: built-in defaults, the file's group ("params"
 * or "metrics") rel/abs, the file's per-name entry, the case's group rel/abs, the case's
 * per-name entry; each layer may set rel, abs or both.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_REGRESS_H
#define BRDFIT_REGRESS_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/fit.h"
#include "brdfit/options.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Built-in defaults, used where the file sets nothing. */
#define BF_REGRESS_PARAMS_REL 1e-6
#define BF_REGRESS_PARAMS_ABS 1e-9
#define BF_REGRESS_METRICS_REL 1e-6
#define BF_REGRESS_METRICS_ABS 1e-12

/* Frozen (docs/api.md): a small value. */
typedef struct bf_tolerance {
    double rel, abs;
} bf_tolerance;

/* One expected quantity: a parameter (scalar, or one value per channel) or a metric.
 * null in the file (a non-finite value) reads as NaN. Frozen (docs/api.md): an array element of bf_regress_case. */
typedef struct bf_regress_value {
    char *name;
    int n;     /* values */
    int array; /* written as an array (colour parameters) */
    double *v;
    int line;
} bf_regress_value;

/* Frozen (docs/api.md): an array element of bf_regress_baseline. */
typedef struct bf_regress_case {
    char *name;
    char *data;      /* as written */
    char *data_path; /* resolved against the baseline's folder */
    char *model;     /* model spec, as for brdfit fit -m (one model) */
    int noptions;
    char **options;    /* brdfit fit's data and fit options, as written */
    int *option_lines; /* line of each option in the baseline */
    int line, data_line, model_line, options_line;
    int expect_ok; /* expected.ok (default true) */
    int nparams, nmetrics;
    bf_regress_value *params, *metrics; /* only those the case pins */
} bf_regress_case;

typedef struct bf_regress_baseline {
    char *path; /* as given */
    char *dir;  /* folder that relative paths in the file start from */
    int ncases;
    bf_regress_case *cases;
    void *doc;  /* internal (the parsed file, a cJSON tree): tolerances and order survive an update */
    char *text; /* the file's text (line numbers of later messages) */
} bf_regress_baseline;

/* Metric names a baseline may pin ("n" and "k" are compared like the others). */
extern BF_API const char *const bf_regress_metric_names[];
extern BF_API const int bf_regress_nmetric_names;

/* Reads and checks a baseline: structure, types, known keys, unique case names, model
 * specs, tolerances >= 0. Errors name the file and line. bf_regress_parse does the same
 * on text already in memory (path: for messages and the relative-path folder). */
BF_API bf_status bf_regress_load(const char *path, bf_regress_baseline **out, bf_error *err);
BF_API bf_status bf_regress_parse(const char *text, const char *path, bf_regress_baseline **out, bf_error *err);
BF_API void bf_regress_baseline_free(bf_regress_baseline *b);

/* path resolved against the baseline's folder (absolute paths unchanged); malloc'd. */
BF_API char *bf_regress_resolve(const bf_regress_baseline *b, const char *path);

/* Case c's run options, the rules every runner of baselines shares: brdfit fit's data
 * and fit options (those BF_TASK_FIT takes), written as the command line writes them ("--max-theta 80" or
 * "--max-theta=80"); threads 1 unless the case sets it, so that results are the same on
 * every machine; --scene relative to the baseline's folder, as the data; the case's data
 * file readable and its scene file valid, so that a bad baseline is found before any
 * fit. -m and -o have no place there (the case's "model" names the model). Errors name
 * the baseline's file and line ("b.json:12: case 'felt': unknown option '--x' (...)");
 * *out (bf_options_free) is NULL then. */
BF_API bf_status bf_regress_case_options(const bf_regress_baseline *b, int c, bf_options **out, bf_error *err);

/* Line of a value in the file: JSON path segments separated by '/', array elements by
 * index, e.g. "cases/0/options/3"; the line of the deepest segment found (1 if none). */
BF_API int bf_regress_line(const bf_regress_baseline *b, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/* The tolerance for a quantity of case c; group "params" or "metrics". */
BF_API bf_tolerance bf_regress_tolerance(const bf_regress_baseline *b, int c, const char *group, const char *name);

typedef enum bf_regress_status {
    BF_REGRESS_PASS = 0,
    BF_REGRESS_FAIL,    /* ran; something moved beyond tolerance or the structure differs */
    BF_REGRESS_ERROR,   /* could not run (data unreadable, fit error) */
    BF_REGRESS_SKIPPED, /* not selected */
} bf_regress_status;

/* What one case did. The caller sets it up with bf_regress_outcome_init (its size:
 * docs/api.md); an array of them passed to the library is read with that size as its
 * stride. */
typedef struct bf_regress_outcome {
    size_t size; /* sizeof, set by bf_regress_outcome_init */
    bf_regress_status status;
    double seconds;
    int nlines;
    char **lines; /* FAIL: one per quantity that moved ("params.alpha: expected ...");
                       ERROR: the reason */
    int nchecked;
    char **checked; /* every compared value, passing or not (for --verbose) */
    int nwarnings;
    char **warnings; /* the fit's diagnostics (fit.h), whatever the status */
} bf_regress_outcome;

/* Compares r with case c's expectations: fills out (status PASS or FAIL, the lines,
 * the fit's warnings).
 * Expected ok false passes when the fit failed (values unchecked) and fails when it
 * succeeded. Returns BF_OK unless memory runs out. */
BF_API bf_status bf_regress_check(const bf_regress_baseline *b, int c, const bf_fit_result *r, bf_regress_outcome *out,
                                  bf_error *err);
/* Marks case c as not runnable with message (status ERROR). */
BF_API bf_status bf_regress_set_error(bf_regress_outcome *out, const char *message, bf_error *err);
BF_API void bf_regress_outcome_clear(bf_regress_outcome *out);
BF_API void bf_regress_outcome_init_size(bf_regress_outcome *out, size_t size);
static inline void bf_regress_outcome_init(bf_regress_outcome *out)
{
    bf_regress_outcome_init_size(out, sizeof *out);
}

/* Sets case c's expectations to r in the document: expected.ok; the parameters and
 * metrics the case pins (every one when it pins none of the group, and the model's own
 * names and channel count where they differ). A failed fit (r->ok 0) sets ok false and
 * leaves the values. Appends one line per change to *changes ("params.alpha: 0.12 ->
 * 0.1201"; caller frees each and the array). */
BF_API bf_status bf_regress_update(bf_regress_baseline *b, int c, const bf_fit_result *r, char ***changes,
                                   int *nchanges, bf_error *err);
/* Writes the document (2-space indent, arrays of scalars on one line, numbers that
 * read back exactly) to path through a temporary file. */
BF_API bf_status bf_regress_write(const bf_regress_baseline *b, const char *path, bf_error *err);

/* JUnit XML: <testsuites><testsuite name="brdfit regress" tests failures errors time>,
 * one <testcase name classname=(baseline path) time> per case not skipped, <failure>
 * holding the diff lines, <error> the reason a case could not run, <system-out> the
 * fit's warnings. Written through a temporary file. */
BF_API bf_status bf_regress_write_junit(const bf_regress_baseline *b, const bf_regress_outcome *outs, const char *path,
                                        bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
