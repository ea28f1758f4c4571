/* brdfit tradeoff DATA -m MODEL [options]: fitting cost against accuracy on one data set,
 * over training sample counts, optimizer methods, residual forms and multistart counts;
 * each setting is fitted on a seeded training set and judged on held-out test samples.
 * The rules are the library's (bf_tradeoff_run, brdfit/tradeoff.h: the split, the grid,
 * the order of the runs, the ranking and the recommendation; the options and their
 * checks are its table's, BF_TASK_TRADEOFF): this file is the argument syntax and the
 * printing.
 *
 * Decisions:
 *  - The cost is fitting work (--cost work, the default: sample evaluations, the same on
 *    every machine), so the front, the recommendation and the files are reproducible to
 *    the byte; --cost seconds uses wall time instead and --timing writes it (implied
 *    by --cost seconds).
 *  - Every option, model, method and output path is checked before any data is read or
 *    fit run: bad usage costs no time and leaves no file (exit 2).
 *  - Exit: 0 when every setting fitted; 1 bad data, a failed fit (the tables are still
 *    written, the row marked) or an unwritable output; 2 bad usage. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/render.h"
#include "brdfit/tradeoff.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"
#include "fit_options.h"

static const char cmd[] = "brdfit tradeoff";

static void print_table(FILE *out, const bf_tradeoff *t)
{
    fprintf(out, "%s  %s  (%zu samples: %zu train, %zu test; %d channel%s)\n", t->data, t->model, t->total, t->train_n,
            t->test_n, t->channels, t->channels == 1 ? "" : "s");
    const char *en = bf_compare_metric_name(t->metric);
    fprintf(out, "  %4s %8s %-14s %-9s %6s %9s%s %6s %12s %12s  %s\n", "#", "samples", "method", "residual", "starts",
            "work M", t->timing ? "    time s" : "", "iters", "train", "test", "marks");
    for (int i = 0; i < t->nrows; i++) {
        const bf_tradeoff_row *r = &t->rows[i];
        char n[24];
        if (r->all)
            snprintf(n, sizeof n, "all");
        else
            snprintf(n, sizeof n, "%zu", r->samples);
        char st[16] = "auto";
        if (r->starts > 0)
            snprintf(st, sizeof st, "%d", r->starts);
        fprintf(out, "  %4d %8s %-14s %-9s %6s ", i + 1, n, r->method, bf_residual_name(r->residual), st);
        if (!r->ran) {
            fprintf(out, "error: %s\n", r->message);
            continue;
        }
        char secs[32] = "";
        if (t->timing)
            snprintf(secs, sizeof secs, " %9.3f", r->seconds);
        fprintf(out, "%9.4g%s %6d %12.6g %12.6g  %s%s%s%s%s\n", r->work / 1e6, secs, r->iterations,
                bf_compare_metric_value(&r->train, t->metric), bf_compare_metric_value(&r->test, t->metric),
                r->ok ? "" : "FAILED ", r->on_front ? "front " : "", r->within_tolerance ? "tol " : "",
                i == t->best ? "best " : "", i == t->recommended ? "<- recommended" : "");
    }
    fprintf(out,
            "  (train/test: %s; work M: millions of sample evaluations; front: Pareto front of %s against "
            "test error; tol: within %g%% of the best)\n",
            en, t->cost == BF_TRADEOFF_COST_SECONDS ? "time" : "work", 100.0 * t->tolerance);
    for (int i = 0; i < t->nrows; i++)
        for (int w = 0; w < t->rows[i].nwarnings; w++)
            fprintf(out, "  warning: #%d: %s\n", i + 1, t->rows[i].warnings[w]);
}

/* What the command line asked for, and what the run holds (freed by run_free). */
typedef struct tradeoff_run {
    bf_options *o; /* the library's options: the tradeoff's own, the fit's and the data's */
    char *specs[2];
    int nspecs;
    const char *data, *json_path, *csv_path, *plot_path;
    bf_tradeoff *t;
} tradeoff_run;

/* -m: exactly one model (a later -m replaces an earlier one). */
static int take_model(void *target, const cli_option *o, const char *v, const char *c)
{
    tradeoff_run *r = target;
    (void)o;
    for (int k = 0; k < r->nspecs; k++)
        free(r->specs[k]);
    if ((r->nspecs = fit_options_split_models(v, r->specs, 0, 2, c)) < 0) {
        r->nspecs = 0;
        return -1;
    }
    if (r->nspecs != 1) {
        fprintf(stderr, "%s: -m takes one model, got '%s'\n", c, v);
        return -1;
    }
    return 0;
}

static const cli_option own[] = {
    {"--model", 'm', "SPEC", "the model to fit (one)", "model", CLI_CALLS(take_model)},
    CLI_LIB("--samples"),
    CLI_LIB("--methods"),
    CLI_LIB("--residuals"),
    CLI_LIB("--starts-list"),
    CLI_LIB("--test-fraction"),
    CLI_LIB("--cost"),
    CLI_LIB("--timing"),
    CLI_LIB("--repeats"),
    CLI_LIB("--error"),
    CLI_LIB("--tolerance"),
    {"--json", 0, "FILE", "the table, machine-readable (stable keys; - for standard output)", "file",
     CLI_STRING_AT(tradeoff_run, json_path)},
    {"--csv", 0, "FILE", "one row per setting (- for standard output)", "file", CLI_STRING_AT(tradeoff_run, csv_path)},
    {"--plot", 0, "FILE.png|.svg|.pdf",
     "test error against the cost with the Pareto front (format by\n"
     "the extension)",
     "file", CLI_STRING_AT(tradeoff_run, plot_path)},
    CLI_LIB("--plot-size"),
};
static const cli_group own_group = CLI_GROUP_OPTIONS(NULL, own, BF_TASK_TRADEOFF, tradeoff_run, o);
static const cli_group *const groups[] = {&own_group, &fit_options_fitting, &fit_options_optimizer,
                                          &data_options_reading, &data_options_preprocessing};
const cli_command cli_tradeoff = {
    "brdfit",
    "tradeoff",
    "DATA -m MODEL [options] [--json F] [--csv F] [--plot F.png|.svg|.pdf]",
    "measure fitting cost against accuracy",
    "Fits one model to a training share of DATA under every combination of sample count, method, residual and "
    "start count, measures each fit's error on the held-out samples, and recommends the cheapest setting within "
    "the tolerance of the best.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

static int take_data(void *r, const char *v, const char *c)
{
    return data_options_take_file(&((tradeoff_run *)r)->data, v, c);
}

/* Takes the parsed command line into r (the targets follow the groups): 0, or -1 after a
 * one-line error. */
static int take_args(tradeoff_run *r, const cli_args *args)
{
    void *const targets[] = {r, &r->o, &r->o, &r->o, &r->o};
    return cli_take(&cli_tradeoff, targets, CLI_COUNT(targets), args, take_data, r, cmd);
}

/* Every check before any data is read (what must be there, the plot's name, the model and
 * the options with the tradeoff's lists, the outputs): bad usage costs no time and leaves
 * no file. Returns 0, or the exit status after a one-line error. */
static int check_usage(tradeoff_run *r)
{
    if (!r->data || r->nspecs == 0) {
        fprintf(stderr, "%s: %s (see brdfit tradeoff --help)\n", cmd,
                !r->data ? "a data file is required" : "-m MODEL is required");
        return 2;
    }
    if (r->plot_path && !bf_plot_format_of(r->plot_path)) {
        fprintf(stderr, "%s: --plot %s: the name must end in .png, .svg or .pdf\n", cmd, r->plot_path);
        return 2;
    }
    if (r->plot_path && !strcmp(r->plot_path, "-")) {
        fprintf(stderr, "%s: --plot needs a file name\n", cmd);
        return 2;
    }
    if (fit_options_check(r->o, r->specs, 1, cmd) < 0)
        return 2;
    char scene[4096];
    const bf_path_use in[] = {{"data file", r->data}, {"--scene file", data_options_scene(r->o, scene, sizeof scene)}},
                      out[] = {{"--json", r->json_path}, {"--csv", r->csv_path}, {"--plot", r->plot_path}};
    return args_check_outputs(cmd, in, 2, out, 3);
}

/* A row's outcome on stderr, as it finishes. */
static void print_progress(void *user, const bf_tradeoff *t, int i)
{
    const bf_tradeoff_row *r = &t->rows[i];
    (void)user;
    fprintf(stderr, "%s: %d/%d %zu%s %s %s starts %d: ", cmd, i + 1, t->nrows, r->samples, r->all ? " (all)" : "",
            r->method, bf_residual_name(r->residual), r->starts);
    if (r->ran)
        fprintf(stderr, "%s%s %.4g, %.4g M sample evaluations, %.3f s\n", r->ok ? "" : "FAILED, ",
                bf_compare_metric_name(t->metric), bf_compare_metric_value(&r->test, t->metric), r->work / 1e6,
                r->seconds);
    else
        fprintf(stderr, "error: %s\n", r->message);
    fflush(stderr);
}

/* Reads the data and runs the tradeoff (the library's split, rows and ranking): 0, or the
 * exit status after a one-line error. */
static int run(tradeoff_run *r)
{
    bf_error err;
    bf_samples *all = data_options_load(r->o, r->data, NULL, NULL, cmd);
    if (!all)
        return 1;
    bf_status rc =
        bf_tradeoff_run(all, r->data, r->specs[0], r->o, cli_quiet() ? NULL : print_progress, NULL, &r->t, &err);
    bf_samples_free(all);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    return 0;
}

/* The recommended setting as a brdfit fit command line (or that none fitted). */
static void print_recommendation(FILE *info, const bf_tradeoff *t)
{
    if (t->recommended < 0) {
        fprintf(info, "recommended: none (no setting fitted)\n");
        return;
    }
    const bf_tradeoff_row *r = &t->rows[t->recommended], *b = &t->rows[t->best];
    char rc[48], bc[48], *command = NULL;
    bf_error err;
    if (t->cost == BF_TRADEOFF_COST_SECONDS) {
        snprintf(rc, sizeof rc, "%.3f s", r->seconds);
        snprintf(bc, sizeof bc, "%.3f s", b->seconds);
    } else {
        snprintf(rc, sizeof rc, "%.4g M sample evaluations", r->work / 1e6);
        snprintf(bc, sizeof bc, "%.4g M", b->work / 1e6);
    }
    if (bf_tradeoff_fit_command(t, t->recommended, &command, &err) != BF_OK)
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
    fprintf(info, "recommended: #%d (%s %.4g for %s; best #%d: %.4g for %s): %s\n", t->recommended + 1,
            bf_compare_metric_name(t->metric), r->error, rc, t->best + 1, b->error, bc, command ? command : "");
    bf_free(command);
}

/* What the plot's axes span, for a reader of the terminal. */
static void print_plot_axes(FILE *info, const bf_tradeoff *t, const char *plot_path, const bf_plot_axes *axes)
{
    int seconds = t->cost == BF_TRADEOFF_COST_SECONDS;
    fprintf(info,
            "plot %s: test %s (y, %s axis, %.4g to %.4g) against fitting %s (x, log axis, %s, %.4g to %.4g); "
            "Pareto front labelled #N\n",
            plot_path, bf_compare_metric_name(t->metric), axes->log_y ? "log" : "linear", axes->y_lo, axes->y_hi,
            seconds ? "time" : "work", seconds ? "s" : "sample evaluations", axes->x_lo, axes->x_hi);
}

/* The table and the recommendation (to stdout unless a machine-readable output goes
 * there), then the files. 0, or -1 after an error writing one. */
static int report(tradeoff_run *r)
{
    bf_error err;
    bf_plot_axes range;
    bf_plot_axes_init(&range);
    int stdout_taken = (r->json_path && !strcmp(r->json_path, "-")) || (r->csv_path && !strcmp(r->csv_path, "-"));
    FILE *info = stdout_taken ? stderr : stdout;
    print_table(info, r->t);
    print_recommendation(info, r->t);
    fflush(info);
    if ((r->json_path && bf_tradeoff_write_json(r->t, r->json_path, &err) != BF_OK) ||
        (r->csv_path && bf_tradeoff_write_csv(r->t, r->csv_path, &err) != BF_OK) ||
        (r->plot_path && bf_tradeoff_write_plot(r->t, r->plot_path, BF_PLOT_BY_NAME, r->t->plot_width,
                                                r->t->plot_height, &range, &err) != BF_OK)) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    if (r->plot_path)
        print_plot_axes(info, r->t, r->plot_path, &range);
    return 0;
}

static void run_free(tradeoff_run *r)
{
    bf_tradeoff_free(r->t);
    for (int k = 0; k < r->nspecs; k++)
        free(r->specs[k]);
    bf_options_free(r->o);
}

int cmd_tradeoff(int argc, char **argv)
{
    tradeoff_run r;
    memset(&r, 0, sizeof r);
    if (!(r.o = cmd_options_new(BF_TASK_TRADEOFF, cmd)))
        return 1;
    cli_args args;
    int p = cli_parse(&cli_tradeoff, argc, argv, &args);
    if (p != CLI_OK) {
        run_free(&r);
        return p == CLI_EXIT ? 0 : 2;
    }
    int status = take_args(&r, &args) < 0 ? 2 : check_usage(&r);
    if (status == 0)
        status = run(&r);
    if (status == 0)
        status = report(&r) < 0 ? 1 : 0;
    int all_ok = 1;
    for (int i = 0; status == 0 && i < r.t->nrows; i++)
        all_ok &= r.t->rows[i].ran && r.t->rows[i].ok;
    if (status == 0 && !all_ok)
        fprintf(stderr, "%s: %s\n", cmd, r.t->recommended >= 0 ? "some settings failed" : "every setting failed");
    if (status == 0)
        status = all_ok ? 0 : 1;
    cli_args_free(&args);
    run_free(&r);
    return status;
}
