/* The lobes of a multi-lobe fit in order, narrowest first (lobe_order.h).
 *
 * A model of K lobes, "rho_d/pi + sum rho_s_k lobe_k", has K! equal optima, one per
 * numbering of its lobes; the search may end in any of them. Lobe k's parameters are the
 * ones whose bf_param_info.lobe is k, in the same order for every k, so renumbering moves
 * blocks of entries. */
#include "lobe_order.h"

#include <stdlib.h>
#include <string.h>

#include "models/lobes.h"

/* Half width at half maximum in theta_h (radians) of lobe k at theta_d = 10 degrees in
 * the plane of incidence; 0 when it does not fall to half within 80 degrees (a broad
 * lobe). */
double bf_fit_lobe_hwhm(const bf_model *m, const double *x, int k)
{
    enum { NT = 120 };
    double th[NT], L[3 * NT], V[3 * NT], S[BF_LOBE_BLOCK];
    const double td = 10.0 * (M_PI / 180.0);
    for (int i = 0; i < NT; i++) {
        th[i] = i == 0 ? 0.0 : 1e-5 * pow(80.0 * (M_PI / 180.0) / 1e-5, (double)(i - 1) / (NT - 2));
        const double c = cos(th[i]), s = sin(th[i]);
        const double d[3] = {sin(td), 0.0, cos(td)};
        L[3 * i] = d[0] * c + d[2] * s, L[3 * i + 1] = 0.0, L[3 * i + 2] = d[2] * c - d[0] * s;
        V[3 * i] = d[2] * s - d[0] * c, V[3 * i + 1] = 0.0, V[3 * i + 2] = d[2] * c + d[0] * s;
    }
    bf_error err;
    bf_geometry *g = NULL;
    if (bf_geometry_from_vectors(NT, L, V, &g, &err) != BF_OK)
        return 0.0;
    bf_model_lobe_shape(m, x, k, g, 0, NT, S, NULL);
    bf_geometry_free(g);
    int p = 0;
    for (int i = 1; i < NT; i++)
        if (S[i] > S[p])
            p = i;
    if (!(S[p] > 0.0))
        return 0.0;
    for (int i = p + 1; i < NT; i++)
        if (S[i] < 0.5 * S[p])
            return th[i];
    return 0.0;
}

/* The entries of lobe k (1-based) in parameter order: their count, into e. */
static int lobe_entries(const bf_model *m, int k, int *e, int max)
{
    const int C = bf_model_channels(m);
    int n = 0;
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        if (p->lobe != k)
            continue;
        const int off = bf_model_param_offset(m, i);
        for (int c = 0; c < (p->color ? C : 1) && n < max; c++)
            e[n++] = off + c;
    }
    return n;
}

void bf_fit_order_lobes(const bf_objective *o, double *x)
{
    const bf_model *m = o->model;
    const int K = bf_model_lobes(m), P = bf_model_nvalues(m);
    if (K < 2 || K > BF_MAX_LOBES)
        return;
    const int *map;
    const bf_model *um = bf_model_untied(m, &map);
    bf_lobe_layout lay;
    if (!bf_model_lobe_layout(um, &lay) || lay.lobes != K)
        return;
    int *e = malloc((size_t)K * (size_t)P * sizeof *e);
    double *xu = malloc(((size_t)bf_model_nvalues(um) + 1) * sizeof *xu), *saved = malloc((size_t)P * sizeof *saved);
    int n = -1;
    for (int k = 1; e && k <= K; k++) {
        int nk = lobe_entries(m, k, e + (size_t)(k - 1) * P, P);
        n = n < 0 || nk == n ? nk : -2;
    }
    if (!e || !xu || !saved || n <= 0)
        goto done;
    /* Interchangeable: the same bounds and fixed values, entry by entry. */
    for (int k = 2; k <= K; k++)
        for (int j = 0; j < n; j++) {
            const int a = e[j], b = e[(size_t)(k - 1) * P + j];
            if (o->lo[a] != o->lo[b] || o->hi[a] != o->hi[b] || o->fixed[a] != o->fixed[b] ||
                (o->fixed[a] && o->fixval[a] != o->fixval[b]))
                goto done;
        }
    for (int k = 0; k < bf_model_nvalues(um); k++)
        xu[k] = x[map ? map[k] : k];
    double w[BF_MAX_LOBES];
    int order[BF_MAX_LOBES];
    for (int k = 0; k < K; k++) {
        w[k] = bf_fit_lobe_hwhm(um, xu, k);
        if (!(w[k] > 0.0))
            w[k] = INFINITY; /* broad, or no peak: last */
        order[k] = k;
    }
    for (int a = 1; a < K; a++) /* insertion sort: stable, K is small */
        for (int b = a; b > 0 && w[order[b]] < w[order[b - 1]]; b--) {
            int t = order[b];
            order[b] = order[b - 1];
            order[b - 1] = t;
        }
    memcpy(saved, x, (size_t)P * sizeof *saved);
    for (int k = 0; k < K; k++)
        for (int j = 0; j < n; j++)
            x[e[(size_t)k * P + j]] = saved[e[(size_t)order[k] * P + j]];
done:
    free(e);
    free(xu);
    free(saved);
}
