/* The tradeoff grid: methods, the train/test split and the rows in their order (the
 * methods themselves are taken as the options take them: fit/tradeoff_options.c).
 *
 * Decisions:
 *  - The test set is a uniform random subset (not stratified): it then has the same
 *    angular density as the data, so its error is the error a user of the whole data set
 *    would see. The training subsamples are stratified (bf_samples_prep), as
 *    `brdfit fit --subsample` does, so a tradeoff row is exactly what fit would run.
 *  - Sample counts at or above the training size are the same setting as "all": one row. */
#include "brdfit/tradeoff.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/prep.h"
#include "base/rng.h"
#include "base/sized.h"
#include "compare/compare_impl.h"
#include "run_options.h"
#include "tradeoff/tradeoff_impl.h"

/* ---- Methods ------------------------------------------------------------------- */

bf_status bf_tradeoff_method_check(const char *text, const bf_options *base, bf_error *err)
{
    bf_fit_options f;
    options_fit_get(base, &f);
    return bf_tradeoff_method_apply(text, &f.solver, err);
}

/* ---- Train / test split -------------------------------------------------------- */

bf_status bf_tradeoff_split(const bf_samples *s, double fraction, uint64_t seed, bf_samples **train, bf_samples **test,
                            bf_error *err)
{
    *train = *test = NULL;
    if (!(fraction > 0.0 && fraction < 1.0))
        return bf_fail(err, BF_ERR_ARG, "test fraction must be in (0, 1), got %g", fraction);
    const size_t n = s->n;
    if (n < 2)
        return bf_fail(err, BF_ERR_ARG, "%zu sample%s: too few to hold any out for testing", n, n == 1 ? "" : "s");
    double want = floor((double)n * fraction + 0.5);
    size_t k = want < 1.0 ? 1 : want > (double)(n - 1) ? n - 1 : (size_t)want;
    unsigned char *mask = malloc(n + 1);
    if (!mask)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for the train/test split");
    /* Selection sampling (Knuth, TAOCP 3.4.2 Algorithm S): exactly k of n, uniformly; the
     * stream is set apart from the subsampling one by a constant. */
    uint64_t state = seed ^ 0x5465737453706c74ull;
    size_t need = k;
    for (size_t i = 0; i < n; i++) {
        double u = (double)(bf_splitmix64(&state) >> 11) * 0x1.0p-53;
        mask[i] = (double)(n - i) * u < (double)need;
        need -= mask[i];
    }
    *train = NULL;
    bf_status rc = bf_samples_copy(s, mask, test, err);
    for (size_t i = 0; i < n; i++)
        mask[i] = !mask[i];
    if (rc == BF_OK && (rc = bf_samples_copy(s, mask, train, err)) != BF_OK) {
        bf_samples_free(*test);
        *test = NULL;
    }
    free(mask);
    return rc;
}

/* ---- Grid ---------------------------------------------------------------------- */

static int cmp_size(const void *a, const void *b)
{
    size_t x = *(const size_t *)a, y = *(const size_t *)b;
    return x < y ? -1 : x > y;
}

BF_SIZED_INIT_ZERO(bf_tradeoff_grid)

/* The grid's usage errors, before anything is allocated. */
static bf_status grid_check(const bf_tradeoff_grid *g, size_t train_n, bf_error *err)
{
    if (bf_sized_check(g, sizeof *g, "bf_tradeoff_grid", err) != BF_OK)
        return BF_ERR_ARG;
    if (g->ncounts < 1 || g->nmethods < 1 || g->nresiduals < 1 || g->nstarts < 1)
        return bf_fail(err, BF_ERR_ARG, "tradeoff: every list (samples, methods, residuals, starts) needs an entry");
    if (train_n < 1)
        return bf_fail(err, BF_ERR_ARG, "tradeoff: no training sample");
    for (int s = 0; s < g->nstarts; s++)
        if (g->starts[s] < 0)
            return bf_fail(err, BF_ERR_ARG, "tradeoff: a start count must be >= 0 (0: automatic), got %d",
                           g->starts[s]);
    return BF_OK;
}

/* The grid's sample counts, sorted and unique, counts >= the training size (and 0) as
 * train_n, "all": into *out (malloc'd), their number into *n. */
static bf_status grid_counts(const bf_tradeoff_grid *g, size_t train_n, size_t **out, int *n, bf_error *err)
{
    size_t *c = malloc((size_t)g->ncounts * sizeof *c);
    if (!c)
        return bf_fail(err, BF_ERR_NOMEM, "tradeoff: out of memory");
    for (int k = 0; k < g->ncounts; k++)
        c[k] = g->counts[k] == 0 || g->counts[k] >= train_n ? train_n : g->counts[k];
    qsort(c, (size_t)g->ncounts, sizeof *c, cmp_size);
    int nc = 0;
    for (int k = 0; k < g->ncounts; k++)
        if (nc == 0 || c[k] != c[nc - 1])
            c[nc++] = c[k];
    *out = c;
    *n = nc;
    return BF_OK;
}

/* The methods' names, copied into one block (names) the rows point into; at[m]: where
 * method m starts in it. */
static void copy_names(const bf_tradeoff_grid *g, char *names, size_t *at)
{
    size_t k = 0;
    for (int m = 0; m < g->nmethods; m++) {
        const char *text = g->methods[m] ? g->methods[m] : "";
        at[m] = k;
        memcpy(names + k, text, strlen(text) + 1);
        k += strlen(text) + 1;
    }
}

bf_status bf_tradeoff_init(bf_tradeoff *t, const char *data, const char *model, size_t train_n,
                           const bf_tradeoff_grid *g, bf_error *err)
{
    memset(t, 0, sizeof *t);
    t->best = t->recommended = -1;
    t->repeats = 1;
    t->tolerance = 0.05;
    t->metric = BF_CMP_RMSE_LOG;
    t->train_n = train_n;
    size_t *c = NULL;
    int nc = 0;
    bf_status rc = grid_check(g, train_n, err);
    if (rc != BF_OK || (rc = grid_counts(g, train_n, &c, &nc, err)) != BF_OK)
        return rc;
    size_t rows = (size_t)nc * (size_t)g->nmethods * (size_t)g->nresiduals * (size_t)g->nstarts;
    if (rows > BF_TRADEOFF_MAX_ROWS) {
        free(c);
        return bf_fail(err, BF_ERR_ARG, "tradeoff: %zu settings is too many (at most %d)", rows, BF_TRADEOFF_MAX_ROWS);
    }
    size_t names = 0;
    for (int m = 0; m < g->nmethods; m++)
        names += strlen(g->methods[m] ? g->methods[m] : "") + 1;
    t->data = strdup(data ? data : "");
    t->model = strdup(model ? model : "");
    t->rows = calloc(rows, sizeof *t->rows);
    t->names = malloc(names);
    size_t *at = malloc((size_t)g->nmethods * sizeof *at);
    if (!t->data || !t->model || !t->rows || !t->names || !at) {
        free(c);
        free(at);
        bf_tradeoff_clear(t);
        return bf_fail(err, BF_ERR_NOMEM, "tradeoff: out of memory");
    }
    copy_names(g, t->names, at);
    t->nrows = (int)rows;
    int i = 0;
    for (int a = 0; a < nc; a++)
        for (int m = 0; m < g->nmethods; m++)
            for (int r = 0; r < g->nresiduals; r++)
                for (int s = 0; s < g->nstarts; s++) {
                    bf_tradeoff_row *row = &t->rows[i++];
                    row->samples = c[a];
                    row->all = c[a] == train_n;
                    row->method = t->names + at[m];
                    row->residual = g->residuals[r];
                    row->starts = g->starts[s];
                    row->error = NAN;
                }
    free(c);
    free(at);
    return BF_OK;
}

void bf_tradeoff_clear(bf_tradeoff *t)
{
    free(t->data);
    free(t->model);
    for (int i = 0; t->rows && i < t->nrows; i++)
        free(t->rows[i].warnings);
    free(t->rows);
    free(t->fit_options);
    free(t->names);
    memset(t, 0, sizeof *t);
    t->best = t->recommended = -1;
}

bf_status bf_tradeoff_new_grid(const char *data, const char *model, size_t train_n, const bf_tradeoff_grid *grid,
                               bf_tradeoff **out, bf_error *err)
{
    bf_tradeoff *t = malloc(sizeof *t);
    *out = NULL;
    if (!t)
        return bf_fail(err, BF_ERR_NOMEM, "tradeoff: out of memory");
    bf_status rc = bf_tradeoff_init(t, data, model, train_n, grid, err);
    if (rc != BF_OK) {
        free(t);
        return rc;
    }
    *out = t;
    return BF_OK;
}

/* Positional, deprecated (docs/api.md: a function is replaced, not changed in place). */
bf_status bf_tradeoff_new(const char *data, const char *model, size_t train_n, int ncounts, const size_t *counts,
                          int nmethods, const char *const *methods, int nresiduals, const bf_residual *residuals,
                          int nstarts, const int *starts, bf_tradeoff **out, bf_error *err)
{
    bf_tradeoff_grid g;
    bf_tradeoff_grid_init(&g);
    g.ncounts = ncounts;
    g.counts = counts;
    g.nmethods = nmethods;
    g.methods = methods;
    g.nresiduals = nresiduals;
    g.residuals = residuals;
    g.nstarts = nstarts;
    g.starts = starts;
    return bf_tradeoff_new_grid(data, model, train_n, &g, out, err);
}

void bf_tradeoff_free(bf_tradeoff *t)
{
    if (!t)
        return;
    bf_tradeoff_clear(t);
    free(t);
}
