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
 *  - --accuracy fast|balanced|best is a bundle of options (fit_options.c); options the
 *    user gives win whatever their order. The fast preset's subsample reaches the data
 *    options here, after parsing, and only when no --subsample was given.
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

static const cli_option own[] = {
    {"--model", 'm', "SPECS",
     "models to fit, e.g. walter or microfacet:D=ggx,G=smith_ggx,lambert\n"
     "(a comma starts a new model where a model name follows; repeatable)",
     "model"},
    {"--output", 'o', "FILE", "result JSON (one model: a parameter file; several: {\"fits\": [...]});\n- for standard output",
     "file"},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &fit_options_accuracy, &fit_options_fitting, &fit_options_optimizer, &data_options_reading, &data_options_preprocessing};
const cli_command cli_fit = {
    "brdfit", "fit", "DATA -m MODEL[,MODEL...] [options] [-o RESULT.json]",
    "fit models to measured or synthetic reflectance",
    "Fits each model to the data file (CSV, MERL .binary, Cornell, ALTA; - for standard input), prints a short "
    "summary per model and writes the result file, which brdfit eval and brdfit render take as a parameter file.",
    "file", groups, sizeof groups / sizeof groups[0],
};

static void print_values(FILE *out, const bf_param_info *pi, const double *v, const double *se,
                         const unsigned char *fixed, int C)
{
    char buf[40];
    int n = pi->colour ? C : 1;
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

int cmd_fit(int argc, char **argv)
{
    data_options dopt;
    memset(&dopt, 0, sizeof dopt);
    fit_options fopt;
    fit_options_init(&fopt);
    int nmodels = 0, status = 2;
    char *specs[MAX_MODELS] = {0};
    const char *data = NULL, *out_path = NULL;
    bf_error err;
    bf_samples *s = NULL;
    bf_fit_result results[MAX_MODELS];
    int nres = 0;

    cli_args args;
    int p = cli_parse(&cli_fit, argc, argv, &args);
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
        if (d < 0)
            goto done;
        if (d > 0)
            continue;
        if (!strcmp(a, "--output")) {
            out_path = v;
        } else { /* --model */
            int k = fit_options_split_models(v, specs, nmodels, MAX_MODELS, cmd);
            if (k < 0)
                goto done;
            nmodels = k;
        }
    }
    if (!data || nmodels == 0) {
        fprintf(stderr, "%s: %s (see brdfit fit --help)\n", cmd,
                !data ? "a data file is required" : "-m MODEL is required");
        goto done;
    }
    /* Model specs are checked before any data is read. */
    if (fit_options_check_models(&fopt, specs, nmodels, cmd) < 0)
        goto done;
    fit_options_finish(&fopt, &dopt);
    /* And the output, before the data is read and the fits run. */
    const bf_path_use in[] = {{"data file", data}, {"--scene file", dopt.scene}}, out[] = {{"-o", out_path}};
    if ((status = args_check_outputs(cmd, in, 2, out, 1)) != 0)
        goto done;

    status = 1;
    if (!(s = data_options_load(&dopt, data, NULL, cmd)))
        goto done;
    /* The summary goes to stdout unless the result does. */
    FILE *info = out_path && !strcmp(out_path, "-") ? stderr : stdout;
    int all_ok = 1;
    for (int k = 0; k < nmodels; k++) {
        cli_note(cmd, "fitting %s", specs[k]);
        int rc = bf_fit(s, specs[k], &fopt.fit, &results[nres], &err);
        if (rc != BF_OK) {
            fprintf(stderr, "%s: %s: %s\n", cmd, specs[k], err.msg);
            status = rc == BF_ERR_ARG ? 2 : 1;
            goto done;
        }
        if (!cli_quiet())
            summary(info, &results[nres]);
        all_ok &= results[nres].ok;
        nres++;
    }
    fflush(info);
    if (out_path) {
        const bf_fit_result *list[MAX_MODELS];
        for (int k = 0; k < nres; k++)
            list[k] = &results[k];
        int rc = nres == 1 ? bf_fit_write_json(&results[0], data, out_path, &err)
                           : bf_fit_write_json_list(list, nres, data, out_path, &err);
        if (rc != BF_OK) {
            fprintf(stderr, "%s: %s\n", cmd, err.msg);
            goto done;
        }
    }
    if (!all_ok)
        fprintf(stderr, "%s: %s\n", cmd, nres == 1 ? "the fit failed" : "a fit failed");
    status = all_ok ? 0 : 1;
done:
    cli_args_free(&args);
    for (int k = 0; k < nres; k++)
        bf_fit_result_free(&results[k]);
    for (int k = 0; k < nmodels; k++)
        free(specs[k]);
    bf_samples_free(s);
    return status;
}
