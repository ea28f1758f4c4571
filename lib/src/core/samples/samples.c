/* Sample sets: allocation, channel names, weights, directions, geometry, filtering. */
#include "brdfit/samples.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/big_alloc.h"
#include "io/merl_cells.h"

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

/* The parts every sample set has: channel names and values. */
static bf_status new_common(size_t n, int channels, bf_samples **out, bf_error *err)
{
    *out = NULL;
    if (channels < 1 || channels > BF_MAX_CHANNELS)
        return bf_fail(err, BF_ERR_ARG, "a sample set has 1 to %d channels, not %d", BF_MAX_CHANNELS, channels);
    /* The sizes below (n * C values, 4 n angles) must not wrap around. */
    if (n > SIZE_MAX / sizeof(double) / ((size_t)channels + 4))
        return bf_fail(err, BF_ERR_NOMEM, "%zu samples of %d channels are too many", n, channels);
    bf_samples *s = calloc(1, sizeof *s);
    if (!s)
        goto nomem;
    s->n = n;
    s->channels = channels;
    s->channel_names = calloc((size_t)channels, sizeof *s->channel_names);
    s->value = bf_big_calloc(n * (size_t)channels + 1, sizeof *s->value);
    if (!s->channel_names || !s->value)
        goto nomem;
    for (int c = 0; c < channels; c++) {
        char buf[16];
        if (!(s->channel_names[c] = strdup(default_name(channels, c, buf, sizeof buf))))
            goto nomem;
    }
    *out = s;
    return BF_OK;
nomem:
    bf_samples_free(s);
    return bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu samples of %d channels", n, channels);
}

bf_status bf_samples_new(size_t n, int channels, bf_samples **out, bf_error *err)
{
    *out = NULL;
    bf_samples *s;
    bf_status rc = new_common(n, channels, &s, err);
    if (rc != BF_OK)
        return rc;
    /* One block for the four angle arrays; +1 keeps n = 0 allocations valid. */
    if (!(s->theta_i = bf_big_calloc(4 * n + 1, sizeof *s->theta_i))) {
        bf_samples_free(s);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu samples of %d channels", n, channels);
    }
    s->phi_i = s->theta_i + n;
    s->theta_o = s->theta_i + 2 * n;
    s->phi_o = s->theta_i + 3 * n;
    *out = s;
    return BF_OK;
}

bf_status bf_samples_new_cells(size_t n, int channels, bf_samples **out, bf_error *err)
{
    *out = NULL;
    bf_samples *s;
    bf_status rc = new_common(n, channels, &s, err);
    if (rc != BF_OK)
        return rc;
    if (!(s->merl = calloc(1, sizeof *s->merl)) || !(s->merl->cell = bf_big_calloc(n + 1, sizeof *s->merl->cell))) {
        bf_samples_free(s);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu samples of %d channels", n, channels);
    }
    *out = s;
    return BF_OK;
}

void bf_samples_drop_origin(bf_samples *s)
{
    if (s->merl) {
        free(s->merl->raw);
        s->merl->raw = NULL;
    }
}

void bf_samples_angle_block(const bf_samples *s, size_t i0, size_t cnt, double *buf, const double *dir[4])
{
    if (s->theta_i) {
        dir[0] = s->theta_i + i0;
        dir[1] = s->phi_i + i0;
        dir[2] = s->theta_o + i0;
        dir[3] = s->phi_o + i0;
        return;
    }
    const bf_merl_trig *t = bf_merl_trig_get();
    double *ti = buf, *pi_ = buf + cnt, *to = buf + 2 * cnt, *po = buf + 3 * cnt;
    for (size_t j = 0; j < cnt; j++)
        bf_merl_cell_angles(t, s->merl->cell[i0 + j], &ti[j], &pi_[j], &to[j], &po[j]);
    dir[0] = ti, dir[1] = pi_, dir[2] = to, dir[3] = po;
}

void bf_samples_direction(const bf_samples *s, size_t i, double dir[4])
{
    const double *d[4];
    bf_samples_angle_block(s, i, 1, dir, d);
    for (int k = 0; k < 4; k++)
        dir[k] = d[k][0];
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
    if (s->merl) {
        free(s->merl->raw);
        free(s->merl->cell);
        free(s->merl);
    }
    bf_geometry_free(s->geom);
    free(s);
}

bf_status bf_samples_set_channel_name(bf_samples *s, int c, const char *name, bf_error *err)
{
    char *copy = strdup(name);
    if (!copy)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    free(s->channel_names[c]);
    s->channel_names[c] = copy;
    return BF_OK;
}

bf_status bf_samples_add_weights(bf_samples *s, bf_error *err)
{
    if (s->weight)
        return BF_OK;
    if (!(s->weight = bf_big_malloc((s->n + 1) * sizeof *s->weight)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu weights", s->n);
    for (size_t i = 0; i < s->n; i++)
        s->weight[i] = 1.0;
    return BF_OK;
}

bf_status bf_samples_geometry(bf_samples *s, const bf_geometry **out, bf_error *err)
{
    bf_status rc = BF_OK;
    if (!s->geom && !s->theta_i) {
        rc = bf_geometry_from_merl_cells(s->n, s->merl->cell, &s->geom, err);
    } else if (!s->geom) {
        double *rad = bf_big_malloc((4 * s->n + 1) * sizeof *rad);
        if (!rad) {
            *out = NULL;
            return bf_fail(err, BF_ERR_NOMEM, "out of memory for the geometry of %zu samples", s->n);
        }
        /* Each array by its own pointer: a caller that lowered n after bf_samples_new
         * leaves them apart by the old n. */
        const double *deg[4] = {s->theta_i, s->phi_i, s->theta_o, s->phi_o};
        for (size_t a = 0; a < 4; a++)
            for (size_t k = 0; k < s->n; k++)
                rad[a * s->n + k] = deg[a][k] * (M_PI / 180.0);
        rc = bf_geometry_from_angles(s->n, rad, rad + s->n, rad + 2 * s->n, rad + 3 * s->n, &s->geom, err);
        free(rad);
    }
    *out = s->geom;
    return rc;
}

bf_status bf_samples_keep(bf_samples *s, const unsigned char *keep, bf_error *err)
{
    (void)err; /* compaction happens in place: nothing to allocate */
    const size_t C = (size_t)s->channels;
    size_t j = 0;
    for (size_t i = 0; i < s->n; i++) {
        if (!keep[i]) {
            if (s->merl && s->merl->raw) { /* the written table must not bring the sample back */
                int32_t cell = s->merl->cell[i];
                for (int p = 0; p < 3; p++)
                    s->merl->raw[(size_t)p * BF_MERL_CELLS + (size_t)cell] = -1.0;
            }
            continue;
        }
        if (s->theta_i) {
            s->theta_i[j] = s->theta_i[i];
            s->phi_i[j] = s->phi_i[i];
            s->theta_o[j] = s->theta_o[i];
            s->phi_o[j] = s->phi_o[i];
        }
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
        if (s->theta_i) {
            /* The angle arrays live in one block of 4n: move the three later ones down. */
            memmove(s->theta_i + j, s->phi_i, j * sizeof *s->theta_i);
            memmove(s->theta_i + 2 * j, s->theta_o, j * sizeof *s->theta_i);
            memmove(s->theta_i + 3 * j, s->phi_o, j * sizeof *s->theta_i);
            s->phi_i = s->theta_i + j;
            s->theta_o = s->theta_i + 2 * j;
            s->phi_o = s->theta_i + 3 * j;
        }
        s->n = j;
        bf_geometry_free(s->geom);
        s->geom = NULL;
    }
    return BF_OK;
}

bf_status bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_samples **out, bf_error *err)
{
    const size_t C = (size_t)s->channels;
    size_t n = 0;
    for (size_t i = 0; i < s->n; i++)
        n += !keep || keep[i];
    *out = NULL;
    bf_samples *o;
    bf_status rc = s->theta_i ? bf_samples_new(n, s->channels, &o, err) : bf_samples_new_cells(n, s->channels, &o, err);
    if (rc != BF_OK)
        return rc;
    /* MERL cells are per-sample data (solid-angle weights use them), whichever way the
     * directions are held. */
    if (s->merl && !o->merl &&
        (!(o->merl = calloc(1, sizeof *o->merl)) || !(o->merl->cell = bf_big_calloc(n + 1, sizeof *o->merl->cell)))) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory copying samples");
        goto fail;
    }
    for (size_t c = 0; c < C; c++)
        if ((rc = bf_samples_set_channel_name(o, (int)c, s->channel_names[c], err)) != BF_OK)
            goto fail;
    if (s->wavelength) {
        if (!(o->wavelength = malloc(C * sizeof *o->wavelength))) {
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory copying samples");
            goto fail;
        }
        memcpy(o->wavelength, s->wavelength, C * sizeof *o->wavelength);
    }
    if (s->weight && (rc = bf_samples_add_weights(o, err)) != BF_OK)
        goto fail;
    if (s->scene_weight && !(o->scene_weight = malloc((n + 1) * sizeof *o->scene_weight))) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory copying samples");
        goto fail;
    }
    size_t j = 0;
    for (size_t i = 0; i < s->n; i++) {
        if (keep && !keep[i])
            continue;
        if (s->theta_i) {
            o->theta_i[j] = s->theta_i[i];
            o->phi_i[j] = s->phi_i[i];
            o->theta_o[j] = s->theta_o[i];
            o->phi_o[j] = s->phi_o[i];
        }
        if (s->merl)
            o->merl->cell[j] = s->merl->cell[i];
        memcpy(o->value + j * C, s->value + i * C, C * sizeof *o->value);
        if (s->weight)
            o->weight[j] = s->weight[i];
        if (s->scene_weight)
            o->scene_weight[j] = s->scene_weight[i];
        j++;
    }
    *out = o;
    return BF_OK;
fail:
    bf_samples_free(o);
    return rc;
}
