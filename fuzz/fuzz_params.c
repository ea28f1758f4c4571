/* Parameter and result files as brdfit eval --params reads them: the JSON, the model
 * built from "model" and "options" (mono= ties, lobes), "channels", every parameter.
 * What reads is evaluated with gradients at a few direction pairs, written back as a
 * fit result file and read again: the same model spec and the same values. */
#include "fuzz_common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/fit.h"
#include "brdfit/io.h"
#include "brdfit/model.h"

/* Four direction pairs in radians: normal, off-specular, grazing, below the horizon. */
static const double ti[4] = {0.0, 0.5, 1.5, 1.7}, pi_[4] = {0.0, 0.3, 1.0, 0.0};
static const double to[4] = {0.0, 0.6, 1.4, 0.2}, po[4] = {0.0, 3.4, 4.0, 3.1};

static void evaluate(const bf_model *m, const double *x)
{
    bf_error err;
    bf_geometry *g = NULL;
    if (bf_geometry_from_angles(4, ti, pi_, to, po, &g, &err) != BF_OK)
        fuzz_fail("geometry: %s", err.msg);
    const size_t C = (size_t)bf_model_channels(m), P = (size_t)bf_model_nvalues(m);
    /* The Jacobian is C x P per sample: up to 10,000 x 640,000; only the smaller ones. */
    double *v = malloc(4 * C * sizeof *v), *grad = C * P <= 1000000 ? malloc(4 * C * P * sizeof *grad) : NULL;
    if (!v || (!grad && C * P <= 1000000))
        fuzz_fail("out of memory for %zu channels x %zu parameters", C, P);
    bf_model_eval(m, x, g, v, grad);
    free(v);
    free(grad);
    bf_geometry_free(g);
}

static void round_trip(bf_model *m, double *x)
{
    const int P = bf_model_nvalues(m);
    bf_fit_result r;
    bf_fit_result_init(&r);
    r.model = m;
    r.x = x;
    r.stderr_ = calloc((size_t)P, sizeof *r.stderr_);
    r.fixed = calloc((size_t)P, 1);
    if (!r.stderr_ || !r.fixed)
        fuzz_fail("out of memory for %d parameters", P);
    r.ok = 1;
    bf_error err;
    const char *path = fuzz_path("result.json");
    if (bf_fit_write_json(&r, NULL, path, &err) != BF_OK)
        fuzz_fail("writing the result: %s", err.msg);
    bf_model *m2 = NULL;
    double *x2 = NULL;
    if (bf_params_read(path, &m2, &x2, &err) != BF_OK)
        fuzz_fail("reading back the result written for %s: %s", bf_model_spec(m), err.msg);
    if (strcmp(bf_model_spec(m), bf_model_spec(m2)) != 0 || bf_model_channels(m) != bf_model_channels(m2) ||
        bf_model_nvalues(m2) != P)
        fuzz_fail("model %s (%d channels) read back as %s (%d)", bf_model_spec(m), bf_model_channels(m),
                  bf_model_spec(m2), bf_model_channels(m2));
    for (int k = 0; k < P; k++)
        if (x[k] != x2[k])
            fuzz_fail("%s: entry %d: %.17g read back as %.17g", bf_model_spec(m), k, x[k], x2[k]);
    bf_model_free(m2);
    free(x2);
    free(r.stderr_);
    free(r.fixed);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write("params.json", data, size);
    bf_error err;
    bf_model *m = NULL;
    double *x = NULL;
    int rc = bf_params_read(path, &m, &x, &err);
    fuzz_check_result(rc, &err, m);
    if (m) {
        if (!x)
            fuzz_fail("a model without values");
        if (bf_model_check(m, x, &err) != BF_OK)
            fuzz_fail("values read are outside the model's bounds: %s", err.msg);
        evaluate(m, x);
        round_trip(m, x);
    }
    bf_model_free(m);
    free(x);
    return 0;
}
