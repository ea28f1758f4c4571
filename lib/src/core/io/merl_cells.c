/* MERL table cell arithmetic (merl_cells.h): centre angles, vectors and directions of a
 * cell, and the cell of a direction pair. */
#include "merl_cells.h"

#include <math.h>
#include <pthread.h>

double bf_merl_centre_theta_h(int i)
{
    double u = (i + 0.5) / BF_MERL_TH;
    return u * u * (M_PI / 2);
}
double bf_merl_centre_theta_d(int j)
{
    return (j + 0.5) / BF_MERL_TD * (M_PI / 2);
}
double bf_merl_centre_phi_d(int k)
{
    return (k + 0.5) / BF_MERL_PD * M_PI;
}

static bf_merl_trig trig;
static pthread_once_t trig_once = PTHREAD_ONCE_INIT;

static void trig_init(void)
{
    for (int i = 0; i < BF_MERL_TH; i++) {
        trig.sth[i] = sin(bf_merl_centre_theta_h(i));
        trig.cth[i] = cos(bf_merl_centre_theta_h(i));
    }
    for (int j = 0; j < BF_MERL_TD; j++) {
        trig.std_[j] = sin(bf_merl_centre_theta_d(j));
        trig.ctd[j] = cos(bf_merl_centre_theta_d(j));
    }
    for (int k = 0; k < BF_MERL_PD; k++) {
        trig.spd[k] = sin(bf_merl_centre_phi_d(k));
        trig.cpd[k] = cos(bf_merl_centre_phi_d(k));
    }
}

const bf_merl_trig *bf_merl_trig_get(void)
{
    pthread_once(&trig_once, trig_init);
    return &trig;
}

void bf_merl_cell_vectors(const bf_merl_trig *t, int32_t cell, double L[3], double V[3], double H[3], double *vh,
                          double *sin2h)
{
    int i, j, k;
    bf_merl_cell_split(cell, &i, &j, &k);
    bf_merl_centre_lv(t->sth[i], t->cth[i], t->std_[j], t->ctd[j], t->spd[k], t->cpd[k], L, V);
    H[0] = t->sth[i];
    H[1] = 0.0;
    H[2] = t->cth[i];
    *vh = t->ctd[j];
    *sin2h = t->sth[i] * t->sth[i];
}

/* Directions in degrees from the centre's sines and cosines. theta by atan2 rather than
 * acos keeps full precision near the pole; phi_i lies in (0, 180) and phi_o in
 * (180, 360) because phi_d is in (0, pi). */
void bf_merl_cell_angles(const bf_merl_trig *t, int32_t cell, double *ti, double *pi_, double *to, double *po)
{
    int i, j, k;
    bf_merl_cell_split(cell, &i, &j, &k);
    const double r2d = 180.0 / M_PI, sth = t->sth[i], cth = t->cth[i];
    double dx = t->std_[j] * t->cpd[k], dy = t->std_[j] * t->spd[k], dz = t->ctd[j];
    double lx = dx * cth + dz * sth, lz = dz * cth - dx * sth;
    double vx = dz * sth - dx * cth, vz = dz * cth + dx * sth;
    double pxy_l = sqrt(lx * lx + dy * dy), pxy_v = sqrt(vx * vx + dy * dy);
    *ti = atan2(pxy_l, lz) * r2d;
    *pi_ = atan2(dy, lx) * r2d;
    *to = atan2(pxy_v, vz) * r2d;
    *po = (atan2(-dy, vx) + 2 * M_PI) * r2d;
}

void bf_merl_cell_directions(int32_t cell, double *theta_i, double *phi_i, double *theta_o, double *phi_o)
{
    bf_merl_cell_angles(bf_merl_trig_get(), cell, theta_i, phi_i, theta_o, phi_o);
}

int32_t bf_merl_cell_of(double theta_i, double phi_i, double theta_o, double phi_o)
{
    const double d2r = M_PI / 180.0, tol = 1e-9;
    if (!isfinite(theta_i) || !isfinite(phi_i) || !isfinite(theta_o) || !isfinite(phi_o))
        return -1;
    double ti = theta_i * d2r, pi_ = phi_i * d2r, to = theta_o * d2r, po = phi_o * d2r;
    double L[3] = {sin(ti) * cos(pi_), sin(ti) * sin(pi_), cos(ti)};
    double V[3] = {sin(to) * cos(po), sin(to) * sin(po), cos(to)};
    double H[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    double hxy = sqrt(H[0] * H[0] + H[1] * H[1]);
    if (hxy == 0.0)
        return -1; /* theta_h = 0 (or L = -V): no cell centre */
    /* MERL's std_coords_to_half_diff_coords: D = Ry(-theta_h) Rz(-phi_h) L. */
    double th = atan2(hxy, H[2]), ph = atan2(H[1], H[0]);
    double cph = cos(ph), sph = sin(ph), cth = cos(th), sth = sin(th);
    double tx = cph * L[0] + sph * L[1], ty = cph * L[1] - sph * L[0], tz = L[2];
    double dx = tx * cth - tz * sth, dy = ty, dz = tx * sth + tz * cth;
    double td = atan2(sqrt(dx * dx + dy * dy), dz), pd = atan2(dy, dx);
    if (pd < 0.0) /* reciprocity: phi_d and phi_d + pi are the same cell */
        pd += M_PI;
    if (pd >= M_PI)
        pd -= M_PI;
    /* MERL's lookup bins (floor), then the centre of that bin must match. */
    double fi = floor(sqrt(th / (M_PI / 2)) * BF_MERL_TH);
    double fj = floor(td / (M_PI / 2) * BF_MERL_TD), fk = floor(pd / M_PI * BF_MERL_PD);
    if (!(fi >= 0 && fi < BF_MERL_TH && fj >= 0 && fj < BF_MERL_TD && fk >= 0 && fk < BF_MERL_PD))
        return -1;
    int i = (int)fi, j = (int)fj, k = (int)fk;
    /* phi_d is measured from the plane of N and H, whose azimuth phi_h is only as
     * precise as (L + V)_xy: near normal H with L and V near grazing (|(L + V)_xy| down to
     * 8.5e-7 at theta_h bin 0, theta_d bin 89) the directions' own rounding (about 1e-15)
     * moves phi_d by more than 1e-9. Its tolerance grows accordingly, which still is far
     * below the bin width (pi/180) and amounts to directions within 1e-14 of the centre. */
    double tol_pd = tol + 1e-14 / hxy;
    if (fabs(th - bf_merl_centre_theta_h(i)) > tol || fabs(td - bf_merl_centre_theta_d(j)) > tol ||
        fabs(pd - bf_merl_centre_phi_d(k)) > tol_pd)
        return -1;
    return (int32_t)(k + BF_MERL_PD * (j + BF_MERL_TD * i));
}
