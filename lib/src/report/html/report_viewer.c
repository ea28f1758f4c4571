/* The report's interactive viewer: per material, a script of data (mN-viewer.js: the
 * measurement and every ranked model tabulated by viewer_table.c, or the measured samples
 * as points) beside the page, and the viewer's code (viewer.js, compiled into the
 * library from lib/src/report/html/viewer.js), so the page works from disk with no
 * server and nothing fetched (docs/report.md).
 *
 * Decisions:
 *  - Data files are scripts calling brdfitViewer.add(JSON), not JSON fetched by the
 *    page: browsers refuse fetch() on file:// but load <script src> there.
 *  - Scattered measurements (Cornell, ALTA, CSV; a MERL subsample whose table is not at
 *    hand) are shown as their samples, at most VIEWER_POINTS of them (every k-th, so the
 *    same data gives the same file), angles in hundredths of a degree, values as the
 *    tables' log codes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"
#include "html/report.h"
#include "html/viewer_table.h"
#include "render/color.h"

enum { VIEWER_POINTS = 4000 };

extern const unsigned char report_viewer_js[]; /* viewer.js, NUL-terminated */

/* A file of the report's folder written whole (bf_outfile: checked, synced). */
static bf_status write_file(report_page *r, const char *name, const char *head, const char *body, const char *tail)
{
    char path[4200];
    if (snprintf(path, sizeof path, "%s/%s", r->tmp, name) >= (int)sizeof path)
        return bf_fail(r->err, BF_ERR_ARG, "%s: path too long", r->tmp);
    bf_outfile o;
    bf_status rc = bf_outfile_open(&o, path, r->err);
    if (rc != BF_OK)
        return rc;
    fputs(head, o.fp);
    fputs(body, o.fp);
    fputs(tail, o.fp);
    return bf_outfile_commit(&o, r->err);
}

bf_status report_viewer_code(report_page *r)
{
    /* The embedded bytes end with a NUL (cmake/embed.cmake): a string as they are. */
    return write_file(r, "viewer.js", "", (const char *)report_viewer_js, "");
}

/* A table as {"lo", "step", "data"} added to o under "table". */
static bf_status add_table(report_page *r, cJSON *o, const double *v)
{
    cJSON *t = viewer_encode(v, 3, VIEWER_NODES, VIEWER_NH, r->err);
    if (!t)
        return r->err->code;
    cJSON_AddItemToObject(o, "table", t);
    return BF_OK;
}

/* Up to VIEWER_POINTS samples: {"n", "angles": 4 columns, "values": 3 channels}. */
static bf_status add_points(report_page *r, cJSON *o, const bf_samples *s)
{
    const size_t stride = (s->n + VIEWER_POINTS - 1) / VIEWER_POINTS, n = (s->n + stride - 1) / stride;
    uint16_t *ang = malloc(4 * n * sizeof *ang);
    double *val = malloc(3 * n * sizeof *val), *c = malloc((size_t)s->channels * sizeof *c);
    bf_status rc = ang && val && c ? BF_OK : bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    for (size_t q = 0; q < n && rc == BF_OK; q++) {
        const size_t i = q * stride;
        double d[4], rgb[3];
        bf_samples_direction(s, i, d);
        for (int a = 0; a < 4; a++) {
            double deg = a % 2 ? fmod(fmod(d[a], 360.0) + 360.0, 360.0) : fmin(fmax(d[a], 0.0), 90.0);
            ang[(size_t)a * n + q] = (uint16_t)(lround(deg * 100.0) % 36000);
        }
        for (int ch = 0; ch < s->channels; ch++)
            c[ch] = s->value[i * (size_t)s->channels + (size_t)ch];
        bf_channels_to_rgb(c, s->channels, rgb);
        for (int ch = 0; ch < 3; ch++)
            val[(size_t)ch * n + q] = rgb[ch];
    }
    cJSON *p = rc == BF_OK ? cJSON_CreateObject() : NULL, *a = NULL, *v = NULL;
    if (rc == BF_OK &&
        (!p || !(a = viewer_encode_u16(ang, 4, n, r->err)) || !(v = viewer_encode(val, 3, n, n, r->err))))
        rc = p ? r->err->code : bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    if (rc == BF_OK) {
        cJSON_AddNumberToObject(p, "n", (double)n);
        cJSON_AddNumberToObject(p, "of", (double)s->n);
        cJSON_AddItemToObject(p, "angles", a);
        cJSON_AddItemToObject(p, "values", v);
        cJSON_AddItemToObject(o, "points", p);
    } else {
        cJSON_Delete(p);
        cJSON_Delete(a);
        cJSON_Delete(v);
    }
    free(ang);
    free(val);
    free(c);
    return rc;
}

/* The measurement: a table, points, or the reason there is neither. */
static bf_status add_measured(report_page *r, cJSON *o, int i, const bf_samples *table, const char *why, double *v)
{
    const bf_samples *s = r->o->samples ? r->o->samples[i] : NULL;
    cJSON *m = cJSON_AddObjectToObject(o, "measured");
    if (!m)
        return bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    bf_status rc = BF_OK;
    if (table) {
        if ((rc = viewer_table_merl(table, v, r->err)) == BF_OK)
            rc = add_table(r, m, v);
    } else if (s && s->n > 0) {
        rc = add_points(r, m, s);
    } else {
        cJSON_AddStringToObject(m, "why", why ? why : "no measured data was given to the report");
    }
    return rc;
}

bf_status report_viewer(report_page *r, int i, const bf_compare_material *m, const bf_samples *table, const char *why)
{
    const bf_compare *c = r->c;
    double *v = malloc(3 * VIEWER_NODES * sizeof *v);
    cJSON *o = cJSON_CreateObject(), *models = cJSON_AddArrayToObject(o, "models");
    bf_status rc = v && o && models ? BF_OK : bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    char id[32];
    snprintf(id, sizeof id, "m%d", i + 1);
    if (rc == BF_OK) {
        cJSON_AddStringToObject(o, "id", id);
        cJSON_AddStringToObject(o, "title", report_base_name(m->data));
        cJSON *grid = cJSON_AddObjectToObject(o, "grid");
        cJSON_AddNumberToObject(grid, "nh", VIEWER_NH);
        cJSON_AddNumberToObject(grid, "nd", VIEWER_ND);
        cJSON_AddNumberToObject(grid, "np", VIEWER_NP);
        rc = add_measured(r, o, i, table, why, v);
    }
    for (int j = 0; j < c->nmodels && rc == BF_OK; j++) {
        const bf_fit_result *res = report_fitted(&m->fits[j]);
        if (!res)
            continue;
        cJSON *e = cJSON_CreateObject();
        if (!e || !cJSON_AddItemToArray(models, e)) {
            cJSON_Delete(e);
            rc = bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
            break;
        }
        cJSON_AddStringToObject(e, "name", c->models[j]);
        cJSON_AddNumberToObject(e, "index", j + 1);
        cJSON_AddNumberToObject(e, "rank", m->fits[j].rank);
        cJSON_AddNumberToObject(e, "k", m->fits[j].metrics.k);
        if ((rc = viewer_table_model(res->model, res->x, v, r->err)) == BF_OK)
            rc = add_table(r, e, v);
    }
    char *json = rc == BF_OK ? cJSON_PrintUnformatted(o) : NULL;
    if (rc == BF_OK && !json)
        rc = bf_fail(r->err, BF_ERR_NOMEM, "report: out of memory");
    char name[64];
    snprintf(name, sizeof name, "%s-viewer.js", id);
    if (rc == BF_OK)
        rc = write_file(r, name, "brdfitViewer.add(", json, ");\n");
    if (rc == BF_OK)
        fprintf(r->fp,
                "<h3>Explore</h3>\n<div class=\"brdfit-viewer\" id=\"viewer-%s\"><p class=\"noscript\">The "
                "viewer needs JavaScript and WebGL 2.</p></div>\n<script src=\"%s\"></script>\n",
                id, name);
    free(json);
    cJSON_Delete(o);
    free(v);
    return rc;
}
