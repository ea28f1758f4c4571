/* Reading an export material, as every writer does (export_impl.h): a parameter's value
 * per channel, and the note on how well the conversion held. */
#include <stdio.h>

#include "brdfit/model.h"
#include "export_impl.h"

double bf_export_param(const bf_export_material *e, const char *name, int c)
{
    int i = bf_model_find_param(e->model, name);
    const bf_param_info *p = bf_model_param(e->model, i);
    int off = bf_model_param_offset(e->model, i);
    return p->color && bf_model_channels(e->model) > 1 ? e->x[off + c] : e->x[off];
}

void bf_export_conversion_note(const bf_export_material *e, FILE *fp)
{
    fprintf(fp,
            "conversion over %zu direction pairs: rmse %.6g, rmse_cos %.6g, rmse_log %.6g, rmse_rel %.6g, "
            "max_err %.6g (1/sr)",
            e->directions, e->metrics.rmse, e->metrics.rmse_cos, e->metrics.rmse_log, e->metrics.rmse_rel,
            e->metrics.max_err);
}
