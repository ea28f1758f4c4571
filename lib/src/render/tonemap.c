/* Display mapping of linear values for 8-bit images (render.h). */
#include <math.h>

#include "brdfit/render.h"

void bf_tonemap(float *v, size_t n, bf_tonemap_mode mode, double exposure, double decades)
{
    if (mode == BF_TONEMAP_LOG) {
        double hi = 0.0;
        for (size_t i = 0; i < n; i++)
            if (v[i] * exposure > hi)
                hi = v[i] * exposure;
        if (!(hi > 0.0) || !(decades > 0.0)) {
            for (size_t i = 0; i < n; i++)
                v[i] = 0.0f;
            return;
        }
        double top = log10(hi), bottom = top - decades;
        for (size_t i = 0; i < n; i++) {
            double e = v[i] * exposure;
            v[i] = e > 0.0 ? (float)fmax(0.0, (log10(e) - bottom) / decades) : 0.0f;
        }
        return;
    }
    for (size_t i = 0; i < n; i++) {
        double e = v[i] * exposure;
        v[i] = (float)(mode == BF_TONEMAP_REINHARD ? (e > 0.0 ? e / (1.0 + e) : 0.0) : e);
    }
}
