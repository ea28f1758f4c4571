/* The lit sphere: per-pixel local frames on an orthographic unit sphere, one batched
 * model evaluation per light over every pixel of the disc. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/sized.h"
#include "brdfit/render.h"
#include "color.h"

static void dir_vec(bf_dir d, double v[3])
{
    double t = d.theta * (M_PI / 180.0), p = d.phi * (M_PI / 180.0);
    v[0] = sin(t) * cos(p);
    v[1] = sin(t) * sin(p);
    v[2] = cos(t);
}

static double dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalise(double v[3])
{
    double l = sqrt(dot(v, v));
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
}

/* What a sphere shows: C channels of f at every sample of a geometry (0 below the
 * horizon). A model, or a measured table. */
typedef struct source {
    int C;
    void (*eval)(const struct source *src, const bf_geometry *g, double *f);
    const bf_model *m;
    const double *x;
    const bf_samples *s;
    const int32_t *sample_of; /* MERL cell -> sample, -1 for none */
} source;

static void eval_model(const source *src, const bf_geometry *g, double *f)
{
    bf_model_eval(src->m, src->x, g, f, NULL);
}

/* The MERL cell MERL's own lookup picks for directions L, V in the local frame (half and
 * difference angles, phi_d folded into [0, pi) by reciprocity), or -1. */
static int32_t merl_lookup(const double L[3], const double V[3])
{
    double h[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
    normalise(h);
    double th = acos(h[2] > 1.0 ? 1.0 : h[2]), ph = atan2(h[1], h[0]);
    /* D = L rotated by -phi_h about z, then by -theta_h about y. */
    double c = cos(-ph), s_ = sin(-ph);
    double d0 = c * L[0] - s_ * L[1], d1 = s_ * L[0] + c * L[1], d2 = L[2];
    double ct = cos(-th), st = sin(-th);
    double e0 = ct * d0 + st * d2, e2 = -st * d0 + ct * d2;
    double td = acos(e2 > 1.0 ? 1.0 : e2 < -1.0 ? -1.0 : e2), pd = atan2(d1, e0);
    if (pd < 0.0)
        pd += M_PI;
    int ih = (int)floor(sqrt(th / (M_PI / 2)) * BF_MERL_TH), jd = (int)floor(td / (M_PI / 2) * BF_MERL_TD);
    int kd = (int)floor(pd / M_PI * BF_MERL_PD);
    if (ih < 0 || ih >= BF_MERL_TH || jd < 0 || jd >= BF_MERL_TD)
        return -1;
    kd = kd < 0 ? 0 : kd >= BF_MERL_PD ? BF_MERL_PD - 1 : kd;
    return kd + jd * BF_MERL_PD + ih * BF_MERL_PD * BF_MERL_TD;
}

static void eval_merl(const source *src, const bf_geometry *g, double *f)
{
    const int C = src->C;
    for (size_t q = 0; q < g->n; q++) {
        double L[3] = {g->lx[q], g->ly[q], g->lz[q]}, V[3] = {g->vx[q], g->vy[q], g->vz[q]};
        int32_t cell = bf_geometry_valid(g, q) ? merl_lookup(L, V) : -1;
        int32_t smp = cell >= 0 ? src->sample_of[cell] : -1;
        for (int c = 0; c < C; c++)
            f[q * (size_t)C + (size_t)c] = smp >= 0 ? src->s->value[(size_t)smp * (size_t)C + (size_t)c] : 0.0;
    }
}

/* Rows of the image rendered at once: memory stays O(size x BAND) whatever the size. */
enum { BAND = 64 };

/* The camera's basis: w towards the viewer, u and up across the image. */
typedef struct camera {
    double w[3], u[3], up[3];
} camera;

/* Pixels of rows j0 .. j1-1 of the N x N image inside the disc and their local frames
 * (t, b, n) as rows; returns how many. */
static size_t band_frames(int N, int j0, int j1, const camera *cam, size_t *index, double *frame)
{
    const double *u = cam->u, *up = cam->up, *w = cam->w;
    size_t n = 0;
    for (int j = j0; j < j1; j++)
        for (int i = 0; i < N; i++) {
            double sx = 2.0 * (i + 0.5) / N - 1.0, sy = 1.0 - 2.0 * (j + 0.5) / N;
            double r2 = sx * sx + sy * sy;
            if (r2 >= 1.0)
                continue;
            double sz = sqrt(1.0 - r2), *F = frame + 9 * n;
            double *tn = F, *bn = F + 3, *nn = F + 6;
            for (int k = 0; k < 3; k++)
                nn[k] = sx * u[k] + sy * up[k] + sz * w[k];
            normalise(nn);
            /* Tangent from a fixed world axis, so anisotropic models have a stable
             * direction; +y where the normal is (nearly) +-x. */
            double a[3] = {1.0, 0.0, 0.0};
            if (fabs(nn[0]) > 1.0 - 1e-6) {
                a[0] = 0.0;
                a[1] = 1.0;
            }
            double an = dot(a, nn);
            for (int k = 0; k < 3; k++)
                tn[k] = a[k] - an * nn[k];
            normalise(tn);
            cross(nn, tn, bn);
            index[n++] = (size_t)(j - j0) * (size_t)N + (size_t)i;
        }
    return n;
}

static bf_status render(const source *src, const bf_sphere_options *o, float *rgb, bf_error *err)
{
    bf_status rc = bf_sphere_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    const int N = o->resolution, C = src->C;
    const size_t npx = (size_t)N * (size_t)N, nb = (size_t)N * (size_t)(N < BAND ? N : BAND);
    memset(rgb, 0, npx * 3 * sizeof *rgb);

    camera cam;
    double *w = cam.w, *u = cam.u, *up = cam.up;
    dir_vec(o->view, w);
    double t = o->view.theta * (M_PI / 180.0), p = o->view.phi * (M_PI / 180.0);
    u[0] = cos(t) * cos(p); /* d w / d theta */
    u[1] = cos(t) * sin(p);
    u[2] = -sin(t);
    normalise(u);
    cross(w, u, up);

    size_t *index = malloc(nb * sizeof *index);
    double *frame = malloc(nb * 9 * sizeof *frame);
    double *L = malloc(nb * 3 * sizeof *L), *V = malloc(nb * 3 * sizeof *V);
    double *f = malloc(nb * (size_t)C * sizeof *f);
    double *acc = malloc(nb * 3 * sizeof *acc);
    int status = BF_OK;
    if (!index || !frame || !L || !V || !f || !acc) {
        status = bf_fail(err, BF_ERR_NOMEM, "sphere render: out of memory for %dx%d pixels", N, N);
        goto done;
    }
    for (int j0 = 0; j0 < N && status == BF_OK; j0 += BAND) {
        const int j1 = j0 + BAND < N ? j0 + BAND : N;
        const size_t n = band_frames(N, j0, j1, &cam, index, frame);
        memset(acc, 0, nb * 3 * sizeof *acc);
        for (int l = 0; l < o->nlights && n > 0; l++) {
            double Lw[3];
            dir_vec(o->lights[l], Lw);
            for (size_t q = 0; q < n; q++) {
                const double *F = frame + 9 * q;
                for (int k = 0; k < 3; k++) {
                    L[3 * q + k] = dot(F + 3 * k, Lw);
                    V[3 * q + k] = dot(F + 3 * k, w);
                }
            }
            bf_geometry *g;
            if ((status = bf_geometry_from_vectors(n, L, V, &g, err)) != BF_OK)
                break;
            src->eval(src, g, f);
            for (size_t q = 0; q < n; q++) {
                if (!bf_geometry_valid(g, q))
                    continue; /* sources give 0 there; skip to keep the sum exact */
                double c[3];
                bf_channels_to_rgb(f + q * (size_t)C, C, c);
                for (int k = 0; k < 3; k++)
                    acc[3 * index[q] + (size_t)k] += c[k] * g->lz[q];
            }
            bf_geometry_free(g);
        }
        float *out = rgb + (size_t)j0 * (size_t)N * 3;
        for (size_t q = 0; q < (size_t)(j1 - j0) * (size_t)N * 3; q++)
            out[q] = (float)acc[q];
    }
done:
    free(index);
    free(frame);
    free(L);
    free(V);
    free(f);
    free(acc);
    return status;
}

bf_status bf_render_sphere(const bf_model *m, const double *x, const bf_sphere_options *o, float *rgb, bf_error *err)
{
    source src = {bf_model_channels(m), eval_model, m, x, NULL, NULL};
    return render(&src, o, rgb, err);
}

bf_status bf_render_sphere_merl(const bf_samples *s, const bf_sphere_options *o, float *rgb, bf_error *err)
{
    if (!s || !s->merl)
        return bf_fail(err, BF_ERR_ARG, "sphere render: the data is not a MERL table as read");
    int32_t *sample_of = malloc((size_t)BF_MERL_CELLS * sizeof *sample_of);
    if (!sample_of)
        return bf_fail(err, BF_ERR_NOMEM, "sphere render: out of memory");
    for (size_t c = 0; c < (size_t)BF_MERL_CELLS; c++)
        sample_of[c] = -1;
    for (size_t i = 0; i < s->n; i++)
        if (s->merl->cell[i] >= 0 && s->merl->cell[i] < BF_MERL_CELLS)
            sample_of[s->merl->cell[i]] = (int32_t)i;
    source src = {s->channels, eval_merl, NULL, NULL, s, sample_of};
    bf_status rc = render(&src, o, rgb, err);
    free(sample_of);
    return rc;
}
