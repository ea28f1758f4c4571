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
 *    in: each has its slot.
 *  - Every data file is read (and checked) before any fit starts: bad data costs no fit
 *    time and leaves no output. The samples stay in memory for the whole run.
 *  - SIGINT: no new fit starts, running fits finish, the outputs are written with what
 *    finished ("interrupted": true; fits never run are "not_run") and the exit status is
 *    130. A second SIGINT ends the process at once (default action).
 *  - `all` is every registered family with its default options.
 *  - --html DIR writes a report folder (compare.h, report_html.c). DIR is checked before
 *    any fit: an existing DIR that is neither empty nor a previous report is refused
 *    (exit 1) rather than replaced. The report is written after the summary is printed.
 *  - --json and --csv are checked before any data is read (args_check_outputs): the same
 *    file as a data file, the scene or each other, under any name, is refused (exit 2);
 *    an unwritable one fails (exit 1) before any fit.
 *  - --scene FILE (a data option): every fit and every error in the ranking is over the
 *    scene's samples with their scene weights (fit.weighted_metrics), so the selection
 *    follows the directions the scene uses; the summary names the scene.
 *  - Exit: 0 all fits ok; 1 bad data, a failed fit or an unwritable output; 2 bad usage;
 *    130 interrupted. */
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "brdfit/compare.h"
#include "brdfit/fit.h"
#include "args.h"
#include "cli.h"
#include "commands.h"
#include "data_options.h"
#include "fit_options.h"
#include "rank_options.h"

static const char cmd[] = "brdfit compare";

#define MAX_MODELS 128

static const cli_option own[] = {
    {"--model", 'm', "SPECS", "models to compare (as brdfit fit; repeatable), or all: every\n"
                              "registered model with its default options", "model"},
    {"--error", 0, "rmse|rmse_log|rmse_cos|rmse_rel", "error for the Pareto fronts and the tolerance\n"
                                                       "(default rmse_log; with --rank cv the cross-validated error)",
     NULL},
    {"--tolerance", 0, "T", "relative: the simplest model with error <= best * (1 + T)\nis chosen (default 0.05)",
     NULL},
    {"--jobs", 0, "N", "fits run at once (default 1); each gets --threads / N threads", NULL},
    {"--json", 0, "FILE", "everything, machine-readable (stable keys; - for standard output)", "file"},
    {"--csv", 0, "FILE", "one row per material x model (- for standard output)", "file"},
    {"--html", 0, "DIR", "a report to read in a browser: DIR/index.html and its images\n"
                         "(an existing DIR is replaced only if it is a previous report)", "dir"},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group *const groups[] = {&own_group, &rank_options_bic, &fit_options_fitting, &fit_options_optimizer, &data_options_reading, &data_options_preprocessing};
const cli_command cli_compare = {
    "brdfit", "compare", "DATA... -m MODEL[,MODEL...]|all [options] [--json R.json] [--csv R.csv] [--html DIR]",
    "fit many models to many materials and rank them",
    "Fits every model to every data file, ranks the models per material and across materials (by an information "
    "criterion, cross-validated error or plain error), marks the Pareto fronts of error against free parameters and "
    "fitting work, and writes the tables and a report. Ctrl-C stops starting new fits and writes what finished "
    "(exit 130).",
    "file", groups, sizeof groups / sizeof groups[0],
};

static volatile sig_atomic_t interrupted;
static void on_sigint(int sig)
{
    (void)sig;
    interrupted = 1;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* The shared state of the fitting workers. */
typedef struct run {
    bf_compare *cmp;
    bf_samples **samples;
    bf_fit_result *results; /* nmaterials * nmodels; slot i * nmodels + j */
    unsigned char *have;    /* 1 where results[] holds a result to free */
    const bf_fit_options *fo;
    int folds;              /* > 0: cross-validate every fit */
    uint64_t seed;
    pthread_mutex_t lock;
    int next, total, done, running;
    int quiet, tty;
    double t0;
} run;

/* Called with the lock held. */
static void progress(run *r, int idx)
{
    if (r->quiet)
        return;
    if (r->tty) {
        char bar[31];
        int w = (int)(30.0 * r->done / r->total);
        for (int k = 0; k < 30; k++)
            bar[k] = k < w ? '#' : '.';
        bar[30] = '\0';
        double el = now() - r->t0, eta = r->done ? el / r->done * (r->total - r->done) : NAN;
        fprintf(stderr, "\r%s: [%s] %d/%d fits", cmd, bar, r->done, r->total);
        if (isfinite(eta))
            fprintf(stderr, ", ETA %.0f s   ", eta);
        if (r->done == r->total)
            fputc('\n', stderr);
    } else {
        int nm = r->cmp->nmodels;
        const bf_compare_fit *f = &r->cmp->materials[idx / nm].fits[idx % nm];
        fprintf(stderr, "%s: %d/%d %s on %s: %s", cmd, r->done, r->total, r->cmp->models[idx % nm],
                r->cmp->materials[idx / nm].data, bf_compare_state_name(f->state));
        if (f->state == BF_CMP_ERROR)
            fprintf(stderr, " (%s)", f->message);
        else
            fprintf(stderr, ", %s %.4g, %.2f s", bf_compare_metric_name(r->cmp->metric),
                    bf_compare_metric_value(&f->metrics, r->cmp->metric), f->seconds);
        if (r->folds > 0 && f->state == BF_CMP_OK)
            fprintf(stderr, ", cv %.4g", f->cv_error);
        fputc('\n', stderr);
    }
    fflush(stderr);
}

static void *worker(void *arg)
{
    run *r = arg;
    int nm = r->cmp->nmodels;
    for (;;) {
        pthread_mutex_lock(&r->lock);
        if (interrupted || r->next >= r->total) {
            pthread_mutex_unlock(&r->lock);
            return NULL;
        }
        int idx = r->next++;
        r->running++;
        pthread_mutex_unlock(&r->lock);

        bf_error err;
        bf_fit_result *res = &r->results[idx];
        const double t0 = now();
        int rc = bf_fit(r->samples[idx / nm], r->cmp->models[idx % nm], r->fo, res, &err);
        bf_cv_result cv = {.error = NAN};
        if (rc == BF_OK && r->folds > 0 && res->ok) {
            rc = bf_fit_cv(r->samples[idx / nm], r->cmp->models[idx % nm], r->fo, r->folds, r->seed, &cv, &err);
            if (rc != BF_OK)
                bf_fit_result_free(res);
        }
        const double seconds = now() - t0;

        pthread_mutex_lock(&r->lock);
        bf_compare_fit *f = &r->cmp->materials[idx / nm].fits[idx % nm];
        if (rc == BF_OK) {
            r->have[idx] = 1;
            f->state = res->ok ? BF_CMP_OK : BF_CMP_FAILED;
            f->metrics = res->metrics;
            f->seconds = seconds;
            f->work = bf_compare_work(res);
            f->cv_error = cv.error;
            f->result = res;
        } else {
            f->state = BF_CMP_ERROR;
            snprintf(f->message, sizeof f->message, "%s", err.msg);
        }
        r->running--;
        r->done++;
        progress(r, idx);
        pthread_mutex_unlock(&r->lock);
    }
}

static const char *error_name(const bf_compare *c)
{
    return c->rank_by == BF_RANK_CV ? "cv" : bf_compare_metric_name(c->metric);
}

static void print_material(FILE *out, const bf_compare *c, const bf_compare_material *m)
{
    fprintf(out, "%s  (%zu samples, %d channel%s)\n", m->data, m->samples, m->channels, m->channels == 1 ? "" : "s");
    /* work M: millions of sample evaluations; wall time only when asked, so that the
     * table, like the files, is the same from run to run. */
    fprintf(out, "  %-5s %-28s %4s %12s %13s %13s %13s %11s%s  %s\n", "rank", "model", "k", error_name(c), "AIC",
            "AICc", "BIC", "work M", c->timing ? "   time s" : "", "pareto");
    /* Ranked fits by rank (ties in model order), then the rest in model order. */
    for (int rank = 1; rank <= c->nmodels; rank++)
        for (int j = 0; j < c->nmodels; j++) {
            const bf_compare_fit *f = &m->fits[j];
            if (f->rank != rank)
                continue;
            char secs[32] = "";
            if (c->timing)
                snprintf(secs, sizeof secs, " %8.3f", f->seconds);
            fprintf(out, "  %-5d %-28s %4d %12.6g %13.6g %13.6g %13.6g %11.4g%s  %s%s%s\n", f->rank, c->models[j],
                    f->metrics.k, f->error, f->metrics.aic, f->metrics.aicc, f->metrics.bic, f->work / 1e6, secs,
                    f->pareto_k ? "k" : "-", f->pareto_work ? "w" : "-", m->simplest == j ? "  <- simplest" : "");
        }
    for (int j = 0; j < c->nmodels; j++)
        if (!m->fits[j].rank)
            fprintf(out, "  %-5s %-28s %s%s%s\n", "-", c->models[j], bf_compare_state_name(m->fits[j].state),
                    m->fits[j].state == BF_CMP_ERROR ? ": " : "", m->fits[j].state == BF_CMP_ERROR ? m->fits[j].message : "");
    if (m->simplest >= 0)
        fprintf(out, "  ranked by %s; simplest within %g%% of the best %s (%s): %s\n", bf_compare_rank_name(c->rank_by),
                100.0 * c->tolerance, error_name(c), c->models[m->best], c->models[m->simplest]);
    else
        fprintf(out, "  no model fitted\n");
    for (int j = 0; j < c->nmodels; j++) {
        const bf_fit_result *r = m->fits[j].result;
        for (int w = 0; r && (m->fits[j].state == BF_CMP_OK || m->fits[j].state == BF_CMP_FAILED) && w < r->nwarnings;
             w++)
            fprintf(out, "  warning: %s: %s\n", c->models[j], r->warnings[w]);
    }
}

static void print_summary(FILE *out, const bf_compare *c)
{
    fprintf(out, "summary over %d materials\n", c->nmaterials);
    fprintf(out, "  %-28s %9s %13s %13s %13s %14s %8s\n", "model", "materials", "mean rank", "BIC rank", "AIC rank",
            "mean error", "simplest");
    for (int j = 0; j < c->nmodels; j++) {
        const bf_compare_summary *s = &c->summary[j];
        fprintf(out, "  %-28s %9d %13.3g %13.3g %13.3g %14.6g %8d\n", c->models[j], s->ranked, s->mean_rank,
                s->mean_rank_bic, s->mean_rank_aic, s->mean_error, s->chosen);
    }
}

int cmd_compare(int argc, char **argv)
{
    data_options dopt;
    memset(&dopt, 0, sizeof dopt);
    fit_options fopt;
    fit_options_init(&fopt);
    int status = 2, nmodels = 0, ndata = 0, jobs = 1, all = 0;
    rank_options ro;
    rank_options_init(&ro, BF_RANK_BIC);
    char *specs[MAX_MODELS] = {0};
    const char **data = calloc((size_t)argc, sizeof *data);
    const char *json_path = NULL, *csv_path = NULL, *html_dir = NULL;
    bf_compare_metric metric = BF_CMP_RMSE_LOG;
    double tolerance = 0.05;
    bf_compare cmp;
    memset(&cmp, 0, sizeof cmp);
    bf_samples **samples = NULL;
    bf_fit_result *results = NULL;
    unsigned char *have = NULL;
    bf_path_use *inputs = NULL;
    bf_error err;
    if (!data) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return 1;
    }

    cli_args args;
    int p = cli_parse(&cli_compare, argc, argv, &args);
    if (p != CLI_OK) {
        free(data);
        return p == CLI_EXIT ? 0 : 2;
    }
    for (int i = 0; i < args.n; i++) {
        const char *a = args.v[i].name, *v = args.v[i].value;
        if (!a) {
            data[ndata++] = v;
            continue;
        }
        int d = data_options_parse(&dopt, a, v, cmd);
        if (d == 0)
            d = fit_options_parse(&fopt, a, v, cmd);
        if (d == 0)
            d = rank_options_parse(&ro, a, v, cmd);
        if (d < 0)
            goto done;
        if (d > 0)
            continue;
        if (!strcmp(a, "--model")) {
            if (!strcmp(v, "all")) {
                all = 1;
                continue;
            }
            int k = fit_options_split_models(v, specs, nmodels, MAX_MODELS, cmd);
            if (k < 0)
                goto done;
            nmodels = k;
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
        } else if (!strcmp(a, "--jobs")) {
            long n;
            if (!args_int(v, 1, 1024, &n)) {
                fprintf(stderr, "%s: --jobs needs an integer from 1 to 1024, got '%s'\n", cmd, v);
                goto done;
            }
            jobs = (int)n;
        } else if (!strcmp(a, "--json")) {
            json_path = v;
        } else if (!strcmp(a, "--html")) {
            html_dir = v;
        } else { /* --csv */
            csv_path = v;
        }
    }
    if (all)
        for (int f = 0; f < bf_family_count(); f++) {
            if (nmodels >= MAX_MODELS) {
                fprintf(stderr, "%s: more than %d models\n", cmd, MAX_MODELS);
                goto done;
            }
            if (!(specs[nmodels] = strdup(bf_family_get(f)->name)))
                goto done;
            nmodels++;
        }
    if (ndata == 0 || nmodels == 0) {
        fprintf(stderr, "%s: %s (see brdfit compare --help)\n", cmd,
                ndata == 0 ? "at least one data file is required" : "-m MODEL,...|all is required");
        goto done;
    }
    /* A folder the report may not replace is refused before any fit runs. */
    if (html_dir && bf_compare_html_check(html_dir, &err) != BF_OK) {
        fprintf(stderr, "%s: --html %s\n", cmd, err.msg);
        status = err.code == BF_ERR_ARG ? 2 : 1;
        goto done;
    }
    if (rank_options_check(&ro, &fopt.fit, cmd) < 0)
        goto done;
    /* Model specs are checked before any data is read. */
    if (fit_options_check_models(&fopt, specs, nmodels, cmd) < 0)
        goto done;
    fit_options_finish(&fopt, &dopt);
    /* The --threads budget is shared between the concurrent fits. */
    if (jobs > nmodels * ndata)
        jobs = nmodels * ndata;
    fopt.fit.solver.threads = fopt.fit.solver.threads / jobs > 1 ? fopt.fit.solver.threads / jobs : 1;
    /* The outputs, before any data is read: never over an input, writable. */
    if (!(inputs = calloc((size_t)ndata + 1, sizeof *inputs))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        status = 1;
        goto done;
    }
    for (int i = 0; i < ndata; i++)
        inputs[i] = (bf_path_use){"data file", data[i]};
    inputs[ndata] = (bf_path_use){"--scene file", dopt.scene};
    const bf_path_use out[] = {{"--json", json_path}, {"--csv", csv_path}};
    if ((status = args_check_outputs(cmd, inputs, ndata + 1, out, 2)) != 0)
        goto done;

    status = 1;
    if (bf_compare_init(&cmp, ndata, data, nmodels, (const char *const *)specs, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    cmp.metric = metric;
    cmp.rank_by = ro.rank_by;
    cmp.folds = ro.rank_by == BF_RANK_CV ? ro.folds : 0;
    cmp.timing = ro.timing;
    cmp.tolerance = tolerance;
    cmp.residual = bf_residual_name(fopt.fit.objective.residual);
    size_t total = (size_t)ndata * (size_t)nmodels;
    samples = calloc((size_t)ndata, sizeof *samples);
    results = calloc(total, sizeof *results);
    have = calloc(total, 1);
    if (!samples || !results || !have) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        goto done;
    }
    for (int i = 0; i < ndata; i++) {
        if (!(samples[i] = data_options_load(&dopt, data[i], NULL, cmd)))
            goto done;
        /* The geometry is computed on first use: compute it here, before threads share it. */
        if (!bf_samples_geometry(samples[i], &err)) {
            fprintf(stderr, "%s: %s: %s\n", cmd, data[i], err.msg);
            goto done;
        }
        cmp.materials[i].samples = samples[i]->n;
        cmp.materials[i].channels = samples[i]->channels;
    }

    run r = {.cmp = &cmp, .samples = samples, .results = results, .have = have, .fo = &fopt.fit,
             .folds = cmp.folds, .seed = fopt.fit.seed, .total = (int)total, .quiet = cli_quiet(),
             .tty = isatty(STDERR_FILENO), .t0 = now()};
    pthread_mutex_init(&r.lock, NULL);
    struct sigaction sa, old;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_sigint;
    sa.sa_flags = SA_RESETHAND; /* a second ^C ends the process */
    sigemptyset(&sa.sa_mask);
    interrupted = 0;
    sigaction(SIGINT, &sa, &old);
    pthread_t tid[1024];
    int started = 0;
    for (; started < jobs; started++)
        if (pthread_create(&tid[started], NULL, worker, &r) != 0)
            break;
    if (started == 0)
        worker(&r); /* no thread to be had: fit on this one */
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    sigaction(SIGINT, &old, NULL);
    pthread_mutex_destroy(&r.lock);
    cmp.interrupted = r.done < r.total;
    if (cmp.interrupted && !cli_quiet() && r.tty)
        fputc('\n', stderr);

    bf_compare_rank(&cmp);
    if (data_options_has_scene(&dopt))
        printf("scene %s: errors and criteria over the scene's directions, weighted as it weighs them\n",
               dopt.scene);
    for (int i = 0; i < ndata; i++)
        print_material(stdout, &cmp, &cmp.materials[i]);
    if (ndata > 1)
        print_summary(stdout, &cmp);
    fflush(stdout);

    /* The HTML report: the ranked table, each fit's result and the samples. */
    if (html_dir && bf_compare_write_html(&cmp, samples, html_dir, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    if (json_path && bf_compare_write_json(&cmp, json_path, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    if (csv_path && bf_compare_write_csv(&cmp, csv_path, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        goto done;
    }
    int bad = 0;
    for (int i = 0; i < ndata; i++)
        for (int j = 0; j < nmodels; j++)
            bad += cmp.materials[i].fits[j].state == BF_CMP_FAILED || cmp.materials[i].fits[j].state == BF_CMP_ERROR;
    if (cmp.interrupted) {
        fprintf(stderr, "%s: interrupted after %d of %d fits; the outputs hold the finished ones\n", cmd, r.done,
                r.total);
        status = 130;
    } else if (bad) {
        fprintf(stderr, "%s: %d of %d fits failed\n", cmd, bad, r.total);
        status = 1;
    } else {
        status = 0;
    }
done:
    cli_args_free(&args);
    if (results)
        for (size_t k = 0; k < (size_t)ndata * (size_t)nmodels; k++)
            if (have[k])
                bf_fit_result_free(&results[k]);
    if (samples)
        for (int i = 0; i < ndata; i++)
            bf_samples_free(samples[i]);
    free(samples);
    free(results);
    free(have);
    bf_compare_free(&cmp);
    for (int k = 0; k < nmodels; k++)
        free(specs[k]);
    free(data);
    free(inputs);
    return status;
}
