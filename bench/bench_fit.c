/* Fit speed on a full MERL table: walter (GGX, Smith, Schlick; one lobe, RGB) with the
 * parameters of examples/walter_rgb.json, sampled at every MERL cell centre above the
 * horizon (about 1.1 M cells x 3 channels, noiseless), then fitted from the data-driven
 * start with Ceres and the NLopt methods. First the parts: the data-driven start, one
 * fused pass of the objective (the floor under a Ceres iteration), a cost-only pass,
 * metrics and standard errors. Per method: the whole bf_fit (start, solve, metrics,
 * standard errors) and the solve alone, iterations, evaluations, time per iteration,
 * final cost and the recovered alpha's relative error. Times are the best of the
 * repeats; every repeat fits the same data from the same start.
 *
 * usage: bench_fit [--threads N] [--residual FORM] [--repeats R]
 *                  [--methods ceres,LD_LBFGS,...] [--data TABLE.binary] [--write TABLE.binary]
 * --data fits a MERL table read from a file instead of the generated one; --write saves
 * the generated table (for timing `brdfit fit` on the same data). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "brdfit/formats.h"
#include "brdfit/fit.h"
#include "brdfit/objective.h"
#include "brdfit/samples.h"
#include "synth.h"

static const double kRhoD[3] = {0.8, 0.5, 0.2}, kRhoS[3] = {0.9, 0.9, 0.9};
static const double kAlpha = 0.1, kF0 = 0.04;
#define SPEC "walter:fresnel=schlick"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* CPU seconds of every thread of the process: steadier than wall time on a shared
 * machine, and wall x threads against it shows how well the threads are used. */
static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static void die(const char *what, const bf_error *err)
{
    fprintf(stderr, "bench_fit: %s%s%s\n", what, err ? ": " : "", err ? err->msg : "");
    exit(1);
}

static void set_param(const bf_model *m, double *x, const char *name, const double *v)
{
    int i = bf_model_find_param(m, name);
    if (i < 0)
        die(name, NULL);
    int cnt = bf_model_param(m, i)->color ? bf_model_channels(m) : 1;
    for (int c = 0; c < cnt; c++)
        x[bf_model_param_offset(m, i) + c] = v[c];
}

static bf_samples *generate(bf_error *err)
{
    bf_model *m = NULL;
    if (bf_model_new(SPEC, 3, &m, err) != BF_OK)
        die("model", err);
    double x[16];
    bf_model_defaults(m, x);
    set_param(m, x, "rho_d", kRhoD);
    set_param(m, x, "rho_s", kRhoS);
    set_param(m, x, "alpha", &kAlpha);
    set_param(m, x, "f0", &kF0);
    bf_synth_options so;
    memset(&so, 0, sizeof so);
    so.pattern = BF_SYNTH_MERL;
    so.seed = 1;
    bf_samples *s = NULL;
    if (bf_synth_generate(m, x, &so, &s, err) != BF_OK)
        die("generate", err);
    bf_model_free(m);
    return s;
}

/* The parts of a fit besides the solve, at the start (best of 3): one fused pass of the
 * objective (cost, J'r and J'J: what a Ceres iteration costs) and a cost-only pass on
 * `threads` threads, then the metrics and the standard errors. */
static void time_parts(bf_samples *s, const bf_objective_options *oo, int threads, double *t_pass, double *t_cost,
                       double *t_metrics, double *t_stderr, bf_error *err)
{
    bf_model *m;
    bf_objective *obj;
    if (bf_model_new(SPEC, 3, &m, err) != BF_OK || bf_objective_new(m, s, oo, &obj, err) != BF_OK)
        die("objective", err);
    const bf_problem *p = bf_objective_problem(obj);
    double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x), z[16], jtr[16], jtj[256], ssq;
    if (bf_fit_initial_guess(m, s, x, err) != BF_OK)
        die("initial guess", err);
    bf_objective_to_internal(obj, x, z);
    *t_pass = *t_cost = 1e30;
    for (int rep = 0; rep < 3; rep++) {
        double t0 = now();
        if (bf_problem_normal(p, z, NULL, threads, &ssq, jtr, jtj) != 0)
            die("fused pass", NULL);
        double t1 = now();
        if (bf_problem_normal(p, z, NULL, threads, &ssq, NULL, NULL) != 0)
            die("cost pass", NULL);
        *t_pass = fmin(*t_pass, t1 - t0);
        *t_cost = fmin(*t_cost, now() - t1);
    }
    double se[16];
    bf_metrics met;
    *t_metrics = *t_stderr = 1e30;
    for (int rep = 0; rep < 3; rep++) {
        double t0 = now();
        if (bf_metrics_compute(m, x, s, p->npar, threads, &met, err) != BF_OK)
            die("metrics", err);
        double t1 = now();
        if (bf_objective_stderr(obj, x, se, err) != BF_OK)
            die("stderr", err);
        *t_metrics = fmin(*t_metrics, t1 - t0);
        *t_stderr = fmin(*t_stderr, now() - t1);
    }
    free(x);
    bf_objective_free(obj);
    bf_model_free(m);
}

int main(int argc, char **argv)
{
    int threads = 2, repeats = 3;
    const char *residual = "log", *methods = "ceres,LD_LBFGS,LD_SLSQP,LN_BOBYQA";
    const char *data = NULL, *write = NULL;
    for (int a = 1; a < argc; a += 2) { /* every option takes a value */
        const char *v = a + 1 < argc ? argv[a + 1] : NULL;
        if (!v)
            die("every option takes a value", NULL);
        if (!strcmp(argv[a], "--threads"))
            threads = atoi(v);
        else if (!strcmp(argv[a], "--residual"))
            residual = v;
        else if (!strcmp(argv[a], "--repeats"))
            repeats = atoi(v);
        else if (!strcmp(argv[a], "--methods"))
            methods = v;
        else if (!strcmp(argv[a], "--data"))
            data = v;
        else if (!strcmp(argv[a], "--write"))
            write = v;
        else
            die("unknown option (--threads --residual --repeats --methods --data --write)", NULL);
    }
    if (repeats < 1)
        repeats = 1;

    bf_error err;
    bf_options *fo = NULL;
    char threads_text[32];
    snprintf(threads_text, sizeof threads_text, "%d", threads);
    if (bf_options_new(BF_TASK_FIT, &fo, &err) != BF_OK || bf_options_set(fo, "starts", "1", &err) != BF_OK ||
        bf_options_set(fo, "threads", threads_text, &err) != BF_OK)
        die("options", &err);
    if (bf_options_set(fo, "residual", residual, &err) != BF_OK)
        die("--residual", &err);
    bf_objective_options oo;
    bf_objective_options_init(&oo);
    oo.use_weights = 0; /* unweighted, as the timings so far were taken */
    if (bf_residual_parse(residual, &oo.residual, &err) != BF_OK)
        die("--residual", &err);

    double t0 = now();
    bf_samples *s = NULL;
    if (data) {
        if (bf_samples_read_merl(data, 0, &s, &err) != BF_OK)
            die(data, &err);
    } else {
        s = generate(&err);
    }
    if (write && bf_samples_write_merl(s, write, &err) != BF_OK)
        die(write, &err);
    const bf_geometry *g;
    if (bf_samples_geometry(s, &g, &err) != BF_OK)
        die("geometry", &err);
    printf("walter (%s), %zu samples x %d channels (%s in %.2f s), residual %s, %d thread%s\n", SPEC, s->n, s->channels,
           data ? "read" : "generated", now() - t0, residual, threads, threads == 1 ? "" : "s");

    bf_model *m = NULL;
    bf_model_new(SPEC, 3, &m, &err);
    double x0[16];
    double ts = now();
    if (!m || bf_fit_initial_guess(m, s, x0, &err) != BF_OK)
        die("initial guess", &err);
    const int ia = bf_model_param_offset(m, bf_model_find_param(m, "alpha"));
    ts = now() - ts;
    double t_pass, t_cost, t_metrics, t_stderr;
    oo.threads = threads;
    time_parts(s, &oo, threads, &t_pass, &t_cost, &t_metrics, &t_stderr, &err);
    printf("data-driven start %.3f s (alpha %.4g); %d thread%s: fused pass (cost, J'r, J'J) %.4f s, "
           "cost alone %.4f s, metrics %.4f s, standard errors %.4f s\n",
           ts, x0[ia], threads, threads == 1 ? "" : "s", t_pass, t_cost, t_metrics, t_stderr);
    printf("%-10s %8s %8s %8s %6s %6s %10s %12s %10s\n", "method", "fit s", "fit cpu", "solve s", "iter", "evals",
           "s/iter", "final cost", "alpha err");

    char list[256];
    snprintf(list, sizeof list, "%s", methods);
    for (char *tok = strtok(list, ","); tok; tok = strtok(NULL, ",")) {
        if (bf_options_set(fo, "backend", strcmp(tok, "ceres") ? "nlopt" : "ceres", &err) != BF_OK ||
            (strcmp(tok, "ceres") ? bf_options_set(fo, "algorithm", tok, &err)
                                  : bf_options_reset(fo, "algorithm", &err)) != BF_OK)
            die(tok, &err);
        double best_fit = 1e30, best_solve = 1e30, best_cpu = 1e30;
        bf_fit_result r;
        for (int rep = 0; rep < repeats; rep++) {
            double c0 = cpu_now();
            if (bf_fit(s, SPEC, fo, &r, &err) != BF_OK)
                die(tok, &err);
            best_cpu = fmin(best_cpu, cpu_now() - c0);
            best_fit = fmin(best_fit, r.seconds);
            best_solve = fmin(best_solve, r.solution.seconds);
            if (rep + 1 < repeats)
                bf_fit_result_clear(&r);
        }
        int it = r.solution.iterations;
        printf("%-10s %8.3f %8.3f %8.3f %6d %6d %10.4f %12.6g %10.2e%s\n", tok, best_fit, best_cpu, best_solve, it,
               r.solution.evaluations, it > 0 ? best_solve / it : NAN, r.solution.final_cost,
               fabs(r.x[ia] - kAlpha) / kAlpha, r.ok ? "" : "  (not usable)");
        printf("%-10s %s\n", "", r.solution.termination);
        bf_fit_result_clear(&r);
    }
    bf_model_free(m);
    bf_samples_free(s);
    bf_options_free(fo);
    return 0;
}
