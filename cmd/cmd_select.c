/* brdfit select DATA [-m MODEL,...] [--tolerance T] [--scene SCENE.json] [options]:
 * fits candidate models and names the one with the fewest free parameters whose error
 * is within T of the best candidate's (see lib/include/brdfit/select.h).
 *
 * Decisions:
 *  - Without -m, the default candidates (bf_select_default_candidates): diffuse models,
 *    isotropic and anisotropic single lobes, two lobes, and for colour data each model
 *    with a coloured highlight also with mono=specular (one highlight value for every
 *    channel).
 *  - The error is --error (default rmse_log, as compare) over the fitted samples; with
 *    --scene the samples are the scene's and the error is weighted by the scene, so the
 *    choice follows what the scene can see.
 *  - --abs-tolerance (default 1e-6) treats errors this close to the best as equal: on
 *    noiseless data every adequate model reaches ~1e-15, where a relative tolerance alone
 *    would pick whichever rounding was luckiest.
 *  - --rank: error (default, the above), cv (the same with the cross-validated error of
 *    the fitted objective, --folds K), or bic, aic, aicc (the lowest criterion; the
 *    tolerances do not enter). select defaults to the error because it answers "the
 *    smallest model good enough": on a million samples a criterion rewards any parameter
 *    that lowers the error at all. A robust loss allows only error and cv.
 *  - Nothing printed or written depends on wall time (the work column is in sample
 *    evaluations); --timing adds the seconds to the table and the JSON.
 *  - -o writes the chosen model's fit result (a parameter file for brdfit eval).
 *  - Exit: 0 when a model was chosen; 1 for bad data or when no candidate could be
 *    fitted; 2 for bad usage. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/select.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"
#include "fit_options.h"
#include "rank_options.h"

static const char cmd[] = "brdfit select";

#define MAX_MODELS 128

static const cli_option own[] = {
    {"--models", 'm', "SPECS", "candidates (as brdfit fit; repeatable); default: diffuse models,\n"
                               "one isotropic lobe, anisotropic lobes, two lobes, and for colour\n"
                               "data each with mono=specular (a white highlight)", "model"},
    {"--model", 0, "SPECS", "the same as --models", "model"},
    {"--tolerance", 0, "T", "relative: candidates with error <= best * (1 + T) + A qualify\n"
                            "(default 0.05); the one with the fewest free parameters is chosen,\n"
                            "then isotropic, one lobe, monochrome highlight, lower error", NULL},
    {"--abs-tolerance", 0, "A", "absolute part of the tolerance (default 1e-6)", NULL},
    {"--error", 0, "rmse|rmse_log|rmse_cos|rmse_rel", "the error compared (default rmse_log)", NULL},
    {"--json", 0, "FILE", "every candidate and the choice, machine-readable (- for standard output)", "file"},
    {"--output", 'o', "FILE", "the chosen model's fit result (a parameter file; - for standard output)", "file"},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &rank_options_error, &fit_options_accuracy, &fit_options_fitting, &fit_options_optimizer, &data_options_reading, &data_options_preprocessing};
const cli_command cli_select = {
    "brdfit", "select", "DATA [-m MODEL,...] [--tolerance T] [--scene SCENE.json] [options]",
    "choose the smallest model that serves",
    "Fits every candidate to DATA (- for standard input) and chooses the one with the fewest free parameters "
    "whose error is within the tolerance of the best; with --scene, error is measured over the directions the "
    "scene uses.",
    "file", groups, sizeof groups / sizeof groups[0],
};

static void progress(void *ctx, const bf_select *s, int i)
{
    (void)ctx;
    const bf_select_candidate *c = &s->c[i];
    if (c->state == BF_CMP_ERROR)
        fprintf(stderr, "[%d/%d] %s: %s\n", i + 1, s->n, c->spec, c->message);
    else
        fprintf(stderr, "[%d/%d] %s: k %d, %s %.6g, %.3f s%s\n", i + 1, s->n, c->spec, c->result.metrics.k,
                bf_compare_metric_name(s->metric), bf_compare_metric_value(&c->result.metrics, s->metric),
                c->seconds, c->state == BF_CMP_OK ? "" : " (failed)");
}

static const char *error_name(const bf_select *s)
{
    return s->rank_by == BF_RANK_CV ? "cv" : bf_compare_metric_name(s->metric);
}

static void table(FILE *out, const bf_select *s)
{
    int *order = malloc((size_t)s->n * sizeof *order);
    if (!order)
        return;
    bf_select_order(s, order);
    const int criterion = s->rank_by != BF_RANK_ERROR && s->rank_by != BF_RANK_CV;
    fprintf(out, "%-3s %-40s %4s %-6s %5s %-8s %12s %13s %5s %9s%s\n", "", "model", "k", "aniso", "lobes", "specular",
            error_name(s), criterion ? bf_compare_rank_name(s->rank_by) : "", "rank", "work M",
            s->timing ? "  seconds" : "");
    for (int j = 0; j < s->n; j++) {
        const bf_select_candidate *c = &s->c[order[j]];
        const char *mark = order[j] == s->chosen ? "=>" : c->within ? "ok" : "";
        char err[32], crit[32] = "", rank[16] = "-", secs[32] = "";
        if (c->state == BF_CMP_OK && isfinite(c->error))
            snprintf(err, sizeof err, "%.6g", c->error);
        else
            snprintf(err, sizeof err, "%s", c->state == BF_CMP_OK ? "-" : bf_compare_state_name(c->state));
        if (criterion && isfinite(c->criterion))
            snprintf(crit, sizeof crit, "%.6g", c->criterion);
        if (c->rank)
            snprintf(rank, sizeof rank, "%d", c->rank);
        if (s->timing)
            snprintf(secs, sizeof secs, " %8.3f", c->seconds);
        fprintf(out, "%-3s %-40s %4d %-6s %5d %-8s %12s %13s %5s %9.4g%s\n", mark, c->spec, c->k,
                c->anisotropic ? "yes" : "no", c->lobes, c->coloured_specular ? "colour" : "mono", err, crit, rank,
                c->work / 1e6, secs);
    }
    free(order);
    if (s->chosen >= 0) {
        const bf_select_candidate *b = &s->c[s->best], *c = &s->c[s->chosen];
        if (criterion)
            fprintf(out, "chosen: %s (k %d, lowest %s %.6g; %s %.6g; best %s %.6g with k %d)\n", c->spec, c->k,
                    bf_compare_rank_name(s->rank_by), c->criterion, error_name(s), c->error, b->spec, b->error, b->k);
        else
            fprintf(out, "chosen: %s (k %d, %s %.6g; best %s %.6g with k %d; tolerance %g + %g)\n", c->spec, c->k,
                    error_name(s), c->error, b->spec, b->error, b->k, s->tolerance, s->abs_tolerance);
    }
    for (int i = 0; i < s->n; i++) {
        const bf_select_candidate *c = &s->c[i];
        for (int w = 0; (c->state == BF_CMP_OK || c->state == BF_CMP_FAILED) && w < c->result.nwarnings; w++)
            fprintf(out, "warning: %s: %s\n", c->spec, c->result.warnings[w]);
    }
}

int cmd_select(int argc, char **argv)
{
    data_options dopt;
    memset(&dopt, 0, sizeof dopt);
    fit_options fopt;
    fit_options_init(&fopt);
    char *specs[MAX_MODELS] = {0};
    int nmodels = 0, status = 2;
    double tolerance = 0.05, abs_tolerance = 1e-6;
    bf_compare_metric metric = BF_CMP_RMSE_LOG;
    const char *data = NULL, *json_path = NULL, *out_path = NULL;
    const char **defaults = NULL;
    bf_samples *s = NULL;
    bf_select sel;
    memset(&sel, 0, sizeof sel);
    bf_error err;
    rank_options ro;
    rank_options_init(&ro, BF_RANK_ERROR);

    cli_args args;
    int p = cli_parse(&cli_select, argc, argv, &args);
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
        if (d == 0)
            d = fit_options_parse(&fopt, a, v, cmd);
        if (d == 0)
            d = fit_options_parse_accuracy(&fopt, a, v, cmd);
        if (d == 0)
            d = rank_options_parse(&ro, a, v, cmd);
        if (d < 0)
            goto done;
        if (d > 0)
            continue;
        if (!strcmp(a, "--model") || !strcmp(a, "--models")) {
            int k = fit_options_split_models(v, specs, nmodels, MAX_MODELS, cmd);
            if (k < 0)
                goto done;
            nmodels = k;
        } else if (!strcmp(a, "--tolerance") || !strcmp(a, "--abs-tolerance")) {
            if (!args_number(v, 0.0, HUGE_VAL, !strcmp(a, "--tolerance") ? &tolerance : &abs_tolerance)) {
                fprintf(stderr, "%s: %s needs a number >= 0, got '%s'\n", cmd, a, v);
                goto done;
            }
        } else if (!strcmp(a, "--error")) {
            if (bf_compare_metric_parse(v, &metric, &err) != BF_OK) {
                fprintf(stderr, "%s: --error: %s\n", cmd, err.msg);
                goto done;
            }
        } else if (!strcmp(a, "--json")) {
            json_path = v;
        } else { /* --output */
            out_path = v;
        }
    }
    if (!data) {
        fprintf(stderr, "%s: a data file is required (see brdfit select --help)\n", cmd);
        goto done;
    }
    if (rank_options_check(&ro, &fopt.fit, cmd) < 0)
        goto done;
    /* Model specs are checked before any data is read. */
    if (fit_options_check_models(&fopt, specs, nmodels, cmd) < 0)
        goto done;
    /* With a scene, error is reported over the scene's directions; --accuracy fast's
     * subsample is drawn inside the scene. */
    fit_options_finish(&fopt, &dopt);
    const bf_path_use in[] = {{"data file", data}, {"--scene file", dopt.scene}},
                      out[] = {{"--json", json_path}, {"-o", out_path}};
    if ((status = args_check_outputs(cmd, in, 2, out, 2)) != 0)
        goto done;

    status = 1;
    if (!(s = data_options_load(&dopt, data, NULL, cmd)))
        goto done;
    const char *const *list = (const char *const *)specs;
    int n = nmodels;
    if (n == 0) {
        if ((n = bf_select_default_candidates(s->channels, &defaults)) < 0) {
            fprintf(stderr, "%s: out of memory\n", cmd);
            goto done;
        }
        list = defaults;
    }
    if (bf_select_init(&sel, n, list, s->channels, metric, tolerance, abs_tolerance, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        status = err.code == BF_ERR_ARG ? 2 : 1;
        goto done;
    }
    sel.rank_by = ro.rank_by;
    sel.folds = ro.folds;
    sel.timing = ro.timing;
    if (bf_select_run(&sel, s, &fopt.fit, cli_quiet() ? NULL : progress, NULL, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    FILE *info = (json_path && !strcmp(json_path, "-")) || (out_path && !strcmp(out_path, "-")) ? stderr : stdout;
    table(info, &sel);
    if (sel.chosen < 0) {
        fprintf(stderr, "%s: no candidate could be fitted to %s\n", cmd, data);
        goto done;
    }
    if (json_path && bf_select_write_json(&sel, data, json_path, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    if (out_path && bf_fit_write_json(&sel.c[sel.chosen].result, data, out_path, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    status = 0;
done:
    cli_args_free(&args);
    bf_select_free(&sel);
    free(defaults);
    for (int k = 0; k < nmodels; k++)
        free(specs[k]);
    bf_samples_free(s);
    return status;
}
