/* The tradeoff table's error-against-cost plot (the table's JSON and CSV are
 * lib/src/study/tradeoff/output.c). */
#include "brdfit/tradeoff.h"

#include "base/sized.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "brdfit/render.h"
#include "plot/scatter.h"

bf_status bf_tradeoff_write_plot(const bf_tradeoff *t, const char *path, int format, int width, int height,
                                 bf_plot_axes *axes, bf_error *err)
{
    if (axes && bf_sized_check(axes, sizeof *axes, "bf_plot_axes", err) != BF_OK)
        return BF_ERR_ARG;
    if (width < 40 || height < 40 || width > 8192 || height > 8192)
        return bf_fail(err, BF_ERR_ARG, "plot size %dx%d: each side must be 40 to 8192", width, height);
    int fmt = format ? format : bf_plot_format_of(path);
    if (!fmt)
        return bf_fail(err, BF_ERR_ARG, "%s: unknown plot format (.png, .svg or .pdf)", path ? path : "-");
    int n = t->nrows > 0 ? t->nrows : 1;
    double *x = malloc(2 * (size_t)n * sizeof *x);
    int *on = malloc((size_t)n * sizeof *on);
    char(*text)[16] = malloc((size_t)n * sizeof *text);
    const char **labels = malloc((size_t)n * sizeof *labels);
    plot *p = NULL;
    bf_status rc = BF_OK;
    if (!x || !on || !text || !labels) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the plot", path);
        goto done;
    }
    double *y = x + n;
    /* Errors span decades: a log axis, linear when one is 0 (an exact fit). Only the
     * front's points are labelled (#N as in the table): the others would crowd it. */
    int log_y = 1, nfront = 0, ok = 0;
    for (int i = 0; i < t->nrows; i++) {
        const bf_tradeoff_row *r = &t->rows[i];
        x[i] = r->error >= 0.0 ? bf_tradeoff_row_cost(t, r) : NAN;
        y[i] = r->error;
        on[i] = r->on_front;
        nfront += r->on_front;
        ok += r->ok;
        log_y &= !(y[i] <= 0.0);
        snprintf(text[i], sizeof text[i], "#%d", i + 1);
        labels[i] = r->on_front || i == t->recommended ? text[i] : NULL;
    }
    char title[256], ytitle[96], points[64], front[64], chosen[64];
    snprintf(title, sizeof title, "Test error against fitting cost: %s", t->model);
    snprintf(ytitle, sizeof ytitle, "test error (%s)", bf_compare_metric_name(t->metric));
    snprintf(points, sizeof points, "settings (%d fitted)", ok);
    snprintf(front, sizeof front, "Pareto front (%d)", nfront);
    snprintf(chosen, sizeof chosen, "recommended (#%d)", t->recommended + 1);
    plot_scatter_spec sp = {
        title,    t->cost == BF_TRADEOFF_COST_SECONDS ? "fitting time (s)" : "fitting work (sample evaluations)",
        ytitle,   1,
        log_y,    0,
        t->nrows, x,
        y,        on,
        labels,   points,
        front,    t->recommended,
        chosen};
    if (!(p = plot_scatter(&sp)) || plot_note(p, "#N: the setting's number in the table") < 0) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the plot", path);
        goto done;
    }
    rc = plot_write(p, path, (bf_plot_format)fmt, width, height, err);
    if (rc == BF_OK && axes)
        plot_scatter_axes(p, &sp, width, height, axes);
done:
    plot_free(p);
    free(x);
    free(on);
    free(text);
    free(labels);
    return rc;
}
