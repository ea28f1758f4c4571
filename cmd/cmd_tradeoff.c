/* brdfit tradeoff DATA -m MODEL [options]: fitting cost against accuracy on one data set,
 * over training sample counts, optimizer methods, residual forms and multistart counts;
 * each setting is fitted on a seeded training set and judged on held-out test samples.
 *
 * Decisions:
 *  - The data options (reading, preprocessing, even --subsample) apply to the file as
 *    read; then --test-fraction of what is left is held out (seeded uniform random,
 *    tradeoff.h), and --samples counts apply to the rest: each a seeded stratified
 *    subsample, as `brdfit fit --subsample N` draws it. Counts at or above the training
 *    size are one "all" row.
 *  - The fit options are the base setting; the lists replace their part of it. Without
 *    --methods: the base method if --backend or --algorithm was given, else
 *    ceres,LD_LBFGS. Without --residuals / --starts-list: the base residual / starts.
 *  - The cost is fitting work (--cost work, the default: sample evaluations, the same on
 *    every machine), so the front, the recommendation and the files are reproducible to
 *    the byte; --cost seconds uses wall time instead and --timing writes it (implied
 *    by --cost seconds). Fits run one at a time (each with --threads), so that times
 *    are comparable; --repeats R refits each setting R times and keeps the least time.
 *  - Every option, model, method and output path is checked before any data is read or
 *    fit run: bad usage costs no time and leaves no file (exit 2).
 *  - Exit: 0 when every setting fitted; 1 bad data, a failed fit (the tables are still
 *    written, the row marked) or an unwritable output; 2 bad usage. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/image.h"
#include "brdfit/tradeoff.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"
#include "fit_options.h"

static const char cmd[] = "brdfit tradeoff";

#define MAX_LIST 64

static const cli_option own[] = {
    {"--model", 'm', "SPEC", "the model to fit (one)", "model"},
    {"--samples", 0, "N,...|all", "training sample counts (default 1000,4000,16000,64000,all;\n"
                                  "'k' suffix: thousands); counts >= the training set are 'all'", NULL},
    {"--methods", 0, "M,...", "ceres (Levenberg-Marquardt), ceres:dogleg, or NLopt names\n"
                              "(LD_LBFGS, LD_SLSQP, LN_BOBYQA ...); default: the --backend /\n"
                              "--algorithm setting if given, else ceres,LD_LBFGS", NULL},
    {"--residuals", 0, "R,...", "residual forms (default: --residual, log)", NULL},
    {"--starts-list", 0, "N,...", "multistart counts (default: --starts, 1)", NULL},
    {"--test-fraction", 0, "F", "held-out share of the samples, seeded random (default 0.2)", NULL},
    {"--cost", 0, "work|seconds", "what a setting costs: sample evaluations (default; the same on\n"
                                  "every machine) or wall time (varies from run to run)", NULL},
    {"--timing", 0, NULL, "wall times in the table and the files too", NULL},
    {"--repeats", 0, "N", "fit each setting N times, keep the least time (default 1)", NULL},
    {"--error", 0, "rmse|rmse_log|rmse_cos|rmse_rel", "test error to judge by (default rmse_log)", NULL},
    {"--tolerance", 0, "T", "recommend the cheapest setting with test error <= best * (1 + T)\n(default 0.05)",
     NULL},
    {"--json", 0, "FILE", "the table, machine-readable (stable keys; - for standard output)", "file"},
    {"--csv", 0, "FILE", "one row per setting (- for standard output)", "file"},
    {"--plot", 0, "FILE.png|.exr", "test error against the cost, Pareto front in red", "file"},
    {"--plot-size", 0, "WxH", "(default 640x400)", NULL},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &fit_options_fitting, &fit_options_optimizer, &data_options_reading, &data_options_preprocessing};
const cli_command cli_tradeoff = {
    "brdfit", "tradeoff", "DATA -m MODEL [options] [--json F] [--csv F] [--plot F.png]",
    "measure fitting cost against accuracy",
    "Fits one model to a training share of DATA under every combination of sample count, method, residual and "
    "start count, measures each fit's error on the held-out samples, and recommends the cheapest setting within "
    "the tolerance of the best.",
    "file", groups, sizeof groups / sizeof groups[0],
};

/* Splits a comma list into at most MAX_LIST items (pointers into buf). */
static int split_list(char *buf, char **items, const char *opt)
{
    int n = 0;
    for (char *p = buf;;) {
        char *comma = strchr(p, ',');
        if (comma)
            *comma = '\0';
        if (!*p) {
            fprintf(stderr, "%s: %s: empty item in the list\n", cmd, opt);
            return -1;
        }
        if (n >= MAX_LIST) {
            fprintf(stderr, "%s: %s: more than %d items\n", cmd, opt, MAX_LIST);
            return -1;
        }
        items[n++] = p;
        if (!comma)
            return n;
        p = comma + 1;
    }
}

/* A count, digits only, with an optional k (thousands) suffix. */
static int parse_count(const char *s, long hi, long *out)
{
    char buf[32];
    size_t len = strlen(s);
    long mul = 1;
    if (len > 1 && len < sizeof buf && (s[len - 1] == 'k' || s[len - 1] == 'K')) {
        memcpy(buf, s, len - 1);
        buf[len - 1] = '\0';
        s = buf;
        mul = 1000;
    }
    long v;
    if (!args_int(s, 1, hi / mul, &v))
        return 0;
    *out = v * mul;
    return 1;
}

static const char *method_of(const bf_solver_options *so)
{
    if (so->backend == BF_BACKEND_CERES)
        return so->algorithm && !strcmp(so->algorithm, "dogleg") ? "ceres:dogleg" : "ceres";
    return so->algorithm ? so->algorithm : "LD_LBFGS";
}

/* The setting as brdfit fit options. */
static void fit_args(const bf_tradeoff_row *r, char *buf, size_t size)
{
    char sub[48] = "";
    if (!r->all)
        snprintf(sub, sizeof sub, "--subsample %zu ", r->samples);
    const char *m = r->method;
    if (!strcmp(m, "ceres") || !strcmp(m, "lm") || !strcmp(m, "ceres:lm"))
        m = "--backend ceres";
    else if (!strcmp(m, "ceres:dogleg") || !strcmp(m, "dogleg"))
        m = "--backend ceres --algorithm dogleg";
    char mbuf[128];
    if (m == r->method) {
        const char *alg = !strncmp(r->method, "nlopt:", 6) ? r->method + 6 : r->method;
        snprintf(mbuf, sizeof mbuf, "--backend nlopt --algorithm %s", strcmp(alg, "nlopt") ? alg : "LD_LBFGS");
        m = mbuf;
    }
    snprintf(buf, size, "%s%s --residual %s --starts %d", sub, m, bf_residual_name(r->residual), r->starts);
}

/* Appends " ARG" to buf, in single quotes when the shell would split or expand it. */
static void append_arg(char *buf, size_t size, const char *arg)
{
    size_t len = strlen(buf);
    int plain = *arg && !strpbrk(arg, " \t\n'\"\\$`*?[]{}()<>|&;#~!");
    snprintf(buf + len, size - len, plain ? " %s" : " '%s'", arg);
}

/* The fit options each row sets itself (fit_args), left out of the repeated base ones. */
static int row_sets(const char *opt)
{
    static const char *const set[] = {"--backend", "--algorithm", "--residual", "--starts"};
    for (size_t k = 0; k < sizeof set / sizeof set[0]; k++)
        if (!strcmp(opt, set[k]))
            return 1;
    return 0;
}

static void print_table(FILE *out, const bf_tradeoff *t)
{
    fprintf(out, "%s  %s  (%zu samples: %zu train, %zu test; %d channel%s)\n", t->data, t->model, t->total,
            t->train_n, t->test_n, t->channels, t->channels == 1 ? "" : "s");
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
        fprintf(out, "  %4d %8s %-14s %-9s %6d ", i + 1, n, r->method, bf_residual_name(r->residual), r->starts);
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
    fprintf(out, "  (train/test: %s; work M: millions of sample evaluations; front: Pareto front of %s against "
                 "test error; tol: within %g%% of the best)\n",
            en, t->cost == BF_TRADEOFF_COST_SECONDS ? "time" : "work", 100.0 * t->tolerance);
    for (int i = 0; i < t->nrows; i++)
        for (int w = 0; w < t->rows[i].nwarnings; w++)
            fprintf(out, "  warning: #%d: %s\n", i + 1, t->rows[i].warnings[w]);
}

int cmd_tradeoff(int argc, char **argv)
{
    data_options dopt;
    memset(&dopt, 0, sizeof dopt);
    fit_options fopt;
    fit_options_init(&fopt);
    int status = 2, nspecs = 0;
    char *specs[2] = {0};
    const char *data = NULL, *json_path = NULL, *csv_path = NULL, *plot_path = NULL;
    const char *samples_arg = "1000,4000,16000,64000,all", *methods_arg = NULL, *residuals_arg = NULL,
               *starts_arg = NULL;
    double test_fraction = 0.2, tolerance = 0.05;
    int repeats = 1, plot_w = 640, plot_h = 400, timing = 0;
    bf_tradeoff_cost cost = BF_TRADEOFF_COST_WORK;
    bf_compare_metric metric = BF_CMP_RMSE_LOG;
    char *bufs[4] = {0};
    bf_samples *all = NULL, *train = NULL, *test = NULL;
    bf_tradeoff t;
    memset(&t, 0, sizeof t);
    bf_error err;
    char data_args[2048] = ""; /* data and base fit options, for the recommended command */

    cli_args args;
    int p = cli_parse(&cli_tradeoff, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    for (int i = 0; i < args.n; i++) {
        const char *a = args.v[i].name, *v = args.v[i].value;
        if (!a) {
            if (data) {
                fprintf(stderr, "%s: one data file only, got '%s' and '%s'\n", cmd, data, v);
                goto done;
            }
            data = v;
            continue;
        }
        int d = data_options_parse(&dopt, a, v, cmd);
        /* Data options and the base fit setting are repeated in the recommended command. */
        int repeat = d > 0;
        if (d == 0 && (d = fit_options_parse(&fopt, a, v, cmd)) > 0 && !row_sets(a))
            repeat = 1;
        if (repeat) {
            append_arg(data_args, sizeof data_args, a);
            if (v)
                append_arg(data_args, sizeof data_args, v);
        }
        if (d < 0)
            goto done;
        if (d > 0)
            continue;
        if (!strcmp(a, "--timing")) {
            timing = 1;
            continue;
        }
        long n;
        if (!strcmp(a, "--model")) {
            for (int k = 0; k < nspecs; k++)
                free(specs[k]);
            if ((nspecs = fit_options_split_models(v, specs, 0, 2, cmd)) < 0) {
                nspecs = 0;
                goto done;
            }
            if (nspecs != 1) {
                fprintf(stderr, "%s: -m takes one model, got '%s'\n", cmd, v);
                goto done;
            }
        } else if (!strcmp(a, "--cost")) {
            if (strcmp(v, "work") && strcmp(v, "seconds")) {
                fprintf(stderr, "%s: --cost needs work or seconds, got '%s'\n", cmd, v);
                goto done;
            }
            cost = !strcmp(v, "work") ? BF_TRADEOFF_COST_WORK : BF_TRADEOFF_COST_SECONDS;
        } else if (!strcmp(a, "--samples")) {
            samples_arg = v;
        } else if (!strcmp(a, "--methods")) {
            methods_arg = v;
        } else if (!strcmp(a, "--residuals")) {
            residuals_arg = v;
        } else if (!strcmp(a, "--starts-list")) {
            starts_arg = v;
        } else if (!strcmp(a, "--test-fraction")) {
            if (!args_number(v, 0.0, 1.0, &test_fraction) || !(test_fraction > 0.0 && test_fraction < 1.0)) {
                fprintf(stderr, "%s: --test-fraction needs a number between 0 and 1 (exclusive), got '%s'\n", cmd,
                        v);
                goto done;
            }
        } else if (!strcmp(a, "--repeats")) {
            if (!parse_count(v, 1000, &n)) {
                fprintf(stderr, "%s: --repeats needs an integer from 1 to 1000, got '%s'\n", cmd, v);
                goto done;
            }
            repeats = (int)n;
        } else if (!strcmp(a, "--error")) {
            if (bf_compare_metric_parse(v, &metric, &err) != BF_OK) {
                fprintf(stderr, "%s: --error: %s\n", cmd, err.msg);
                goto done;
            }
        } else if (!strcmp(a, "--tolerance")) {
            if (!args_number(v, 0.0, HUGE_VAL, &tolerance)) {
                fprintf(stderr, "%s: --tolerance needs a number >= 0 (relative, 0.05 = 5%%), got '%s'\n", cmd, v);
                goto done;
            }
        } else if (!strcmp(a, "--plot-size")) {
            if (!strchr(v, 'x') || !args_size(v, 40, 8192, &plot_w, &plot_h)) {
                fprintf(stderr, "%s: --plot-size needs WxH, each 40 to 8192, got '%s'\n", cmd, v);
                goto done;
            }
        } else if (!strcmp(a, "--json")) {
            json_path = v;
        } else if (!strcmp(a, "--csv")) {
            csv_path = v;
        } else { /* --plot */
            plot_path = v;
        }
    }
    if (!data || nspecs == 0) {
        fprintf(stderr, "%s: %s (see brdfit tradeoff --help)\n", cmd,
                !data ? "a data file is required" : "-m MODEL is required");
        goto done;
    }
    if (plot_path && !bf_image_format_of(plot_path)) {
        fprintf(stderr, "%s: --plot %s: the name must end in .png or .exr\n", cmd, plot_path);
        goto done;
    }
    if (plot_path && !strcmp(plot_path, "-")) {
        fprintf(stderr, "%s: --plot needs a file name\n", cmd);
        goto done;
    }
    if (fit_options_check_models(&fopt, specs, 1, cmd) < 0)
        goto done;
    /* With a scene, errors are measured over the scene's directions, weighted by it. */
    fit_options_finish(&fopt, &dopt);

    /* The lists. */
    if (!methods_arg)
        methods_arg = fopt.fit.solver.backend != BF_BACKEND_CERES || fopt.fit.solver.algorithm
                          ? method_of(&fopt.fit.solver)
                          : "ceres,LD_LBFGS";
    char starts_default[16], *items[4][MAX_LIST];
    snprintf(starts_default, sizeof starts_default, "%d", fopt.fit.starts);
    const char *lists[4] = {samples_arg, methods_arg,
                           residuals_arg ? residuals_arg : bf_residual_name(fopt.fit.objective.residual),
                           starts_arg ? starts_arg : starts_default};
    static const char *const names[4] = {"--samples", "--methods", "--residuals", "--starts-list"};
    int counts_n[4];
    for (int l = 0; l < 4; l++) {
        if (!(bufs[l] = strdup(lists[l]))) {
            fprintf(stderr, "%s: out of memory\n", cmd);
            goto done;
        }
        if ((counts_n[l] = split_list(bufs[l], items[l], names[l])) < 0)
            goto done;
    }
    size_t sample_counts[MAX_LIST];
    bf_residual residuals[MAX_LIST];
    int starts[MAX_LIST];
    for (int k = 0; k < counts_n[0]; k++) {
        long n;
        if (!strcmp(items[0][k], "all"))
            sample_counts[k] = 0;
        else if (parse_count(items[0][k], 1000000000L, &n))
            sample_counts[k] = (size_t)n;
        else {
            fprintf(stderr, "%s: --samples: '%s' is not a positive count or 'all'\n", cmd, items[0][k]);
            goto done;
        }
    }
    for (int k = 0; k < counts_n[1]; k++) {
        bf_solver_options so = fopt.fit.solver;
        if (bf_tradeoff_method_apply(items[1][k], &so, &err) != BF_OK) {
            fprintf(stderr, "%s: --methods: %s\n", cmd, err.msg);
            goto done;
        }
    }
    for (int k = 0; k < counts_n[2]; k++)
        if (bf_residual_parse(items[2][k], &residuals[k], &err) != BF_OK) {
            fprintf(stderr, "%s: --residuals: %s\n", cmd, err.msg);
            goto done;
        }
    for (int k = 0; k < counts_n[3]; k++) {
        long n;
        if (!parse_count(items[3][k], 100000, &n)) {
            fprintf(stderr, "%s: --starts-list: '%s' is not a positive integer\n", cmd, items[3][k]);
            goto done;
        }
        starts[k] = (int)n;
    }

    /* Bad usage before any data is read (the sample counts may still merge later). */
    double settings = (double)counts_n[0] * counts_n[1] * counts_n[2] * counts_n[3];
    if (settings > BF_TRADEOFF_MAX_ROWS) {
        fprintf(stderr, "%s: %.0f settings is too many (at most %d): shorten the lists\n", cmd, settings,
                BF_TRADEOFF_MAX_ROWS);
        goto done;
    }
    const bf_path_use in[] = {{"data file", data}, {"--scene file", dopt.scene}},
                      out[] = {{"--json", json_path}, {"--csv", csv_path}, {"--plot", plot_path}};
    if ((status = args_check_outputs(cmd, in, 2, out, 3)) != 0)
        goto done;
    status = 1;
    if (!(all = data_options_load(&dopt, data, NULL, cmd)))
        goto done;
    if (bf_tradeoff_split(all, test_fraction, dopt.prep.seed, &train, &test, &err) != BF_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, data, err.msg);
        goto done;
    }
    if (bf_tradeoff_init(&t, data, specs[0], train->n, counts_n[0], sample_counts, counts_n[1],
                         (const char *const *)items[1], counts_n[2], residuals, counts_n[3], starts, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = err.code == BF_ERR_ARG ? 2 : 1;
        goto done;
    }
    t.total = all->n;
    t.test_n = test->n;
    t.channels = all->channels;
    t.test_fraction = test_fraction;
    t.seed = dopt.prep.seed;
    t.repeats = repeats;
    t.metric = metric;
    t.tolerance = tolerance;
    t.cost = cost;
    t.timing = timing || cost == BF_TRADEOFF_COST_SECONDS;
    bf_samples_free(all);
    all = NULL;

    int all_ok = 1;
    bf_scatter_range range;
    memset(&range, 0, sizeof range);
    for (int i = 0; i < t.nrows; i++) {
        const bf_tradeoff_row *r = &t.rows[i];
        int rc = bf_tradeoff_run_row(&t, i, train, test, &fopt.fit, &err);
        if (rc == BF_ERR_NOMEM) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            goto done;
        }
        all_ok &= r->ran && r->ok;
        if (!cli_quiet()) {
            fprintf(stderr, "%s: %d/%d %zu%s %s %s starts %d: ", cmd, i + 1, t.nrows, r->samples,
                    r->all ? " (all)" : "", r->method, bf_residual_name(r->residual), r->starts);
            if (r->ran)
                fprintf(stderr, "%s%s %.4g, %.4g M sample evaluations, %.3f s\n", r->ok ? "" : "FAILED, ",
                        bf_compare_metric_name(metric), bf_compare_metric_value(&r->test, metric), r->work / 1e6,
                        r->seconds);
            else
                fprintf(stderr, "error: %s\n", r->message);
            fflush(stderr);
        }
    }
    bf_tradeoff_rank(&t);
    /* The table goes to stdout unless a machine-readable output does. */
    FILE *info = (json_path && !strcmp(json_path, "-")) || (csv_path && !strcmp(csv_path, "-")) ? stderr : stdout;
    print_table(info, &t);
    if (t.recommended >= 0) {
        const bf_tradeoff_row *r = &t.rows[t.recommended], *b = &t.rows[t.best];
        char fa[256];
        fit_args(r, fa, sizeof fa);
        char rc[48], bc[48];
        if (cost == BF_TRADEOFF_COST_SECONDS) {
            snprintf(rc, sizeof rc, "%.3f s", r->seconds);
            snprintf(bc, sizeof bc, "%.3f s", b->seconds);
        } else {
            snprintf(rc, sizeof rc, "%.4g M sample evaluations", r->work / 1e6);
            snprintf(bc, sizeof bc, "%.4g M", b->work / 1e6);
        }
        fprintf(info, "recommended: #%d (%s %.4g for %s; best #%d: %.4g for %s): brdfit fit %s%s -m %s %s\n",
                t.recommended + 1, bf_compare_metric_name(metric), r->error, rc, t.best + 1, b->error, bc, data,
                data_args, t.model, fa);
    } else {
        fprintf(info, "recommended: none (no setting fitted)\n");
    }
    fflush(info);

    if ((json_path && bf_tradeoff_write_json(&t, json_path, &err) != BF_OK) ||
        (csv_path && bf_tradeoff_write_csv(&t, csv_path, &err) != BF_OK) ||
        (plot_path && bf_tradeoff_write_plot(&t, plot_path, plot_w, plot_h, &range, &err) != BF_OK)) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    /* The image has no text: its axes are said here. */
    int log_y = 1; /* as bf_tradeoff_write_plot decides */
    for (int i = 0; i < t.nrows; i++)
        log_y &= !(t.rows[i].error <= 0.0);
    if (plot_path)
        fprintf(info, "plot %s: test %s (y, %s%.3g to %.3g) against fitting %s (x, log10 %s, %.3g to %.3g); "
                      "red: Pareto front\n",
                plot_path, bf_compare_metric_name(metric), log_y ? "log10 " : "", range.y_lo, range.y_hi,
                cost == BF_TRADEOFF_COST_SECONDS ? "time" : "work",
                cost == BF_TRADEOFF_COST_SECONDS ? "s" : "sample evaluations", range.x_lo, range.x_hi);
    if (!all_ok)
        fprintf(stderr, "%s: %s\n", cmd, t.recommended >= 0 ? "some settings failed" : "every setting failed");
    status = all_ok ? 0 : 1;
done:
    cli_args_free(&args);
    bf_tradeoff_free(&t);
    bf_samples_free(all);
    bf_samples_free(train);
    bf_samples_free(test);
    for (int k = 0; k < nspecs; k++)
        free(specs[k]);
    for (int l = 0; l < 4; l++)
        free(bufs[l]);
    return status;
}
