/* The optimizer's scale of a parameter (bf_scale, model.h): z = x, ln x or ln(1 + x),
 * so that one step means the same for a Phong exponent of 1e4 as for a roughness of
 * 0.01. */
#include "models/scale.h"

#include <math.h>

double bf_scale_to_z(bf_scale sc, double x)
{
    switch (sc) {
    case BF_SCALE_LOG: return log(x);
    case BF_SCALE_LOG1P: return log1p(x);
    default: return x;
    }
}

double bf_scale_to_x(bf_scale sc, double z)
{
    switch (sc) {
    case BF_SCALE_LOG: return exp(z);
    case BF_SCALE_LOG1P: return expm1(z);
    default: return z;
    }
}

double bf_scale_dxdz(bf_scale sc, double x)
{
    switch (sc) {
    case BF_SCALE_LOG: return x;         /* d e^z / dz = e^z = x */
    case BF_SCALE_LOG1P: return 1.0 + x; /* d (e^z - 1) / dz = e^z = 1 + x */
    default: return 1.0;
    }
}
