/* The comparison as an HTML report: one folder holding index.html, its images and its
 * plots, links relative, so it opens from disk without a server. This file writes the
 * page, its tables and the folder; report_pictures.c the pictures of each material.
 *
 * Decisions:
 *  - The folder is built under a registered temporary sibling (DIR.tmp.XXXXXX, removed
 *    by a fatal signal too), every file through bf_outfile (writes checked, synced),
 *    and renamed into place at the end (io/out_folder.h): a failed run leaves no report
 *    and no partial folder, and an old report stays whole until the new one replaces it.
 *  - An existing DIR is replaced only when it holds BF_REPORT_MARKER (a previous report)
 *    or is empty; anything else is refused, so a typo cannot wipe a user's folder.
 *  - Plots (error against k and against work, slices, half/difference images) are Cairo
 *    figures (plot/plot.h) with axes, ticks, legends and colour bars, embedded as PNG or
 *    SVG (bf_report_options.format); with format PDF, PNG with a PDF of each beside it
 *    (linked).
 *  - The page says how it was made: the command line, the data options, the scene and
 *    the tool's version; each model's row holds its fitted parameters and warnings. The
 *    error column is not repeated under its metric's own name.
 *  - Only ranked (successful) fits get pictures; the others are listed with their state. */
#include "brdfit/compare.h"
#include "base/sized.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/image.h"
#include "brdfit/io.h"
#include "brdfit/render.h"
#include "brdfit/version.h"
#include "io/out_folder.h"
#include "html/report.h"
#include "plot/scatter.h"

enum { PLOT_W = 520, PLOT_H = 360 };

static void num(FILE *fp, double v)
{
    if (isfinite(v))
        fprintf(fp, "<td>%.5g</td>", v);
    else
        fputs("<td>&ndash;</td>", fp);
}

/* The error the fronts and the tolerance use, by name. */
static const char *error_name(const bf_compare *c)
{
    return c->rank_by == BF_RANK_CV ? "cross-validated error" : bf_compare_metric_name(c->metric);
}

static void model_table(report_page *r, int i, const bf_compare_material *m)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    /* RMSE and log RMSE beside the error, unless the error is one of them (one number,
     * one column). */
    const int ranked_by_cv = c->rank_by == BF_RANK_CV;
    const int show_rmse = ranked_by_cv || c->metric != BF_CMP_RMSE;
    const int show_log = ranked_by_cv || c->metric != BF_CMP_RMSE_LOG;
    fprintf(fp,
            "<table>\n<tr><th>rank (%s)</th><th>model</th><th>k</th><th>%s</th>%s%s"
            "<th>AIC</th><th>AICc</th><th>BIC</th><th>CV error</th><th>work (M sample evaluations)</th>"
            "<th>Pareto k</th><th>Pareto work</th><th>simplest</th><th>parameters</th><th>warnings</th></tr>\n",
            bf_compare_rank_name(c->rank_by), error_name(c), show_rmse ? "<th>RMSE</th>" : "",
            show_log ? "<th>log RMSE</th>" : "");
    int unsure = 0;
    for (int j = 0; j < c->nmodels; j++) {
        const bf_compare_fit *f = &m->fits[j];
        fprintf(fp, "<tr%s>", m->simplest == j ? " class=\"chosen\"" : "");
        if (f->rank)
            fprintf(fp, "<td>%d</td>", f->rank);
        else
            fputs("<td>&ndash;</td>", fp);
        /* A ranked model's name links to its view in the material's viewer. */
        fputs("<td class=\"spec\">", fp);
        if (f->rank)
            fprintf(fp, "<a href=\"#m%d-view-%d\">", i + 1, j + 1);
        report_esc(fp, c->models[j]);
        fputs(f->rank ? "</a></td>" : "</td>", fp);
        if (!f->rank) {
            fprintf(fp, "<td colspan=\"%d\">%s", 12 + show_rmse + show_log, bf_compare_state_name(f->state));
            if (f->state == BF_CMP_ERROR) {
                fputs(": ", fp);
                report_esc(fp, f->message);
            }
            fputs("</td></tr>\n", fp);
            continue;
        }
        fprintf(fp, "<td>%d</td>", f->metrics.k);
        if (bf_fit_result_unsure(f->result)) {
            /* The search reached this optimum from one start only (the warning says so). */
            fprintf(fp,
                    "<td class=\"unsure\" title=\"the best optimum was reached from one start only: a better "
                    "one may have been missed\">%.5g?</td>",
                    f->error);
            unsure++;
        } else {
            num(fp, f->error);
        }
        if (show_rmse)
            num(fp, f->metrics.rmse);
        if (show_log)
            num(fp, f->metrics.rmse_log);
        num(fp, f->metrics.aic);
        num(fp, f->metrics.aicc);
        num(fp, f->metrics.bic);
        num(fp, f->cv_error);
        num(fp, f->work / 1e6);
        fprintf(fp, "<td>%s</td><td>%s</td><td>%s</td>", f->pareto_k ? "&#9679;" : "", f->pareto_work ? "&#9679;" : "",
                m->simplest == j ? "simplest" : (f->within_tolerance ? "within" : ""));
        /* Every fitted entry, and what to doubt. */
        const bf_fit_result *res = f->result;
        fputs("<td class=\"params\">", fp);
        for (int k = 0; res && k < bf_model_nvalues(res->model); k++) {
            char name[64];
            report_esc(fp, bf_model_entry_name(res->model, k, name, sizeof name));
            fprintf(fp, "&nbsp;%.6g%s", res->x[k], k + 1 < bf_model_nvalues(res->model) ? "<br>" : "");
        }
        /* What to doubt: one warning as it is; several collapsed to their count, opened on
         * a click, so the column stays as narrow as the numbers. */
        fputs("</td><td class=\"warn\">", fp);
        const int nw = res ? res->nwarnings : 0;
        if (nw > 1)
            fprintf(fp, "<details><summary>%d warnings</summary>", nw);
        for (int w = 0; w < nw; w++) {
            report_esc(fp, res->warnings[w]);
            fputs(w + 1 < nw ? "<br>" : "", fp);
        }
        fputs(nw > 1 ? "</details></td></tr>\n" : "</td></tr>\n", fp);
    }
    fputs("</table>\n", fp);
    if (m->simplest >= 0) {
        fprintf(fp, "<p>Ranked by %s. Simplest model within %g%% of the best %s (", bf_compare_rank_name(c->rank_by),
                100.0 * c->tolerance, error_name(c));
        report_esc(fp, c->models[m->best]);
        fputs("): <b>", fp);
        report_esc(fp, c->models[m->simplest]);
        fputs("</b>. &#9679; marks the Pareto fronts of k and of fitting work against that error (no other "
              "model is at least as good in both and better in one).</p>\n",
              fp);
    } else {
        fputs("<p>No model fitted.</p>\n", fp);
    }
    if (unsure)
        fputs("<p>? marks a fit whose best optimum the search reached from one start only: a better one may have "
              "been missed (<code>--accuracy best</code> searches harder).</p>\n",
              fp);
}

/* The published fits beside material i's (brdfit compare --reference): who, the
 * objective the fit minimised at their values and at brdfit's, the error metrics, and
 * what to note (outside the bounds, brdfit worse). Nothing when none matched. */
static void reference_table(report_page *r, int i)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    int n = 0;
    for (int k = 0; k < c->nreference; k++)
        n += c->reference[k].material == i;
    if (!n)
        return;
    fprintf(fp,
            "<table class=\"references\">\n<tr><th>model</th><th>published fit</th><th>objective</th>"
            "<th>brdfit's objective</th><th>%s</th><th>RMSE</th><th>log RMSE</th><th>note</th></tr>\n",
            bf_compare_metric_name(c->metric));
    for (int k = 0; k < c->nreference; k++) {
        const bf_compare_reference *q = &c->reference[k];
        const bf_reference *ref = q->reference;
        if (q->material != i)
            continue;
        fprintf(fp, "<tr%s><td class=\"spec\">", q->brdfit_worse ? " class=\"worse\"" : "");
        report_esc(fp, c->models[q->model]);
        fputs("</td><td>", fp);
        report_esc(fp, ref->source);
        if (ref->table) {
            fputs(", ", fp);
            report_esc(fp, ref->table);
        }
        fputs("</td>", fp);
        num(fp, q->cost);
        num(fp, q->brdfit_cost);
        const int ok = !q->message[0];
        num(fp, ok ? bf_compare_metric_value(&q->metrics, c->metric) : NAN);
        num(fp, ok ? q->metrics.rmse : NAN);
        num(fp, ok ? q->metrics.rmse_log : NAN);
        fputs("<td class=\"warn\">", fp);
        if (!ok)
            report_esc(fp, q->message);
        if (q->brdfit_worse)
            fputs("brdfit's objective is higher: its search missed a better optimum", fp);
        if (ref->outside[0]) {
            fputs(q->brdfit_worse ? "<br>outside brdfit's bounds: " : "outside brdfit's bounds: ", fp);
            report_esc(fp, ref->outside);
        }
        fputs("</td></tr>\n", fp);
    }
    fputs("</table>\n<p>Published fits of these models to this material, judged as brdfit judges its own: the "
          "objective its fit minimises (residual, weights and loss as fitted) and the same error metrics.</p>\n",
          fp);
}

static bf_status scatter(report_page *r, int i, const bf_compare_material *m, int by_work)
{
    const bf_compare *c = r->c;
    int n = c->nmodels;
    double *x = malloc(2 * (size_t)n * sizeof *x);
    int *on = malloc((size_t)n * sizeof *on);
    const char **labels = malloc((size_t)n * sizeof *labels);
    if (!x || !on || !labels) {
        free(x);
        free(on);
        free(labels);
        return bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    }
    double *y = x + n;
    for (int j = 0; j < n; j++) {
        const bf_compare_fit *f = &m->fits[j];
        x[j] = f->rank ? (by_work ? f->work : (double)f->metrics.k) : NAN;
        y[j] = f->rank ? f->error : NAN;
        on[j] = by_work ? f->pareto_work : f->pareto_k;
        labels[j] = c->models[j];
    }
    /* Errors span decades, so a log axis; linear when one is 0 (an exact fit). */
    int log_y = 1;
    for (int j = 0; j < n; j++)
        log_y &= !(y[j] <= 0.0);
    char title[512], ytitle[128], chosen[128], name[64];
    snprintf(title, sizeof title, "%s: error against %s", report_base_name(m->data),
             by_work ? "fitting work" : "free parameters");
    snprintf(ytitle, sizeof ytitle, "%s", error_name(c));
    snprintf(chosen, sizeof chosen, "simplest within %g%% of the best", 100.0 * c->tolerance);
    plot_scatter_spec sp = {title,
                            by_work ? "fitting work (sample evaluations)" : "free parameters k",
                            ytitle,
                            by_work,
                            log_y,
                            !by_work,
                            n,
                            x,
                            y,
                            on,
                            labels,
                            "models (labelled)",
                            "Pareto front",
                            m->simplest,
                            chosen};
    plot *p = plot_scatter(&sp);
    free(on);
    free(labels);
    bf_status rc = p ? BF_OK : bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    snprintf(name, sizeof name, "m%d-%s", i + 1, by_work ? "work" : "k");
    char alt[128];
    snprintf(alt, sizeof alt, "%s against %s", error_name(c), by_work ? "fitting work" : "free parameters");
    fputs("<figure>", r->fp);
    if (rc == BF_OK)
        rc = report_figure(r, name, p, PLOT_W, PLOT_H, alt);
    plot_free(p);
    free(x);
    if (rc != BF_OK)
        return rc;
    fprintf(r->fp,
            "<figcaption>%s (y, %s axis) against %s (x, %s axis); the Pareto front joins the models no "
            "other beats in both</figcaption></figure>\n",
            error_name(c), log_y ? "log" : "linear", by_work ? "fitting work" : "free parameters k",
            by_work ? "log" : "linear");
    return BF_OK;
}

static void summary(report_page *r)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    fprintf(fp,
            "<h2 id=\"summary\">Summary over %d materials</h2>\n<table class=\"summary\">\n<tr><th>model</th>"
            "<th>materials ranked</th><th>mean rank (%s)</th><th>mean BIC rank</th><th>mean AIC rank</th>"
            "<th>mean %s</th><th>chosen simplest</th></tr>\n",
            c->nmaterials, bf_compare_rank_name(c->rank_by), error_name(c));
    for (int j = 0; j < c->nmodels; j++) {
        const bf_compare_summary *s = &c->summary[j];
        fputs("<tr><td class=\"spec\">", fp);
        report_esc(fp, c->models[j]);
        fprintf(fp, "</td><td>%d</td>", s->ranked);
        num(fp, s->mean_rank);
        num(fp, s->mean_rank_bic);
        num(fp, s->mean_rank_aic);
        num(fp, s->mean_error);
        fprintf(fp, "<td>%d</td></tr>\n", s->chosen);
    }
    fputs("</table>\n", fp);
}

static const char css[] = "body{font-family:sans-serif;margin:1.5em;color:#222;max-width:1200px}"
                          "table{border-collapse:collapse;margin:.5em 0}"
                          "th,td{border:1px solid #bbb;padding:.2em .5em;text-align:right;font-size:90%}"
                          "th{background:#eee}td.spec{text-align:left;font-family:monospace}"
                          "td.params{text-align:left;font-family:monospace;font-size:80%;white-space:nowrap}"
                          "td.warn{text-align:left;font-size:80%;color:#a40;max-width:24em}"
                          "td.warn summary{cursor:pointer;white-space:nowrap}"
                          "tr.chosen td{background:#e6f4e6;font-weight:bold}tr.worse td{background:#fbe9e7}"
                          "td.unsure{color:#a40}"
                          ".row{display:flex;flex-wrap:wrap;gap:.8em}figure{margin:0}"
                          "figcaption{font-size:80%;max-width:520px;font-family:monospace}a.pdf{font-size:75%}"
                          "h2{border-bottom:2px solid #ccc;margin-top:1.5em}"
                          "table.made th,table.made td{text-align:left}"
                          ".brdfit-viewer canvas{border:1px solid #ccc}.brdfit-viewer canvas.sphere{cursor:crosshair}"
                          ".brdfit-viewer .nosphere{width:160px;height:160px;font-size:75%;background:#f4f4f4}"
                          "pre.readout{font-size:80%;min-width:20em;margin:0}p.hdtext{font-size:80%;max-width:560px}";

/* How the report was made, so that it can be made again. */
static void how_made(report_page *r)
{
    const bf_report_options *o = r->o;
    FILE *fp = r->fp;
    fputs("<table class=\"made\">\n<tr><th>tool</th><td>brdfit ", fp);
    report_esc(fp, bf_version());
    fputs("</td></tr>\n", fp);
    if (o->command_line) {
        fputs("<tr><th>command</th><td><code>", fp);
        report_esc(fp, o->command_line);
        fputs("</code></td></tr>\n", fp);
    }
    fputs("<tr><th>data options</th><td><code>", fp);
    report_esc(fp, o->data_options && *o->data_options ? o->data_options : "(none: every sample as read)");
    fputs("</code></td></tr>\n<tr><th>scene</th><td>", fp);
    if (o->scene) {
        fputs("<code>", fp);
        report_esc(fp, o->scene);
        fputs("</code>: errors and criteria over its directions, weighted as it weighs them", fp);
    } else
        fputs("none: errors over every sample", fp);
    fputs("</td></tr>\n</table>\n", fp);
}

static bf_status page(report_page *r)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    fprintf(fp,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
            "<title>brdfit comparison</title>\n<style>%s</style>\n<script src=\"viewer.js\"></script>\n"
            "</head>\n<body>\n"
            "<h1>brdfit comparison: %d material%s, %d model%s</h1>\n",
            css, c->nmaterials, c->nmaterials == 1 ? "" : "s", c->nmodels, c->nmodels == 1 ? "" : "s");
    fprintf(fp, "<p>Error: %s; tolerance %g%%", bf_compare_metric_name(c->metric), 100.0 * c->tolerance);
    if (c->residual)
        fprintf(fp, "; fit residual: %s", c->residual);
    fputs(c->interrupted ? ". <b>Interrupted: some fits never ran.</b></p>\n" : ".</p>\n", fp);
    how_made(r);
    if (c->nmaterials > 1)
        summary(r);
    for (int i = 0; i < c->nmaterials; i++) {
        const bf_compare_material *m = &c->materials[i];
        fprintf(fp, "<h2 id=\"m%d\">", i + 1);
        report_esc(fp, m->data);
        fprintf(fp, "</h2>\n<p>%zu samples, %d channel%s.</p>\n", m->samples, m->channels, m->channels == 1 ? "" : "s");
        model_table(r, i, m);
        reference_table(r, i);
        fputs("<div class=\"row\">\n", fp);
        bf_status rc;
        if ((rc = scatter(r, i, m, 0)) != BF_OK || (rc = scatter(r, i, m, 1)) != BF_OK)
            return rc;
        fputs("</div>\n", fp);
        const char *why;
        const bf_samples *table = report_measured_table(r, i, &why);
        if ((rc = report_viewer(r, i, m, table, why)) != BF_OK || (rc = report_pictures(r, i, m)) != BF_OK)
            return rc;
    }
    bf_status rc = report_viewer_code(r);
    if (rc != BF_OK)
        return rc;
    fputs("<footer><p>Written by brdfit ", fp);
    report_esc(fp, bf_version());
    fputs(".</p></footer>\n</body>\n</html>\n", fp);
    return BF_OK;
}

bf_status bf_compare_html_check(const char *dir, bf_error *err)
{
    return bf_out_folder_check(dir, BF_REPORT_MARKER, "report", err);
}

/* A report file (index.html) through bf_outfile: every write checked. */
static bf_status open_in(const bf_out_folder *f, bf_outfile *o, const char *name, bf_error *err)
{
    char path[4200];
    bf_status rc = bf_out_folder_path(f, name, path, sizeof path, err);
    return rc == BF_OK ? bf_outfile_open(o, path, err) : rc;
}

bf_status bf_compare_write_html(const bf_compare *c, bf_samples *const *samples, const char *dir, bf_error *err)
{
    bf_report_options o;
    bf_report_options_init(&o);
    o.samples = samples;
    return bf_compare_write_report(c, &o, dir, err);
}

BF_SIZED_INIT_ZERO(bf_report_options)

bf_status bf_compare_write_report(const bf_compare *c, const bf_report_options *o, const char *dir, bf_error *err)
{
    if (!c || !o)
        return bf_fail(err, BF_ERR_ARG, "report: no comparison");
    /* Every member of this version lies within the first version's size. */
    if (bf_sized_check(o, sizeof *o, "bf_report_options", err) != BF_OK)
        return BF_ERR_ARG;
    /* Checked, built under a registered temporary sibling holding the marker. */
    bf_out_folder f;
    bf_status rc =
        bf_out_folder_begin(&f, dir, BF_REPORT_MARKER, "report",
                            "brdfit compare report: this folder is replaced by the next report written here\n", err);
    if (rc != BF_OK)
        return rc;

    report_page r = {c, o, f.tmp, NULL, err};
    bf_outfile index;
    if ((rc = open_in(&f, &index, "index.html", err)) == BF_OK) {
        r.fp = index.fp;
        rc = page(&r);
        if (rc == BF_OK)
            rc = bf_outfile_commit(&index, err);
        else
            bf_outfile_abort(&index);
    }
    /* Into place (an old report is removed only once the new one is in), or removed. */
    return bf_out_folder_end(&f, rc, err);
}
