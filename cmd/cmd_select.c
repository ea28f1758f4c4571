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
 *  - --jobs N fits N candidates at once (bf_compare_run, as compare), each with
 *    --threads / N threads; the table and --json do not depend on it (the progress lines
 *    come in the order fits finish; the -o fit file records its solver threads and wall
 *    time, as brdfit fit's does).
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

/* What the command line asked for, and what the run holds (freed by run_free). */
typedef struct select_run {
    bf_options *o;
    char *specs[MAX_MODELS];
    int nmodels;
    const char *data, *json_path, *out_path;
    const char **defaults;
    bf_samples *s;
    bf_select *sel;
} select_run;

/* --models and --model, the same option. */
static int take_models(void *target, const cli_option *o, const char *v, const char *c)
{
    select_run *r = target;
    (void)o;
    int k = fit_options_split_models(v, r->specs, r->nmodels, MAX_MODELS, c);
    if (k < 0)
        return -1;
    r->nmodels = k;
    return 0;
}

static const cli_option own[] = {
    {"--models", 'm', "SPECS",
     "candidates (as brdfit fit; repeatable); default: diffuse models,\n"
     "one isotropic lobe, anisotropic lobes, two lobes, and for colour\n"
     "data each with mono=specular (a white highlight)",
     "model", CLI_CALLS(take_models)},
    {"--model", 0, "SPECS", "the same as --models", "model", CLI_CALLS(take_models)},
    CLI_LIB("--tolerance"),
    CLI_LIB("--abs-tolerance"),
    CLI_LIB("--jobs"),
    CLI_LIB("--error"),
    {"--json", 0, "FILE", "every candidate and the choice, machine-readable (- for standard output)", "file",
     CLI_STRING_AT(select_run, json_path)},
    {"--output", 'o', "FILE", "the chosen model's fit result (a parameter file; - for standard output)", "file",
     CLI_STRING_AT(select_run, out_path)},
};
static const cli_group own_group = CLI_GROUP_OPTIONS(NULL, own, BF_TASK_SELECT, select_run, o);
static const cli_group *const groups[] = {&own_group,
                                          &rank_options_error,
                                          &fit_options_accuracy,
                                          &fit_options_fitting,
                                          &fit_options_optimizer,
                                          &data_options_reading,
                                          &data_options_preprocessing};
const cli_command cli_select = {
    "brdfit",
    "select",
    "DATA [-m MODEL,...] [--tolerance T] [--scene SCENE.json] [options]",
    "choose the smallest model that serves",
    "Fits every candidate to DATA (- for standard input) and chooses the one with the fewest free parameters "
    "whose error is within the tolerance of the best; with --scene, error is measured over the directions the "
    "scene uses.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

static void progress(void *user, const bf_select *s, int i, int done)
{
    (void)user;
    const bf_select_candidate *c = &s->c[i];
    if (c->state == BF_CMP_ERROR)
        fprintf(stderr, "[%d/%d] %s: %s\n", done, s->n, c->spec, c->message);
    else
        fprintf(stderr, "[%d/%d] %s: k %d, %s %.6g, %.3f s%s\n", done, s->n, c->spec, c->result->metrics.k,
                bf_compare_metric_name(s->metric), bf_compare_metric_value(&c->result->metrics, s->metric), c->seconds,
                c->state == BF_CMP_OK ? "" : " (failed)");
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
                c->anisotropic ? "yes" : "no", c->lobes, c->colored_specular ? "colour" : "mono", err, crit, rank,
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
        for (int w = 0; (c->state == BF_CMP_OK || c->state == BF_CMP_FAILED) && w < c->result->nwarnings; w++)
            fprintf(out, "warning: %s: %s\n", c->spec, c->result->warnings[w]);
    }
}

static int take_data(void *r, const char *v, const char *c)
{
    return data_options_take_file(&((select_run *)r)->data, v, c);
}

/* Takes the parsed command line into r (the targets follow the groups): 0, or -1 after a
 * one-line error. */
static int take_args(select_run *r, const cli_args *args)
{
    void *const targets[] = {r, &r->o, &r->o, &r->o, &r->o, &r->o, &r->o};
    return cli_take(&cli_select, targets, CLI_COUNT(targets), args, take_data, r, cmd);
}

/* Bad usage is found before any data is read. Returns 0, or the exit status after a
 * one-line error. */
static int check_usage(select_run *r)
{
    if (!r->data) {
        fprintf(stderr, "%s: a data file is required (see brdfit select --help)\n", cmd);
        return 2;
    }
    if (fit_options_check(r->o, r->specs, r->nmodels, cmd) < 0)
        return 2;
    char scene[4096];
    const bf_path_use in[] = {{"data file", r->data}, {"--scene file", data_options_scene(r->o, scene, sizeof scene)}},
                      out[] = {{"--json", r->json_path}, {"-o", r->out_path}};
    return args_check_outputs(cmd, in, 2, out, 2);
}

/* Sets up the candidates (-m, or the defaults for the data's channel count) and fits
 * them. Returns 0, or the exit status after a one-line error. */
static int fit_candidates(select_run *r)
{
    bf_error err;
    const char *const *list = (const char *const *)r->specs;
    int n = r->nmodels;
    if (n == 0) {
        if ((n = bf_select_default_candidates(r->s->channels, &r->defaults)) < 0) {
            fprintf(stderr, "%s: out of memory\n", cmd);
            return 1;
        }
        list = r->defaults;
    }
    if (bf_select_new(n, list, r->s->channels, r->o, &r->sel, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return err.code == BF_ERR_ARG ? 2 : 1;
    }
    if (bf_select_run(r->sel, r->s, r->o, cli_quiet() ? NULL : progress, NULL, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    return 0;
}

/* The table, then --json and -o. Returns the exit status. */
static int report(select_run *r)
{
    bf_error err;
    const bf_select *sel = r->sel;
    int stdout_taken = (r->json_path && !strcmp(r->json_path, "-")) || (r->out_path && !strcmp(r->out_path, "-"));
    table(stdout_taken ? stderr : stdout, sel);
    if (sel->chosen < 0) {
        fprintf(stderr, "%s: no candidate could be fitted to %s\n", cmd, r->data);
        return 1;
    }
    if ((r->json_path && bf_select_write_json(sel, r->data, r->json_path, &err) != BF_OK) ||
        (r->out_path && bf_fit_write_json(sel->c[sel->chosen].result, r->data, r->out_path, &err) != BF_OK)) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    return 0;
}

static void run_free(select_run *r)
{
    bf_select_free(r->sel);
    free(r->defaults);
    for (int k = 0; k < r->nmodels; k++)
        free(r->specs[k]);
    bf_samples_free(r->s);
    bf_options_free(r->o);
}

int cmd_select(int argc, char **argv)
{
    select_run r;
    memset(&r, 0, sizeof r);
    if (!(r.o = cmd_options_new(BF_TASK_SELECT, cmd)))
        return 1;
    cli_args args;
    int p = cli_parse(&cli_select, argc, argv, &args);
    if (p != CLI_OK) {
        run_free(&r);
        return p == CLI_EXIT ? 0 : 2;
    }
    int status = take_args(&r, &args) < 0 ? 2 : check_usage(&r);
    if (status == 0)
        status = !(r.s = data_options_load(r.o, r.data, NULL, NULL, cmd)) ? 1 : fit_candidates(&r);
    if (status == 0)
        status = report(&r);
    cli_args_free(&args);
    run_free(&r);
    return status;
}
