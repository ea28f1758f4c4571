/* brdfit fit DATA -m MODEL[,MODEL...] [options] [-o RESULT.json]: fits each model to the
 * data, prints a short summary per model, and writes the result file.
 *
 * Decisions:
 *  - -m takes a comma-separated list; a comma starts a new model only where the next
 *    token is a model name (no '=', or a ':' of its own), so option lists stay whole:
 *    "-m microfacet:D=ggx,G=smith_ggx,walter" is two models. -m may also be repeated.
 *  - --residual defaults to log (ln(1 + f cos theta_i)): measured BRDFs span decades
 *    between the diffuse floor and the highlight, and the log form weighs both, while a
 *    linear fit serves the peak alone; the cosine inside also tames grazing samples.
 *  - --threads defaults to every online core; results are the same for every thread
 *    count (fixed chunks summed in a fixed order; the count is written to the result).
 *  - --seed seeds everything random: the data options' subsampling and the multistart.
 *  - -o with one model writes the result object (a parameter file for brdfit eval);
 *    with several, {"fits": [result, ...]}, which eval does not take. A failed fit is
 *    still written (ok: false, the start as parameters) and the exit status is 1.
 *  - --accuracy fast|balanced|best is a bundle of options (the library's option table,
 *    brdfit/options.h); options the user gives win whatever their order, the fast
 *    preset's subsample included.
 *  - -o is checked before the data is read (args_check_outputs): the same file as the
 *    data or the scene under any name is refused (exit 2), an unwritable one fails
 *    (exit 1) before any fit.
 *  - Exit: 0 when every fit is ok; 1 for bad data, a failed fit or an unwritable output;
 *    2 for bad usage (options, model specs, parameter names in --fix/--bound). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "brdfit/fit.h"
#include "brdfit/io.h"
#include "args.h"
#include "commands.h"
#include "data_options.h"
#include "fit_options.h"

static const char cmd[] = "brdfit fit";

#define MAX_MODELS 64

/* What the command line asked for, and what the run holds (freed by run_free). */
typedef struct fit_run {
    bf_options *o;
    char *specs[MAX_MODELS];
    int nmodels;
    const char *data, *out_path;
    bf_samples *s;
    bf_fit_result results[MAX_MODELS];
    int nres;
} fit_run;

static int take_model(void *target, const cli_option *o, const char *v, const char *c)
{
    fit_run *f = target;
    (void)o;
    int k = fit_options_split_models(v, f->specs, f->nmodels, MAX_MODELS, c);
    if (k < 0)
        return -1;
    f->nmodels = k;
    return 0;
}

static const cli_option own[] = {
    {"--model", 'm', "SPECS",
     "models to fit, e.g. walter or microfacet:D=ggx,G=smith_ggx,lambert\n"
     "(a comma starts a new model where a model name follows; repeatable)",
     "model", CLI_CALLS(take_model)},
    {"--output", 'o', "FILE",
     "result JSON (one model: a parameter file; several: {\"fits\": [...]});\n- for standard output", "file",
     CLI_STRING_AT(fit_run, out_path)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group,
                                          &fit_options_accuracy,
                                          &fit_options_fitting,
                                          &fit_options_optimizer,
                                          &data_options_reading,
                                          &data_options_preprocessing};
const cli_command cli_fit = {
    "brdfit",
    "fit",
    "DATA -m MODEL[,MODEL...] [options] [-o RESULT.json]",
    "fit models to measured or synthetic reflectance",
    "Fits each model to the data file (CSV, MERL .binary, Cornell, ALTA; - for standard input), prints a short "
    "summary per model and writes the result file, which brdfit eval and brdfit render take as a parameter file.",
    "file",
    groups,
    sizeof groups / sizeof groups[0],
};

static void print_values(FILE *out, const bf_param_info *pi, const double *v, const double *se,
                         const unsigned char *fixed, int C)
{
    char buf[40];
    int n = pi->color ? C : 1;
    fprintf(out, "    %-16s", pi->name);
    for (int c = 0; c < n; c++) {
        fprintf(out, " %.6g", v[c]);
        if (fixed[c])
            fprintf(out, " (fixed)");
        else if (isnan(se[c]))
            fprintf(out, " (+- ?)");
        else /* 0 on data the model reproduces exactly */
            fprintf(out, " (+- %s)", (snprintf(buf, sizeof buf, "%.2g", se[c]), buf));
    }
    fputc('\n', out);
}

static void summary(FILE *out, const bf_fit_result *r)
{
    const bf_model *m = r->model;
    const bf_solution *s = &r->solution;
    fprintf(out, "%s  %s\n", bf_model_spec(m), r->ok ? "ok" : "FAILED");
    fprintf(out, "  rmse %.6g  log rmse %.6g  k %d  %s/%s  %d iterations  %.3f s  (%d start%s", r->metrics.rmse,
            r->metrics.rmse_log, r->metrics.k, s->backend, s->algorithm, s->iterations, r->seconds, r->starts,
            r->starts == 1 ? "" : "s");
    if (r->starts > 1)
        fprintf(out, ", %d at the best", r->starts_at_best);
    if (r->candidates > 0)
        fprintf(out, "; screened from %d candidates on %zu samples", r->candidates, r->screen.samples);
    if (r->presolve.samples > 0)
        fprintf(out, "; presolved on %zu samples in %d iterations", r->presolve.samples, r->presolve.iterations);
    fputs(")\n", out);
    fprintf(out, "  termination: %s\n", s->termination);
    for (int i = 0; i < bf_model_nparams(m); i++) {
        int o = bf_model_param_offset(m, i);
        print_values(out, bf_model_param(m, i), r->x + o, r->stderr_ + o, r->fixed + o, bf_model_channels(m));
    }
    for (int w = 0; w < r->nwarnings; w++)
        fprintf(out, "  warning: %s\n", r->warnings[w]);
}

static int take_data(void *f, const char *v, const char *c)
{
    return data_options_take_file(&((fit_run *)f)->data, v, c);
}

/* Takes the parsed command line into f (the targets follow the groups): 0, or -1 after a
 * one-line error. */
static int take_args(fit_run *f, const cli_args *args)
{
    void *const targets[] = {f, &f->o, &f->o, &f->o, &f->o, &f->o};
    return cli_take(&cli_fit, targets, CLI_COUNT(targets), args, take_data, f, cmd);
}

/* Bad usage is found before any data is read: what is missing, the model specs, the
 * output. Returns 0, or the exit status after a one-line error. */
static int check_usage(fit_run *f)
{
    if (!f->data || f->nmodels == 0) {
        fprintf(stderr, "%s: %s (see brdfit fit --help)\n", cmd,
                !f->data ? "a data file is required" : "-m MODEL is required");
        return 2;
    }
    if (fit_options_check(f->o, f->specs, f->nmodels, cmd) < 0)
        return 2;
    char scene[4096];
    const bf_path_use in[] = {{"data file", f->data}, {"--scene file", data_options_scene(f->o, scene, sizeof scene)}},
                      out[] = {{"-o", f->out_path}};
    return args_check_outputs(cmd, in, 2, out, 1);
}

/* Fits every model in turn, printing each summary to info; *all_ok becomes 0 when a fit
 * failed. Returns 0, or the exit status of an error that stops the run. */
static int fit_models(fit_run *f, FILE *info, int *all_ok)
{
    bf_error err;
    for (int k = 0; k < f->nmodels; k++) {
        cli_note(cmd, "fitting %s", f->specs[k]);
        bf_fit_result *r = &f->results[f->nres];
        bf_fit_result_init(r);
        int rc = bf_fit(f->s, f->specs[k], f->o, r, &err);
        if (rc != BF_OK) {
            fprintf(stderr, "%s: %s: %s\n", cmd, f->specs[k], err.msg);
            return rc == BF_ERR_ARG ? 2 : 1;
        }
        f->nres++;
        if (!cli_quiet())
            summary(info, r);
        *all_ok &= r->ok;
    }
    fflush(info);
    return 0;
}

/* -o: one result object, or {"fits": [...]} for several. 0, or -1 after the error. */
static int write_results(const fit_run *f)
{
    if (!f->out_path)
        return 0;
    bf_error err;
    const bf_fit_result *list[MAX_MODELS];
    for (int k = 0; k < f->nres; k++)
        list[k] = &f->results[k];
    int rc = f->nres == 1 ? bf_fit_write_json(&f->results[0], f->data, f->out_path, &err)
                          : bf_fit_write_json_list(list, f->nres, f->data, f->out_path, &err);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    return 0;
}

/* Reads the data, fits, writes: the exit status. */
static int run(fit_run *f)
{
    if (!(f->s = data_options_load(f->o, f->data, NULL, NULL, cmd)))
        return 1;
    /* The summary goes to stdout unless the result does. */
    FILE *info = f->out_path && !strcmp(f->out_path, "-") ? stderr : stdout;
    int all_ok = 1, status = fit_models(f, info, &all_ok);
    if (status != 0)
        return status;
    if (write_results(f) < 0)
        return 1;
    if (!all_ok)
        fprintf(stderr, "%s: %s\n", cmd, f->nres == 1 ? "the fit failed" : "a fit failed");
    return all_ok ? 0 : 1;
}

static void run_free(fit_run *f)
{
    for (int k = 0; k < f->nres; k++)
        bf_fit_result_clear(&f->results[k]);
    for (int k = 0; k < f->nmodels; k++)
        free(f->specs[k]);
    bf_samples_free(f->s);
    bf_options_free(f->o);
}

int cmd_fit(int argc, char **argv)
{
    fit_run f;
    memset(&f, 0, sizeof f);
    if (!(f.o = cmd_options_new(BF_TASK_FIT, cmd)))
        return 1;
    cli_args args;
    int p = cli_parse(&cli_fit, argc, argv, &args);
    if (p != CLI_OK) {
        run_free(&f);
        return p == CLI_EXIT ? 0 : 2;
    }
    int status = take_args(&f, &args) < 0 ? 2 : check_usage(&f);
    if (status == 0)
        status = run(&f);
    cli_args_free(&args);
    run_free(&f);
    return status;
}
