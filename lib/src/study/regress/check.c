/* Comparing a fit result with a baseline case: ok, each pinned parameter value (per
 * channel) and metric, within its tolerance; one line per quantity that moved. */
#include "brdfit/formats.h"
#include "brdfit/regress.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"
#include "brdfit/io.h"
#include "regress/regress_impl.h"

typedef struct checker {
    bf_regress_outcome *out;
    int nomem;
} checker;

#define ADD(CK, LIST, N, ...) ((CK)->nomem |= bf_regress_addf(&(CK)->out->LIST, &(CK)->out->N, __VA_ARGS__) != 0)

static void fail(checker *ck, const char *fmt, const char *a, const char *b)
{
    ck->out->status = BF_REGRESS_FAIL;
    ADD(ck, lines, nlines, fmt, a, b);
}

/* One value: non-finite values match only the same kind (null in the file is NaN). */
static void compare(checker *ck, const char *label, double expected, double got, bf_tolerance t)
{
    char e[32], g[32];
    bf_format_double(expected, e, sizeof e);
    bf_format_double(got, g, sizeof g);
    double diff = fabs(got - expected), tol = t.abs + t.rel * fabs(expected);
    int pass;
    if (!isfinite(expected) || !isfinite(got))
        pass = (isnan(expected) && isnan(got)) || expected == got;
    else
        pass = diff <= tol;
    if (pass) {
        ADD(ck, checked, nchecked, "  %s: expected %s, got %s (|diff| %.2g <= tol %.2g)", label, e, g, diff, tol);
        return;
    }
    ck->out->status = BF_REGRESS_FAIL;
    ADD(ck, checked, nchecked, "  %s: expected %s, got %s (|diff| %.2g > tol %.2g)", label, e, g, diff, tol);
    ADD(ck, lines, nlines, "  %s: expected %s, got %s (|diff| %.2g > tol %.2g)", label, e, g, diff, tol);
}

/* "rho_d, rho_s, alpha, f0" */
static void param_list(const bf_model *m, char *buf, size_t size)
{
    buf[0] = '\0';
    for (int i = 0; i < bf_model_nparams(m); i++) {
        size_t len = strlen(buf);
        snprintf(buf + len, size - len, "%s%s", i ? ", " : "", bf_model_param(m, i)->name);
    }
}

static void check_params(checker *ck, const bf_regress_baseline *b, int c, const bf_fit_result *r)
{
    const bf_regress_case *cs = &b->cases[c];
    const bf_model *m = r->model;
    int C = bf_model_channels(m);
    for (int i = 0; i < cs->nparams; i++) {
        const bf_regress_value *v = &cs->params[i];
        int idx = bf_model_find_param(m, v->name);
        if (idx < 0) {
            char names[512];
            param_list(m, names, sizeof names);
            ck->out->status = BF_REGRESS_FAIL;
            ADD(ck, lines, nlines, "  params.%s: not a parameter of %s (its parameters: %s)", v->name, bf_model_spec(m),
                names);
            continue;
        }
        const bf_param_info *pi = bf_model_param(m, idx);
        int n = pi->color ? C : 1;
        if (v->n != n) {
            ck->out->status = BF_REGRESS_FAIL;
            if (pi->color)
                ADD(ck, lines, nlines, "  params.%s: expected holds %d value%s, the fit has %d (one per channel)",
                    v->name, v->n, v->n == 1 ? "" : "s", n);
            else
                ADD(ck, lines, nlines, "  params.%s: expected holds %d values, the parameter is a scalar", v->name,
                    v->n);
            continue;
        }
        const double *x = r->x + bf_model_param_offset(m, idx);
        bf_tolerance t = bf_regress_tolerance(b, c, "params", v->name);
        for (int k = 0; k < n; k++) {
            char label[160];
            if (v->array)
                snprintf(label, sizeof label, "params.%s[%d]", v->name, k);
            else
                snprintf(label, sizeof label, "params.%s", v->name);
            compare(ck, label, v->v[k], x[k], t);
        }
    }
}

bf_status bf_regress_check(const bf_regress_baseline *b, int c, const bf_fit_result *r, bf_regress_outcome *out,
                           bf_error *err)
{
    if (bf_sized_check(out, sizeof *out, "bf_regress_outcome", err) != BF_OK)
        return BF_ERR_ARG;
    bf_regress_outcome_clear(out);
    out->status = BF_REGRESS_PASS;
    out->seconds = r->seconds;
    checker ck = {out, 0};
    const bf_regress_case *cs = &b->cases[c];
    for (int w = 0; w < r->nwarnings; w++)
        ADD(&ck, warnings, nwarnings, "%s", r->warnings[w]);
    if (!r->ok || !cs->expect_ok) {
        const char *got = r->ok ? "true" : "false", *exp = cs->expect_ok ? "true" : "false";
        if (r->ok != cs->expect_ok)
            fail(&ck, r->ok ? "  ok: expected %s, got %s" : "  ok: expected %s, got %s (the fit failed)", exp, got);
        ADD(&ck, checked, nchecked, "  ok: expected %s, got %s", exp, got);
        if (!r->ok && cs->expect_ok)
            ADD(&ck, lines, nlines, "  termination: %s", r->solution.termination);
    } else {
        ADD(&ck, checked, nchecked, "  ok: expected true, got true");
        check_params(&ck, b, c, r);
        for (int i = 0; i < cs->nmetrics; i++) {
            const bf_regress_value *v = &cs->metrics[i];
            double got = NAN;
            bf_regress_metric(&r->metrics, v->name, &got);
            char label[160];
            snprintf(label, sizeof label, "metrics.%s", v->name);
            compare(&ck, label, v->v[0], got, bf_regress_tolerance(b, c, "metrics", v->name));
        }
    }
    if (ck.nomem) {
        bf_regress_outcome_clear(out);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory comparing case '%s'", cs->name);
    }
    return BF_OK;
}

bf_status bf_regress_set_error(bf_regress_outcome *out, const char *message, bf_error *err)
{
    if (bf_sized_check(out, sizeof *out, "bf_regress_outcome", err) != BF_OK)
        return BF_ERR_ARG;
    bf_regress_outcome_clear(out);
    out->status = BF_REGRESS_ERROR;
    if (bf_regress_addf(&out->lines, &out->nlines, "%s", message) != 0)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    return BF_OK;
}

void bf_regress_outcome_clear(bf_regress_outcome *out)
{
    for (int i = 0; i < out->nlines; i++)
        free(out->lines[i]);
    for (int i = 0; i < out->nchecked; i++)
        free(out->checked[i]);
    for (int i = 0; i < out->nwarnings; i++)
        free(out->warnings[i]);
    free(out->warnings);
    free(out->lines);
    free(out->checked);
    const size_t size = out->size; /* the caller's: it stays ready for another run */
    memset(out, 0, sizeof *out);
    out->size = size;
}

BF_SIZED_INIT_ZERO(bf_regress_outcome)
