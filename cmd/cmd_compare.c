/* brdfit compare DATA... -m MODEL,...|all [options]: fits every model to every data file,
 * ranks the models per material and across materials, prints a summary and writes the
 * JSON and CSV tables and the HTML report.
 *
 * Decisions:
 *  - --rank picks what the models are ranked by: bic (default), aic or aicc, from the
 *    likelihood of the residuals each fit minimised (metrics.h), cv (the error of the
 *    fitted objective on held-out samples, --folds K seeded stratified folds, K more fits
 *    per model) or error (the --error metric). A robust loss minimises no likelihood, so
 *    with --loss the ranking must be cv or error (refused otherwise, exit 2).
 *  - --error picks the error behind the Pareto fronts, the tolerance and the mean error:
 *    rmse_log (default; ln(1 + f cos) weighs the diffuse floor and the highlight alike,
 *    as the default log residual does), rmse, rmse_cos or rmse_rel; with --rank cv the
 *    cross-validated error takes its place.
 *  - Outputs are reproducible to the byte: nothing ranked, flagged or chosen depends on
 *    wall time (the second Pareto front is of fitting work, in sample evaluations), and
 *    wall times enter the JSON and CSV only with --timing.
 *  - --tolerance is relative: a model is within it when its error <= best * (1 + tol).
 *    The simplest model is the one with the fewest free parameters within tolerance
 *    (ties: lower error, then earlier in -m).
 *  - Only fits that succeeded are ranked; failed ones are listed and counted (exit 1).
 *  - --jobs N fits N models/materials at once, each fit with --threads / N threads (at
 *    least 1). Results depend neither on the thread counts nor on the order fits finish
 *    in: each has its slot. The fits run in the library (bf_compare_run); this command
 *    parses, checks, shows the progress it reports, and prints and writes the results.
 *  - Every data file is read (and checked) before any fit starts: bad data costs no fit
 *    time and leaves no output. The samples stay in memory for the whole run.
 *  - SIGINT: no new fit starts, running fits finish, the outputs are written with what
 *    finished ("interrupted": true; fits never run are "not_run") and the exit status is
 *    130. A second SIGINT ends the process at once (default action). The handler only
 *    sets the flag bf_compare_run reads before each fit.
 *  - `all` is every registered family with its default options.
 *  - --html DIR writes a report folder (compare.h, report_html.c). DIR is checked before
 *    any fit: an existing DIR that is neither empty nor a previous report is refused
 *    (exit 1) rather than replaced. The report is written after the summary is printed;
 *    it shows the command line (but for --jobs and --threads, which change no result, so
 *    that the report is the same bytes whatever they are) and the data options as given. With --subsample, a MERL
 *    table is read again whole for the report's pictures of the measurement (the fits
 *    still use the subsample). --plot-format picks the embedded plots' format (--format is
 *    the data file's).
 *  - --json and --csv are checked before any data is read (args_check_outputs): the same
 *    file as a data file, the scene or each other, under any name, is refused (exit 2);
 *    an unwritable one fails (exit 1) before any fit.
 *  - --scene FILE (a data option): every fit and every error in the ranking is over the
 *    scene's samples with their scene weights (fit.weighted_metrics), so the selection
 *    follows the directions the scene uses; the summary names the scene.
 *  - Exit: 0 all fits ok; 1 bad data, a failed fit or an unwritable output; 2 bad usage;
 *    130 interrupted. */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brdfit/compare.h"
#include "brdfit/fit.h"
#include "brdfit/formats.h"
#include "brdfit/render.h"
#include "args.h"
#include "brdfit/clock.h"
#include "cli.h"
#include "commands.h"
#include "compare_print.h"
#include "data_options.h"
#include "fit_options.h"
#include "interrupt.h"
#include "rank_options.h"

static const char cmd[] = "brdfit compare";

#define MAX_MODELS 128

/* The command line, parsed. data points into args (kept until the end). */
typedef struct compare_args {
    cli_args args;
    bf_options *o;
    char *specs[MAX_MODELS];
    const char **data;
    int nmodels, ndata, all;
    const char *json_path, *csv_path, *html_dir;
    int plot_format;    /* --plot-format: a bf_plot_format */
    char *command_line; /* as typed, for the report (NULL when out of memory) */
    char *data_opts;    /* the data options given, for the report */
} compare_args;

static int take_model(void *target, const cli_option *o, const char *v, const char *c)
{
    compare_args *a = target;
    (void)o;
    if (!strcmp(v, "all")) {
        a->all = 1;
        return 0;
    }
    int k = fit_options_split_models(v, a->specs, a->nmodels, MAX_MODELS, c);
    if (k < 0)
        return -1;
    a->nmodels = k;
    return 0;
}

static int take_plot_format(void *target, const cli_option *o, const char *v, const char *c)
{
    (void)o;
    return compare_plot_format(c, v, &((compare_args *)target)->plot_format);
}

static const cli_option own[] = {
    {"--model", 'm', "SPECS",
     "models to compare (as brdfit fit; repeatable), or all: every\n"
     "registered model with its default options",
     "model", CLI_CALLS(take_model)},
    CLI_LIB("--error"),
    CLI_LIB("--tolerance"),
    CLI_LIB("--jobs"),
    CLI_LIB("--reference"),
    {"--json", 0, "FILE", "everything, machine-readable (stable keys; - for standard output)", "file",
     CLI_STRING_AT(compare_args, json_path)},
    {"--csv", 0, "FILE", "one row per material x model (- for standard output)", "file",
     CLI_STRING_AT(compare_args, csv_path)},
    {"--html", 0, "DIR",
     "a report to read in a browser: DIR/index.html and its images\n"
     "(an existing DIR is replaced only if it is a previous report)",
     "dir", CLI_STRING_AT(compare_args, html_dir)},
    {"--plot-format", 0, "png|svg|pdf",
     "the report's plots: embedded as PNG (default) or SVG; pdf\n"
     "embeds PNG and writes a PDF of each plot, linked",
     NULL, CLI_CALLS(take_plot_format)},
};
static const cli_group own_group = CLI_GROUP_OPTIONS(NULL, own, BF_TASK_COMPARE, compare_args, o);
static const cli_group *const groups[] = {&own_group,
                                          &rank_options_bic,
                                          &fit_options_fitting,
                                          &fit_options_optimizer,
                                          &data_options_reading,
                                          &data_options_preprocessing};
const cli_command cli_compare = {
    "brdfit",
    "compare",
    "DATA... -m MODEL[,MODEL...]|all [options] [--json R.json] [--csv R.csv] [--html DIR]",
    "fit many models to many materials and rank them",
    "Fits every model to every data file, ranks the models per material and across materials (by an information "
    "criterion, cross-validated error or plain error), marks the Pareto fronts of error against free parameters and "
    "fitting work, and writes the tables and a report. Ctrl-C stops starting new fits and writes what finished "
    "(exit 130).",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

static void compare_args_free(compare_args *a)
{
    cli_args_free(&a->args);
    for (int k = 0; k < a->nmodels; k++)
        free(a->specs[k]);
    free(a->data);
    free(a->command_line);
    free(a->data_opts);
    bf_options_free(a->o);
}

/* -m all: every registered family, after the models named. 0, or -1 after an error. */
static int add_all_models(compare_args *a)
{
    for (int f = 0; a->all && f < bf_family_count(); f++) {
        if (a->nmodels >= MAX_MODELS) {
            fprintf(stderr, "%s: more than %d models\n", cmd, MAX_MODELS);
            return -1;
        }
        if (!(a->specs[a->nmodels] = strdup(bf_family_get(f)->name))) {
            fprintf(stderr, "%s: out of memory\n", cmd);
            return -1;
        }
        a->nmodels++;
    }
    return 0;
}

/* A data file operand (data has room for every word of the command line). */
static int take_data(void *ctx, const char *v, const char *c)
{
    compare_args *a = ctx;
    (void)c;
    a->data[a->ndata++] = v;
    return 0;
}

/* Parses the command line into a (initialised here; compare_args_free it whatever the
 * outcome). Returns -1 to go on, else the exit status (0 after --help). */
static int parse(compare_args *a, int argc, char **argv)
{
    memset(a, 0, sizeof *a);
    if (!(a->o = cmd_options_new(BF_TASK_COMPARE, cmd)))
        return 1;
    if (!(a->data = calloc((size_t)argc, sizeof *a->data))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return 1;
    }
    int p = cli_parse(&cli_compare, argc, argv, &a->args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    args_append_word(&a->command_line, "brdfit");
    for (int i = 0, opts = 1; i < argc; i++) {
        /* --jobs and --threads change no result: left out, the report is the same bytes
         * whatever they are. */
        const char *w = argv[i];
        if (opts && (!strcmp(w, "--jobs") || !strcmp(w, "--threads"))) {
            i++;
            continue;
        }
        if (opts && (!strncmp(w, "--jobs=", 7) || !strncmp(w, "--threads=", 10)))
            continue;
        opts &= strcmp(w, "--") != 0;
        args_append_word(&a->command_line, w);
    }
    void *const targets[] = {a, &a->o, &a->o, &a->o, &a->o, &a->o};
    if (cli_take(&cli_compare, targets, CLI_COUNT(targets), &a->args, take_data, a, cmd) < 0)
        return 2;
    for (int i = 0; i < a->args.n; i++) { /* for the report: how the data was read */
        const cli_arg *x = &a->args.v[i];
        const cli_group *g = x->option ? groups[x->group] : NULL;
        if (g == &data_options_reading || g == &data_options_preprocessing) {
            args_append_word(&a->data_opts, x->name);
            if (x->value)
                args_append_word(&a->data_opts, x->value);
        }
    }
    return add_all_models(a) < 0 ? 2 : -1;
}

/* Everything checked before any data is read: operands, the report folder, the ranking,
 * the model specs and the outputs. 0, or the exit status after a one-line error. */
static int check(compare_args *a)
{
    bf_error err;
    if (a->ndata == 0 || a->nmodels == 0) {
        fprintf(stderr, "%s: %s (see brdfit compare --help)\n", cmd,
                a->ndata == 0 ? "at least one data file is required" : "-m MODEL,...|all is required");
        return 2;
    }
    /* A folder the report may not replace is refused before any fit runs. */
    if (a->html_dir && bf_compare_html_check(a->html_dir, &err) != BF_OK) {
        fprintf(stderr, "%s: --html %s\n", cmd, err.msg);
        return err.code == BF_ERR_ARG ? 2 : 1;
    }
    if (fit_options_check(a->o, a->specs, a->nmodels, cmd) < 0)
        return 2;
    /* The outputs: never over an input, writable. */
    bf_path_use *inputs = calloc((size_t)a->ndata + 1, sizeof *inputs);
    if (!inputs) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return 1;
    }
    for (int i = 0; i < a->ndata; i++)
        inputs[i] = (bf_path_use){"data file", a->data[i]};
    char scene[4096];
    inputs[a->ndata] = (bf_path_use){"--scene file", data_options_scene(a->o, scene, sizeof scene)};
    const bf_path_use out[] = {{"--json", a->json_path}, {"--csv", a->csv_path}};
    int status = args_check_outputs(cmd, inputs, a->ndata + 1, out, 2);
    free(inputs);
    return status;
}

/* The comparison's table, set up from the options. 0, or 1 after an error. */
static int setup(const compare_args *a, bf_compare **out)
{
    bf_error err;
    if (bf_compare_new(a->ndata, a->data, a->nmodels, (const char *const *)a->specs, out, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    bf_compare *c = *out;
    if (bf_compare_set_options(c, a->o, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    return 0;
}

static void free_samples(bf_samples **samples, int n)
{
    for (int i = 0; samples && i < n; i++)
        bf_samples_free(samples[i]);
    free(samples);
}

/* Every data file, read and checked before any fit (the geometry computed too, so bad
 * data costs no fit time); NULL after a one-line error. Free with free_samples. */
static bf_samples **load(const compare_args *a)
{
    bf_samples **samples = calloc((size_t)a->ndata, sizeof *samples);
    if (!samples) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return NULL;
    }
    for (int i = 0; i < a->ndata; i++) {
        bf_error err;
        const bf_geometry *g;
        if (!(samples[i] = data_options_load(a->o, a->data[i], NULL, NULL, cmd)) ||
            bf_samples_geometry(samples[i], &g, &err) != BF_OK) {
            if (samples[i])
                fprintf(stderr, "%s: %s: %s\n", cmd, a->data[i], err.msg);
            free_samples(samples, a->ndata);
            return NULL;
        }
    }
    return samples;
}

/* ---- Progress: a bar on a terminal, else one line per fit ---------------------------- */

typedef struct progress_state {
    int tty;
    double t0;
} progress_state;

static void progress_bar(const progress_state *ps, int done, int total)
{
    char bar[31];
    int w = (int)(30.0 * done / total);
    for (int k = 0; k < 30; k++)
        bar[k] = k < w ? '#' : '.';
    bar[30] = '\0';
    double el = bf_now_seconds() - ps->t0, eta = done ? el / done * (total - done) : NAN;
    fprintf(stderr, "\r%s: [%s] %d/%d fits", cmd, bar, done, total);
    if (isfinite(eta))
        fprintf(stderr, ", ETA %.0f s   ", eta);
    if (done == total)
        fputc('\n', stderr);
}

/* bf_compare_progress: called once per finished fit, one call at a time. */
static void progress(void *user, const bf_compare *c, int i, int j, int done, int total)
{
    const progress_state *ps = user;
    if (ps->tty) {
        progress_bar(ps, done, total);
    } else {
        const bf_compare_fit *f = &c->materials[i].fits[j];
        fprintf(stderr, "%s: %d/%d %s on %s: %s", cmd, done, total, c->models[j], c->materials[i].data,
                bf_compare_state_name(f->state));
        if (f->state == BF_CMP_ERROR)
            fprintf(stderr, " (%s)", f->message);
        else
            fprintf(stderr, ", %s %.4g, %.2f s", bf_compare_metric_name(c->metric),
                    bf_compare_metric_value(&f->metrics, c->metric), f->seconds);
        if (c->folds > 0 && f->state == BF_CMP_OK)
            fprintf(stderr, ", cv %.4g", f->cv_error);
        fputc('\n', stderr);
    }
    fflush(stderr);
}

/* The fits, in the library, with progress on stderr and SIGINT as a cancel. 0, or 1
 * after an error. */
static int run_fits(const compare_args *a, bf_compare *c, bf_samples *const *samples)
{
    progress_state ps = {.tty = isatty(STDERR_FILENO), .t0 = bf_now_seconds()};
    struct sigaction old;
    interrupt_catch(&old);
    bf_options_set_cancel(a->o, NULL, &interrupt_flag);
    bf_error err;
    int rc = bf_compare_run(c, samples, a->o, cli_quiet() ? NULL : progress, &ps, &err);
    bf_options_set_cancel(a->o, NULL, NULL);
    interrupt_release(&old);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    if (c->interrupted && !cli_quiet() && ps.tty)
        fputc('\n', stderr);
    return 0;
}

/* The tables on stdout: per material, then across them. */
static void print_results(const compare_args *a, const bf_compare *c)
{
    char scene[4096];
    if (data_options_scene(a->o, scene, sizeof scene))
        printf("scene %s: errors and criteria over the scene's directions, weighted as it weighs them\n", scene);
    compare_print_tables(stdout, c);
}

/* The measurement of material i on every MERL cell, for the report's pictures of it (NULL
 * when the samples already are that, or the format cannot give it): a MERL table read
 * whole when the fits had a subsample of it; an RGL .bsdf or NVIDIA .mbsdf file
 * evaluated at the MERL cell centres (--grid merl), read with the same options as the
 * data, subsample and scene aside. *failed: 1 after a one-line error. */
static bf_samples *whole_table(const compare_args *a, bf_samples *const *samples, int i, int *failed)
{
    bf_samples *t = NULL;
    bf_error err;
    char format[32], subsample[32];
    *failed = 0;
    bf_options_get(a->o, "format", format, sizeof format, NULL);
    bf_options_get(a->o, "subsample", subsample, sizeof subsample, NULL);
    bf_format f = BF_FORMAT_AUTO;
    if (!*format || bf_format_parse(format, &f, NULL) != BF_OK)
        f = bf_format_by_extension(a->data[i]);
    if (!samples[i]->merl && (f == BF_FORMAT_RGL || f == BF_FORMAT_MBSDF)) {
        bf_options *d = NULL;
        if (bf_options_copy(a->o, &d, &err) != BF_OK || bf_options_set(d, "grid", "merl", &err) != BF_OK ||
            bf_options_set(d, "subsample", "all", &err) != BF_OK || bf_options_reset(d, "scene", &err) != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            *failed = 1;
        } else if (!(t = data_options_load(d, a->data[i], NULL, NULL, cmd)))
            *failed = 1;
        bf_options_free(d);
        return t;
    }
    if (!samples[i]->merl || !strcmp(subsample, "all"))
        return NULL;
    if (bf_samples_read_merl(a->data[i], 0, &t, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        *failed = 1;
    }
    return t;
}

/* The HTML report: the ranked table, each fit's result, the samples and the tables.
 * 0, or 1 after a one-line error. */
static int write_report(const compare_args *a, const bf_compare *c, bf_samples *const *samples)
{
    bf_samples **tables = calloc((size_t)a->ndata, sizeof *tables);
    if (!tables) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return 1;
    }
    int failed = 0;
    for (int i = 0; i < a->ndata && !failed; i++)
        tables[i] = whole_table(a, samples, i, &failed);
    char scene[4096];
    bf_report_options o;
    bf_report_options_init(&o);
    o.samples = samples;
    o.tables = tables;
    o.format = a->plot_format;
    o.command_line = a->command_line;
    o.data_options = a->data_opts;
    o.scene = data_options_scene(a->o, scene, sizeof scene);
    bf_error err;
    if (!failed && bf_compare_write_report(c, &o, a->html_dir, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        failed = 1;
    }
    free_samples(tables, a->ndata);
    return failed;
}

/* The report, the JSON and the CSV; 0, or 1 after a one-line error. */
static int write_outputs(const compare_args *a, const bf_compare *c, bf_samples *const *samples)
{
    if (a->html_dir && write_report(a, c, samples) != 0)
        return 1;
    return compare_write_tables(cmd, c, a->json_path, a->csv_path);
}

/* 130 interrupted, 1 some fit failed, else 0; a line on stderr but for 0. */
static int outcome(const bf_compare *c)
{
    int total, not_run, bad;
    compare_counts(c, &total, &not_run, &bad);
    if (c->interrupted) {
        fprintf(stderr, "%s: interrupted after %d of %d fits; the outputs hold the finished ones\n", cmd,
                total - not_run, total);
        return 130;
    }
    if (bad) {
        fprintf(stderr, "%s: %d of %d fits failed\n", cmd, bad, total);
        return 1;
    }
    return 0;
}

/* After parsing: checks, loads, fits, prints and writes; the exit status. */
static int compare(const compare_args *a)
{
    bf_compare *cmp = NULL;
    bf_samples **samples = NULL;
    int status = setup(a, &cmp);
    if (status == 0 && !(samples = load(a)))
        status = 1;
    if (status == 0)
        status = run_fits(a, cmp, samples);
    if (status == 0) {
        bf_compare_rank(cmp);
        print_results(a, cmp);
        status = write_outputs(a, cmp, samples);
    }
    if (status == 0)
        status = outcome(cmp);
    free_samples(samples, a->ndata);
    bf_compare_free(cmp);
    return status;
}

int cmd_compare(int argc, char **argv)
{
    compare_args a;
    int status = parse(&a, argc, argv);
    if (status < 0 && (status = check(&a)) == 0) /* parse: -1 to go on */
        status = compare(&a);
    compare_args_free(&a);
    return status;
}
