/* Solid-angle weights for samples read from a MERL table.
 *
 * A MERL cell (i, j, k) covers a box in Rusinkiewicz's half/difference angles
 * (theta_h, theta_d, phi_d) (S. Rusinkiewicz, "A New Change of Variables for Efficient
 * BRDF Representation", EGWR 1998), and the boxes are far from equal in the measure that
 * matters, d omega_i d omega_o. That measure in these coordinates:
 *   - for fixed omega_i, omega_o = 2 (omega_i.h) h - omega_i is the reflection of omega_i
 *     about h, and d omega_o = 4 (omega_i.h) d omega_h = 4 cos(theta_d) d omega_h (the
 *     usual half-vector Jacobian, e.g. Walter et al. 2007, eq. 14);
 *   - omega_d is omega_i expressed in a frame rotated with h, a rotation for fixed h, so
 *     the map (h, omega_d) -> (h, omega_i) is triangular with unit determinant:
 *     d omega_h d omega_i = d omega_h d omega_d.
 * Hence d omega_i d omega_o = 4 cos(theta_d) d omega_h d omega_d
 *                            = 4 cos(theta_d) sin(theta_h) sin(theta_d)
 *                              d theta_h d phi_h d theta_d d phi_d.
 * MERL tables are isotropic (phi_h integrated out: a constant 2 pi) and fold phi_d + pi
 * onto phi_d (a constant 2), and phi_d cells are uniform, so a cell's weight is, up to a
 * constant,
 *   integral over [th0, th1] of sin(theta_h)                 = cos th0 - cos th1
 *   times integral over [td0, td1] of cos(t) sin(t) dt       = (sin^2 td1 - sin^2 td0) / 2
 * with the cell's actual edges: theta_h edges (i/90)^2 pi/2 (the table's non-uniform
 * spacing, cells narrow near the normal), theta_d edges j/90 pi/2. The differences are
 * written as products of sines (exact identities) to keep precision in the tiny cells
 * near theta_h = 0. The weights are scaled to mean 1 over the samples above the horizon
 * (the only ones that contribute), so weighted and unweighted costs are comparable. */
#include <math.h>
#include <stdlib.h>

#include "objective_state.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static double theta_h_edge(int i)
{
    double t = (double)i / BF_MERL_TH;
    return t * t * (M_PI / 2);
}

static double theta_d_edge(int j)
{
    return (double)j / BF_MERL_TD * (M_PI / 2);
}

bf_status bf_obj_solid_angle_weights(bf_samples *s, const bf_geometry *g, double *w, bf_error *err)
{
    if (!s->merl || !s->merl->cell)
        return bf_fail(err, BF_ERR_ARG, "solid-angle weights need MERL data (this sample set has no MERL cells)");
    double sum = 0.0;
    size_t nvalid = 0;
    for (size_t n = 0; n < s->n; n++) {
        int32_t cell = s->merl->cell[n];
        if (cell < 0 || cell >= BF_MERL_CELLS)
            return bf_fail(err, BF_ERR_ARG, "solid-angle weights: sample %zu has no MERL cell", n);
        int i = cell / (BF_MERL_PD * BF_MERL_TD), j = (cell / BF_MERL_PD) % BF_MERL_TD;
        double h0 = theta_h_edge(i), h1 = theta_h_edge(i + 1);
        double d0 = theta_d_edge(j), d1 = theta_d_edge(j + 1);
        double wh = 2.0 * sin(0.5 * (h0 + h1)) * sin(0.5 * (h1 - h0)); /* cos h0 - cos h1 */
        double wd = 0.5 * sin(d1 + d0) * sin(d1 - d0);                 /* (sin^2 d1 - sin^2 d0)/2 */
        w[n] = wh * wd;
        if (bf_geometry_valid_at(g, n)) {
            sum += w[n];
            nvalid++;
        }
    }
    if (nvalid > 0 && sum > 0.0) {
        double scale = (double)nvalid / sum;
        for (size_t n = 0; n < s->n; n++)
            w[n] *= scale;
    }
    return BF_OK;
}
