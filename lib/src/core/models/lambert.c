/* Lambert: rho_d / pi. The diffuse-only case of the shared lobe driver. */
#include "family.h"

static bf_status configure(bf_model *m, bf_error *err)
{
    m->energy_conserving = 1;
    return bf_model_add_param(m, "rho_d", 1, 0.0, 1.0, 0.5, BF_SCALE_LINEAR, 0, BF_ROLE_DIFFUSE, err);
}

const bf_family bf_family_lambert = {
    .info = {.name = "lambert",
             .summary = "ideal diffuse reflector",
             .reference = "Lambert 1760",
             .options = NULL,
             .lobes = 0,
             .anisotropic = 0},
    .configure = configure,
    .eval = bf_eval_diffuse_lobes, /* diffuse only: no lobe shapes */
};
