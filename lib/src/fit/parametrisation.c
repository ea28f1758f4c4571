/* The internal parametrisation: each free entry of the model vector is searched in the
 * scale its parameter table suggests, so that one optimizer step means the same for a
 * Phong exponent of 1e4 as for a roughness of 0.01:
 *   LINEAR  z = x
 *   LOG     z = ln x        (lower bound > 0)
 *   LOG1P   z = ln(1 + x)   (lower bound >= 0)
 * A LOG entry whose effective lower bound is not positive falls back to LOG1P (bound 0)
 * or LINEAR (bound < 0), and a LOG1P one with a negative bound to LINEAR: the log would
 * not cover the range. (Overrides may only narrow the model's bounds, and every LOG
 * parameter of the tables has a positive bound, so the fallback guards future tables.)
 * Internal bounds are the transformed effective bounds. */
#include <math.h>

#include "objective_state.h"

void bf_obj_setup_scale(bf_objective *o)
{
    const bf_model *m = o->model;
    int np = bf_model_nparams(m);
    o->nz = 0;
    for (int i = 0; i < np; i++) {
        const bf_param_info *p = bf_model_param(m, i);
        int off = bf_model_param_offset(m, i), cnt = p->color ? o->C : 1;
        for (int c = 0; c < cnt; c++) {
            int k = off + c;
            bf_scale sc = p->scale;
            if (sc == BF_SCALE_LOG && !(o->lo[k] > 0.0))
                sc = o->lo[k] == 0.0 ? BF_SCALE_LOG1P : BF_SCALE_LINEAR;
            if (sc == BF_SCALE_LOG1P && !(o->lo[k] >= 0.0))
                sc = BF_SCALE_LINEAR;
            o->scale[k] = sc;
            if (o->fixed[k]) {
                o->zpos[k] = -1;
                continue;
            }
            int j = o->nz++;
            o->zpos[k] = j;
            o->kidx[j] = k;
            o->zlo[j] = bf_scale_to_z(sc, o->lo[k]);
            o->zhi[j] = bf_scale_to_z(sc, o->hi[k]);
        }
    }
}

static double clamp(double v, double lo, double hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

void bf_objective_to_internal(const bf_objective *o, const double *x, double *z)
{
    for (int j = 0; j < o->nz; j++) {
        int k = o->kidx[j];
        double v = isnan(x[k]) ? o->lo[k] : clamp(x[k], o->lo[k], o->hi[k]);
        z[j] = bf_scale_to_z(o->scale[k], v);
    }
}

void bf_objective_to_model(const bf_objective *o, const double *z, double *x)
{
    for (int k = 0; k < o->P; k++) {
        if (o->fixed[k]) {
            x[k] = o->fixval[k];
            continue;
        }
        /* exp(ln hi) may round just past hi: clamp, so x always passes bf_model_check. */
        x[k] = clamp(bf_scale_to_x(o->scale[k], z[o->zpos[k]]), o->lo[k], o->hi[k]);
    }
}
