/* Residual form names (the forms themselves are inline in objective_state.h). */
#include <string.h>

#include "objective_state.h"

static const char *const residual_names[] = {"linear", "cosine", "log", "cbrt", "relative"};
#define NFORMS ((int)(sizeof residual_names / sizeof residual_names[0]))

bf_status bf_residual_parse(const char *name, bf_residual *out, bf_error *err)
{
    for (int i = 0; name && i < NFORMS; i++)
        if (strcmp(name, residual_names[i]) == 0) {
            *out = (bf_residual)i;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "unknown residual form '%s' (linear, cosine, log, cbrt, relative)",
                   name ? name : "");
}

const char *bf_residual_name(bf_residual r)
{
    return ((int)r >= 0 && (int)r < NFORMS) ? residual_names[r] : "unknown";
}
