/* Internal: a parameter's optimizer scale (bf_scale, model.h) and back, for every
 * solver of the library (the fit's objective, the per-pixel photo solve). */
#ifndef BRDFIT_MODELS_SCALE_H
#define BRDFIT_MODELS_SCALE_H

#include "brdfit/model.h"

/* z of x: x, ln x or ln(1 + x). */
double bf_scale_to_z(bf_scale sc, double x);
/* x of z, the inverse. */
double bf_scale_to_x(bf_scale sc, double z);
/* dx/dz at x. */
double bf_scale_dxdz(bf_scale sc, double x);

#endif
