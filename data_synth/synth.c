/* The whole generation: pattern, model values, noise. */
#include "synth.h"

bf_status bf_synth_generate(const bf_model *m, const double *x, const bf_synth_options *o, bf_samples **out,
                            bf_error *err)
{
    *out = NULL;
    const int C = bf_model_channels(m);
    if (o->pattern == BF_SYNTH_MERL && C != 3)
        return bf_fail(err, BF_ERR_ARG, "pattern merl needs a 3-channel (RGB) model, this one has %d", C);
    int rc = bf_model_check(m, x, err);
    if (rc != BF_OK || (rc = bf_synth_noise_check(&o->noise, err)) != BF_OK)
        return rc;

    /* Two streams from one seed: the directions do not depend on the noise settings. */
    bf_synth_rng dir_rng, noise_rng;
    bf_synth_rng_seed(&dir_rng, o->seed);
    noise_rng = dir_rng;
    bf_synth_rng_jump(&noise_rng);

    bf_samples *s;
    if ((rc = bf_synth_directions(o->pattern, o->count, &o->gonio, &dir_rng, C, &s, err)) != BF_OK)
        return rc;
    const bf_geometry *g;
    if ((rc = bf_samples_geometry(s, &g, err)) != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    bf_model_eval(m, x, g, s->value, NULL);

    bf_synth_noise nz = o->noise;
    if (o->pattern == BF_SYNTH_MERL)
        nz.clamp = 1; /* a negative value would mark the cell invalid */
    if ((rc = bf_synth_noise_apply(s, &nz, &noise_rng, err)) != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}
