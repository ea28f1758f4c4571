/* Pictures: the lit sphere (Lambert radiance exact at the centre, lit where the light
 * is, black background), the theta_h x theta_d image against direct model evaluation
 * and MERL cells, slice plots (curves and overlaid samples where expected), and the
 * OpenImageIO shim (EXR round trip, PNG sRGB codes, errors leave no file). */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "brdfit/image.h"
#include "brdfit/render.h"
#include "plot/plot.h"
#include "render/slices.h"
#include "support.h"

static float *px(float *rgb, int w, int x, int y)
{
    return rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
}

/* Options as the tests give them, through the init functions (docs/api.md). */
static bf_sphere_options sphere_options(int n, bf_dir view, const bf_dir *lights, int nlights)
{
    bf_sphere_options o;
    bf_sphere_options_init(&o);
    o.resolution = n;
    o.view = view;
    o.lights = lights;
    o.nlights = nlights;
    return o;
}

static bf_slice_options slice_options(int width, int height, const double *inc, int ninc, bf_samples *s,
                                      double plane_tol, const char *title, double lo, double hi)
{
    bf_slice_options o;
    bf_slice_options_init(&o);
    o.width = width;
    o.height = height;
    o.incidence = inc;
    o.nincidence = ninc;
    o.samples = s;
    o.plane_tol = plane_tol;
    o.title = title;
    o.log10_lo = lo;
    o.log10_hi = hi;
    return o;
}

static void vec_angles(const double v[3], double *theta, double *phi)
{
    *theta = atan2(sqrt(v[0] * v[0] + v[1] * v[1]), v[2]) / DEG;
    *phi = atan2(v[1], v[0]) / DEG;
}

/* Lambert rho/pi at the centre with the light along the view, through an EXR file. */
static void test_sphere_lambert_exr(void **state)
{
    (void)state;
    const double rho[3] = {0.8, 0.5, 0.2};
    bf_model *m = ts_model("lambert", 3);
    const int N = 65;
    bf_dir light = {0.0, 0.0};
    bf_sphere_options o = sphere_options(N, (bf_dir){0.0, 0.0}, &light, 1);
    float *rgb = malloc((size_t)N * N * 3 * sizeof *rgb);
    bf_error err;
    assert_int_equal(bf_render_sphere(m, rho, &o, rgb, &err), BF_OK);
    const char *path = ts_tmp_path("lambert.exr");
    assert_int_equal(bf_image_write_rgb(path, N, N, rgb, &err), BF_OK);
    bf_image img;
    bf_image_init(&img);
    assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
    assert_int_equal(img.width, N);
    assert_int_equal(img.height, N);
    assert_int_equal(img.channels, 3);
    for (int c = 0; c < 3; c++) {
        ts_assert_near(px(img.pixels, N, 32, 32)[c], rho[c] / M_PI, 1e-6, 1e-7, "centre");
        assert_true(px(img.pixels, N, 0, 0)[c] == 0.0f); /* background exactly 0 */
        assert_true(px(img.pixels, N, N - 1, 5)[c] == 0.0f);
        /* Off-centre: cos(theta_L) = n_z = sqrt(1 - sx^2). */
        double sx = 2.0 * (50 + 0.5) / N - 1.0;
        ts_assert_near(px(img.pixels, N, 50, 32)[c], rho[c] / M_PI * sqrt(1.0 - sx * sx), 1e-6, 1e-7, "off centre");
    }
    bf_image_clear(&img);
    free(rgb);
    bf_model_free(m);
}

/* Lit where the light is, dark behind; several lights add. */
static void test_sphere_lighting(void **state)
{
    (void)state;
    const double rho = 0.5;
    bf_model *m = ts_model("lambert", 1);
    const int N = 64;
    float *a = malloc((size_t)N * N * 3 * sizeof *a), *b = malloc((size_t)N * N * 3 * sizeof *b);
    float *ab = malloc((size_t)N * N * 3 * sizeof *ab);
    bf_error err;
    bf_dir grazing = {80.0, 0.0}, top = {0.0, 0.0}, both[2] = {{80.0, 0.0}, {0.0, 0.0}};
    bf_sphere_options o = sphere_options(N, (bf_dir){0.0, 0.0}, &grazing, 1);
    assert_int_equal(bf_render_sphere(m, &rho, &o, a, &err), BF_OK);
    /* Light from +x at 80 degrees: the +x limb is brighter than the centre, the -x limb black. */
    assert_true(px(a, N, N - 6, N / 2)[0] > px(a, N, N / 2, N / 2)[0]);
    assert_true(px(a, N, 5, N / 2)[0] == 0.0f);
    assert_true(px(a, N, N / 2, N / 2)[0] > 0.0f);
    o.lights = &top;
    assert_int_equal(bf_render_sphere(m, &rho, &o, b, &err), BF_OK);
    assert_true(px(b, N, N / 2, N / 2)[0] > 0.99f * (float)(rho / M_PI));  /* bright centre */
    assert_true(px(b, N, N / 2, N / 2)[0] > 2.0f * px(b, N, 2, N / 2)[0]); /* dim limb (cos 0.39) */
    o.lights = both;
    o.nlights = 2;
    assert_int_equal(bf_render_sphere(m, &rho, &o, ab, &err), BF_OK);
    for (size_t q = 0; q < (size_t)N * N * 3; q++)
        assert_true(fabsf(ab[q] - (a[q] + b[q])) <= 1e-6f);
    /* Grey: the three channels agree. */
    assert_true(px(ab, N, 20, 30)[0] == px(ab, N, 20, 30)[2]);
    /* Viewed from the light's side (view 80,0), the bright limb faces the camera: the
     * centre is brighter than with the top view's grazing light. */
    o.lights = &grazing;
    o.nlights = 1;
    o.view = grazing;
    assert_int_equal(bf_render_sphere(m, &rho, &o, b, &err), BF_OK);
    assert_true(px(b, N, N / 2, N / 2)[0] > 0.99f * (float)(rho / M_PI));
    free(a);
    free(b);
    free(ab);
    bf_model_free(m);
}

/* The half/difference directions are MERL's at cell centres. */
static void test_halfdiff_dirs_merl(void **state)
{
    (void)state;
    const int cells[][3] = {{3, 10, 20}, {45, 60, 90}, {80, 5, 170}, {10, 85, 1}};
    for (size_t t = 0; t < sizeof cells / sizeof cells[0]; t++) {
        int i = cells[t][0], j = cells[t][1], k = cells[t][2];
        double th = ((i + 0.5) / 90) * ((i + 0.5) / 90) * M_PI / 2, td = (j + 0.5) / 90 * M_PI / 2;
        double pd = (k + 0.5) / 180 * M_PI, L[3], V[3], ti, pi_, to, po, eti, epi, eto, epo;
        bf_halfdiff_dirs(th, td, pd, L, V);
        bf_merl_cell_directions(k + j * 180 + i * 180 * 90, &eti, &epi, &eto, &epo);
        vec_angles(L, &ti, &pi_);
        vec_angles(V, &to, &po);
        ts_assert_near(ti, eti, 0, 1e-9, "theta_i");
        ts_assert_near(to, eto, 0, 1e-9, "theta_o");
        ts_assert_near(pi_, epi, 0, 1e-9, "phi_i");
        ts_assert_near(po + 360.0, epo, 0, 1e-9, "phi_o");
    }
}

/* Pixels of the model image equal the model at their (theta_h, theta_d, phi_d). */
static void test_halfdiff_model(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    double x[8];
    assert_true(bf_model_nvalues(m) <= 8);
    bf_model_defaults(m, x);
    const int W = 45, H = 30;
    float *rgb = malloc((size_t)W * H * 3 * sizeof *rgb);
    bf_error err;
    assert_int_equal(bf_render_halfdiff_model(m, x, W, H, 90.0, rgb, &err), BF_OK);
    const int at[][2] = {{0, 0}, {10, 5}, {22, 14}, {44, 29}, {3, 27}};
    for (size_t t = 0; t < sizeof at / sizeof at[0]; t++) {
        int i = at[t][0], j = at[t][1];
        double th = (i + 0.5) / W * (i + 0.5) / W * 90.0 * DEG, td = (j + 0.5) / H * 90.0 * DEG, L[3], V[3];
        double ti, pi_, to, po;
        bf_halfdiff_dirs(th, td, 90.0 * DEG, L, V);
        vec_angles(L, &ti, &pi_);
        vec_angles(V, &to, &po);
        /* Theta_h from the pixel column: H is (sin th, 0, cos th). */
        double Hv[3] = {L[0] + V[0], L[1] + V[1], L[2] + V[2]};
        ts_assert_near(atan2(sqrt(Hv[0] * Hv[0] + Hv[1] * Hv[1]), Hv[2]), th, 0, 1e-12, "theta_h");
        ts_assert_near(acos(L[0] * Hv[0] / sqrt(Hv[0] * Hv[0] + Hv[1] * Hv[1] + Hv[2] * Hv[2]) +
                            L[2] * Hv[2] / sqrt(Hv[0] * Hv[0] + Hv[1] * Hv[1] + Hv[2] * Hv[2])),
                       td, 0, 1e-9, "theta_d");
        for (int c = 0; c < 3; c++)
            ts_assert_near(px(rgb, W, i, j)[c], ts_eval1(m, x, ti, pi_, to, po, c), 1e-6, 1e-9, "pixel");
    }
    free(rgb);
    bf_model_free(m);
}

/* MERL tables: a pixel shows the cell it falls in, invalid cells are 0. */
static void test_halfdiff_merl(void **state)
{
    (void)state;
    bf_error err;
    bf_samples *s = NULL;
    bf_samples_new(2, 3, &s, &err);
    s->merl = calloc(1, sizeof *s->merl);
    s->merl->raw = calloc(3 * (size_t)BF_MERL_CELLS, sizeof(double));
    s->merl->cell = calloc(2, sizeof(int32_t));
    /* Pixel (i, j) of a 90x90 image at phi_d 90: column i is MERL's theta_h bin i (both
     * even in sqrt(theta_h)), theta_d bin j, phi_d bin 90. */
    s->merl->cell[0] = 90 + 7 * 180 + 20 * 180 * 90;
    s->merl->cell[1] = 90 + 7 * 180 + 0 * 180 * 90;
    for (int c = 0; c < 3; c++) {
        s->value[c] = 0.1 * (c + 1);
        s->value[3 + c] = 5.0 + c;
    }
    const int W = 90;
    float *rgb = malloc((size_t)W * W * 3 * sizeof *rgb);
    assert_int_equal(bf_render_halfdiff_merl(s, W, W, 90.0, rgb, &err), BF_OK);
    for (int c = 0; c < 3; c++) {
        assert_true(px(rgb, W, 20, 7)[c] == (float)(0.1 * (c + 1)));
        assert_true(px(rgb, W, 20, 8)[c] == 0.0f); /* another theta_d bin: no sample */
        assert_true(px(rgb, W, 0, 7)[c] == (float)(5.0 + c));
    }
    /* phi_d 270 folds onto 90 by reciprocity. */
    assert_int_equal(bf_render_halfdiff_merl(s, W, W, 270.0, rgb, &err), BF_OK);
    assert_true(px(rgb, W, 20, 7)[0] == (float)0.1);
    /* Samples that are not MERL cells (a copy, its cells taken away): an error. */
    bf_samples *plain = NULL;
    bf_samples_copy(s, NULL, &plain, &err);
    assert_memory_equal(plain->merl->cell, s->merl->cell, s->n * sizeof *s->merl->cell);
    free(plain->merl->cell);
    free(plain->merl);
    plain->merl = NULL;
    assert_int_not_equal(bf_render_halfdiff_merl(plain, W, W, 90.0, rgb, &err), BF_OK);
    bf_samples_free(plain);
    free(rgb);
    bf_samples_free(s);
}

/* A Lambert slice is one flat curve at rho/pi; the in-plane samples overlay it. */
static void test_slice_lambert(void **state)
{
    (void)state;
    bf_model *m = ts_model("lambert", 1);
    const double rho = 0.5, inc[1] = {30.0};
    bf_error err;
    bf_slice_range r;
    bf_slice_range_init(&r);
    /* Measured samples: two in the plane (one each side), one out of it, one at another
     * incidence angle. */
    bf_samples *s = NULL;
    bf_samples_new(4, 1, &s, &err);
    const double ang[4][4] = {{30, 0, 20, 180}, {31, 10, 50, 10}, {30, 0, 45, 90}, {60, 0, 20, 180}};
    for (int q = 0; q < 4; q++) {
        s->theta_i[q] = ang[q][0];
        s->phi_i[q] = ang[q][1];
        s->theta_o[q] = ang[q][2];
        s->phi_o[q] = ang[q][3];
        s->value[q] = 0.5;
    }
    bf_slice_options o = slice_options(200, 150, inc, 1, s, 2.0, NULL, 0.0, 0.0);
    plot *p;
    assert_int_equal(slice_plot_build(m, &rho, &o, &p, &r, &err), BF_OK);
    assert_int_equal(r.overlaid, 2);
    assert_int_equal(r.shown, 2);
    /* The axis covers rho/pi and the samples (0.5), padded, never collapsed. */
    assert_true(r.log10_lo < log10(rho / M_PI) && r.log10_hi > log10(0.5));
    assert_true(r.log10_hi - r.log10_lo < 2.0);
    /* The curve: every point at rho/pi; the samples at +20 and -50. */
    const plot_series *curve = NULL;
    for (int k = 0; k < plot_nseries(p) && !curve; k++)
        if (plot_series_at(p, k)->n == 361)
            curve = plot_series_at(p, k);
    assert_non_null(curve);
    for (size_t i = 0; i < curve->n; i++) /* 0 at grazing view (+-90 degrees) */
        if (fabs(curve->x[i]) < 90.0)
            ts_assert_near(curve->y[i], rho / M_PI, 1e-12, 1e-12, "lambert curve");
    assert_string_equal(curve->name, "\xce\xb8_{i} = 30\xc2\xb0");
    int found = 0;
    for (int k = 0; k < plot_nseries(p); k++) {
        const plot_series *q = plot_series_at(p, k);
        if (q->style == PLOT_MARKERS && q->n == 2) {
            found = 1;
            assert_true((q->x[0] == 20.0 && q->x[1] == -50.0) || (q->x[0] == -50.0 && q->x[1] == 20.0));
            assert_true(q->y[0] == 0.5 && q->y[1] == 0.5);
        }
    }
    assert_true(found);
    plot_layout l;
    assert_int_equal(plot_layout_compute(p, 640, 480, &l), 0);
    /* x: -90..90 every 30 degrees; legend: the incidence and the measured samples. */
    assert_int_equal(l.axis[PLOT_X].ticks.n, 7);
    assert_string_equal(l.axis[PLOT_X].ticks.label[0], "\xe2\x88\x92"
                                                       "90");
    assert_string_equal(l.axis[PLOT_X].ticks.label[6], "90");
    assert_int_equal(l.nlegend, 2);
    plot_free(p);
    /* A shared range is used as given. */
    bf_slice_options shared = slice_options(200, 150, inc, 1, NULL, 2.0, "mine", -3.0, 1.0);
    assert_int_equal(slice_plot_build(m, &rho, &shared, &p, &r, &err), BF_OK);
    assert_true(r.log10_lo == -3.0 && r.log10_hi == 1.0);
    plot_free(p);
    double lo, hi;
    assert_int_equal(bf_slice_extent(m, &rho, &o, &lo, &hi, &err), BF_OK);
    ts_assert_near(lo, log10(rho / M_PI), 1e-12, 1e-12, "extent lo");
    ts_assert_near(hi, log10(0.5), 1e-12, 1e-12, "extent hi");
    bf_samples_free(s);
    bf_model_free(m);
}

/* Slices of measured data: at the incidences it has, the same curves named once, and
 * dense samples thinned to one per degree, drawn under the curves. */
static void test_slice_measured(void **state)
{
    (void)state;
    bf_error err;
    /* Incidences 10.04, 29.96 and 61 degrees (none at 0), 1000 in-plane samples each,
     * every 0.18 degrees of theta_o on the mirror side. */
    const double measured[3] = {10.04, 29.96, 61.0};
    bf_samples *s = NULL;
    bf_samples_new(3000, 1, &s, &err);
    for (size_t q = 0; q < 3000; q++) {
        s->theta_i[q] = measured[q / 1000];
        s->phi_i[q] = 0.0;
        s->theta_o[q] = 0.09 + 0.18 * (double)(q % 500);
        s->phi_o[q] = q % 1000 < 500 ? 180.0 : 0.0;
        s->value[q] = 0.2;
    }
    const double want[3] = {0.0, 30.0, 60.0};
    double inc[BF_SLICE_MAX_INCIDENCE];
    assert_int_equal(bf_slice_incidences(s, want, 3, inc), 3);
    assert_true(inc[0] == 10.0 && inc[1] == 30.0 && inc[2] == 61.0);
    const double near[2] = {0.0, 5.0}; /* both nearest 10.04: one angle */
    assert_int_equal(bf_slice_incidences(s, near, 2, inc), 1);
    assert_int_equal(bf_slice_incidences(NULL, want, 3, inc), 0);
    assert_int_equal(bf_slice_incidences(s, want, 3, inc), 3);

    bf_model *m = ts_model("lambert", 1);
    const double rho = 0.5;
    bf_slice_options o = slice_options(400, 300, inc, 3, s, 1.0, NULL, 0.0, 0.0);
    bf_slice_range r;
    bf_slice_range_init(&r);
    plot *p;
    assert_int_equal(slice_plot_build(m, &rho, &o, &p, &r, &err), BF_OK);
    assert_int_equal(r.overlaid, 3000);
    /* One per degree of theta_o (0..90 on both sides) and incidence: 3 x 180. */
    assert_int_equal(r.shown, 540);
    int curves = 0, last_marker = -1, first_curve = -1;
    for (int k = 0; k < plot_nseries(p); k++) {
        const plot_series *q = plot_series_at(p, k);
        if (q->n == 361) {
            curves++;
            if (first_curve < 0)
                first_curve = k;
            /* Lambert: the three incidences are one curve, named for all three. */
            assert_string_equal(q->name, "\xce\xb8_{i} = 10\xc2\xb0, 30\xc2\xb0, 61\xc2\xb0");
        } else if (q->style == PLOT_MARKERS && q->n > 0)
            last_marker = k;
    }
    assert_int_equal(curves, 1);
    assert_true(last_marker >= 0 && last_marker < first_curve); /* samples under the curve */
    plot_free(p);
    /* The y extent ends a decade under the lowest sample: a curve far below every
     * measurement (here Lambert's 0.16 under samples at 100) does not stretch it. */
    for (size_t q = 0; q < 3000; q++)
        s->value[q] = 100.0;
    double lo, hi;
    assert_int_equal(bf_slice_extent(m, &rho, &o, &lo, &hi, &err), BF_OK);
    assert_true(lo == 1.0 && hi == 2.0);
    /* A glossy model: a curve per incidence, each named alone. */
    bf_model *w = ts_model("walter", 1);
    double x[8];
    bf_model_defaults(w, x);
    assert_int_equal(slice_plot_build(w, x, &o, &p, &r, &err), BF_OK);
    curves = 0;
    for (int k = 0; k < plot_nseries(p); k++)
        if (plot_series_at(p, k)->n == 361)
            assert_null(strchr(plot_series_at(p, k)->name, ',')), curves++;
    assert_int_equal(curves, 3);
    plot_free(p);
    bf_model_free(w);
    bf_model_free(m);
    bf_samples_free(s);
}

/* A glossy slice peaks at the mirror angle, in every channel (dashes tell them apart). */
static void test_slice_peak(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    double x[8];
    bf_model_defaults(m, x);
    const double inc[1] = {40.0};
    bf_error err;
    bf_slice_range r;
    bf_slice_range_init(&r);
    bf_slice_options o = slice_options(361, 240, inc, 1, NULL, 2.0, NULL, 0.0, 0.0);
    plot *p;
    assert_int_equal(slice_plot_build(m, x, &o, &p, &r, &err), BF_OK);
    int curves = 0;
    for (int k = 0; k < plot_nseries(p); k++) {
        const plot_series *c = plot_series_at(p, k);
        if (c->n != 361)
            continue;
        size_t top = 0;
        for (size_t i = 0; i < c->n; i++)
            if (c->y[i] > c->y[top])
                top = i;
        assert_true(fabs(c->x[top] - 40.0) < 3.0);
        assert_true(log10(c->y[top]) <= r.log10_hi);
        assert_int_equal(c->dash, curves); /* solid, dashed, dotted */
        curves++;
    }
    assert_int_equal(curves, 3);
    plot_layout l;
    assert_int_equal(plot_layout_compute(p, 640, 480, &l), 0);
    assert_int_equal(l.nlegend, 4); /* the incidence, then channels R, G, B */
    plot_free(p);
    /* The file: a PNG of the size asked for; a bad name or size fails without a file. */
    const char *path = ts_tmp_path("slice.png");
    assert_int_equal(bf_render_slice(m, x, &o, path, BF_PLOT_BY_NAME, NULL, &err), BF_OK);
    bf_image img;
    bf_image_init(&img);
    assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
    assert_int_equal(img.width, 361);
    assert_int_equal(img.height, 240);
    bf_image_clear(&img);
    assert_int_equal(bf_render_slice(m, x, &o, ts_tmp_path("slice.gif"), BF_PLOT_BY_NAME, NULL, &err), BF_ERR_ARG);
    assert_int_equal(access(ts_tmp_path("slice.gif"), F_OK), -1);
    bf_slice_options tiny = slice_options(10, 10, inc, 1, NULL, 2.0, NULL, 0.0, 0.0);
    assert_int_equal(bf_render_slice(m, x, &tiny, ts_tmp_path("t.png"), BF_PLOT_BY_NAME, NULL, &err), BF_ERR_ARG);
    bf_model_free(m);
}

/* PNG: sRGB-encoded 8-bit codes; errors leave no file. */
static void test_png_and_errors(void **state)
{
    (void)state;
    const float rgb[2 * 1 * 3] = {0.0f, 0.5f, 1.0f, 2.0f, -1.0f, 0.0031308f};
    bf_error err;
    const char *path = ts_tmp_path("two.png");
    assert_int_equal(bf_image_write_rgb(path, 2, 1, rgb, &err), BF_OK);
    bf_image img;
    bf_image_init(&img);
    assert_int_equal(bf_image_read(path, &img, &err), BF_OK);
    assert_int_equal(img.width, 2);
    assert_int_equal(img.height, 1);
    const float want[6] = {0.0f, 188.0f, 255.0f, 255.0f, 0.0f, 10.0f};
    for (int q = 0; q < 6; q++)
        ts_assert_near(img.pixels[q] * 255.0, want[q], 0, 1e-3, "png code");
    bf_image_clear(&img);
    assert_int_equal(access(path, R_OK), 0);
    assert_int_equal(bf_image_write_rgb(ts_tmp_path("x.jpg"), 2, 1, rgb, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "x.jpg"));
    assert_int_equal(bf_image_write_rgb("/nonexistent-dir/x.exr", 2, 1, rgb, &err), BF_ERR_IO);
    assert_non_null(strstr(err.msg, "/nonexistent-dir/x.exr"));
    assert_null(strchr(err.msg, '\n'));
    assert_int_not_equal(bf_image_read(ts_tmp_path("missing.exr"), &img, &err), BF_OK);
    assert_null(img.pixels);
}

static void test_tonemap(void **state)
{
    (void)state;
    float v[4] = {0.0f, 1.0f, 10.0f, 1000.0f};
    bf_tonemap(v, 4, BF_TONEMAP_LOG, 1.0, 4.0);
    assert_true(v[0] == 0.0f && v[3] == 1.0f);
    ts_assert_near(v[1], 0.25, 1e-6, 0, "1 is 3 decades below 1000");
    float w[2] = {1.0f, 3.0f};
    bf_tonemap(w, 2, BF_TONEMAP_REINHARD, 2.0, 0);
    ts_assert_near(w[0], 2.0 / 3.0, 1e-6, 0, "reinhard");
    ts_assert_near(w[1], 6.0 / 7.0, 1e-6, 0, "reinhard");
}

/* Structs the caller allocates carry their size (docs/api.md): the init functions set it
 * and the defaults; one not set up is refused, naming the struct, before anything else. */
static void test_sized_structs(void **state)
{
    (void)state;
    bf_error err;
    bf_sphere_options so;
    bf_sphere_options_init(&so);
    assert_true(so.size == sizeof so && so.resolution == 256 && so.nlights == 1);
    assert_true(so.view.theta == 0.0 && so.lights[0].theta == 45.0 && so.lights[0].phi == 0.0);
    bf_slice_options sl;
    bf_slice_options_init(&sl);
    assert_true(sl.size == sizeof sl && sl.width == 640 && sl.height == 480 && sl.nincidence == 3);
    assert_true(sl.incidence[0] == 0.0 && sl.incidence[1] == 30.0 && sl.incidence[2] == 60.0);
    assert_true(sl.plane_tol == 2.0 && !sl.samples && !sl.title && sl.log10_lo == 0.0 && sl.log10_hi == 0.0);
    bf_model *m = ts_model("lambert", 1);
    const double rho = 0.5;
    float rgb[4 * 4 * 3];
    bf_sphere_options zero_sphere = {0};
    assert_int_equal(bf_render_sphere(m, &rho, &zero_sphere, rgb, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_sphere_options"));
    bf_slice_options zero_slice = {0};
    double lo, hi;
    assert_int_equal(bf_slice_extent(m, &rho, &zero_slice, &lo, &hi, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_slice_options"));
    assert_int_equal(bf_render_slice(m, &rho, &zero_slice, ts_tmp_path("z.svg"), BF_PLOT_BY_NAME, NULL, &err),
                     BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_slice_options"));
    bf_slice_range zero_range = {0};
    assert_int_equal(bf_render_slice(m, &rho, &sl, ts_tmp_path("z.svg"), BF_PLOT_BY_NAME, &zero_range, &err),
                     BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_slice_range"));
    assert_int_equal(access(ts_tmp_path("z.svg"), F_OK), -1);
    /* The defaults draw: 640x480 slices at 0, 30 and 60 degrees. */
    bf_slice_range r;
    bf_slice_range_init(&r);
    assert_int_equal(bf_render_slice(m, &rho, &sl, ts_tmp_path("d.svg"), BF_PLOT_BY_NAME, &r, &err), BF_OK);
    assert_true(r.size == sizeof r && r.log10_lo < log10(rho / M_PI) && r.log10_hi > log10(rho / M_PI));
    /* Images: refused before the module is needed; clearing an empty one is harmless. */
    bf_image zero_image = {0};
    assert_int_equal(bf_image_read(ts_tmp_path("missing.exr"), &zero_image, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_image"));
    assert_int_equal(bf_image_read_rows(ts_tmp_path("missing.exr"), 0, 1, &zero_image, &err), BF_ERR_ARG);
    bf_image_clear(&zero_image);
    bf_image_spec zero_spec = {0};
    assert_int_equal(bf_image_info(ts_tmp_path("missing.exr"), &zero_spec, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "bf_image_spec"));
    bf_image img;
    bf_image_init(&img);
    bf_image_spec sp;
    bf_image_spec_init(&sp);
    assert_true(img.size == sizeof img && !img.pixels && sp.size == sizeof sp && sp.width == 0);
    bf_model_free(m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sphere_lambert_exr), cmocka_unit_test(test_sphere_lighting),
        cmocka_unit_test(test_halfdiff_dirs_merl), cmocka_unit_test(test_halfdiff_model),
        cmocka_unit_test(test_halfdiff_merl),      cmocka_unit_test(test_slice_lambert),
        cmocka_unit_test(test_slice_measured),     cmocka_unit_test(test_slice_peak),
        cmocka_unit_test(test_png_and_errors),     cmocka_unit_test(test_tonemap),
        cmocka_unit_test(test_sized_structs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
