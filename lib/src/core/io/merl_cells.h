/* Internal: MERL table cell arithmetic, shared by the reader and writer (io/merl.c), the
 * geometry of cell-addressed sample sets (geometry.c), their directions in degrees
 * (samples.c) and the stratified subsample (samples_prep.c).
 *
 * Cell (i, j, k) = (theta_h, theta_d, phi_d) has index k + j*180 + i*180*90 and stands
 * for the direction pair at its centre: theta_h = ((i + 0.5)/90)^2 pi/2, theta_d =
 * (j + 0.5)/90 pi/2, phi_d = (k + 0.5)/180 pi, phi_h = 0. In MERL's own half/difference
 * convention (std_coords_to_half_diff_coords in BRDFRead.cpp) the difference vector D is
 * L rotated by -theta_h about the binormal Y, so with phi_h = 0:
 *   L = Ry(theta_h) D,  V = Ry(theta_h) (-Dx, -Dy, Dz),  H = Ry(theta_h) N,
 * i.e. V is L mirrored about H, and V.H = cos theta_d exactly. */
#ifndef BF_MERL_CELLS_H
#define BF_MERL_CELLS_H

#include <math.h>
#include <stdint.h>

#include "brdfit/samples.h"

/* Sines and cosines of the centre angles per bin index, computed once per process
 * (thread-safe), so a whole table costs 360 sin/cos pairs. */
typedef struct bf_merl_trig {
    double sth[BF_MERL_TH], cth[BF_MERL_TH];
    double std_[BF_MERL_TD], ctd[BF_MERL_TD];
    double spd[BF_MERL_PD], cpd[BF_MERL_PD];
} bf_merl_trig;

const bf_merl_trig *bf_merl_trig_get(void);

/* Centre angles in radians of bin i (theta_h, non-linear), j (theta_d), k (phi_d). */
double bf_merl_centre_theta_h(int i);
double bf_merl_centre_theta_d(int j);
double bf_merl_centre_phi_d(int k);

static inline void bf_merl_cell_split(int32_t cell, int *i, int *j, int *k)
{
    *k = cell % BF_MERL_PD;
    *j = cell / BF_MERL_PD % BF_MERL_TD;
    *i = cell / (BF_MERL_PD * BF_MERL_TD);
}

/* L and V of a cell centre from the sines and cosines of its theta_h (sth, cth),
 * theta_d (std_, ctd) and phi_d (spd, cpd). H = (sth, 0, cth) and V.H = ctd. A z
 * component within 1e-15 of zero is set to 0 (on the horizon), as
 * bf_geometry_from_angles does. */
static inline void bf_merl_centre_lv(double sth, double cth, double std_, double ctd, double spd, double cpd,
                                     double L[3], double V[3])
{
    const double dx = std_ * cpd, dy = std_ * spd, dz = ctd;
    const double lz = dz * cth - dx * sth, vz = dz * cth + dx * sth;
    L[0] = dx * cth + dz * sth;
    L[1] = dy;
    L[2] = fabs(lz) < 1e-15 ? 0.0 : lz;
    V[0] = dz * sth - dx * cth;
    V[1] = -dy;
    V[2] = fabs(vz) < 1e-15 ? 0.0 : vz;
}

/* The unit vectors of a cell centre in the local frame (N = +z): L, V, H, and V.H and
 * sin^2 theta_h without cancellation (bf_merl_centre_lv). */
void bf_merl_cell_vectors(const bf_merl_trig *t, int32_t cell, double L[3], double V[3], double H[3], double *vh,
                          double *sin2h);

/* The directions of a cell centre in degrees: phi_i in (0, 180), phi_o in (180, 360).
 * The same bits as bf_merl_cell_directions. */
void bf_merl_cell_angles(const bf_merl_trig *t, int32_t cell, double *theta_i, double *phi_i, double *theta_o,
                         double *phi_o);

#endif
