/* The tradeoff's own run options (BF_TASK_TRADEOFF, brdfit tradeoff): how the table's
 * rows take and give them, and the lists a set holds, split, parsed and checked with the
 * command line's messages. In the fit layer because the table is and because the
 * methods are checked against the method registry; the tradeoff itself (study layer,
 * brdfit/tradeoff.h) reads them through options_tradeoff_get. */
#ifndef BRDFIT_TRADEOFF_OPTIONS_H
#define BRDFIT_TRADEOFF_OPTIONS_H

#include <stddef.h>

#include "brdfit/objective.h"
#include "brdfit/options.h"
#include "brdfit/solve.h"

/* The most items one list may hold. */
#define OPTIONS_TRADEOFF_MAX_LIST 64

/* The four lists, in this order everywhere: samples, methods, residuals, starts_list. */
enum { TRADEOFF_SAMPLES, TRADEOFF_METHODS, TRADEOFF_RESIDUALS, TRADEOFF_STARTS, TRADEOFF_NLISTS };

/* What a set of tradeoff options asks for, every list parsed (options_tradeoff_get). */
typedef struct options_tradeoff {
    /* Each list as used (owned, split in place), and its items (into it). */
    char *text[TRADEOFF_NLISTS];
    const char *items[TRADEOFF_NLISTS][OPTIONS_TRADEOFF_MAX_LIST];
    int n[TRADEOFF_NLISTS];
    size_t counts[OPTIONS_TRADEOFF_MAX_LIST]; /* 0: all */
    bf_residual residuals[OPTIONS_TRADEOFF_MAX_LIST];
    int starts[OPTIONS_TRADEOFF_MAX_LIST]; /* 0: brdfit fit's automatic count */
    double test_fraction;
    int repeats, cost_seconds, plot_width, plot_height;
} options_tradeoff;

/* The lists of o (given, or their defaults from the base setting) split and parsed, each
 * item checked (a method against the registry with the base's other settings), the
 * grid's size against BF_TRADEOFF_MAX_ROWS, and the other values read. BF_ERR_ARG with
 * a one-line message naming the list as o spells it. out is cleared on failure. */
bf_status options_tradeoff_get(const bf_options *o, options_tradeoff *out, bf_error *err);
void options_tradeoff_clear(options_tradeoff *t);
/* options_tradeoff_get's checks alone (bf_options_check's part for the tradeoff task). */
bf_status options_tradeoff_check(const bf_options *o, bf_error *err);

/* A method as the command line names it ("ceres", "ceres:dogleg", "LN_BOBYQA", ...)
 * set into so (backend and the registry's algorithm name), after checking it with so's
 * other settings (bf_solver_options_check); so is unchanged on error. */
bf_status bf_tradeoff_method_apply(const char *text, bf_solver_options *so, bf_error *err);

/* A count, digits only, with an optional k (thousands) suffix, from 1 to hi: 1, or 0. */
int options_tradeoff_count(const char *s, long hi, long *out);

/* The table's takers and givers of the tradeoff's rows (option_table.c). */
typedef struct option_row option_row;
/* A number or count in the row's range (a count may end in k), kept as given. */
bf_status options_tradeoff_set_number(bf_options *o, const option_row *r, const char *v, bf_error *err);
bf_status options_tradeoff_set_cost(bf_options *o, const option_row *r, const char *v, bf_error *err);
bf_status options_tradeoff_set_plot_size(bf_options *o, const option_row *r, const char *v, bf_error *err);
/* The value kept, or the row's default. */
void options_tradeoff_get_kept(const bf_options *o, const option_row *r, char *buf, size_t size);
/* The lists' defaults follow the base setting: methods its method if --backend or
 * --algorithm was given (else ceres,LD_LBFGS), residuals its residual, starts_list its
 * starts (or auto). */
void options_tradeoff_get_list(const bf_options *o, const option_row *r, char *buf, size_t size);

#endif
