/* The ranking tables of brdfit compare and brdfit report (compare_print.h). Wall times
 * appear only with --timing, so that the tables, like the files, are the same from run
 * to run. */
#include "compare_print.h"

#include "brdfit/render.h"

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
    int unsure = 0;
    for (int rank = 1; rank <= c->nmodels; rank++)
        for (int j = 0; j < c->nmodels; j++) {
            const bf_compare_fit *f = &m->fits[j];
            if (f->rank != rank)
                continue;
            char secs[32] = "", error[40];
            if (c->timing)
                snprintf(secs, sizeof secs, " %8.3f", f->seconds);
            /* '?': the search reached this optimum from one start only (footnote). */
            snprintf(error, sizeof error, "%.6g%s", f->error, bf_fit_result_unsure(f->result) ? "?" : "");
            unsure += bf_fit_result_unsure(f->result);
            fprintf(out, "  %-5d %-28s %4d %12s %13.6g %13.6g %13.6g %11.4g%s  %s%s%s\n", f->rank, c->models[j],
                    f->metrics.k, error, f->metrics.aic, f->metrics.aicc, f->metrics.bic, f->work / 1e6, secs,
                    f->pareto_k ? "k" : "-", f->pareto_work ? "w" : "-", m->simplest == j ? "  <- simplest" : "");
        }
    for (int j = 0; j < c->nmodels; j++)
        if (!m->fits[j].rank)
            fprintf(out, "  %-5s %-28s %s%s%s\n", "-", c->models[j], bf_compare_state_name(m->fits[j].state),
                    m->fits[j].state == BF_CMP_ERROR ? ": " : "",
                    m->fits[j].state == BF_CMP_ERROR ? m->fits[j].message : "");
    if (m->simplest >= 0)
        fprintf(out, "  ranked by %s; simplest within %g%% of the best %s (%s): %s\n", bf_compare_rank_name(c->rank_by),
                100.0 * c->tolerance, error_name(c), c->models[m->best], c->models[m->simplest]);
    else
        fprintf(out, "  no model fitted\n");
    if (unsure)
        fprintf(out, "  ?: the best optimum was reached from one start only: a better one may have been missed\n");
    for (int j = 0; j < c->nmodels; j++) {
        const bf_fit_result *r = m->fits[j].result;
        for (int w = 0; r && (m->fits[j].state == BF_CMP_OK || m->fits[j].state == BF_CMP_FAILED) && w < r->nwarnings;
             w++)
            fprintf(out, "  warning: %s: %s\n", c->models[j], r->warnings[w]);
    }
}

/* The published fits beside material i's (compare.h, bf_compare_reference). */
static void print_references(FILE *out, const bf_compare *c, int i)
{
    for (int k = 0; k < c->nreference; k++) {
        const bf_compare_reference *q = &c->reference[k];
        const bf_reference *r = q->reference;
        if (q->material != i)
            continue;
        fprintf(out, "  reference %s: %s%s%s: ", c->models[q->model], r->source, r->table ? ", " : "",
                r->table ? r->table : "");
        if (q->message[0]) {
            fprintf(out, "not evaluated (%s)\n", q->message);
            continue;
        }
        fprintf(out, "objective %.6g (brdfit %.6g%s), %s %.6g", q->cost, q->brdfit_cost,
                q->brdfit_worse ? ", worse" : "", bf_compare_metric_name(c->metric),
                bf_compare_metric_value(&q->metrics, c->metric));
        if (r->outside[0])
            fprintf(out, "; outside the bounds: %s", r->outside);
        fputc('\n', out);
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

void compare_print_tables(FILE *out, const bf_compare *c)
{
    for (int i = 0; i < c->nmaterials; i++) {
        print_material(out, c, &c->materials[i]);
        print_references(out, c, i);
    }
    if (c->nmaterials > 1)
        print_summary(out, c);
    fflush(out);
}

void compare_counts(const bf_compare *c, int *total, int *not_run, int *bad)
{
    *total = c->nmaterials * c->nmodels;
    *not_run = bf_compare_count(c, BF_CMP_NOT_RUN);
    *bad = bf_compare_count(c, BF_CMP_FAILED) + bf_compare_count(c, BF_CMP_ERROR);
}

int compare_write_tables(const char *cmd, const bf_compare *c, const char *json_path, const char *csv_path)
{
    bf_error err;
    if ((json_path && bf_compare_write_json(c, json_path, &err) != BF_OK) ||
        (csv_path && bf_compare_write_csv(c, csv_path, &err) != BF_OK)) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return 1;
    }
    return 0;
}

int compare_plot_format(const char *cmd, const char *v, int *format)
{
    bf_plot_format f;
    if (bf_plot_format_parse(v, &f, NULL) != BF_OK) {
        fprintf(stderr, "%s: --plot-format needs png, svg or pdf, got '%s'\n", cmd, v);
        return -1;
    }
    *format = (int)f;
    return 0;
}
