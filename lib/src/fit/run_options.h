/* The options of a run (brdfit/options.h) inside the library: the set's values, the
 * table's rows, and the structs the readers, the preprocessing and the fit take, derived
 * from a set with its couplings applied (the seed shared by the subsample and the
 * search, an --accuracy preset where the user set nothing, a scene's weighted metrics,
 * folds only for a cross-validated ranking). */
#ifndef BRDFIT_RUN_OPTIONS_H
#define BRDFIT_RUN_OPTIONS_H

#include "brdfit/compare.h"
#include "brdfit/fit.h"
#include "fit_impl.h"
#include "brdfit/formats.h"
#include "brdfit/options.h"
#include "brdfit/prep.h"
#include "io/read_options.h"
#include "samples/prep_options.h"

#define OPTION_ROWS_MAX 64

/* One value set, as given (copies and resets set them again, in order). */
typedef struct option_set {
    int row;
    char *value; /* NULL for a flag without a value */
} option_set;

struct bf_options {
    bf_task task;
    bf_option_spelling spelling;
    unsigned char given[OPTION_ROWS_MAX]; /* by row: set by the user */
    char *text[OPTION_ROWS_MAX];          /* by row: a TEXT option's value (owned), or NULL */
    /* Reading and preparing. */
    bf_format format;
    int radians, keep_origin;
    int spectral_row; /* the row that chose what spectral data becomes (rgb, color,
                         rgb_bands, luminance), or -1 */
    bf_color color;
    int to_bands, to_luminance;
    bf_illuminant illuminant;
    double max_theta;
    bf_negative negative;
    size_t subsample; /* 0: every sample */
    uint64_t seed;
    /* Fitting. */
    bf_residual residual;
    bf_loss loss;
    bf_override *overrides; /* noverrides, owned: fix entries, then bound entries, in order */
    int noverrides;
    int solid_angle, no_weights, use_constraint;
    bf_backend backend;
    int max_iterations, starts, screen, threads;
    long presolve;
    bf_fit_accuracy accuracy;
    unsigned fit_given; /* BF_FIT_GIVEN_*: what a preset gives way to */
    /* Ranking, comparing, selecting. */
    bf_compare_rank_by rank_by;
    int folds, timing, jobs;
    bf_compare_metric metric;
    double tolerance, abs_tolerance;
    option_set *log; /* every value set, in order (nlog) */
    int nlog;
    double *start; /* nstart values (owned), or NULL */
    int nstart;
    /* Hooks. */
    const bf_cancel_flag *cancel, *finish;
    bf_progress_fn progress;
    void *progress_user;
    bf_progress_report_fn report;
    void *report_user;
};

/* One row of the table: the public declaration and how it is taken. */
typedef struct option_row option_row;
struct option_row {
    bf_option d;
    /* NULL: by d.type into the field at `at` (FLAG: an int set to flag_on or cleared,
     * INT: an int, NUMBER: a double, TEXT: o->text[row]). */
    bf_status (*set)(bf_options *o, const option_row *r, const char *value, bf_error *err);
    /* NULL: by d.type from the field (a TEXT: its text). */
    void (*get)(const bf_options *o, const option_row *r, char *buf, size_t size);
    size_t at;
    int flag_on;
    unsigned fit_given; /* BF_FIT_GIVEN_* or'ed into o->fit_given when set */
};

extern const option_row option_rows[];
extern const int option_nrows;

/* The row's index in option_rows. */
int option_row_index(const option_row *r);
/* The option's name as the set's messages spell it, into buf. */
const char *option_spelled(const bf_options *o, const char *name, char *buf, size_t size);
/* v kept (copied) as row r's text in o. */
bf_status option_keep_text(bf_options *o, const option_row *r, const char *v, bf_error *err);
/* Value k (from 0) set for the rows called name, in the order set (NULL past the last):
 * a repeatable option's values. */
const char *option_list_value(const bf_options *o, const char *name, int k);
/* The text of a TEXT row of o by name (NULL when not set). */
const char *option_text(const bf_options *o, const char *name);

/* What reading takes: the format, the CSV mapping (angles split into buf) and the grid. */
typedef struct options_reading {
    bf_read_options read;
    char angles[1024];
} options_reading;
void options_read_get(const bf_options *o, options_reading *out);
/* The preprocessing, the preset's subsample included. */
void options_prep_get(const bf_options *o, bf_prep *out);
/* The scene file, or NULL. */
const char *options_scene(const bf_options *o);
/* The fit, everything applied (overrides point into o). */
void options_fit_get(const bf_options *o, bf_fit_options *out);
/* Folds of the cross-validation: o->folds when ranking by cv, else 0. */
int options_folds(const bf_options *o);

#endif
