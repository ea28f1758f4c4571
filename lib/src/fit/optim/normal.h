/* Internal: accumulating the fused sums of bf_problem.normal (solve.h), shared by the
 * generic path (normal.c) and the objective's own pass (fit/objective.c). */
#ifndef BF_OPTIM_NORMAL_H
#define BF_OPTIM_NORMAL_H

/* Adds one Jacobian row jr (npar entries) of residual g: jtr += g jr and, when jtj is
 * not NULL, the lower triangle of jtj += jr' jr (row-major, jtj[a * npar + b] with
 * b <= a). Zero entries are skipped: in a colour fit half of every row is zero (a
 * channel's residual ignores the other channels' colour parameters). NaN and Inf are
 * not zero, so they reach the sums. idx: scratch of npar ints. */
static inline void bf_normal_add_row(int npar, double g, const double *jr, int *idx, double *jtr, double *jtj)
{
    int m = 0;
    for (int a = 0; a < npar; a++)
        if (jr[a] != 0.0)
            idx[m++] = a;
    for (int u = 0; u < m; u++) {
        const int a = idx[u];
        const double ja = jr[a];
        jtr[a] += g * ja;
        if (jtj) {
            double *row = jtj + (long)a * npar;
            for (int v = 0; v <= u; v++)
                row[idx[v]] += ja * jr[idx[v]];
        }
    }
}

/* The lower triangle copied to the upper one. */
static inline void bf_normal_symmetrise(int npar, double *jtj)
{
    for (int a = 0; a < npar; a++)
        for (int b = a + 1; b < npar; b++)
            jtj[a * npar + b] = jtj[b * npar + a];
}

#endif
