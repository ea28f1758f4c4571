/* The options of a run (reading and preparing data, fitting, comparing, selecting,
 * measuring cost against accuracy), in one place: a table that declares each option once
 * (name, type, range, default, help) and an opaque set of values checked against it. The
 * command line's options, its --help, man pages and completion, and the Python package's
 * keyword arguments all come from this table (docs/api.md), so they mean, allow and
 * refuse the same.
 *
 *     bf_options *o;
 *     bf_options_new(BF_TASK_FIT, &o, &err);
 *     bf_options_set(o, "rgb", NULL, &err);            flags take NULL (or "true")
 *     bf_options_set(o, "scene", "turntable.json", &err);
 *     bf_options_set(o, "max_theta", "80", &err);      values as text, as typed
 *     bf_options_check(o, &err);                       the couplings (optional: every
 *                                                      function that takes o checks)
 *     bf_samples_load("cayman.brdf", o, &s, NULL, &err);
 *     bf_fit_result_init(&r);
 *     bf_fit(s, "walter", o, &r, &err);
 *     bf_options_free(o);
 *
 * Values are copied: the caller's strings need not outlive the call. A set of options
 * may be read by several threads at once (fits running in parallel); setting a value
 * while another thread uses the options is not allowed.
 * Status codes and ownership follow brdfit/error.h. */
#ifndef BRDFIT_OPTIONS_H
#define BRDFIT_OPTIONS_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/solve.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What a set of options is for: it takes the options of its task (each option says
 * which, bf_option.tasks) and has its task's defaults (compare ranks by bic, select by
 * error). */
typedef enum bf_task {
    BF_TASK_READ = 1u << 0,     /* reading and preparing data (brdfit info, convert) */
    BF_TASK_FIT = 1u << 1,      /* and fitting (brdfit fit, regress) */
    BF_TASK_COMPARE = 1u << 2,  /* and comparing models across materials (brdfit compare) */
    BF_TASK_SELECT = 1u << 3,   /* and choosing the smallest model that serves (brdfit select) */
    BF_TASK_TRADEOFF = 1u << 4, /* and measuring fitting cost against accuracy (brdfit tradeoff) */
} bf_task;

typedef enum bf_option_type {
    BF_OPTION_FLAG = 0, /* on or off: NULL, "true" or "1" turns it on, "false" or "0" off */
    BF_OPTION_INT,      /* an integer in [lo, hi] (digits only) */
    BF_OPTION_NUMBER,   /* a finite number in [lo, hi] (open at lo when range says so) */
    BF_OPTION_TEXT,     /* any text, checked where it is used (a file, column names) */
    BF_OPTION_CHOICE,   /* one of the words in choices, or a form help describes ("N|all") */
    BF_OPTION_LIST,     /* repeatable: each value adds an entry ("alpha=0.1" for fix) */
} bf_option_type;

/* One option, as the table declares it. The library owns these; new fields are only
 * ever added at the end (docs/api.md). */
typedef struct bf_option {
    const char *name;  /* keyword: "max_theta"; the command line writes "--max-theta" */
    const char *group; /* "reading", "preprocessing", "accuracy", "fitting", "optimizer",
                             "ranking", "comparing", "selecting", "tradeoff" */
    unsigned tasks;    /* bf_task bits of the tasks that take it */
    bf_option_type type;
    const char *arg;      /* the value's name in help ("DEG", "keep|drop|clamp"); NULL for a flag */
    const char *help;     /* one or more lines ('\n' between them), options named as on the
                             command line */
    const char *complete; /* what completes a value: NULL, "file", "dir", "model", "method",
                             "local_method", or choices "a|b|c" */
    const char *choices;  /* BF_OPTION_CHOICE: the words it takes, '|'-separated (a form such
                             as "N|all" lists only its words, "all") */
    const char *def;      /* the default as text ("log", "5", "0.05"); NULL: none or automatic
                             (help says which) */
    double lo, hi;        /* BF_OPTION_INT, BF_OPTION_NUMBER: the range */
    const char *range;    /* the range in words, as messages say it ("an integer from 1 to
                             1024", "degrees in (0, 90]") */
} bf_option;

/* The table: bf_option_count() entries, in the order help lists them. One name may
 * appear twice, for different tasks (compare's and select's --tolerance). */
BF_API int bf_option_count(void);
BF_API const bf_option *bf_option_get(int i);
/* The option of that name (keyword "max_theta" or command-line "--max-theta") that task
 * takes (0: any task); NULL when there is none. */
BF_API const bf_option *bf_option_find(const char *name, unsigned task);

typedef struct bf_options bf_options;

/* How messages name options: as keywords ("max_theta needs ...", for APIs) or as the
 * command line writes them ("--max-theta needs ..."; the default). */
typedef enum bf_option_spelling { BF_SPELL_COMMAND_LINE = 0, BF_SPELL_KEYWORD } bf_option_spelling;

/* A set of options for task, every option at its default. */
BF_API bf_status bf_options_new(bf_task task, bf_options **out, bf_error *err);
/* A copy of o (its values, callbacks and flags), for example the options shared by
 * many materials with one material's own added. */
BF_API bf_status bf_options_copy(const bf_options *o, bf_options **out, bf_error *err);
BF_API void bf_options_free(bf_options *o);
BF_API bf_task bf_options_task(const bf_options *o);
BF_API void bf_options_set_spelling(bf_options *o, bf_option_spelling spelling);

/* Sets option name (keyword or command-line spelling) from its text, as the command
 * line takes it: BF_ERR_ARG with a one-line message naming the option (an unknown
 * option, one this task does not take, a value out of its range, two options that
 * exclude each other). A LIST option adds an entry each time. */
BF_API bf_status bf_options_set(bf_options *o, const char *name, const char *value, bf_error *err);
/* Puts option name back to its default, as if never set (a LIST option loses every
 * entry). BF_ERR_ARG for an unknown name. */
BF_API bf_status bf_options_reset(bf_options *o, const char *name, bf_error *err);
/* 1 when name was set (to anything, its default included), else 0. */
BF_API int bf_options_given(const bf_options *o, const char *name);
/* The value the task will use, as text ("log", "0.05"; "" for none), into buf: an
 * --accuracy preset's values where the user gave none, the couplings applied (as
 * bf_options_check leaves them). A LIST option gives its entries joined by ",".
 * BF_ERR_ARG for an unknown name or a buf too small. */
BF_API bf_status bf_options_get(const bf_options *o, const char *name, char *buf, size_t size, bf_error *err);

/* What couples options, checked before any work, with the command line's messages: a
 * ranking by a likelihood criterion with a robust loss (which has none), a method
 * against the method registry (its local method, the constraint). Every function that
 * takes options checks them; calling this first reports bad usage before data is read. */
BF_API bf_status bf_options_check(const bf_options *o, bf_error *err);
/* Each model spec against the registry, and the fix and bound options against each
 * model (an unknown parameter, a value outside its bounds). */
BF_API bf_status bf_options_check_models(const bf_options *o, const char *const *specs, int n, bf_error *err);

/* Keep what writing the data back byte for byte needs (a MERL table's raw cells, 35 MB):
 * only a program that writes the format back asks (brdfit convert). */
BF_API void bf_options_keep_origin(bf_options *o, int keep);

/* The fit's start: n values of the model's vector (bf_model_nvalues entries, in its
 * order: a fit's x) instead of the data-driven start, copied; NULL clears it. Only a
 * BF_TASK_FIT set takes one (a comparison fits many models); bf_fit refuses a start of
 * another length than its model's. The search still adds its own starts unless the
 * option starts is 1. */
BF_API bf_status bf_options_set_start(bf_options *o, const double *x, int n, bf_error *err);

/* The flags are bf_cancel_flag (brdfit/error.h). cancel: read at every iteration of every
 * solve and before every fit: once set, running solves stop at their next iteration (the
 * fit ends cancelled) and no new fit starts; a load stops too (bf_samples_load:
 * BF_ERR_CANCELLED). finish: read before each fit of a comparison or selection: once
 * set, no new fit starts and running ones finish (brdfit compare's first Ctrl-C). Either
 * may be NULL; the flags must outlive every use of o. */
BF_API void bf_options_set_cancel(bf_options *o, const bf_cancel_flag *cancel, const bf_cancel_flag *finish);
/* Called after every iteration of every solve (Ceres) or evaluation (NLopt), from the
 * solving thread, with user as its first argument; non-zero stops the fit as cancel
 * does. NULL: none. */
BF_API void bf_options_set_progress(bf_options *o, bf_progress_fn progress, void *user);

/* ---- Progress reports: where a fit, a comparison or a selection is ----------------- */

/* The phases of a fit's search (docs/fitting.md), in the order a fit goes through them;
 * a fit skips those its options and data leave out. */
typedef enum bf_fit_phase {
    BF_PHASE_CANDIDATES = 0, /* the screened search's random candidates, each scored by its
                                cost on the screening set (no solve: iteration 0) */
    BF_PHASE_SCREEN,         /* the chosen starts solved on the screening set, then its best
                                revived (the screening set is the data when that has at
                                most BF_FIT_SCREEN_SAMPLES, fit.h, and the fit ends here) */
    BF_PHASE_PRESOLVE,       /* starts solved on the presolve's subsample (option presolve) */
    BF_PHASE_DATA,           /* solves on all the samples */
    BF_PHASE_DONE,           /* the fit has ended: reported once, last (not when it was
                                cancelled), with start 0 of 1, the solution's iterations and
                                final cost (NaN for a failed fit) and the data's samples;
                                what the callback returns then is not looked at */
} bf_fit_phase;

/* "candidates", "screen", "presolve", "data", "done" ("?" out of range). */
BF_API const char *bf_fit_phase_name(bf_fit_phase phase);

/* One report, made by the library and read through the pointer during the callback
 * only. Its first member is the library's sizeof: fields are only added at the end
 * (docs/api.md), and a program reads a field its header has but an older library may
 * not fill only when size reaches past it (offsetof(bf_progress_report, f) + sizeof f
 * <= size). */
typedef struct bf_progress_report {
    size_t size;
    bf_fit_phase phase;
    int start;                 /* the phase's solve (CANDIDATES: its candidate), from 0 */
    int starts;                /* the solves (candidates) the phase runs at most: start <
                                  starts; one with nothing to do is skipped, so a phase may
                                  end before start reaches starts - 1 */
    int iteration;             /* the solve's iteration (NLopt: evaluation); 0 for a
                                  candidate */
    double cost;               /* the cost there, 1/2 sum rho(r^2) over the set solved (a
                                  candidate's: NaN when not finite) */
    size_t samples;            /* the samples of that set: the screening set, the
                                  presolve's subsample or the data */
    const char *spec;          /* the model being fitted */
    int material;              /* bf_compare_run: the material's index; -1 otherwise */
    const char *material_name; /* bf_compare_run: its name (the data); NULL otherwise */
    int model;                 /* bf_compare_run: the model's index; bf_select_run: the
                                  candidate's; -1 in a fit alone */
    int fold;                  /* 0: the fit of all the samples; k = 1 to K: the fit
                                  leaving out fold k of a cross-validation (compare and
                                  select ranked by cv) */
} bf_progress_report;

/* Called as bf_progress_fn is (after every iteration or evaluation of every solve, from
 * the solving thread), and once for each candidate the screened search scores, with
 * where the fit is; non-zero stops the fit as cancel does. In bf_compare_run and
 * bf_select_run the fits running at once (option jobs) call it from their own threads,
 * concurrently. */
typedef int (*bf_progress_report_fn)(void *user, const bf_progress_report *report);

/* Sets the report callback (NULL: none), with user as its first argument. It and the
 * callback of bf_options_set_progress may both be set: each is called (the older first,
 * and the report only when it did not ask to stop). */
BF_API void bf_options_set_progress_report(bf_options *o, bf_progress_report_fn progress, void *user);

#ifdef __cplusplus
}
#endif
#endif
