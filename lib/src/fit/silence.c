/* Silent entries and the bounds that silence them (silence.h).
 *
 * An entry is silent when the diagonal of J'J (the sum of its squared derivatives over
 * every residual) is zero, or below SILENT_REL of the largest diagonal entry: no sample
 * tells anything about it. The models compute such derivatives as exact zeros (a weight
 * of 0 multiplies the whole lobe), so the threshold only absorbs the rounding of
 * cancelling terms. A silent entry's gate is found by moving the entries of each model
 * parameter that sits on a bound inward by GATE_STEP of their range, one parameter at a
 * time, and seeing which silent entries then have an effect: the first such parameter
 * (in the model's order) is the gate. */
#include "silence.h"

#include <stdlib.h>
#include <string.h>

#define SILENT_REL 1e-24
#define GATE_STEP 1e-3

int bf_silence_at_bound(const bf_problem *p, const double *z, int j)
{
    const double range = p->hi[j] - p->lo[j];
    if (!isfinite(range))
        return 0;
    return z[j] <= p->lo[j] + 1e-9 * range ? -1 : z[j] >= p->hi[j] - 1e-9 * range ? 1 : 0;
}

int bf_silence_param_of(const bf_model *m, int k)
{
    const int C = bf_model_channels(m);
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const int off = bf_model_param_offset(m, i), n = bf_model_param(m, i)->color ? C : 1;
        if (k >= off && k < off + n)
            return i;
    }
    return -1;
}

/* The diagonal of J'J at z, and its largest entry. */
static int diagonal(const bf_problem *p, const double *z, const bf_loss *loss, int threads, double *jtj, double *d,
                    double *dmax)
{
    double ssq;
    if (bf_problem_normal(p, z, loss, threads, &ssq, NULL, jtj) != 0)
        return -1;
    *dmax = 0.0;
    for (int j = 0; j < p->npar; j++) {
        d[j] = jtj[(size_t)j * p->npar + j];
        if (d[j] > *dmax)
            *dmax = d[j];
    }
    return 0;
}

static int is_silent(double d, double dmax)
{
    return !(d > SILENT_REL * dmax);
}

bf_status bf_silence_find(const bf_problem *p, const bf_objective *o, const double *z, const bf_loss *loss, int threads,
                          bf_silence *out, bf_error *err)
{
    const int nz = p->npar;
    const bf_model *m = o->model;
    memset(out, 0, sizeof *out);
    out->nz = nz;
    out->bound = calloc((size_t)nz + 1, 1);
    out->silent = calloc((size_t)nz + 1, 1);
    out->gate = malloc(((size_t)nz + 1) * sizeof *out->gate);
    double *jtj = malloc(((size_t)nz * nz + 1) * sizeof *jtj);
    double *d = malloc(((size_t)nz + 1) * sizeof *d), *d1 = malloc(((size_t)nz + 1) * sizeof *d1);
    double *zi = malloc(((size_t)nz + 1) * sizeof *zi);
    int *tried = calloc((size_t)bf_model_nparams(m) + 1, sizeof *tried);
    bf_status rc = BF_OK;
    double dmax, dmax1;
    if (!out->bound || !out->silent || !out->gate || !jtj || !d || !d1 || !zi || !tried) {
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
        goto done;
    }
    if (diagonal(p, z, loss, threads, jtj, d, &dmax) != 0) {
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory");
        goto done;
    }
    for (int j = 0; j < nz; j++) {
        out->bound[j] = (signed char)bf_silence_at_bound(p, z, j);
        out->silent[j] = (unsigned char)is_silent(d[j], dmax);
        out->gate[j] = -1;
        out->nsilent += out->silent[j];
    }
    if (out->nsilent == 0 || !(dmax > 0.0))
        goto done;
    for (int j = 0; j < nz; j++) {
        const int i = bf_silence_param_of(m, o->kidx[j]);
        if (!out->bound[j] || i < 0 || tried[i])
            continue;
        tried[i] = 1;
        memcpy(zi, z, (size_t)nz * sizeof *zi);
        for (int q = 0; q < nz; q++)
            if (out->bound[q] && bf_silence_param_of(m, o->kidx[q]) == i)
                zi[q] -= out->bound[q] * GATE_STEP * (p->hi[q] - p->lo[q]);
        if (diagonal(p, zi, loss, threads, jtj, d1, &dmax1) != 0)
            continue;
        for (int q = 0; q < nz; q++)
            if (out->silent[q] && out->gate[q] < 0 && bf_silence_param_of(m, o->kidx[q]) != i &&
                !is_silent(d1[q], dmax1))
                out->gate[q] = i;
    }
done:
    free(jtj);
    free(d);
    free(d1);
    free(zi);
    free(tried);
    if (rc != BF_OK)
        bf_silence_free(out);
    return rc;
}

void bf_silence_free(bf_silence *s)
{
    if (!s)
        return;
    free(s->bound);
    free(s->silent);
    free(s->gate);
    memset(s, 0, sizeof *s);
}
