/* Ranking the tradeoff rows: test error, the Pareto front of fitting cost against it,
 * the best row and the recommendation (the cheapest row within tolerance of the best). */
#include "brdfit/tradeoff.h"

#include <math.h>
#include <stdlib.h>

const char *bf_tradeoff_cost_name(bf_tradeoff_cost c)
{
    return c == BF_TRADEOFF_COST_SECONDS ? "seconds" : "work";
}

double bf_tradeoff_row_cost(const bf_tradeoff *t, const bf_tradeoff_row *r)
{
    if (!r->ran)
        return NAN;
    return t->cost == BF_TRADEOFF_COST_SECONDS ? r->seconds : r->work;
}

void bf_tradeoff_rank(bf_tradeoff *t)
{
    int n = t->nrows;
    t->best = t->recommended = -1;
    double *x = malloc(2 * (size_t)(n > 0 ? n : 1) * sizeof *x);
    int *on = malloc((size_t)(n > 0 ? n : 1) * sizeof *on);
    double *y = x ? x + (n > 0 ? n : 1) : NULL;
    for (int i = 0; i < n; i++) {
        bf_tradeoff_row *r = &t->rows[i];
        int ranked = r->ran && r->ok;
        r->error = ranked ? bf_compare_metric_value(&r->test, t->metric) : NAN;
        const double cost = bf_tradeoff_row_cost(t, r);
        if (!isfinite(r->error) || !isfinite(cost))
            r->error = NAN;
        r->on_front = r->within_tolerance = 0;
        if (!isnan(r->error) &&
            (t->best < 0 || r->error < t->rows[t->best].error ||
             (r->error == t->rows[t->best].error && cost < bf_tradeoff_row_cost(t, &t->rows[t->best]))))
            t->best = i;
        if (x) {
            x[i] = isnan(r->error) ? NAN : cost;
            y[i] = r->error;
        }
    }
    if (x && on && n > 0) {
        bf_compare_pareto(n, x, y, on);
        for (int i = 0; i < n; i++)
            t->rows[i].on_front = !isnan(t->rows[i].error) && on[i];
    }
    free(x);
    free(on);
    if (t->best < 0)
        return;
    double limit = t->rows[t->best].error * (1.0 + t->tolerance);
    for (int i = 0; i < n; i++) {
        bf_tradeoff_row *r = &t->rows[i];
        if (isnan(r->error) || !(r->error <= limit))
            continue;
        r->within_tolerance = 1;
        const bf_tradeoff_row *c = t->recommended >= 0 ? &t->rows[t->recommended] : NULL;
        const double rc = bf_tradeoff_row_cost(t, r), cc = c ? bf_tradeoff_row_cost(t, c) : NAN;
        if (!c || rc < cc || (rc == cc && r->error < c->error))
            t->recommended = i;
    }
}
