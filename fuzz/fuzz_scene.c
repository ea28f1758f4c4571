/* Scene files: the JSON, then the weights of a fixed set of samples and the
 * restriction to the scene. Weights must be finite and >= 0. */
#include "fuzz_common.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/scene.h"

enum { N = 48 };

/* Samples over the hemisphere pair: theta in 0..88 degrees, phi over the circle. */
static bf_samples *samples(void)
{
    bf_error err;
    bf_samples *s = NULL;
    if (bf_samples_new(N, 1, &s, &err) != BF_OK)
        fuzz_fail("samples: %s", err.msg);
    for (size_t i = 0; i < N; i++) {
        s->theta_i[i] = (double)(i * 11 % 89);
        s->phi_i[i] = (double)(i * 37 % 360);
        s->theta_o[i] = (double)(i * 23 % 89);
        s->phi_o[i] = (double)(i * 71 % 360) - 180.0;
        s->value[i] = 0.1;
    }
    return s;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0'; /* the reader's text is NUL-terminated; a NUL inside ends it */
    bf_error err;
    bf_scene *sc = NULL;
    int rc = bf_scene_parse(text, "scene.json", &sc, &err);
    fuzz_check_result(rc, &err, sc);
    /* The file reader too (it refuses NUL bytes itself). */
    bf_scene *sc2 = NULL;
    rc = bf_scene_read(fuzz_write("scene.json", data, size), &sc2, &err);
    fuzz_check_result(rc, &err, sc2);
    bf_scene_free(sc2);
    if (sc) {
        bf_samples *s = samples();
        double w[N];
        if (bf_scene_weights(sc, s, w, &err) != BF_OK)
            fuzz_fail("scene weights: %s", err.msg);
        for (size_t i = 0; i < N; i++)
            if (!(isfinite(w[i]) && w[i] >= 0.0))
                fuzz_fail("sample %zu: scene weight %g", i, w[i]);
        size_t kept = 0;
        rc = bf_scene_apply(sc, s, &kept, &err);
        fuzz_check_result(rc, &err, rc == BF_OK ? s : NULL);
        if (rc == BF_OK && (kept == 0 || kept != s->n))
            fuzz_fail("scene kept %zu of %d samples, the set has %zu", kept, N, s->n);
        bf_samples_free(s);
    }
    bf_scene_free(sc);
    free(text);
    return 0;
}
