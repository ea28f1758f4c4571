/* RGL-EPFL measured materials (.bsdf; rgl_bsdf.h), after Dupuy and Jakob 2018, "An
 * adaptive parameterization for efficient material acquisition and rendering".
 *
 * The paper measures a material, for each incident direction wi, at outgoing
 * directions chosen by warping a regular grid of sample-space points through the
 * visible normal distribution (VNDF) of wi: a grid point s maps to a microfacet normal
 * wm (the VNDF warp, stored as the field "vndf" over the normal's coordinates
 * u = (sqrt(theta_m / (pi/2)), (phi_m - phi_i + pi) / (2 pi))), and wo is wi mirrored
 * about wm. The values stored at the grid points ("rgb" or "spectra") are the
 * reflectance divided by the density of that choice, D(wm) / (4 sigma(wi)), where D is
 * the normal distribution ("ndf") and sigma the projected microfacet area ("sigma");
 * the flag "jacobian" says they are. Mitsuba and pbrt-v4 evaluate them the same way:
 * with the gonio-photometer's cosine included, f cos(theta_o) = value * D / (4 sigma).
 *
 * Evaluating at a pair of directions therefore runs the warps backwards: wm from wi and
 * wo, u from wm, s from u (the inverse VNDF warp), the stored values interpolated
 * bilinearly at s (and linearly between the measured incident elevations), times
 * D / (4 sigma cos theta_o). The fields "luminance" (for importance sampling) and
 * "valid" (undocumented; the reference loaders do not read it) are not used. */
#include "rgl_bsdf.h"

#include "brdfit/formats.h"
#include "brdfit/limits.h"
#include "brdfit/samples.h"

#include "base/big_alloc.h"
#include "direction_grid.h"
#include "read_binary.h"
#include "rgl_tensor_file.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* Measured points whose outgoing direction is this close to the horizon (in cosine) are
 * not samples: the stored value is f cos(theta_o), so the BRDF there is a limit 0/0 that
 * the division turns into noise of up to 1e9 (the grid's edge maps to theta_m = 90
 * degrees, and the grazing incidence theta_i = 90 degrees mirrors to grazing exitance). */
#define GRAZING_COS 1e-6

/* ---- Reading --------------------------------------------------------------------- */

static const char *const dtype_names[] = {"?",     "uint8",  "int8",  "uint16",  "int16",   "uint32",
                                          "int32", "uint64", "int64", "float16", "float32", "float64"};

/* *out: field `name`, which must have this type and number of dimensions. */
static bf_status need(const bf_tensor_file *t, const char *name, int dtype, int ndim, const bf_tensor_field **out,
                      bf_error *err)
{
    const bf_tensor_field *f = *out = bf_tensor_file_field(t, name);
    if (!f)
        return bf_fail(err, BF_ERR_PARSE, "%s: no field '%s' (not an RGL-EPFL material?)", t->path, name);
    if (f->dtype != dtype || f->ndim != ndim) {
        *out = NULL;
        return bf_fail(err, BF_ERR_PARSE, "%s: field '%s' is %s with %d dimensions, expected %s with %d", t->path, name,
                       dtype_names[f->dtype], f->ndim, dtype_names[dtype], ndim);
    }
    return BF_OK;
}

/* The grid extents (last two) of a field: at least 2 x 2 for bilinear patches. */
static bf_status grid_ok(const bf_tensor_file *t, const bf_tensor_field *f, bf_error *err)
{
    const size_t ny = f->shape[f->ndim - 2], nx = f->shape[f->ndim - 1];
    if (nx < 2 || ny < 2)
        return bf_fail(err, BF_ERR_PARSE, "%s: field '%s' has a %zu x %zu grid (at least 2 x 2)", t->path, f->name, ny,
                       nx);
    return BF_OK;
}

/* The incident angles: theta_i increasing within [0, pi/2]; phi_i one value (two are
 * also isotropic, as Mitsuba reads them); more are an anisotropic material. */
static bf_status read_incident(const bf_tensor_file *t, bf_rgl_bsdf *b, size_t *n_phi, bf_error *err)
{
    const bf_tensor_field *ft, *fp;
    bf_status rc;
    if ((rc = need(t, "theta_i", BF_TENSOR_FLOAT32, 1, &ft, err)) != BF_OK ||
        (rc = need(t, "phi_i", BF_TENSOR_FLOAT32, 1, &fp, err)) != BF_OK)
        return rc;
    if (fp->count > 2)
        return bf_fail(err, BF_ERR_PARSE,
                       "%s: anisotropic material (%zu incident azimuths): brdfit reads isotropic RGL files only",
                       t->path, fp->count);
    if (ft->count < 1 || fp->count < 1)
        return bf_fail(err, BF_ERR_PARSE, "%s: no incident %s", t->path, ft->count < 1 ? "elevation" : "azimuth");
    double *phi;
    if ((rc = bf_tensor_field_doubles(t, fp, &phi, err)) != BF_OK)
        return rc;
    if ((rc = bf_tensor_field_doubles(t, ft, &b->theta_i, err)) != BF_OK) {
        free(phi);
        return rc;
    }
    b->phi_i = phi[0];
    free(phi);
    *n_phi = fp->count;
    b->n_theta = ft->count;
    for (size_t k = 0; k < b->n_theta; k++)
        if (b->theta_i[k] < 0.0 || b->theta_i[k] > M_PI / 2 + 1e-6 || (k && !(b->theta_i[k] > b->theta_i[k - 1])))
            return bf_fail(err, BF_ERR_PARSE,
                           "%s: field 'theta_i': value %zu (%g rad) is not increasing within [0, pi/2]", t->path, k,
                           b->theta_i[k]);
    return BF_OK;
}

/* A field's values as a warp (with_cdf: normalised, with its CDFs). */
static bf_status read_warp(const bf_tensor_file *t, const bf_tensor_field *f, size_t slices, int with_cdf,
                           bf_rgl_warp *w, bf_error *err)
{
    double *d;
    bf_status rc;
    if ((rc = grid_ok(t, f, err)) != BF_OK || (rc = bf_tensor_field_doubles(t, f, &d, err)) != BF_OK)
        return rc;
    size_t bad;
    if (bf_rgl_warp_init(w, f->shape[f->ndim - 1], f->shape[f->ndim - 2], slices, d, with_cdf, &bad) != 0) {
        if (bad == (size_t)-1)
            return bf_fail_memory(err, t->path, 0, 2 * f->count * sizeof(double));
        return bf_fail(err, BF_ERR_PARSE, "%s: field '%s': slice %zu is not a density (a negative value, or nothing)",
                       t->path, f->name, bad);
    }
    return BF_OK;
}

/* ndf and sigma: plain interpolants of D and sigma, which must be >= 0 and > 0 (sigma
 * divides). */
static bf_status read_ndf_sigma(const bf_tensor_file *t, bf_rgl_bsdf *b, bf_error *err)
{
    const bf_tensor_field *fn, *fs;
    bf_status rc;
    if ((rc = need(t, "ndf", BF_TENSOR_FLOAT32, 2, &fn, err)) != BF_OK ||
        (rc = need(t, "sigma", BF_TENSOR_FLOAT32, 2, &fs, err)) != BF_OK)
        return rc;
    rc = read_warp(t, fn, 1, 0, &b->ndf, err);
    if (rc == BF_OK)
        rc = read_warp(t, fs, 1, 0, &b->sigma, err);
    for (size_t i = 0; rc == BF_OK && i < fn->count; i++)
        if (b->ndf.data[i] < 0.0)
            rc = bf_fail(err, BF_ERR_PARSE, "%s: field 'ndf': value %zu is negative (%g)", t->path, i, b->ndf.data[i]);
    for (size_t i = 0; rc == BF_OK && i < fs->count; i++)
        if (!(b->sigma.data[i] > 0.0))
            rc = bf_fail(err, BF_ERR_PARSE, "%s: field 'sigma': value %zu is not positive (%g)", t->path, i,
                         b->sigma.data[i]);
    return rc;
}

/* *out: the measured values, "rgb" (3 channels) or "spectra" with "wavelengths". */
static bf_status read_channels(const bf_tensor_file *t, bf_rgl_bsdf *b, const bf_tensor_field **out, bf_error *err)
{
    const int rgb = bf_tensor_file_field(t, "rgb") != NULL;
    const bf_tensor_field *f, *fw;
    bf_status rc = need(t, rgb ? "rgb" : "spectra", BF_TENSOR_FLOAT32, 5, &f, err);
    *out = NULL;
    if (rc != BF_OK)
        return rc;
    if (rgb) {
        b->channels = 3;
    } else {
        if ((rc = need(t, "wavelengths", BF_TENSOR_FLOAT32, 1, &fw, err)) != BF_OK)
            return rc;
        if (fw->count < 1 || fw->count > BF_MAX_CHANNELS)
            return bf_fail(err, BF_ERR_PARSE, "%s: %zu wavelengths (1 to %d)", t->path, fw->count, BF_MAX_CHANNELS);
        if ((rc = bf_tensor_field_doubles(t, fw, &b->wavelength, err)) != BF_OK)
            return rc;
        b->channels = (int)fw->count;
    }
    if (f->shape[2] != (size_t)b->channels)
        return bf_fail(err, BF_ERR_PARSE, "%s: field '%s' has %zu channels, expected %d", t->path, f->name, f->shape[2],
                       b->channels);
    *out = f;
    return BF_OK;
}

static bf_status read_fields(const bf_tensor_file *t, bf_rgl_bsdf *b, bf_error *err)
{
    size_t n_phi = 0;
    const bf_tensor_field *fv, *fj, *fc;
    bf_status rc = read_incident(t, b, &n_phi, err);
    if (rc != BF_OK || (rc = read_ndf_sigma(t, b, err)) != BF_OK ||
        (rc = need(t, "vndf", BF_TENSOR_FLOAT32, 4, &fv, err)) != BF_OK ||
        (rc = need(t, "jacobian", BF_TENSOR_UINT8, 1, &fj, err)) != BF_OK ||
        (rc = read_channels(t, b, &fc, err)) != BF_OK)
        return rc;
    if (fj->count < 1)
        return bf_fail(err, BF_ERR_PARSE, "%s: field 'jacobian' is empty", t->path);
    b->jacobian = t->bytes[fj->offset] != 0;
    /* Both tables are stacked over (phi_i, theta_i) in that order. */
    const bf_tensor_field *tab[2] = {fv, fc};
    for (int k = 0; k < 2; k++)
        if (tab[k]->shape[0] != n_phi || tab[k]->shape[1] != b->n_theta)
            return bf_fail(err, BF_ERR_PARSE,
                           "%s: field '%s' is stacked %zu x %zu, expected %zu x %zu (phi_i x theta_i)", t->path,
                           tab[k]->name, tab[k]->shape[0], tab[k]->shape[1], n_phi, b->n_theta);
    const size_t slices = n_phi * b->n_theta;
    if ((rc = read_warp(t, fv, slices, 1, &b->vndf, err)) != BF_OK)
        return rc;
    return read_warp(t, fc, slices * (size_t)b->channels, 0, &b->values, err);
}

bf_status bf_rgl_bsdf_read(const char *path, bf_rgl_bsdf *b, bf_error *err)
{
    memset(b, 0, sizeof *b);
    unsigned char *bytes;
    size_t size;
    bf_status rc = bf_read_binary(path, &bytes, &size, err);
    if (rc != BF_OK)
        return rc;
    bf_tensor_file t;
    rc = bf_tensor_file_parse(path, bytes, size, &t, err);
    if (rc == BF_OK) {
        rc = read_fields(&t, b, err);
        bf_tensor_file_clear(&t);
    }
    free(bytes);
    if (rc != BF_OK)
        bf_rgl_bsdf_clear(b);
    return rc;
}

void bf_rgl_bsdf_clear(bf_rgl_bsdf *b)
{
    free(b->theta_i);
    free(b->wavelength);
    bf_rgl_warp_clear(&b->ndf);
    bf_rgl_warp_clear(&b->sigma);
    bf_rgl_warp_clear(&b->vndf);
    bf_rgl_warp_clear(&b->values);
    memset(b, 0, sizeof *b);
}

/* ---- Evaluation ------------------------------------------------------------------ */

/* The elevation of a unit vector, accurate near the normal too (acos is not). */
static double elevation(const double d[3])
{
    const double h = 0.5 * sqrt(d[0] * d[0] + d[1] * d[1] + (d[2] - 1.0) * (d[2] - 1.0));
    return 2.0 * asin(h < 1.0 ? h : 1.0);
}

static void spherical(double theta, double phi, double d[3])
{
    d[0] = sin(theta) * cos(phi);
    d[1] = sin(theta) * sin(phi);
    d[2] = cos(theta);
}

/* The table slices for incident angles (phi_i, theta_i): the incident azimuth has one
 * slice (two for a file with two, interpolated as Mitsuba does), elevations two. */
static bf_rgl_mix incident_mix(const bf_rgl_bsdf *b, double theta_i)
{
    size_t it[2];
    double wt[2];
    bf_rgl_param_weights(b->theta_i, b->n_theta, theta_i, it, wt);
    bf_rgl_mix m = {0, {0}, {0}};
    for (int k = 0; k < 2; k++)
        if (wt[k] != 0.0 || k == 0) {
            m.slice[m.n] = it[k];
            m.w[m.n++] = wt[k];
        }
    return m;
}

void bf_rgl_bsdf_eval(const bf_rgl_bsdf *b, const double wi[3], const double wo[3], double *f, double *stored)
{
    const int C = b->channels;
    if (!(wi[2] > 0.0 && wo[2] > 0.0)) {
        for (int c = 0; c < C; c++) {
            f[c] = 0.0;
            if (stored)
                stored[c] = 0.0;
        }
        return;
    }
    double wm[3] = {wi[0] + wo[0], wi[1] + wo[1], wi[2] + wo[2]};
    const double len = sqrt(wm[0] * wm[0] + wm[1] * wm[1] + wm[2] * wm[2]);
    for (int k = 0; k < 3; k++)
        wm[k] /= len;
    const double theta_i = elevation(wi), phi_i = atan2(wi[1], wi[0]);
    const double theta_m = elevation(wm), phi_m = atan2(wm[1], wm[0]);
    const double u_wi[2] = {sqrt(theta_i * (2.0 / M_PI)), (phi_i + M_PI) / (2.0 * M_PI)};
    double u_wm[2] = {sqrt(theta_m * (2.0 / M_PI)), (phi_m - phi_i + M_PI) / (2.0 * M_PI)};
    u_wm[1] -= floor(u_wm[1]);
    const bf_rgl_mix m = incident_mix(b, theta_i), one = {1, {0}, {1.0}};
    double s[2];
    bf_rgl_warp_invert(&b->vndf, &m, u_wm, s);
    double factor = 1.0 / wo[2];
    if (b->jacobian)
        factor *= bf_rgl_warp_eval(&b->ndf, &one, u_wm) / (4.0 * bf_rgl_warp_eval(&b->sigma, &one, u_wi));
    for (int c = 0; c < C; c++) {
        bf_rgl_mix mc = m;
        for (int k = 0; k < mc.n; k++)
            mc.slice[k] = mc.slice[k] * (size_t)C + (size_t)c;
        const double v = bf_rgl_warp_eval(&b->values, &mc, s);
        f[c] = v * factor;
        if (stored)
            stored[c] = v;
    }
}

int bf_rgl_bsdf_point(const bf_rgl_bsdf *b, size_t k, size_t x, size_t y, double wi[3], double wo[3], double *f)
{
    const double theta_i = b->theta_i[k];
    spherical(theta_i, b->phi_i, wi);
    const bf_rgl_mix m = incident_mix(b, theta_i), one = {1, {0}, {1.0}};
    const size_t nx = b->values.nx, ny = b->values.ny;
    const double s[2] = {(double)x / (double)(nx - 1), (double)y / (double)(ny - 1)};
    double u[2], wm[3];
    bf_rgl_warp_sample(&b->vndf, &m, s, u);
    spherical(u[0] * u[0] * (M_PI / 2), (2.0 * u[1] - 1.0) * M_PI + b->phi_i, wm);
    const double d = wi[0] * wm[0] + wi[1] * wm[1] + wi[2] * wm[2];
    for (int j = 0; j < 3; j++)
        wo[j] = 2.0 * d * wm[j] - wi[j];
    const double len = sqrt(wo[0] * wo[0] + wo[1] * wo[1] + wo[2] * wo[2]);
    for (int j = 0; j < 3; j++)
        wo[j] /= len;
    if (!(wo[2] > GRAZING_COS))
        return -1;
    if (f) {
        const double u_wi[2] = {sqrt(theta_i * (2.0 / M_PI)), (b->phi_i + M_PI) / (2.0 * M_PI)};
        double factor = 1.0 / wo[2];
        if (b->jacobian)
            factor *= bf_rgl_warp_eval(&b->ndf, &one, u) / (4.0 * bf_rgl_warp_eval(&b->sigma, &one, u_wi));
        const size_t C = (size_t)b->channels;
        for (size_t c = 0; c < C; c++) /* the first azimuth slice, elevation k, channel c */
            f[c] = b->values.data[((k * C + c) * ny + y) * nx + x] * factor;
    }
    return 0;
}

/* ---- Samples --------------------------------------------------------------------- */

static double degrees(double rad)
{
    return rad * (180.0 / M_PI);
}

/* Azimuth in degrees within [0, 360). */
static double azimuth(const double d[3])
{
    const double a = degrees(atan2(d[1], d[0]));
    return a < 0.0 ? a + 360.0 : a;
}

/* Channel names and wavelengths of a spectral material ("rgb" files keep r, g, b). */
static bf_status name_channels(const bf_rgl_bsdf *b, bf_samples *s, bf_error *err)
{
    if (!b->wavelength)
        return BF_OK;
    if (!(s->wavelength = malloc((size_t)b->channels * sizeof *s->wavelength)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for %d wavelengths", b->channels);
    for (int c = 0; c < b->channels; c++) {
        char name[32];
        snprintf(name, sizeof name, "%g", b->wavelength[c]);
        s->wavelength[c] = b->wavelength[c];
        bf_status rc = bf_samples_set_channel_name(s, c, name, err);
        if (rc != BF_OK)
            return rc;
    }
    return BF_OK;
}

/* The measured points with the outgoing direction above the horizon, in file order
 * (elevation, then sample-space row, then column), with the values stored at them. (The
 * evaluation at their directions agrees, except on the grid's column 0, which the warp
 * maps to theta_m = 0 whatever the row: those 32 nodes are one direction pair, measured
 * 32 times.) */
static bf_status measured_samples(const char *path, const bf_rgl_bsdf *b, bf_samples **out, bf_error *err)
{
    const size_t nx = b->values.nx, ny = b->values.ny, C = (size_t)b->channels;
    size_t n = 0;
    double wi[3], wo[3];
    for (size_t k = 0; k < b->n_theta; k++)
        for (size_t y = 0; y < ny; y++)
            for (size_t x = 0; x < nx; x++)
                n += bf_rgl_bsdf_point(b, k, x, y, wi, wo, NULL) == 0;
    if (n == 0)
        return bf_fail(err, BF_ERR_PARSE, "%s: no measured point reflects above the horizon", path);
    bf_samples *s;
    bf_status rc = bf_samples_new(n, b->channels, &s, err);
    if (rc != BF_OK)
        return rc;
    size_t i = 0;
    for (size_t k = 0; k < b->n_theta; k++)
        for (size_t y = 0; y < ny; y++)
            for (size_t x = 0; x < nx; x++) {
                if (bf_rgl_bsdf_point(b, k, x, y, wi, wo, s->value + i * C) != 0)
                    continue;
                s->theta_i[i] = degrees(b->theta_i[k]);
                s->phi_i[i] = azimuth(wi);
                s->theta_o[i] = degrees(elevation(wo));
                s->phi_o[i] = azimuth(wo);
                i++;
            }
    rc = name_channels(b, s, err);
    if (rc != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}

/* The material evaluated on a direction grid (direction_grid.h). */
static bf_status grid_samples(const bf_rgl_bsdf *b, const char *grid, bf_samples **out, bf_error *err)
{
    bf_samples *s;
    bf_status rc = bf_direction_grid(grid, b->channels, &s, err);
    if (rc != BF_OK)
        return rc;
    const size_t C = (size_t)b->channels;
    for (size_t i = 0; i < s->n; i++) {
        double dir[4], wi[3], wo[3];
        bf_samples_direction(s, i, dir);
        spherical(dir[0] * (M_PI / 180.0), dir[1] * (M_PI / 180.0), wi);
        spherical(dir[2] * (M_PI / 180.0), dir[3] * (M_PI / 180.0), wo);
        bf_rgl_bsdf_eval(b, wi, wo, s->value + i * C, NULL);
    }
    if ((rc = name_channels(b, s, err)) != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}

bf_status bf_samples_read_rgl(const char *path, const char *grid, bf_samples **out, bf_error *err)
{
    *out = NULL;
    bf_rgl_bsdf b;
    bf_status rc = bf_rgl_bsdf_read(path, &b, err);
    if (rc != BF_OK)
        return rc;
    rc = grid ? grid_samples(&b, grid, out, err) : measured_samples(path, &b, out, err);
    bf_rgl_bsdf_clear(&b);
    return rc;
}
