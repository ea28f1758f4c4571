/* The comparison as an HTML report: one folder holding index.html, its images and its
 * plots, links relative, so it opens from disk without a server. This file writes the
 * page, its tables and the folder; report_pictures.c the pictures of each material.
 *
 * Decisions:
 *  - The folder is built under a registered temporary sibling (DIR.tmp.XXXXXX, removed
 *    by a fatal signal too), every file through bf_outfile (writes checked, synced),
 *    and renamed into place at the end: a failed run leaves no report and no partial
 *    folder, and an old report stays whole until the new one replaces it.
 *  - An existing DIR is replaced only when it holds BF_REPORT_MARKER (a previous report)
 *    or is empty; anything else is refused, so a typo cannot wipe a user's folder.
 *  - Plots (error against k and against work, slices, half/difference images) are Cairo
 *    figures (plot/plot.h) with axes, ticks, legends and colour bars, embedded as PNG or
 *    SVG (bf_report_options.format), each with a PDF beside it (linked).
 *  - The page says how it was made: the command line, the data options, the scene and
 *    the tool's version; each model's row holds its fitted parameters and warnings. The
 *    error column is not repeated under its metric's own name.
 *  - Only ranked (successful) fits get pictures; the others are listed with their state. */
#define _GNU_SOURCE /* renameat2 */
#include "brdfit/compare.h"

#include <errno.h>
#include <fcntl.h>
#include <ftw.h>
#include <math.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <dirent.h>

#include "brdfit/image.h"
#include "brdfit/io.h"
#include "brdfit/render.h"
#include "brdfit/version.h"
#include "io/out_target.h"
#include "io/temp_registry.h"
#include "compare/report.h"
#include "plot/scatter.h"

enum { PLOT_W = 520, PLOT_H = 360 };

/* Text from the data and the command line as HTML: markup escaped, and control
 * characters and invalid UTF-8, which HTML cannot show, as a terminal shows them
 * (bf_printable_dup; out of memory: dropped). */
void report_esc(FILE *fp, const char *text)
{
    char *safe = bf_printable_dup(text);
    for (const char *s = safe ? safe : ""; *s; s++)
        switch (*s) {
        case '&': fputs("&amp;", fp); break;
        case '<': fputs("&lt;", fp); break;
        case '>': fputs("&gt;", fp); break;
        case '"': fputs("&quot;", fp); break;
        case '\'': fputs("&#39;", fp); break;
        default: fputc(*s, fp);
        }
    free(safe);
}

static void num(FILE *fp, double v)
{
    if (isfinite(v))
        fprintf(fp, "<td>%.5g</td>", v);
    else
        fputs("<td>&ndash;</td>", fp);
}

bf_status report_image(report *r, const char *name, int w, int h, const float *rgb, const char *alt)
{
    char path[4096];
    if (snprintf(path, sizeof path, "%s/%s", r->tmp, name) >= (int)sizeof path)
        return bf_fail(r->err, BF_ERR_ARG, "%s: path too long", r->tmp);
    if (bf_image_write_rgb(path, w, h, rgb, r->err) != BF_OK)
        return r->err->code;
    fprintf(r->fp, "<img src=\"%s\" width=\"%d\" height=\"%d\" alt=\"", name, w, h);
    report_esc(r->fp, alt);
    fputs("\">", r->fp);
    return BF_OK;
}

bf_status report_figure(report *r, const char *name, const plot *p, int w, int h, const char *alt)
{
    /* SVG stays sharp when zoomed; PNG is what any viewer shows; the PDF is for papers. */
    const char *shown = r->o->format == BF_PLOT_SVG ? "svg" : "png";
    const bf_plot_format fmt[2] = {r->o->format == BF_PLOT_SVG ? BF_PLOT_SVG : BF_PLOT_PNG, BF_PLOT_PDF};
    char path[4096];
    for (int f = 0; f < 2; f++) {
        if (snprintf(path, sizeof path, "%s/%s.%s", r->tmp, name, f ? "pdf" : shown) >= (int)sizeof path)
            return bf_fail(r->err, BF_ERR_ARG, "%s: path too long", r->tmp);
        bf_status rc = plot_write(p, path, fmt[f], w, h, r->err);
        if (rc != BF_OK)
            return rc;
    }
    fprintf(r->fp, "<img src=\"%s.%s\" width=\"%d\" height=\"%d\" alt=\"", name, shown, w, h);
    report_esc(r->fp, alt);
    fprintf(r->fp, "\"><br><a class=\"pdf\" href=\"%s.pdf\">PDF</a>", name);
    return BF_OK;
}

/* The data file's name without its folders, for plot titles. */
const char *report_base_name(const char *path)
{
    const char *b = strrchr(path, '/');
    return b && b[1] ? b + 1 : path;
}

const bf_fit_result *report_fitted(const bf_compare_fit *f)
{
    return f->state == BF_CMP_OK && f->result && f->result->model ? f->result : NULL;
}

/* The error the fronts and the tolerance use, by name. */
static const char *error_name(const bf_compare *c)
{
    return c->rank_by == BF_RANK_CV ? "cross-validated error" : bf_compare_metric_name(c->metric);
}

static void model_table(report *r, const bf_compare_material *m)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    /* RMSE and log RMSE beside the error, unless the error is one of them (one number,
     * one column). */
    const int ranked_by_cv = c->rank_by == BF_RANK_CV;
    const int show_rmse = ranked_by_cv || c->metric != BF_CMP_RMSE;
    const int show_log = ranked_by_cv || c->metric != BF_CMP_RMSE_LOG;
    fprintf(fp, "<table>\n<tr><th>rank (%s)</th><th>model</th><th>k</th><th>%s</th>%s%s"
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
        fputs("<td class=\"spec\">", fp);
        report_esc(fp, c->models[j]);
        fputs("</td>", fp);
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
            fprintf(fp, "<td class=\"unsure\" title=\"the best optimum was reached from one start only: a better "
                        "one may have been missed\">%.5g?</td>", f->error);
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
        fputs("</td><td class=\"warn\">", fp);
        for (int w = 0; res && w < res->nwarnings; w++) {
            report_esc(fp, res->warnings[w]);
            fputs(w + 1 < res->nwarnings ? "<br>" : "", fp);
        }
        fputs("</td></tr>\n", fp);
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
              "been missed (<code>--accuracy best</code> searches harder).</p>\n", fp);
}

static bf_status scatter(report *r, int i, const bf_compare_material *m, int by_work)
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
    fprintf(r->fp, "<figcaption>%s (y, %s axis) against %s (x, %s axis); the Pareto front joins the models no "
                   "other beats in both</figcaption></figure>\n",
            error_name(c), log_y ? "log" : "linear", by_work ? "fitting work" : "free parameters k",
            by_work ? "log" : "linear");
    return BF_OK;
}

static void summary(report *r)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    fprintf(fp, "<h2 id=\"summary\">Summary over %d materials</h2>\n<table class=\"summary\">\n<tr><th>model</th>"
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

static const char css[] =
    "body{font-family:sans-serif;margin:1.5em;color:#222;max-width:1200px}"
    "table{border-collapse:collapse;margin:.5em 0}"
    "th,td{border:1px solid #bbb;padding:.2em .5em;text-align:right;font-size:90%}"
    "th{background:#eee}td.spec{text-align:left;font-family:monospace}"
    "td.params{text-align:left;font-family:monospace;font-size:80%;white-space:nowrap}"
    "td.warn{text-align:left;font-size:80%;color:#a40;max-width:24em}"
    "tr.chosen td{background:#e6f4e6;font-weight:bold}"
    "td.unsure{color:#a40}"
    ".row{display:flex;flex-wrap:wrap;gap:.8em}figure{margin:0}"
    "figcaption{font-size:80%;max-width:520px;font-family:monospace}a.pdf{font-size:75%}"
    "h2{border-bottom:2px solid #ccc;margin-top:1.5em}"
    "table.made th,table.made td{text-align:left}";

/* How the report was made, so that it can be made again. */
static void how_made(report *r)
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

static bf_status page(report *r)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    fprintf(fp, "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                "<title>brdfit comparison</title>\n<style>%s</style>\n</head>\n<body>\n"
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
        model_table(r, m);
        fputs("<div class=\"row\">\n", fp);
        bf_status rc;
        if ((rc = scatter(r, i, m, 0)) != BF_OK || (rc = scatter(r, i, m, 1)) != BF_OK)
            return rc;
        fputs("</div>\n", fp);
        if ((rc = report_pictures(r, i, m)) != BF_OK)
            return rc;
    }
    fputs("<footer><p>Written by brdfit ", fp);
    report_esc(fp, bf_version());
    fputs(".</p></footer>\n</body>\n</html>\n", fp);
    return BF_OK;
}

static int remove_entry(const char *path, const struct stat *st, int flag, struct FTW *f)
{
    (void)st;
    (void)flag;
    (void)f;
    return remove(path);
}

static void remove_tree(const char *path)
{
    nftw(path, remove_entry, 16, FTW_DEPTH | FTW_PHYS);
}

/* 1: DIR may be replaced (a previous report, or empty); 0: it may not; -1: not there. */
static int replaceable(const char *dir)
{
    struct stat st;
    if (lstat(dir, &st) != 0)
        return errno == ENOENT ? -1 : 0;
    if (!S_ISDIR(st.st_mode))
        return 0;
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, BF_REPORT_MARKER);
    if (access(path, F_OK) == 0)
        return 1;
    DIR *d = opendir(dir);
    if (!d)
        return 0;
    struct dirent *e;
    int empty = 1;
    while (empty && (e = readdir(d)))
        empty = !strcmp(e->d_name, ".") || !strcmp(e->d_name, "..");
    closedir(d);
    return empty;
}

bf_status bf_compare_html_check(const char *dir, bf_error *err)
{
    if (!dir || !*dir)
        return bf_fail(err, BF_ERR_ARG, "report folder: empty name");
    if (replaceable(dir) == 0)
        return bf_fail(err, BF_ERR_IO, "%s: exists and is not a brdfit report (no %s): not replacing it", dir,
                       BF_REPORT_MARKER);
    /* The report is built beside DIR and renamed there: the parent must take it. */
    size_t len = strlen(dir);
    while (len > 1 && dir[len - 1] == '/')
        len--;
    char *target = strndup(dir, len), *parent = target ? out_dirname(target) : NULL;
    bf_status rc = BF_OK;
    if (!parent)
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
    else if (access(parent, W_OK | X_OK) != 0)
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot write in the folder %s: %s", dir, parent, strerror(errno));
    free(target);
    free(parent);
    return rc;
}

/* A report file (the marker, index.html) through bf_outfile: every write checked. */
static bf_status open_in(report *r, bf_outfile *o, const char *name)
{
    char path[4200];
    if (snprintf(path, sizeof path, "%s/%s", r->tmp, name) >= (int)sizeof path)
        return bf_fail(r->err, BF_ERR_ARG, "%s: path too long", r->tmp);
    return bf_outfile_open(o, path, r->err);
}

/* Puts the finished folder tmp at target. An old report there is exchanged with it in
 * one step where the file system can (RENAME_EXCHANGE: the old one is then at tmp, still
 * registered, and removed by the caller); otherwise it is moved aside to a registered
 * temporary and the new one renamed in, with fatal signals held off between the two
 * renames so that target is never left missing. *aside: where the old report went. */
static bf_status swap_in(const char *tmp, const char *target, int had, char **aside, int *aside_handle, bf_error *err)
{
    *aside = NULL;
    if (had != 1)
        return rename(tmp, target) == 0
                   ? BF_OK
                   : bf_fail(err, BF_ERR_IO, "%s: cannot rename the report into place: %s", target, strerror(errno));
    if (renameat2(AT_FDCWD, tmp, AT_FDCWD, target, RENAME_EXCHANGE) == 0)
        return BF_OK;
    if (bf_temp_create(target, 1, 0700, aside, aside_handle) < 0)
        return bf_fail(err, BF_ERR_IO, "%s: cannot move the previous report aside: %s", target, strerror(errno));
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &old);
    bf_status rc = BF_OK;
    if (rename(target, *aside) != 0)
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot move the previous report aside: %s", target, strerror(errno));
    else if (rename(tmp, target) != 0) {
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot rename the report into place: %s", target, strerror(errno));
        if (rename(*aside, target) != 0) {
            /* The old report stays at *aside; the message above stands. */
        }
    }
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc != BF_OK) {
        rmdir(*aside);
        bf_temp_forget(*aside_handle);
        free(*aside);
        *aside = NULL;
    }
    return rc;
}

/* A message about a file in the folder being built names it as the report will have it:
 * "DIR/index.html", not "DIR.tmp.XXXXXX/index.html". */
static void name_target(bf_error *err, const char *tmp, const char *target)
{
    char *at = err ? strstr(err->msg, tmp) : NULL;
    if (!at)
        return;
    char rest[sizeof err->msg];
    snprintf(rest, sizeof rest, "%s", at + strlen(tmp));
    snprintf(at, sizeof err->msg - (size_t)(at - err->msg), "%s%s", target, rest);
}

bf_status bf_compare_write_html(const bf_compare *c, bf_samples *const *samples, const char *dir, bf_error *err)
{
    bf_report_options o = {.samples = samples};
    return bf_compare_write_report(c, &o, dir, err);
}

bf_status bf_compare_write_report(const bf_compare *c, const bf_report_options *o, const char *dir, bf_error *err)
{
    if (!c || !o)
        return bf_fail(err, BF_ERR_ARG, "report: no comparison");
    bf_status rc = bf_compare_html_check(dir, err);
    if (rc != BF_OK)
        return rc;
    char target[4000];
    size_t len = strlen(dir);
    while (len > 1 && dir[len - 1] == '/')
        len--;
    if (len >= sizeof target)
        return bf_fail(err, BF_ERR_ARG, "%s: path too long", dir);
    memcpy(target, dir, len);
    target[len] = '\0';
    /* Registered, so a fatal signal removes it with whatever it holds. */
    char *tmp = NULL;
    int handle = -1;
    if (bf_temp_create(target, 1, 0777, &tmp, &handle) < 0)
        return bf_fail(err, BF_ERR_IO, "%s: cannot create the report folder: %s", target, strerror(errno));

    report r = {c, o, tmp, NULL, err};
    bf_outfile mk, index;
    if (rc == BF_OK && (rc = open_in(&r, &mk, BF_REPORT_MARKER)) == BF_OK) {
        fputs("brdfit compare report: this folder is replaced by the next report written here\n", mk.fp);
        rc = bf_outfile_commit(&mk, err);
    }
    if (rc == BF_OK && (rc = open_in(&r, &index, "index.html")) == BF_OK) {
        r.fp = index.fp;
        rc = page(&r);
        if (rc == BF_OK)
            rc = bf_outfile_commit(&index, err);
        else
            bf_outfile_abort(&index);
    }

    /* Into place; an old report is removed only once the new one is in. */
    int had = rc == BF_OK ? replaceable(target) : -1;
    if (rc == BF_OK && had == 0)
        rc = bf_fail(err, BF_ERR_IO, "%s: appeared while the report was written and is not a brdfit report", target);
    char *aside = NULL;
    int aside_handle = -1;
    if (rc == BF_OK && (rc = swap_in(tmp, target, had, &aside, &aside_handle, err)) == BF_OK)
        out_sync_folder(target);
    if (rc != BF_OK || had == 1)
        remove_tree(tmp); /* the failed report, or the old one exchanged out */
    if (rc != BF_OK)
        name_target(err, tmp, target);
    bf_temp_forget(handle);
    free(tmp);
    if (aside) {
        remove_tree(aside);
        bf_temp_forget(aside_handle);
        free(aside);
    }
    return rc;
}
