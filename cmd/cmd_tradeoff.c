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

#include "brdfit/render.h"
#include "brdfit/tradeoff.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"
#include "fit_options.h"

static const char cmd[] = "brdfit tradeoff";

#define MAX_LIST 64

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

/* The base setting as a --methods item: "ceres" for its default, "ceres:dogleg", or the
 * NLopt method's name. */
static const char *method_of(bf_backend backend, const char *algorithm, char *buf, size_t size)
{
    const bf_method_info *m = bf_method_find(backend, algorithm);
    if (!m) /* checked before; the default keeps the message to the checker */
        m = bf_method_default(backend);
    if (backend == BF_BACKEND_CERES)
        snprintf(buf, size, "ceres%s%s", m->caps & BF_METHOD_DEFAULT ? "" : ":", m->caps & BF_METHOD_DEFAULT ? "" : m->name);
    else
        snprintf(buf, size, "%s", m->name);
    return buf;
}

/* The setting as brdfit fit options. */
static void fit_args(const bf_tradeoff_row *r, char *buf, size_t size)
{
    char sub[48] = "", mbuf[128];
    if (!r->all)
        snprintf(sub, sizeof sub, "--subsample %zu ", r->samples);
    bf_backend b = BF_BACKEND_CERES;
    const bf_method_info *m = NULL;
    if (bf_method_parse(r->method, &b, &m, NULL) != BF_OK || (b == BF_BACKEND_CERES && (m->caps & BF_METHOD_DEFAULT)))
        snprintf(mbuf, sizeof mbuf, "--backend %s", bf_backend_name(b));
    else
        snprintf(mbuf, sizeof mbuf, "--backend %s --algorithm %s", bf_backend_name(b), m->name);
    char starts[32] = ""; /* automatic starts (0) are brdfit fit's default: no option */
    if (r->starts > 0)
        snprintf(starts, sizeof starts, " --starts %d", r->starts);
    snprintf(buf, size, "%s%s --residual %s%s", sub, mbuf, bf_residual_name(r->residual), starts);
}

/* Appends " ARG" to buf, in single quotes when the shell would split or expand it. */
static void append_arg(char *buf, size_t size, const char *arg)
{
    size_t len = strlen(buf);
    int plain = *arg && !strpbrk(arg, " \t\n'\"\\$`*?[]{}()<>|&;#~!");
    snprintf(buf + len, size - len, plain ? " %s" : " '%s'", arg);
}

/* The fit options each row sets itself (fit_args), left out of the repeated base ones. */
static int row_sets(const cli_option *o)
{
    return !strcmp(o->name, "--backend") || !strcmp(o->name, "--algorithm") || !strcmp(o->name, "--residual") ||
           !strcmp(o->name, "--starts");
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
    fprintf(out, "  (train/test: %s; work M: millions of sample evaluations; front: Pareto front of %s against "
                 "test error; tol: within %g%% of the best)\n",
            en, t->cost == BF_TRADEOFF_COST_SECONDS ? "time" : "work", 100.0 * t->tolerance);
    for (int i = 0; i < t->nrows; i++)
        for (int w = 0; w < t->rows[i].nwarnings; w++)
            fprintf(out, "  warning: #%d: %s\n", i + 1, t->rows[i].warnings[w]);
}

/* The four lists, in this order everywhere: their options, and what they hold. */
enum { L_SAMPLES, L_METHODS, L_RESIDUALS, L_STARTS, NLISTS };
static const char *const list_names[NLISTS] = {"--samples", "--methods", "--residuals", "--starts-list"};

/* What the command line asked for, and what the run holds (freed by run_free). */
typedef struct tradeoff_run {
    bf_options *o;
    char *specs[2];
    int nspecs;
    const char *data, *json_path, *csv_path, *plot_path;
    const char *lists[NLISTS]; /* as given, split and checked once every option is in; NULL: the default */
    double test_fraction, tolerance;
    int repeats, plot_w, plot_h, timing;
    bf_tradeoff_cost cost;
    bf_compare_metric metric;
    char data_args[2048]; /* data and base fit options, for the recommended command */
    /* The lists, split (pointers into bufs) and parsed. */
    char *bufs[NLISTS], *items[NLISTS][MAX_LIST];
    int nitems[NLISTS];
    size_t sample_counts[MAX_LIST];
    bf_residual residuals[MAX_LIST];
    int starts[MAX_LIST];
    bf_samples *train, *test;
    bf_tradeoff *t;
} tradeoff_run;

static void run_init(tradeoff_run *r)
{
    memset(r, 0, sizeof *r);
    r->o = cmd_options_new(BF_TASK_FIT, cmd);
    r->lists[L_SAMPLES] = "1000,4000,16000,64000,all";
    r->test_fraction = 0.2;
    r->tolerance = 0.05;
    r->repeats = 1;
    r->plot_w = 640;
    r->plot_h = 400;
    r->cost = BF_TRADEOFF_COST_WORK;
    r->metric = BF_CMP_RMSE_LOG;
}

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

static int take_cost(void *target, const cli_option *o, const char *v, const char *c)
{
    (void)o;
    if (strcmp(v, "work") && strcmp(v, "seconds")) {
        fprintf(stderr, "%s: --cost needs work or seconds, got '%s'\n", c, v);
        return -1;
    }
    ((tradeoff_run *)target)->cost = !strcmp(v, "work") ? BF_TRADEOFF_COST_WORK : BF_TRADEOFF_COST_SECONDS;
    return 0;
}

/* A number strictly between 0 and 1, which CLI_NUMBER_AT's closed range cannot say. */
static int take_test_fraction(void *target, const cli_option *o, const char *v, const char *c)
{
    double *f = &((tradeoff_run *)target)->test_fraction;
    (void)o;
    if (!args_number(v, 0.0, 1.0, f) || !(*f > 0.0 && *f < 1.0)) {
        fprintf(stderr, "%s: --test-fraction needs a number between 0 and 1 (exclusive), got '%s'\n", c, v);
        return -1;
    }
    return 0;
}

/* A count with the k suffix (parse_count), which CLI_INT_AT does not take. */
static int take_repeats(void *target, const cli_option *o, const char *v, const char *c)
{
    long n;
    (void)o;
    if (!parse_count(v, 1000, &n)) {
        fprintf(stderr, "%s: --repeats needs an integer from 1 to 1000, got '%s'\n", c, v);
        return -1;
    }
    ((tradeoff_run *)target)->repeats = (int)n;
    return 0;
}

static int take_error(void *target, const cli_option *o, const char *v, const char *c)
{
    bf_error err;
    (void)o;
    if (bf_compare_metric_parse(v, &((tradeoff_run *)target)->metric, &err) != BF_OK) {
        fprintf(stderr, "%s: --error: %s\n", c, err.msg);
        return -1;
    }
    return 0;
}

static int take_plot_size(void *target, const cli_option *o, const char *v, const char *c)
{
    tradeoff_run *r = target;
    (void)o;
    if (!strchr(v, 'x') || !args_size(v, 40, 8192, &r->plot_w, &r->plot_h)) {
        fprintf(stderr, "%s: --plot-size needs WxH, each 40 to 8192, got '%s'\n", c, v);
        return -1;
    }
    return 0;
}

static const cli_option own[] = {
    {"--model", 'm', "SPEC", "the model to fit (one)", "model", CLI_CALLS(take_model)},
    {"--samples", 0, "N,...|all", "training sample counts (default 1000,4000,16000,64000,all;\n"
                                  "'k' suffix: thousands); counts >= the training set are 'all'", NULL,
     CLI_STRING_AT(tradeoff_run, lists[L_SAMPLES])},
    {"--methods", 0, "M,...", "ceres (Levenberg-Marquardt), ceres:dogleg, or NLopt names\n"
                              "(LD_LBFGS, LD_SLSQP, LN_BOBYQA ...); default: the --backend /\n"
                              "--algorithm setting if given, else ceres,LD_LBFGS", NULL,
     CLI_STRING_AT(tradeoff_run, lists[L_METHODS])},
    {"--residuals", 0, "R,...", "residual forms (default: --residual, log)", NULL,
     CLI_STRING_AT(tradeoff_run, lists[L_RESIDUALS])},
    {"--starts-list", 0, "N|auto,...", "start counts (brdfit fit --starts; auto: its automatic\ncount; default: --starts, or auto)", NULL,
     CLI_STRING_AT(tradeoff_run, lists[L_STARTS])},
    {"--test-fraction", 0, "F", "held-out share of the samples, seeded random (default 0.2)", NULL,
     CLI_CALLS(take_test_fraction)},
    {"--cost", 0, "work|seconds", "what a setting costs: sample evaluations (default; the same on\n"
                                  "every machine) or wall time (varies from run to run)", NULL,
     CLI_CALLS(take_cost)},
    {"--timing", 0, NULL, "wall times in the table and the files too", NULL,
     CLI_SETS(tradeoff_run, timing, 1)},
    {"--repeats", 0, "N", "fit each setting N times, keep the least time (default 1)", NULL,
     CLI_CALLS(take_repeats)},
    {"--error", 0, "rmse|rmse_log|rmse_cos|rmse_rel", "test error to judge by (default rmse_log)", NULL,
     CLI_CALLS(take_error)},
    {"--tolerance", 0, "T", "recommend the cheapest setting with test error <= best * (1 + T)\n(default 0.05)",
     NULL, CLI_NUMBER_AT(tradeoff_run, tolerance, 0.0, HUGE_VAL, "a number >= 0 (relative, 0.05 = 5%)")},
    {"--json", 0, "FILE", "the table, machine-readable (stable keys; - for standard output)", "file",
     CLI_STRING_AT(tradeoff_run, json_path)},
    {"--csv", 0, "FILE", "one row per setting (- for standard output)", "file",
     CLI_STRING_AT(tradeoff_run, csv_path)},
    {"--plot", 0, "FILE.png|.svg|.pdf", "test error against the cost with the Pareto front (format by\n"
                                        "the extension)", "file",
     CLI_STRING_AT(tradeoff_run, plot_path)},
    {"--plot-size", 0, "WxH", "pixels (PNG) or points (SVG, PDF); default 640x400", NULL,
     CLI_CALLS(take_plot_size)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &fit_options_fitting, &fit_options_optimizer, &data_options_reading, &data_options_preprocessing};
const cli_command cli_tradeoff = {
    "brdfit", "tradeoff", "DATA -m MODEL [options] [--json F] [--csv F] [--plot F.png|.svg|.pdf]",
    "measure fitting cost against accuracy",
    "Fits one model to a training share of DATA under every combination of sample count, method, residual and "
    "start count, measures each fit's error on the held-out samples, and recommends the cheapest setting within "
    "the tolerance of the best.",
    "file", groups, sizeof groups / sizeof groups[0],
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
    if (cli_take(&cli_tradeoff, targets, CLI_COUNT(targets), args, take_data, r, cmd) < 0)
        return -1;
    /* The data options and the base fit setting are repeated in the recommended command. */
    for (int i = 0; i < args->n; i++) {
        const cli_arg *x = &args->v[i];
        if (!x->option || groups[x->group] == &own_group || row_sets(x->option))
            continue;
        append_arg(r->data_args, sizeof r->data_args, x->name);
        if (x->value)
            append_arg(r->data_args, sizeof r->data_args, x->value);
    }
    return 0;
}

/* What must be there, the plot's name and the model: 0, or -1 after a one-line error. */
static int check_args(tradeoff_run *r)
{
    if (!r->data || r->nspecs == 0) {
        fprintf(stderr, "%s: %s (see brdfit tradeoff --help)\n", cmd,
                !r->data ? "a data file is required" : "-m MODEL is required");
        return -1;
    }
    if (r->plot_path && !bf_plot_format_of(r->plot_path)) {
        fprintf(stderr, "%s: --plot %s: the name must end in .png, .svg or .pdf\n", cmd, r->plot_path);
        return -1;
    }
    if (r->plot_path && !strcmp(r->plot_path, "-")) {
        fprintf(stderr, "%s: --plot needs a file name\n", cmd);
        return -1;
    }
    return fit_options_check(r->o, r->specs, 1, cmd);
}

/* Each list as given or by default, split into items: 0, or -1 after the error. The
 * defaults follow the base setting (the library's values of the options). */
static int split_lists(tradeoff_run *r)
{
    char starts_default[32], method[64], starts[32], backend_name[32], algorithm[128], residual[32];
    bf_backend backend = BF_BACKEND_CERES;
    bf_options_get(r->o, "starts", starts, sizeof starts, NULL);
    bf_options_get(r->o, "backend", backend_name, sizeof backend_name, NULL);
    bf_options_get(r->o, "algorithm", algorithm, sizeof algorithm, NULL);
    bf_options_get(r->o, "residual", residual, sizeof residual, NULL);
    bf_backend_parse(backend_name, &backend, NULL);
    snprintf(starts_default, sizeof starts_default, "%s", atoi(starts) > 0 ? starts : "auto");
    const char *lists[NLISTS];
    memcpy(lists, r->lists, sizeof lists);
    if (!lists[L_METHODS])
        lists[L_METHODS] = backend != BF_BACKEND_CERES || *algorithm
                               ? method_of(backend, *algorithm ? algorithm : NULL, method, sizeof method)
                               : "ceres,LD_LBFGS";
    if (!lists[L_RESIDUALS])
        lists[L_RESIDUALS] = residual;
    if (!lists[L_STARTS])
        lists[L_STARTS] = starts_default;
    for (int l = 0; l < NLISTS; l++) {
        if (!(r->bufs[l] = strdup(lists[l]))) {
            fprintf(stderr, "%s: out of memory\n", cmd);
            return -1;
        }
        if ((r->nitems[l] = split_list(r->bufs[l], r->items[l], list_names[l])) < 0)
            return -1;
    }
    return 0;
}

/* The items as counts, methods, residual forms and start counts: 0, or -1 after a
 * one-line error naming the list and the item. */
static int parse_lists(tradeoff_run *r)
{
    bf_error err;
    long n;
    for (int k = 0; k < r->nitems[L_SAMPLES]; k++) {
        const char *item = r->items[L_SAMPLES][k];
        if (!strcmp(item, "all"))
            r->sample_counts[k] = 0;
        else if (parse_count(item, 1000000000L, &n))
            r->sample_counts[k] = (size_t)n;
        else {
            fprintf(stderr, "%s: --samples: '%s' is not a positive count or 'all'\n", cmd, item);
            return -1;
        }
    }
    for (int k = 0; k < r->nitems[L_METHODS]; k++) {
        if (bf_tradeoff_method_check(r->items[L_METHODS][k], r->o, &err) != BF_OK) {
            fprintf(stderr, "%s: --methods: %s\n", cmd, err.msg);
            return -1;
        }
    }
    for (int k = 0; k < r->nitems[L_RESIDUALS]; k++)
        if (bf_residual_parse(r->items[L_RESIDUALS][k], &r->residuals[k], &err) != BF_OK) {
            fprintf(stderr, "%s: --residuals: %s\n", cmd, err.msg);
            return -1;
        }
    for (int k = 0; k < r->nitems[L_STARTS]; k++) {
        if (!strcmp(r->items[L_STARTS][k], "auto")) {
            n = 0; /* brdfit fit's automatic starts */
        } else if (!parse_count(r->items[L_STARTS][k], 100000, &n)) {
            fprintf(stderr, "%s: --starts-list: '%s' is not a positive integer or auto\n", cmd, r->items[L_STARTS][k]);
            return -1;
        }
        r->starts[k] = (int)n;
    }
    /* The sample counts may still merge later; the product is the most there can be. */
    double settings = (double)r->nitems[0] * r->nitems[1] * r->nitems[2] * r->nitems[3];
    if (settings > BF_TRADEOFF_MAX_ROWS) {
        fprintf(stderr, "%s: %.0f settings is too many (at most %d): shorten the lists\n", cmd, settings,
                BF_TRADEOFF_MAX_ROWS);
        return -1;
    }
    return 0;
}

/* Every check before any data is read: bad usage costs no time and leaves no file.
 * Returns 0, or the exit status after a one-line error. */
static int check_usage(tradeoff_run *r)
{
    if (check_args(r) < 0)
        return 2;
    if (split_lists(r) < 0 || parse_lists(r) < 0)
        return 2;
    char scene[4096];
    const bf_path_use in[] = {{"data file", r->data}, {"--scene file", data_options_scene(r->o, scene, sizeof scene)}},
                      out[] = {{"--json", r->json_path}, {"--csv", r->csv_path}, {"--plot", r->plot_path}};
    return args_check_outputs(cmd, in, 2, out, 3);
}

/* Reads the data, holds out the test share and sets up the rows: 0, or the exit
 * status after a one-line error. */
static int load(tradeoff_run *r)
{
    bf_error err;
    bf_tradeoff *t = NULL;
    bf_samples *all = data_options_load(r->o, r->data, NULL, NULL, cmd);
    if (!all)
        return 1;
    char seed_text[32];
    bf_options_get(r->o, "seed", seed_text, sizeof seed_text, NULL);
    const uint64_t seed = strtoull(seed_text, NULL, 10);
    if (bf_tradeoff_split(all, r->test_fraction, seed, &r->train, &r->test, &err) != BF_OK) {
        fprintf(stderr, "%s: %s: %s\n", cmd, r->data, err.msg);
        bf_samples_free(all);
        return 1;
    }
    if (bf_tradeoff_new(r->data, r->specs[0], r->train->n, r->nitems[L_SAMPLES], r->sample_counts, r->nitems[L_METHODS],
                        (const char *const *)r->items[L_METHODS], r->nitems[L_RESIDUALS], r->residuals,
                        r->nitems[L_STARTS], r->starts, &r->t, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        bf_samples_free(all);
        return err.code == BF_ERR_ARG ? 2 : 1;
    }
    t = r->t;
    t->total = all->n;
    t->test_n = r->test->n;
    t->channels = all->channels;
    t->test_fraction = r->test_fraction;
    t->seed = seed;
    t->repeats = r->repeats;
    t->metric = r->metric;
    t->tolerance = r->tolerance;
    t->cost = r->cost;
    t->timing = r->timing || r->cost == BF_TRADEOFF_COST_SECONDS;
    bf_samples_free(all);
    return 0;
}

/* A row's outcome on stderr, as it finishes. */
static void print_progress(const bf_tradeoff *t, int i)
{
    const bf_tradeoff_row *r = &t->rows[i];
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

/* Fits every row in turn (one at a time, so that times compare); *all_ok becomes 0 when
 * a row failed. Returns 0, or -1 after an error that stops the run. */
static int run_rows(tradeoff_run *r, int *all_ok)
{
    bf_error err;
    for (int i = 0; i < r->t->nrows; i++) {
        if (bf_tradeoff_run_row(r->t, i, r->train, r->test, r->o, &err) == BF_ERR_NOMEM) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            return -1;
        }
        *all_ok &= r->t->rows[i].ran && r->t->rows[i].ok;
        if (!cli_quiet())
            print_progress(r->t, i);
    }
    return 0;
}

/* The recommended setting as a brdfit fit command line (or that none fitted). */
static void print_recommendation(FILE *info, const tradeoff_run *run)
{
    const bf_tradeoff *t = run->t;
    if (t->recommended < 0) {
        fprintf(info, "recommended: none (no setting fitted)\n");
        return;
    }
    const bf_tradeoff_row *r = &t->rows[t->recommended], *b = &t->rows[t->best];
    char fa[256], rc[48], bc[48];
    fit_args(r, fa, sizeof fa);
    if (t->cost == BF_TRADEOFF_COST_SECONDS) {
        snprintf(rc, sizeof rc, "%.3f s", r->seconds);
        snprintf(bc, sizeof bc, "%.3f s", b->seconds);
    } else {
        snprintf(rc, sizeof rc, "%.4g M sample evaluations", r->work / 1e6);
        snprintf(bc, sizeof bc, "%.4g M", b->work / 1e6);
    }
    fprintf(info, "recommended: #%d (%s %.4g for %s; best #%d: %.4g for %s): brdfit fit %s%s -m %s %s\n",
            t->recommended + 1, bf_compare_metric_name(t->metric), r->error, rc, t->best + 1, b->error, bc,
            run->data, run->data_args, t->model, fa);
}

/* What the plot's axes span, for a reader of the terminal. */
static void print_plot_axes(FILE *info, const bf_tradeoff *t, const char *plot_path, const bf_plot_axes *axes)
{
    int seconds = t->cost == BF_TRADEOFF_COST_SECONDS;
    fprintf(info, "plot %s: test %s (y, %s axis, %.4g to %.4g) against fitting %s (x, log axis, %s, %.4g to %.4g); "
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
    print_recommendation(info, r);
    fflush(info);
    if ((r->json_path && bf_tradeoff_write_json(r->t, r->json_path, &err) != BF_OK) ||
        (r->csv_path && bf_tradeoff_write_csv(r->t, r->csv_path, &err) != BF_OK) ||
        (r->plot_path &&
         bf_tradeoff_write_plot(r->t, r->plot_path, BF_PLOT_BY_NAME, r->plot_w, r->plot_h, &range, &err) != BF_OK)) {
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
    bf_samples_free(r->train);
    bf_samples_free(r->test);
    for (int k = 0; k < r->nspecs; k++)
        free(r->specs[k]);
    for (int l = 0; l < NLISTS; l++)
        free(r->bufs[l]);
    bf_options_free(r->o);
}

int cmd_tradeoff(int argc, char **argv)
{
    tradeoff_run r;
    run_init(&r);
    if (!r.o)
        return 1;
    cli_args args;
    int p = cli_parse(&cli_tradeoff, argc, argv, &args);
    if (p != CLI_OK) {
        run_free(&r);
        return p == CLI_EXIT ? 0 : 2;
    }
    int all_ok = 1, status = take_args(&r, &args) < 0 ? 2 : check_usage(&r);
    if (status == 0)
        status = load(&r);
    if (status == 0)
        status = run_rows(&r, &all_ok) < 0 ? 1 : 0;
    if (status == 0) {
        bf_tradeoff_rank(r.t);
        status = report(&r) < 0 ? 1 : 0;
    }
    if (status == 0 && !all_ok)
        fprintf(stderr, "%s: %s\n", cmd, r.t->recommended >= 0 ? "some settings failed" : "every setting failed");
    if (status == 0)
        status = all_ok ? 0 : 1;
    cli_args_free(&args);
    run_free(&r);
    return status;
}
