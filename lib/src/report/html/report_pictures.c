/* The report's pictures of one material: slices, spheres and half/difference images.
 *
 * Decisions:
 *  - Every panel of one kind shares its scale across the models of a material (and the
 *    measurement), so that they compare: slices one y range; spheres one exposure, the
 *    99th percentile of the lit pixels of the measured sphere (of the best model's when
 *    the measurement cannot be drawn), stated in the caption; half/difference images one
 *    log colour scale, 4 decades down from the measurement's 99th percentile, with a
 *    colour bar.
 *  - Slices are cut at the incidence angles the data has nearest 0, 30 and 60 degrees.
 *  - Differences are signed, log2(model / measured), on a diverging scale whose white
 *    centre is 0: blue where the model is too dark, red where it is too bright.
 *  - The measurement is drawn as images only from a whole MERL table (the table as read
 *    when the fits used a subsample of it). Scattered samples (Cornell, ALTA, CSV, a
 *    MERL subsample) have no sphere, and the report says why; their half/difference
 *    figures show each sample as a point (every phi_d together), and each model's log2
 *    ratio at those samples, at most HD_POINTS of them (every k-th).
 *  - Sizes are small (spheres 160x160, slices 440x330, half/difference 340x280) so a
 *    report over many fits stays quick. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/render.h"
#include "html/report.h"
#include "render/halfdiff_figure.h"
#include "render/slices.h"

enum { SPHERE = 160, SLICE_W = 440, SLICE_H = 330, HD_W = 340, HD_H = 280, HD_PX = 180 };
/* Scattered samples drawn as points at most: more only overplot at this size (and make
 * the SVG and PDF heavy), so every k-th is drawn. */
enum { HD_POINTS = 4000 };

#define SPHERE_PERCENTILE 99.0
#define HD_DECADES 4.0
#define HD_PERCENTILE 99.0
#define HD_SPAN 2.0 /* log2 ratios saturate at a factor of 4 */

/* A MERL table holds this many cells with a valid value at least when whole enough to
 * draw (a quarter: the valid part of a full table is most of it). */
static int dense(const bf_samples *t)
{
    return t && t->merl && t->n >= (size_t)BF_MERL_CELLS / 4;
}

/* report.h */
const bf_samples *report_measured_table(const report_page *r, int i, const char **why)
{
    const bf_samples *s = r->o->samples ? r->o->samples[i] : NULL;
    const bf_samples *t = r->o->tables && r->o->tables[i] ? r->o->tables[i] : s;
    *why = NULL;
    if (dense(t))
        return t;
    if (!s)
        *why = "no measured data was given to the report";
    else if (!s->merl)
        *why = "the data is not a MERL table, so its samples do not cover every pair of directions a picture needs";
    else
        *why = "only a subsample of the MERL table is at hand (too few of its cells to draw)";
    return NULL;
}

/* Every model's slices alike: the panel's size, within 2 degrees of the plane (as the
 * page says). */
static void slice_options(bf_slice_options *so, const double *inc, int ninc, bf_samples *s)
{
    bf_slice_options_init(so);
    so->width = SLICE_W;
    so->height = SLICE_H;
    so->incidence = inc;
    so->nincidence = ninc;
    so->samples = s;
    so->plane_tol = 2.0;
}

static bf_status slices(report_page *r, int i, const bf_compare_material *m)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    bf_samples *s = r->o->samples ? r->o->samples[i] : NULL;
    static const double want[3] = {0.0, 30.0, 60.0};
    double inc[BF_SLICE_MAX_INCIDENCE];
    int ninc = bf_slice_incidences(s, want, 3, inc);
    if (!ninc) {
        memcpy(inc, want, sizeof want);
        ninc = 3;
    }
    bf_status rc;
    /* One y range for every model's slices (and the samples): they compare. */
    double lo = INFINITY, hi = -INFINITY;
    for (int j = 0; j < c->nmodels; j++) {
        const bf_fit_result *res = report_fitted(&m->fits[j]);
        double a, b;
        if (!res)
            continue;
        bf_slice_options so;
        slice_options(&so, inc, ninc, s);
        if ((rc = bf_slice_extent(res->model, res->x, &so, &a, &b, r->err)) != BF_OK)
            return rc;
        lo = fmin(lo, a);
        hi = fmax(hi, b);
    }
    if (lo <= hi) {
        double a, b;
        lo = fmax(lo, hi - 8.0);
        plot_pad(pow(10.0, lo), pow(10.0, hi), 1, 1, &a, &b);
        lo = log10(a);
        hi = log10(b);
    }
    fprintf(fp,
            "<h3>Slices</h3>\n<p>BRDF f (log axis, the same range for every model: 10<sup>%.2f</sup> to "
            "10<sup>%.2f</sup> sr<sup>&minus;1</sup>) against the viewing angle in the plane of incidence "
            "(&minus;90&deg; to 90&deg;, mirror side right, dotted: the mirror direction) at incidence ",
            lo, hi);
    for (int k = 0; k < ninc; k++)
        fprintf(fp, "%s%g&deg;", k ? (k + 1 < ninc ? ", " : " and ") : "", inc[k]);
    fprintf(fp, " (colours; %s); markers: measured samples within 2&deg; of the plane.</p>\n<div class=\"row\">\n",
            s && s->n ? "the measured incidences nearest 0&deg;, 30&deg; and 60&deg;" : "no data");
    for (int j = 0; j < c->nmodels; j++) {
        const bf_fit_result *res = report_fitted(&m->fits[j]);
        if (!res)
            continue;
        char title[512], name[64];
        snprintf(title, sizeof title, "%s: %s", report_base_name(m->data), c->models[j]);
        bf_slice_options so;
        slice_options(&so, inc, ninc, s);
        so.title = title;
        so.log10_lo = lo;
        so.log10_hi = hi;
        bf_slice_range sr;
        bf_slice_range_init(&sr);
        plot *p;
        if ((rc = slice_plot_build(res->model, res->x, &so, &p, &sr, r->err)) != BF_OK)
            return rc;
        snprintf(name, sizeof name, "m%d-slice-%d", i + 1, j + 1);
        fputs("<figure>", fp);
        rc = report_figure(r, name, p, SLICE_W, SLICE_H, c->models[j]);
        plot_free(p);
        if (rc != BF_OK)
            return rc;
        fputs("<figcaption>", fp);
        report_esc(fp, c->models[j]);
        if (sr.shown < sr.overlaid)
            fprintf(fp, "<br>%zu of %zu in-plane samples shown (one per degree)</figcaption></figure>\n", sr.shown,
                    sr.overlaid);
        else
            fprintf(fp, "<br>%zu in-plane samples shown</figcaption></figure>\n", sr.overlaid);
    }
    fputs("</div>\n", fp);
    return BF_OK;
}

static bf_status spheres(report_page *r, int i, const bf_compare_material *m, const bf_samples *table, const char *why)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    const size_t npx = (size_t)SPHERE * SPHERE;
    float *buf = malloc(3 * npx * sizeof *buf);
    if (!buf)
        return bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    bf_dir light = {45.0, 0.0}; /* as the page says, viewed from above */
    bf_sphere_options sp;
    bf_sphere_options_init(&sp);
    sp.resolution = SPHERE;
    sp.lights = &light;
    sp.nlights = 1;
    /* The exposure, from the measurement, else from the best model (the nearest to it). */
    bf_status rc = BF_OK, first = m->best >= 0 && report_fitted(&m->fits[m->best]) ? m->best : -1;
    for (int j = 0; j < c->nmodels && first < 0; j++)
        if (report_fitted(&m->fits[j]))
            first = j;
    if (table)
        rc = bf_render_sphere_merl(table, &sp, buf, r->err);
    else if (first >= 0)
        rc = bf_render_sphere(m->fits[first].result->model, m->fits[first].result->x, &sp, buf, r->err);
    double exposure = rc == BF_OK ? bf_exposure_percentile(buf, npx, SPHERE_PERCENTILE) : 1.0;
    if (rc == BF_OK && isnan(exposure))
        rc = bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    fputs("<h3>Spheres</h3>\n<p>Light from 45&deg;, viewed from above. ", fp);
    if (rc == BF_OK) {
        fprintf(fp, "One exposure for all, &times;%.4g: the %g<sup>th</sup> percentile of the lit pixels of the ",
                exposure, SPHERE_PERCENTILE);
        if (table)
            fputs("measured sphere is white.", fp);
        else {
            report_esc(fp, first >= 0 ? c->models[first] : "");
            fputs(" sphere is white.", fp);
        }
        if (table)
            fputs(" The first is the measured table itself (each pixel the cell MERL's lookup picks).", fp);
        else {
            fputs(" The measurement is not drawn: ", fp);
            report_esc(fp, why);
            fputs(".", fp);
        }
        fputs("</p>\n<div class=\"row\">\n", fp);
    }
    char name[64];
    for (int j = -1; j < c->nmodels && rc == BF_OK; j++) {
        const bf_fit_result *res = j < 0 ? NULL : report_fitted(&m->fits[j]);
        if (j < 0 ? !table : !res)
            continue;
        rc = j < 0 ? bf_render_sphere_merl(table, &sp, buf, r->err)
                   : bf_render_sphere(res->model, res->x, &sp, buf, r->err);
        if (rc != BF_OK)
            break;
        bf_tonemap(buf, 3 * npx, BF_TONEMAP_CLAMP, exposure, 0.0);
        if (j < 0)
            snprintf(name, sizeof name, "m%d-sphere-measured.png", i + 1);
        else
            snprintf(name, sizeof name, "m%d-sphere-%d.png", i + 1, j + 1);
        fputs("<figure>", fp);
        if ((rc = report_image(r, name, SPHERE, SPHERE, buf, j < 0 ? "measured" : c->models[j])) != BF_OK)
            break;
        fputs("<figcaption>", fp);
        report_esc(fp, j < 0 ? "measured" : c->models[j]);
        fputs("</figcaption></figure>\n", fp);
    }
    if (rc == BF_OK)
        fputs("</div>\n", fp);
    free(buf);
    return rc;
}

/* A half/difference figure written and embedded with its caption (text), and more
 * (HTML, or NULL) on a line under it. */
static bf_status hd_figure(report_page *r, plot *p, const char *name, const char *alt, const char *caption,
                           const char *more)
{
    if (!p)
        return bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    fputs("<figure>", r->fp);
    bf_status rc = report_figure(r, name, p, HD_W, HD_H, alt);
    plot_free(p);
    if (rc == BF_OK) {
        fputs("<figcaption>", r->fp);
        report_esc(r->fp, caption);
        if (more)
            fprintf(r->fp, "<br>%s", more);
        fputs("</figcaption></figure>\n", r->fp);
    }
    return rc;
}

/* The suffix of an ordinal number: 1st, 2nd, 3rd, 4th, 11th, 22nd. */
static const char *ordinal(size_t k)
{
    if (k % 100 / 10 == 1)
        return "th";
    return k % 10 == 1 ? "st" : k % 10 == 2 ? "nd" : k % 10 == 3 ? "rd" : "th";
}

/* The mean of sample p's channels; 0 (no value) below the horizon. */
static double sample_mean(const bf_samples *s, const bf_geometry *g, size_t p)
{
    if (!bf_geometry_valid_at(g, p))
        return 0.0;
    double sum = 0.0;
    for (int ch = 0; ch < s->channels; ch++)
        sum += s->value[p * (size_t)s->channels + (size_t)ch];
    return sum / s->channels;
}

/* No whole table, but samples: each a point at its (theta_h, theta_d), every phi_d
 * together, the measurement on the table figures' log scale (from the samples' values),
 * then each ranked model's log2 ratio at the same samples. Every k-th sample only when
 * there are more than HD_POINTS (deterministic, and quick however many there are). */
static bf_status halfdiff_points(report_page *r, int i, const bf_compare_material *m, bf_samples *s, const char *why)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    const bf_geometry *g = NULL;
    bf_status rc = bf_samples_geometry(s, &g, r->err);
    if (rc != BF_OK)
        return rc;
    const size_t n = s->n, k = (n + HD_POINTS - 1) / HD_POINTS, cnt = (n + k - 1) / k;
    double *all = malloc(n * sizeof *all), *buf = malloc(5 * cnt * sizeof *buf);
    if (!all || !buf) {
        free(all);
        free(buf);
        return bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    }
    double *th = buf, *td = buf + cnt, *meas = buf + 2 * cnt, *model = buf + 3 * cnt, *ratio = buf + 4 * cnt;
    for (size_t p = 0; p < n; p++)
        all[p] = sample_mean(s, g, p);
    /* The scale from every sample, drawn or not: thinning does not move it. */
    double lo, hi;
    if (halfdiff_log_range(all, n, HD_PERCENTILE, HD_DECADES, &lo, &hi) < 0) {
        free(all);
        free(buf);
        fputs("<p>Not drawn: no measured sample above the horizon has a value above 0 (", fp);
        report_esc(fp, why);
        fputs(").</p>\n", fp);
        return BF_OK;
    }
    size_t drawn = 0;
    for (size_t q = 0; q < cnt; q++) {
        double dir[4];
        bf_samples_direction(s, q * k, dir);
        halfdiff_angles(dir, &th[q], &td[q]);
        meas[q] = all[q * k];
        drawn += meas[q] > 0.0 && isfinite(th[q]);
    }
    free(all);
    fputs("<p>The measurement is not drawn as an image: ", fp);
    report_esc(fp, why);
    fprintf(fp,
            ". Its samples are drawn as points instead, each at its &theta;<sub>h</sub> (x, on the square-root "
            "scale MERL tables use) and &theta;<sub>d</sub> (y), every &phi;<sub>d</sub> together (samples at "
            "different &phi;<sub>d</sub> may fall on one place; grey: no sample there); the mean of the channels "
            "on a log colour scale, 10<sup>%.2f</sup> to 10<sup>%.2f</sup> sr<sup>&minus;1</sup> (%g decades down "
            "from the samples' %g<sup>th</sup> percentile; brighter samples show as the top colour), darkest "
            "drawn first. Differences: log<sub>2</sub>(model / measured) at each sample, white where equal, red "
            "where the model is brighter, blue where darker, saturating at a factor of %g, the largest drawn "
            "last. ",
            lo, hi, HD_DECADES, HD_PERCENTILE, pow(2.0, HD_SPAN));
    if (k > 1)
        fprintf(fp, "Every %zu<sup>%s</sup> sample is drawn: %zu of %zu.</p>\n", k, ordinal(k), drawn, n);
    else if (drawn < n)
        fprintf(fp, "%zu of %zu samples drawn (the others have no value above 0 or lie below the horizon).</p>\n",
                drawn, n);
    else
        fprintf(fp, "All %zu samples drawn.</p>\n", n);
    char name[64], title[512], caption[600], more[256];
    fputs("<div class=\"row\">\n", fp);
    snprintf(name, sizeof name, "m%d-hd-measured", i + 1);
    snprintf(title, sizeof title, "%s: measured samples", report_base_name(m->data));
    if (k > 1)
        snprintf(more, sizeof more,
                 "%zu samples as points (every %zu<sup>%s</sup> of %zu), every &phi;<sub>d</sub> together", drawn, k,
                 ordinal(k), n);
    else
        snprintf(more, sizeof more, "%zu samples as points, every &phi;<sub>d</sub> together", drawn);
    rc = hd_figure(r, halfdiff_value_points(cnt, th, td, meas, title, lo, hi), name, "measured samples", "measured",
                   more);
    for (int j = 0; j < c->nmodels && rc == BF_OK; j++) {
        const bf_fit_result *res = report_fitted(&m->fits[j]);
        if (!res)
            continue;
        /* The model at the drawn samples only, the mean of its channels (the data's, as
         * fitted). */
        const int C = bf_model_channels(res->model);
        double *val = malloc((size_t)C * sizeof *val);
        if (!val) {
            rc = bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
            break;
        }
        for (size_t q = 0; q < cnt; q++) {
            bf_model_eval_range(res->model, res->x, g, q * k, q * k + 1, val, NULL);
            double sum = 0.0;
            for (int ch = 0; ch < C; ch++)
                sum += val[ch];
            model[q] = sum / C;
        }
        free(val);
        halfdiff_log2_ratio(model, meas, cnt, ratio);
        snprintf(name, sizeof name, "m%d-hd-diff-%d", i + 1, j + 1);
        snprintf(title, sizeof title, "%s vs measured", c->models[j]);
        snprintf(caption, sizeof caption, "log2(%s / measured)", c->models[j]);
        rc = hd_figure(r, halfdiff_ratio_points(cnt, th, td, ratio, title, HD_SPAN), name, caption, caption,
                       "at the same samples");
    }
    fputs("</div>\n", fp);
    free(buf);
    return rc;
}

static bf_status halfdiff(report_page *r, int i, const bf_compare_material *m, const bf_samples *table, const char *why)
{
    const bf_compare *c = r->c;
    FILE *fp = r->fp;
    fputs("<h3>Half/difference images</h3>\n", fp);
    bf_samples *s = r->o->samples ? r->o->samples[i] : NULL;
    if (!table && s && s->n)
        return halfdiff_points(r, i, m, s, why);
    if (!table) {
        fputs("<p>Not drawn: ", fp);
        report_esc(fp, why ? why : "there are no measured samples");
        fputs(".</p>\n", fp);
        return BF_OK;
    }
    const size_t npx = (size_t)HD_PX * HD_PX;
    float *rgb = malloc(3 * npx * sizeof *rgb);
    double *meas = malloc(3 * npx * sizeof *meas), *model = meas + npx, *ratio = meas + 2 * npx;
    bf_status rc = rgb && meas ? BF_OK : bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    double lo = -HD_DECADES, hi = 0.0;
    if (rc == BF_OK && (rc = bf_render_halfdiff_merl(table, HD_PX, HD_PX, 90.0, rgb, r->err)) == BF_OK) {
        halfdiff_mean(rgb, npx, meas);
        halfdiff_log_range(meas, npx, HD_PERCENTILE, HD_DECADES, &lo, &hi);
        fprintf(fp,
                "<p>&theta;<sub>h</sub> (x, on a square-root scale as MERL tables index it) by &theta;<sub>d</sub> "
                "(y), &phi;<sub>d</sub> 90&deg;; the mean of the channels. Measurement and models share one log "
                "colour scale, 10<sup>%.2f</sup> to 10<sup>%.2f</sup> sr<sup>&minus;1</sup> (%g decades down from "
                "the measurement's %g<sup>th</sup> percentile; brighter cells show as the top colour). Differences: "
                "log<sub>2</sub>(model / measured), white where equal, "
                "red where the model is brighter, blue where darker, saturating at a factor of %g; grey: no "
                "measured value.</p>\n<div class=\"row\">\n",
                lo, hi, HD_DECADES, HD_PERCENTILE, pow(2.0, HD_SPAN));
        char name[64], title[512];
        snprintf(name, sizeof name, "m%d-hd-measured", i + 1);
        snprintf(title, sizeof title, "%s: measured", report_base_name(m->data));
        rc = hd_figure(r, halfdiff_value_figure(meas, HD_PX, HD_PX, title, lo, hi), name, "measured", "measured", NULL);
        fputs("</div>\n", fp);
    }
    for (int j = 0; j < c->nmodels && rc == BF_OK; j++) {
        const bf_fit_result *res = report_fitted(&m->fits[j]);
        if (!res)
            continue;
        if ((rc = bf_render_halfdiff_model(res->model, res->x, HD_PX, HD_PX, 90.0, rgb, r->err)) != BF_OK)
            break;
        halfdiff_mean(rgb, npx, model);
        halfdiff_log2_ratio(model, meas, npx, ratio);
        char name[64], title[512], caption[600];
        fputs("<div class=\"row\">\n", fp);
        snprintf(name, sizeof name, "m%d-hd-model-%d", i + 1, j + 1);
        snprintf(title, sizeof title, "%s", c->models[j]);
        rc = hd_figure(r, halfdiff_value_figure(model, HD_PX, HD_PX, title, lo, hi), name, c->models[j], c->models[j],
                       NULL);
        if (rc != BF_OK)
            break;
        snprintf(name, sizeof name, "m%d-hd-diff-%d", i + 1, j + 1);
        snprintf(title, sizeof title, "%s vs measured", c->models[j]);
        snprintf(caption, sizeof caption, "log2(%s / measured)", c->models[j]);
        rc = hd_figure(r, halfdiff_ratio_figure(ratio, HD_PX, HD_PX, title, HD_SPAN), name, caption, caption, NULL);
        fputs("</div>\n", fp);
    }
    free(rgb);
    free(meas);
    return rc;
}

bf_status report_pictures(report_page *r, int i, const bf_compare_material *m)
{
    const char *why;
    const bf_samples *table = report_measured_table(r, i, &why);
    bf_status rc = slices(r, i, m);
    if (rc == BF_OK)
        rc = spheres(r, i, m, table, why);
    if (rc == BF_OK)
        rc = halfdiff(r, i, m, table, why);
    return rc;
}
