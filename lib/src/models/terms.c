#include "terms.h"

#include <stddef.h>

#include "family.h"

const char *const bf_fresnel_values[] = {"schlick", "dielectric", "none", NULL};

bf_status bf_model_add_fresnel_param(bf_model *m, int kind, int lobe, bf_error *err)
{
    if (kind == BF_FRESNEL_SCHLICK)
        return bf_model_add_param(m, "f0", 0, 0.0, 1.0, 0.04, BF_SCALE_LINEAR, lobe, BF_ROLE_F0, err);
    if (kind == BF_FRESNEL_DIELECTRIC)
        return bf_model_add_param(m, "ior", 0, 1.0, 3.0, 1.5, BF_SCALE_LINEAR, lobe, BF_ROLE_IOR, err);
    return BF_OK;
}
