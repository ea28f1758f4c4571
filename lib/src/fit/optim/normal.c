/* bf_problem_normal: the fused sums (sum g^2, J'g, J'J) every back end works from, for
 * problems that have only a residual function. The residuals are cut into fixed chunks
 * whose size depends on the problem alone; each chunk's sums are kept apart and added in
 * chunk order, so the result is the same for every thread count. */
#include "brdfit/solve.h"

#include <stdlib.h>
#include <string.h>

#include "normal.h"
#include "base/parallel.h"

/* Rows per chunk: a Jacobian chunk of about 256 KiB, at least 64 rows. */
static size_t chunk_rows(int npar)
{
    size_t rows = 32768 / (size_t)npar;
    return rows < 64 ? 64 : rows;
}

typedef struct job {
    const bf_problem *p;
    const double *x;
    const bf_loss *loss;
    size_t rows;
    int want_jtr, want_jtj;
    double *part; /* per chunk: ssq, jtr (npar), jtj (npar^2) */
    int failed;
} job;

static size_t part_size(int npar)
{
    return 1 + (size_t)npar + (size_t)npar * (size_t)npar;
}

static void chunk_sums(void *ctx, size_t c)
{
    job *j = ctx;
    const bf_problem *p = j->p;
    const int np = p->npar;
    size_t r0 = c * j->rows, r1 = r0 + j->rows < p->nres ? r0 + j->rows : p->nres;
    double *res = malloc((r1 - r0) * sizeof *res);
    double *jac = j->want_jtr ? malloc((r1 - r0) * (size_t)np * sizeof *jac) : NULL;
    double *out = j->part + c * part_size(np);
    if (!res || (j->want_jtr && !jac) || p->eval(p->user, j->x, r0, r1, res, jac) != 0) {
        j->failed = 1;
        free(res);
        free(jac);
        return;
    }
    int *idx = j->want_jtr ? malloc((size_t)np * sizeof *idx) : NULL;
    if (j->want_jtr && !idx) {
        j->failed = 1;
        free(res);
        free(jac);
        return;
    }
    double ssq = 0.0;
    for (size_t r = 0; r < r1 - r0; r++) {
        double dg, g = bf_loss_residual(j->loss, res[r], &dg);
        ssq += g * g;
        if (!jac)
            continue;
        double *jr = jac + r * (size_t)np;
        for (int k = 0; k < np; k++)
            jr[k] *= dg;
        bf_normal_add_row(np, g, jr, idx, out + 1, j->want_jtj ? out + 1 + np : NULL);
    }
    out[0] = ssq;
    free(idx);
    free(res);
    free(jac);
}

int bf_problem_normal(const bf_problem *p, const double *x, const bf_loss *loss, int threads, double *ssq, double *jtr,
                      double *jtj)
{
    if (p->normal)
        return p->normal(p->user, x, loss, threads, ssq, jtr, jtj);
    const int np = p->npar;
    const size_t rows = chunk_rows(np), nchunks = (p->nres + rows - 1) / rows, ps = part_size(np);
    job j = {p, x, loss, rows, jtr != NULL || jtj != NULL, jtj != NULL, calloc(nchunks * ps + 1, sizeof(double)), 0};
    if (!j.part)
        return -1;
    bf_parallel_for(nchunks, threads, chunk_sums, &j);
    if (j.failed) {
        free(j.part);
        return -1;
    }
    *ssq = 0.0;
    if (jtr)
        memset(jtr, 0, (size_t)np * sizeof *jtr);
    if (jtj)
        memset(jtj, 0, (size_t)np * (size_t)np * sizeof *jtj);
    for (size_t c = 0; c < nchunks; c++) {
        const double *part = j.part + c * ps;
        *ssq += part[0];
        for (int k = 0; jtr && k < np; k++)
            jtr[k] += part[1 + k];
        for (size_t e = 0; jtj && e < (size_t)np * (size_t)np; e++)
            jtj[e] += part[1 + np + e];
    }
    if (jtj)
        bf_normal_symmetrise(np, jtj);
    free(j.part);
    return 0;
}
