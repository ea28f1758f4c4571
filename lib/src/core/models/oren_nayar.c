/* Oren & Nayar 1994, qualitative model:
 *   f = rho_d/pi (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta)),
 *   A = 1 - sigma^2/(2(sigma^2 + 0.33)), B = 0.45 sigma^2/(sigma^2 + 0.09),
 *   alpha = max(theta_i, theta_o), beta = min(theta_i, theta_o).
 * From the vectors: cos(phi_i - phi_o) sin(theta_i) sin(theta_o) = Lx Vx + Ly Vy, and
 * since beta is the angle with the larger cosine, sin(alpha) tan(beta) =
 * sin(theta_i) sin(theta_o) / max(NL, NV). Hence
 *   max(0, cos dphi) sin(alpha) tan(beta) = max(0, Lx Vx + Ly Vy) / max(NL, NV),
 * which is 0 (not 0/0) at theta = 0 and finite for every valid sample.
 * Own evaluator: f = rho_d_c * shape(sigma), one scalar shared by all channels.
 * Not energy conserving: A + B/2 exceeds 1 for small sigma (max about 1.015 near
 * sigma = 0.2), so the albedo at grazing incidence exceeds rho_d slightly. */
#include "family.h"
#include "terms.h"

#include <string.h>

static void eval(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                 double *grad)
{
    const int C = m->channels, P = m->nfree;
    const double *rho_d = x + m->offset[0];
    const int o_d = m->offset[0], o_sig = m->offset[1];
    const double sig = x[o_sig], s2 = sig * sig;
    const double qa = s2 + 0.33, qb = s2 + 0.09;
    const double A = 1.0 - s2 / (2.0 * qa), B = 0.45 * s2 / qb;
    const double dA = -0.33 * sig / (qa * qa), dB = 0.081 * sig / (qb * qb);

    for (size_t i = i0; i < i1; i++) {
        double *row0 = grad ? grad + (i - i0) * (size_t)C * (size_t)P : NULL;
        if (row0)
            memset(row0, 0, (size_t)C * (size_t)P * sizeof *row0);
        double nl = g->lz[i], nv = g->vz[i];
        double shape = 0.0, dshape = 0.0;
        if (nl > 0.0 && nv > 0.0) {
            double c = g->lx[i] * g->vx[i] + g->ly[i] * g->vy[i];
            double t = c > 0.0 ? c / (nl > nv ? nl : nv) : 0.0;
            shape = (A + B * t) * (1.0 / M_PI);
            dshape = (dA + dB * t) * (1.0 / M_PI);
        }
        for (int c = 0; c < C; c++) {
            values[(i - i0) * (size_t)C + (size_t)c] = rho_d[c] * shape;
            if (row0) {
                double *row = row0 + (size_t)c * (size_t)P;
                row[o_d + c] = shape;
                row[o_sig] = rho_d[c] * dshape;
            }
        }
    }
}

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 0; /* see above: albedo up to about 1.015 rho_d */
    bf_status rc;
    if ((rc = bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err)) ||
        (rc = bf_model_add_param(m, "sigma", 0, 0.0, M_PI / 2.0, 0.3, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE_SHAPE, err)))
        return rc;
    return BF_OK;
}

const bf_family bf_family_oren_nayar = {
    .info = {.name = "oren_nayar",
             .summary = "Oren-Nayar rough diffuse (qualitative model)",
             .reference = "Oren & Nayar 1994",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = eval,
};
