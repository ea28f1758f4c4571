/* Sample sets: allocation, channel names, weights, geometry, filtering. */
#include "brdfit/samples.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *default_name(int C, int c, char *buf, size_t size)
{
    static const char *const rgb[3] = {"r", "g", "b"};
    if (C == 1)
        return "value";
    if (C == 3)
        return rgb[c];
    snprintf(buf, size, "c%d", c);
    return buf;
}

bf_samples *bf_samples_new(size_t n, int channels, bf_error *err)
{
    if (channels < 1) {
        bf_fail(err, BF_ERR_ARG, "a sample set needs at least one channel");
        return NULL;
    }
    bf_samples *s = calloc(1, sizeof *s);
    if (!s)
        goto nomem;
    s->n = n;
    s->channels = channels;
    s->channel_names = calloc((size_t)channels, sizeof *s->channel_names);
    /* One block for the four angle arrays; +1 keeps n = 0 allocations valid. */
    s->theta_i = calloc(4 * n + 1, sizeof *s->theta_i);
    s->value = calloc(n * (size_t)channels + 1, sizeof *s->value);
    if (!s->channel_names || !s->theta_i || !s->value)
        goto nomem;
    s->phi_i = s->theta_i + n;
    s->theta_o = s->theta_i + 2 * n;
    s->phi_o = s->theta_i + 3 * n;
    for (int c = 0; c < channels; c++) {
        char buf[16];
        if (!(s->channel_names[c] = strdup(default_name(channels, c, buf, sizeof buf))))
            goto nomem;
    }
    return s;
nomem:
    bf_samples_free(s);
    bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu samples of %d channels", n, channels);
    return NULL;
}

void bf_samples_drop_origin(bf_samples *s)
{
    if (s->merl) {
        free(s->merl->raw);
        free(s->merl->cell);
        free(s->merl);
        s->merl = NULL;
    }
}

void bf_samples_free(bf_samples *s)
{
    if (!s)
        return;
    for (int c = 0; s->channel_names && c < s->channels; c++)
        free(s->channel_names[c]);
    free(s->channel_names);
    free(s->wavelength);
    free(s->theta_i);
    free(s->value);
    free(s->weight);
    free(s->scene_weight);
    bf_samples_drop_origin(s);
    bf_geometry_free(s->geom);
    free(s);
}

int bf_samples_set_channel_name(bf_samples *s, int c, const char *name, bf_error *err)
{
    char *copy = strdup(name);
    if (!copy)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    free(s->channel_names[c]);
    s->channel_names[c] = copy;
    return BF_OK;
}

int bf_samples_add_weights(bf_samples *s, bf_error *err)
{
    if (s->weight)
        return BF_OK;
    if (!(s->weight = malloc((s->n + 1) * sizeof *s->weight)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu weights", s->n);
    for (size_t i = 0; i < s->n; i++)
        s->weight[i] = 1.0;
    return BF_OK;
}

const bf_geometry *bf_samples_geometry(bf_samples *s, bf_error *err)
{
    if (s->geom)
        return s->geom;
    double *rad = malloc((4 * s->n + 1) * sizeof *rad);
    if (!rad) {
        bf_fail(err, BF_ERR_NOMEM, "out of memory for the geometry of %zu samples", s->n);
        return NULL;
    }
    /* The four angle arrays are one block of 4n (bf_samples_new). */
    for (size_t k = 0; k < 4 * s->n; k++)
        rad[k] = s->theta_i[k] * (M_PI / 180.0);
    s->geom = bf_geometry_from_angles(s->n, rad, rad + s->n, rad + 2 * s->n, rad + 3 * s->n, err);
    free(rad);
    return s->geom;
}

int bf_samples_keep(bf_samples *s, const unsigned char *keep, bf_error *err)
{
    (void)err; /* compaction happens in place: nothing to allocate */
    const size_t C = (size_t)s->channels;
    size_t j = 0;
    for (size_t i = 0; i < s->n; i++) {
        if (!keep[i]) {
            if (s->merl) { /* the written table must not bring the sample back */
                int32_t cell = s->merl->cell[i];
                for (int p = 0; p < 3; p++)
                    s->merl->raw[(size_t)p * BF_MERL_CELLS + (size_t)cell] = -1.0;
            }
            continue;
        }
        s->theta_i[j] = s->theta_i[i];
        s->phi_i[j] = s->phi_i[i];
        s->theta_o[j] = s->theta_o[i];
        s->phi_o[j] = s->phi_o[i];
        memmove(s->value + j * C, s->value + i * C, C * sizeof *s->value);
        if (s->weight)
            s->weight[j] = s->weight[i];
        if (s->scene_weight)
            s->scene_weight[j] = s->scene_weight[i];
        if (s->merl)
            s->merl->cell[j] = s->merl->cell[i];
        j++;
    }
    if (j != s->n) {
        /* The angle arrays live in one block of 4n: move the three later ones down. */
        memmove(s->theta_i + j, s->phi_i, j * sizeof *s->theta_i);
        memmove(s->theta_i + 2 * j, s->theta_o, j * sizeof *s->theta_i);
        memmove(s->theta_i + 3 * j, s->phi_o, j * sizeof *s->theta_i);
        s->phi_i = s->theta_i + j;
        s->theta_o = s->theta_i + 2 * j;
        s->phi_o = s->theta_i + 3 * j;
        s->n = j;
        bf_geometry_free(s->geom);
        s->geom = NULL;
    }
    return BF_OK;
}

bf_samples *bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_error *err)
{
    const size_t C = (size_t)s->channels;
    size_t n = 0;
    for (size_t i = 0; i < s->n; i++)
        n += !keep || keep[i];
    bf_samples *o = bf_samples_new(n, s->channels, err);
    if (!o)
        return NULL;
    for (size_t c = 0; c < C; c++)
        if (bf_samples_set_channel_name(o, (int)c, s->channel_names[c], err) != BF_OK)
            goto fail;
    if (s->wavelength) {
        if (!(o->wavelength = malloc(C * sizeof *o->wavelength))) {
            bf_fail(err, BF_ERR_NOMEM, "out of memory copying samples");
            goto fail;
        }
        memcpy(o->wavelength, s->wavelength, C * sizeof *o->wavelength);
    }
    if (s->weight && bf_samples_add_weights(o, err) != BF_OK)
        goto fail;
    if (s->scene_weight && !(o->scene_weight = malloc((n + 1) * sizeof *o->scene_weight))) {
        bf_fail(err, BF_ERR_NOMEM, "out of memory copying samples");
        goto fail;
    }
    size_t j = 0;
    for (size_t i = 0; i < s->n; i++) {
        if (keep && !keep[i])
            continue;
        o->theta_i[j] = s->theta_i[i];
        o->phi_i[j] = s->phi_i[i];
        o->theta_o[j] = s->theta_o[i];
        o->phi_o[j] = s->phi_o[i];
        memcpy(o->value + j * C, s->value + i * C, C * sizeof *o->value);
        if (s->weight)
            o->weight[j] = s->weight[i];
        if (s->scene_weight)
            o->scene_weight[j] = s->scene_weight[i];
        j++;
    }
    return o;
fail:
    bf_samples_free(o);
    return NULL;
}
