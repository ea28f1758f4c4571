/* Standard errors of the model parameters from the Jacobian at the solution.
 *
 * J is taken with respect to the free model parameters (model space, not the internal
 * scale), for the residuals in the objective's form and weights. Then
 *   cov = s^2 (J^T J)^-1,  s^2 = SSR / (n - k),
 * n the residuals of samples above the horizon, k the free parameters.
 *
 * (J^T J)^-1 is computed from an eigen-decomposition (cyclic Jacobi) of J^T J scaled to
 * unit diagonal rather than a Cholesky factorisation: where J^T J is singular it tells
 * which parameters take part in the null space. Each of those (say rho_s_1 and rho_s_2
 * of two identical lobes) gets NaN, and each determined parameter gets its variance from
 * the non-null part (the pseudo-inverse), which for a regular matrix is the inverse. An
 * eigenvalue counts as null below 1e-12 of the largest (the scaled matrix has unit
 * diagonal, so this is a condition number of 1e12, the limit of double precision for a
 * normal matrix). A parameter the residuals do not depend on at all (zero column) is NaN
 * too. An entry the caller holds for the errors (bf_final_want.held: on a bound, or
 * silent) is left out of J^T J, as a solver with that bound active leaves it, and gets
 * NaN: the others' errors are then those of the parameters the data can move. The
 * correlations come from J^T J without the entries held for them (silent ones): two
 * parameters the data hardly tell apart are worth saying so even where one of them ends
 * on a bound. With n <= k there is no estimate of s^2 and every free parameter is NaN.
 * J^T J comes from the objective's fused pass (fixed chunks added in order), so the
 * result does not depend on the thread count. */
#include <stdlib.h>
#include <string.h>

#include "metrics_impl.h"
#include "objective_state.h"

#define NULL_EIGEN 1e-12
#define NULL_SHARE 1e-6

/* Cyclic Jacobi: a (k x k, symmetric, destroyed) -> eigenvalues on its diagonal, v the
 * eigenvectors as columns. */
static void jacobi(double *a, double *v, int k)
{
    for (int i = 0; i < k; i++)
        for (int j = 0; j < k; j++)
            v[i * k + j] = i == j;
    for (int sweep = 0; sweep < 100; sweep++) {
        double off = 0.0, diag = 0.0;
        for (int i = 0; i < k; i++)
            for (int j = 0; j < k; j++)
                if (i != j)
                    off += a[i * k + j] * a[i * k + j];
                else
                    diag += a[i * k + j] * a[i * k + j];
        if (off <= 1e-32 * diag)
            return;
        for (int p = 0; p < k; p++)
            for (int q = p + 1; q < k; q++) {
                double apq = a[p * k + q];
                if (apq == 0.0)
                    continue;
                double theta = (a[q * k + q] - a[p * k + p]) / (2.0 * apq);
                double t = (theta >= 0 ? 1.0 : -1.0) / (fabs(theta) + sqrt(theta * theta + 1.0));
                double c = 1.0 / sqrt(t * t + 1.0), s = t * c;
                for (int r = 0; r < k; r++) { /* A P */
                    double arp = a[r * k + p], arq = a[r * k + q];
                    a[r * k + p] = c * arp - s * arq;
                    a[r * k + q] = s * arp + c * arq;
                }
                for (int r = 0; r < k; r++) { /* P^T (A P) */
                    double apr = a[p * k + r], aqr = a[q * k + r];
                    a[p * k + r] = c * apr - s * aqr;
                    a[q * k + r] = s * apr + c * aqr;
                }
                for (int r = 0; r < k; r++) { /* V P */
                    double vrp = v[r * k + p], vrq = v[r * k + q];
                    v[r * k + p] = c * vrp - s * vrq;
                    v[r * k + q] = s * vrp + c * vrq;
                }
            }
    }
}

/* The pseudo-inverse's scratch: 2 nz^2 + nz doubles, nz ints. */
typedef struct pinv_work {
    double *work;
    int *idx;
} pinv_work;

/* out->se[j] for the nz free entries from J^T J (nz x nz) and s^2, and when out->corr
 * or out->cov is not NULL the correlations and covariances of each pair of determined
 * entries (nz x nz; NaN where either is undetermined; corr 1 and cov se^2 on the
 * diagonal), all from the same pseudo-inverse. out->metrics is not used. */
static void covariance(const double *jtj, int nz, double s2, const unsigned char *held, const bf_final_out *out,
                       const pinv_work *w)
{
    double *se = out->se, *corr = out->corr, *cov = out->cov, *work = w->work;
    int *idx = w->idx;
    for (size_t e = 0; corr && e < (size_t)nz * nz; e++)
        corr[e] = NAN;
    for (size_t e = 0; cov && e < (size_t)nz * nz; e++)
        cov[e] = NAN;
    double *d = work + 2 * (size_t)nz * nz;
    int k = 0;
    for (int j = 0; j < nz; j++) {
        se[j] = NAN;
        d[j] = jtj[j * nz + j];
        if (d[j] > 0.0 && isfinite(d[j]) && !(held && held[j]))
            idx[k++] = j;
    }
    if (k == 0)
        return;
    double *a = work, *v = work + (size_t)nz * nz;
    for (int p = 0; p < k; p++)
        for (int q = 0; q < k; q++)
            a[p * k + q] = jtj[idx[p] * nz + idx[q]] / sqrt(d[idx[p]] * d[idx[q]]);
    jacobi(a, v, k);
    double lmax = 0.0;
    for (int e = 0; e < k; e++)
        if (a[e * k + e] > lmax)
            lmax = a[e * k + e];
    for (int p = 0; p < k; p++) {
        double var = 0.0, nullshare = 0.0;
        for (int e = 0; e < k; e++) {
            double lam = a[e * k + e], vv = v[p * k + e] * v[p * k + e];
            if (lam > NULL_EIGEN * lmax)
                var += vv / lam;
            else
                nullshare += vv;
        }
        if (nullshare <= NULL_SHARE && isfinite(var))
            se[idx[p]] = sqrt(s2 * var / d[idx[p]]);
    }
    /* Correlations from the same pseudo-inverse (the scaling by d cancels in them, not in
     * the covariances). */
    for (int p = 0; (corr || cov) && p < k; p++)
        for (int q = 0; q <= p; q++) {
            if (isnan(se[idx[p]]) || isnan(se[idx[q]]))
                continue;
            double cpq = 0.0, cpp = 0.0, cqq = 0.0;
            for (int e = 0; e < k; e++) {
                double lam = a[e * k + e];
                if (!(lam > NULL_EIGEN * lmax))
                    continue;
                cpq += v[p * k + e] * v[q * k + e] / lam;
                cpp += v[p * k + e] * v[p * k + e] / lam;
                cqq += v[q * k + e] * v[q * k + e] / lam;
            }
            const int i = idx[p], j = idx[q];
            if (corr)
                corr[i * nz + j] = corr[j * nz + i] = p == q ? 1.0 : cpq / sqrt(cpp * cqq);
            if (cov)
                cov[i * nz + j] = cov[j * nz + i] = p == q ? se[i] * se[i] : s2 * cpq / sqrt(d[i] * d[j]);
        }
}

/* Standard errors from J'J (nz x nz over the free entries, model space) and the sum of
 * squared residuals, into out (model order; out->cov: 0 in a fixed entry's row and
 * column, NaN where either entry is undetermined). */
static bf_status stderr_from(const bf_objective *o, const double *jtj, double ssr, const bf_final_want *want,
                             const bf_final_out *out, bf_error *err)
{
    const int nz = o->nz;
    size_t nz2 = (size_t)nz * nz;
    double *corr = out->corr, *cov = out->cov;
    double *sez = malloc((size_t)nz * sizeof *sez);
    double *work = malloc((2 * nz2 + (size_t)nz) * sizeof *work);
    int *idx = malloc((size_t)nz * sizeof *idx);
    double *covz = cov ? malloc((nz2 + 1) * sizeof *covz) : NULL;
    bf_status rc = BF_OK;
    if (!sez || !work || !idx || (cov && !covz)) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for standard errors");
        goto done;
    }
    size_t n = o->nvalid * (size_t)o->C;
    if (n <= (size_t)nz || !isfinite(ssr)) {
        for (int k = 0; k < nz; k++)
            sez[k] = NAN;
        for (size_t e = 0; corr && e < (size_t)nz * nz; e++)
            corr[e] = NAN;
        for (size_t e = 0; covz && e < nz2; e++)
            covz[e] = NAN;
    } else {
        const double s2 = ssr / (double)(n - (size_t)nz);
        const pinv_work w = {work, idx};
        if (corr && want->held != want->held_corr) { /* two masks: the correlations from their own pass */
            covariance(jtj, nz, s2, want->held_corr, &(bf_final_out){NULL, sez, corr, NULL}, &w);
            corr = NULL;
        }
        covariance(jtj, nz, s2, want->held, &(bf_final_out){NULL, sez, corr, covz}, &w);
    }
    for (int k = 0; k < nz; k++)
        out->se[o->kidx[k]] = sez[k];
    if (cov) {
        const size_t P = (size_t)o->P;
        for (size_t e = 0; e < P * P; e++)
            cov[e] = 0.0;
        for (int a = 0; a < nz; a++)
            for (int b = 0; b < nz; b++)
                cov[(size_t)o->kidx[a] * P + (size_t)o->kidx[b]] = covz[(size_t)a * nz + (size_t)b];
    }
done:
    free(covz);
    free(sez);
    free(work);
    free(idx);
    return rc;
}

/* The pass behind both: J'J of the plain residuals (no loss) with respect to the model
 * parameters, their sum of squares (*wssr), and the metrics' sums when sums is not NULL;
 * the standard errors (and what else out wants) from them. */
static bf_status final_pass(const bf_objective *o, const double *x, const bf_final_want *want, bf_metric_sums *sums,
                            const bf_final_out *out, double *wssr, bf_error *err)
{
    bf_status rc = bf_model_check(o->model, x, err);
    if (rc)
        return rc;
    const int nz = o->nz;
    for (int k = 0; k < o->P; k++)
        out->se[k] = 0.0;
    if (nz == 0 && !sums)
        return BF_OK;
    *wssr = NAN;
    double *ones = calloc((size_t)nz + 1, sizeof *ones);
    double *jtj = calloc((size_t)nz * nz + 1, sizeof *jtj);
    double ssr = 0.0;
    if (!ones || !jtj) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for standard errors");
        goto done;
    }
    for (int k = 0; k < nz; k++)
        ones[k] = 1.0;
    const bf_obj_pass req = {NULL, o->threads, {nz, o->kidx, ones}, want->weighted};
    if (bf_obj_normal_x(o, x, &req, &(bf_obj_pass_out){&ssr, NULL, nz ? jtj : NULL, sums})) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for standard errors");
        goto done;
    }
    if (nz > 0)
        rc = stderr_from(o, jtj, ssr, want, out, err);
    *wssr = ssr;
done:
    free(ones);
    free(jtj);
    return rc;
}

bf_status bf_objective_stderr(const bf_objective *o, const double *x, double *se, bf_error *err)
{
    double wssr;
    return final_pass(o, x, &(bf_final_want){0}, NULL, &(bf_final_out){NULL, se, NULL, NULL}, &wssr, err);
}

bf_status bf_obj_final(const bf_objective *o, const double *x, const bf_final_want *want, const bf_final_out *out,
                       bf_error *err)
{
    bf_metric_sums sums;
    double wssr = NAN;
    bf_status rc = final_pass(o, x, want, &sums, out, &wssr, err);
    if (rc == BF_OK)
        rc = bf_metric_sums_finish(&sums, want->k, want->weighted && o->samples->scene_weight, out->metrics, err);
    if (rc == BF_OK)
        bf_metrics_criteria(out->metrics, o->npos, want->k, wssr, o->sum_log_w);
    return rc;
}
