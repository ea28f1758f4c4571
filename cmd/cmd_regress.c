/* brdfit regress BASELINE.json [--update] [--junit OUT.xml] [--case NAME] [--verbose]:
 * re-runs the fits a baseline lists and compares them with its expected values.
 *
 * Decisions:
 *  - What a case's "options" may hold, and how they are read, is the library's
 *    (bf_regress_case_options: brdfit fit's data and fit options, --threads 1 unless
 *    set, --scene and "data" relative to the baseline's folder).
 *  - Everything that can be checked before fitting is: every case's options, model and
 *    data file. A bad baseline stops with exit 2 and one line naming the file and line,
 *    before any fit runs and without writing the JUnit file.
 *  - A case that cannot run (unreadable data, a fit error) is an error, not a failure:
 *    JUnit <error>, exit 1, and --update writes nothing.
 *  - Exit: 0 every case passed (or --update wrote the baseline); 1 a case failed or could
 *    not run, or an output could not be written; 2 bad usage or a bad baseline. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brdfit/formats.h"
#include "brdfit/fit.h"
#include "brdfit/regress.h"
#include "brdfit/scene.h"
#include "args.h"
#include "brdfit/clock.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"

static const char cmd[] = "brdfit regress";

#define MAX_SELECTED 256

/* The command line, parsed (the strings point into argv). */
typedef struct regress_args {
    const char *path, *junit;
    const char *selected[MAX_SELECTED];
    int nselected, update;
} regress_args;

static int take_case(void *target, const cli_option *o, const char *v, const char *c)
{
    regress_args *a = target;
    (void)o;
    if (a->nselected >= MAX_SELECTED) {
        fprintf(stderr, "%s: more than %d --case options\n", c, MAX_SELECTED);
        return -1;
    }
    a->selected[a->nselected++] = v;
    return 0;
}

static const cli_option own[] = {
    {"--update", 0, NULL,
     "run every case and rewrite the baseline with the values obtained\n"
     "(names, data, options and tolerances kept; nothing written if a case\n"
     "cannot run)",
     NULL, CLI_SETS(regress_args, update, 1)},
    {"--junit", 0, "FILE", "JUnit XML report for CI systems (- for standard output)", "file",
     CLI_STRING_AT(regress_args, junit)},
    {"--case", 0, "NAME", "run only this case (repeatable)", NULL, CLI_CALLS(take_case)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group};
const cli_command cli_regress = {
    "brdfit",
    "regress",
    "BASELINE.json [--update] [--junit OUT.xml] [--case NAME]... [--verbose]",
    "re-run fits and compare them with a baseline",
    "Each case of the baseline names a data file (relative to the baseline's folder), a model, brdfit fit's data "
    "and fit options (--threads defaults to 1) and the expected parameters and metrics with their tolerances. "
    "--verbose prints every compared value, not only those that moved.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

/* One case's run options (bf_regress_case_options: the library's rules for what a case
 * holds) and the scene file they name, or "". */
typedef struct case_run {
    bf_options *o;
    char scene[4096];
} case_run;

static void case_run_free(case_run *r)
{
    bf_options_free(r->o);
}

/* Case c's options; 0, or 2 after a one-line error naming the baseline's line. */
static int prepare(const bf_regress_baseline *b, int c, case_run *r)
{
    memset(r, 0, sizeof *r);
    bf_error e;
    if (bf_regress_case_options(b, c, &r->o, &e) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, e.msg);
        return 2;
    }
    data_options_scene(r->o, r->scene, sizeof r->scene);
    return 0;
}

/* Loads, fits and compares case c; the fit stays in *r for --update. Returns BF_OK, or
 * an error only when memory runs out (a case that cannot run is an ERROR outcome, its
 * reason printed on stderr). */
static bf_status run(const bf_regress_baseline *b, int c, case_run *cr, bf_fit_result *r, bf_regress_outcome *out,
                     bf_error *err)
{
    const bf_regress_case *cs = &b->cases[c];
    char prefix[1024], msg[1200];
    snprintf(prefix, sizeof prefix, "%s: %s:%d: case '%s'", cmd, b->path, cs->data_line, cs->name);
    double t0 = bf_now_seconds();
    bf_error why;
    bf_samples *s = data_options_load(cr->o, cs->data_path, NULL, &why, prefix);
    int rc;
    if (!s) {
        rc = bf_regress_set_error(out, why.msg, err);
    } else if (bf_fit(s, cs->model, cr->o, r, err) != BF_OK) {
        fprintf(stderr, "%s: %s:%d: case '%s': %s\n", cmd, b->path, cs->model_line, cs->name, err->msg);
        snprintf(msg, sizeof msg, "%s", err->msg);
        rc = bf_regress_set_error(out, msg, err);
    } else {
        rc = bf_regress_check(b, c, r, out, err);
    }
    bf_samples_free(s);
    out->seconds = bf_now_seconds() - t0;
    return rc;
}

/* The outputs before any fit: the JUnit report never over the baseline or a case's data
 * or scene (under any name), and both it and, for --update, the baseline writable.
 * 0, or the exit status after a one-line error. */
static int check_outputs(const bf_regress_baseline *b, const case_run *runs, const char *path, const char *junit,
                         int update)
{
    bf_path_use *in = calloc(2 * (size_t)b->ncases + 1, sizeof *in);
    if (!in) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return 1;
    }
    int nin = 0;
    in[nin++] = (bf_path_use){"baseline", path};
    for (int c = 0; c < b->ncases; c++) {
        in[nin++] = (bf_path_use){"data file", b->cases[c].data_path};
        in[nin++] = (bf_path_use){"--scene file", *runs[c].scene ? runs[c].scene : NULL};
    }
    /* --update rewrites the baseline in place, as intended: it is an input, and checked
     * for writing on its own. */
    const bf_path_use out[] = {{"--junit", junit}, {"--update: the baseline", update ? path : NULL}};
    int st = args_check_outputs(cmd, in, nin, out, 1);
    if (st == 0)
        st = args_check_outputs(cmd, NULL, 0, out + 1, 1);
    free(in);
    return st;
}

static void print_lines(char *const *lines, int n)
{
    for (int i = 0; i < n; i++)
        printf("%s\n", lines[i]);
}

static int take_baseline(void *ctx, const char *v, const char *c)
{
    regress_args *a = ctx;
    if (a->path) {
        fprintf(stderr, "%s: one baseline only, got '%s' and '%s'\n", c, a->path, v);
        return -1;
    }
    a->path = v;
    return 0;
}

/* Returns -1 to go on, else the exit status (0 after --help). */
static int parse(regress_args *a, int argc, char **argv)
{
    memset(a, 0, sizeof *a);
    cli_args args;
    int p = cli_parse(&cli_regress, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    void *const targets[] = {a};
    int status = cli_take(&cli_regress, targets, CLI_COUNT(targets), &args, take_baseline, a, cmd) < 0 ? 2 : -1;
    cli_args_free(&args);
    if (status < 0 && !a->path) {
        fprintf(stderr, "%s: a baseline file is required (see brdfit regress --help)\n", cmd);
        status = 2;
    }
    return status;
}

/* Marks the cases to run (all without --case) and parses every case's options (the
 * whole baseline is checked, whatever is selected). 0, or 2 after a one-line error. */
static int prepare_cases(const regress_args *a, const bf_regress_baseline *b, case_run *runs, unsigned char *run_it)
{
    for (int k = 0; k < a->nselected; k++) {
        int found = 0;
        for (int c = 0; c < b->ncases; c++)
            if (!strcmp(b->cases[c].name, a->selected[k]))
                found = run_it[c] = 1;
        if (!found) {
            fprintf(stderr, "%s: %s: no case named '%s'\n", cmd, a->path, a->selected[k]);
            return 2;
        }
    }
    for (int c = 0; c < b->ncases; c++) {
        run_it[c] |= a->nselected == 0;
        if (prepare(b, c, &runs[c]) != 0)
            return 2;
    }
    return 0;
}

/* What the cases came to. */
typedef struct tally {
    int passed, failed, errors, changed;
} tally;

/* --update: case c's expectations set to r, and the changes printed. 0, or 1 after an
 * error. */
static int update_case(bf_regress_baseline *b, int c, const bf_fit_result *r, const bf_regress_outcome *o, tally *t)
{
    char **changes = NULL;
    int nchanges = 0;
    bf_error err;
    int rc = bf_regress_update(b, c, r, &changes, &nchanges, &err);
    if (rc == BF_OK) {
        printf("%s %s (%.2f s)\n", nchanges ? "UPDATED" : "UNCHANGED", b->cases[c].name, o->seconds);
        print_lines(changes, nchanges);
        t->changed += nchanges > 0;
    } else {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
    }
    for (int k = 0; k < nchanges; k++)
        free(changes[k]);
    free(changes);
    return rc == BF_OK ? 0 : 1;
}

/* Runs case c, prints its outcome (or, with --update, its changes) and counts it. 0, or
 * 1 after an error that stops the run. */
static int run_case(bf_regress_baseline *b, int c, case_run *cr, int update, bf_regress_outcome *o, tally *t)
{
    const bf_regress_case *cs = &b->cases[c];
    bf_fit_result r;
    bf_fit_result_init(&r);
    bf_error err;
    int status = 0;
    if (run(b, c, cr, &r, o, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        bf_fit_result_clear(&r);
        return 1;
    }
    t->passed += o->status == BF_REGRESS_PASS;
    t->failed += o->status == BF_REGRESS_FAIL;
    t->errors += o->status == BF_REGRESS_ERROR;
    if (o->status == BF_REGRESS_ERROR) {
        printf("ERROR %s (could not run)\n  %s\n", cs->name, o->lines[0]);
    } else if (!update) {
        const int verbose = cli_verbose();
        printf("%s %s (%.2f s)\n", o->status == BF_REGRESS_PASS ? "PASS" : "FAIL", cs->name, o->seconds);
        print_lines(verbose ? o->checked : o->lines, verbose ? o->nchecked : o->nlines);
        for (int w = 0; w < o->nwarnings; w++)
            printf("  warning: %s\n", o->warnings[w]);
    } else {
        status = update_case(b, c, &r, o, t);
    }
    fflush(stdout);
    bf_fit_result_clear(&r);
    return status;
}

/* The JUnit report, the rewritten baseline (--update) and the summary line; the exit
 * status. */
static int finish(const regress_args *a, const bf_regress_baseline *b, const bf_regress_outcome *outs, const tally *t)
{
    bf_error err;
    int write_failed = 0;
    if (a->junit && bf_regress_write_junit(b, outs, a->junit, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        write_failed = 1;
    }
    if (!a->update) {
        printf("regress: %d passed, %d failed", t->passed, t->failed);
        if (t->errors)
            printf(", %d could not run", t->errors);
        printf("\n");
        return t->failed || t->errors || write_failed ? 1 : 0;
    }
    const int ran = t->passed + t->failed;
    if (t->errors) {
        printf("regress: %s not updated: %d case%s could not run\n", a->path, t->errors, t->errors == 1 ? "" : "s");
    } else if (bf_regress_write(b, a->path, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        write_failed = 1;
    } else {
        printf("regress: wrote %s (%d case%s run, %d changed)\n", a->path, ran, ran == 1 ? "" : "s", t->changed);
    }
    return t->errors || write_failed ? 1 : 0;
}

/* Checks the whole baseline and the outputs, then runs the selected cases in order. */
static int run_baseline(const regress_args *a, bf_regress_baseline *b, case_run *runs, bf_regress_outcome *outs,
                        unsigned char *run_it)
{
    int status = prepare_cases(a, b, runs, run_it);
    if (status == 0)
        status = check_outputs(b, runs, a->path, a->junit, a->update);
    if (status != 0)
        return status;
    tally t = {0};
    for (int c = 0; c < b->ncases; c++) {
        if (!run_it[c])
            outs[c].status = BF_REGRESS_SKIPPED;
        else if (run_case(b, c, &runs[c], a->update, &outs[c], &t) != 0)
            return 1;
    }
    return finish(a, b, outs, &t);
}

int cmd_regress(int argc, char **argv)
{
    regress_args a;
    int status = parse(&a, argc, argv);
    if (status >= 0)
        return status;
    bf_error err;
    bf_regress_baseline *b = NULL;
    if (bf_regress_load(a.path, &b, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return err.code == BF_ERR_NOMEM ? 1 : 2;
    }
    const int n = b->ncases;
    case_run *runs = calloc((size_t)n, sizeof *runs);
    bf_regress_outcome *outs = calloc((size_t)n, sizeof *outs);
    for (int c = 0; outs && c < n; c++)
        bf_regress_outcome_init(&outs[c]);
    unsigned char *run_it = calloc((size_t)n, 1);
    if (!runs || !outs || !run_it) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        status = 1;
    } else {
        status = run_baseline(&a, b, runs, outs, run_it);
    }
    for (int c = 0; runs && c < n; c++)
        case_run_free(&runs[c]);
    for (int c = 0; outs && c < n; c++)
        bf_regress_outcome_clear(&outs[c]);
    free(runs);
    free(outs);
    free(run_it);
    bf_regress_baseline_free(b);
    return status;
}
