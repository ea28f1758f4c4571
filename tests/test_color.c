/* Colorimetry (brdfit/color.h, bf_prep.color): white points of the CIE tables, neutral
 * spectra to neutral RGB, the RGB matrices against their published forms, and
 * ColorChecker spectra against BabelColor's published chromaticities
 * (tests/data/colorchecker/SOURCE.txt). */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/color.h"
#include "brdfit/prep.h"
#include "support.h"

#define NW 31 /* Cornell's grid: 400, 410, ..., 700 nm */

static void grid(double *wl)
{
    for (int i = 0; i < NW; i++)
        wl[i] = 400.0 + 10.0 * i;
}

/* out = W v for weights W of n channels. */
static void apply(const double *w, int n, const double *v, double out[3])
{
    for (int k = 0; k < 3; k++) {
        out[k] = 0.0;
        for (int i = 0; i < n; i++)
            out[k] += w[k * n + i] * v[i];
    }
}

/* The XYZ weights and those of space c on the Cornell grid, under D65. */
static void d65_weights(bf_color c, double *w_xyz, double *w_c)
{
    double wl[NW];
    grid(wl);
    assert_int_equal(bf_color_weights(wl, NW, BF_COLOR_XYZ, BF_ILLUMINANT_D65, w_xyz, NULL), BF_OK);
    assert_int_equal(bf_color_weights(wl, NW, c, BF_ILLUMINANT_D65, w_c, NULL), BF_OK);
}

static void test_white_points(void **state)
{
    (void)state;
    /* The full table grid, so nothing is extrapolated: the sums are the illuminants'
     * white points. CIE 015:2018 gives them to 5 digits from the 1 nm tables; summing
     * the 5 nm tables moves them by up to 2.2e-5 (D65: 0.31271, 0.32901). */
    double wl[95], one[95], w[3 * 95], X[3];
    for (int i = 0; i < 95; i++) {
        wl[i] = 360.0 + 5.0 * i;
        one[i] = 1.0;
    }
    static const struct {
        bf_illuminant ill;
        double x, y;
    } ref[] = {{BF_ILLUMINANT_D65, 0.31272, 0.32903},
               {BF_ILLUMINANT_A, 0.44757, 0.40745},
               {BF_ILLUMINANT_D50, 0.34567, 0.35850},
               {BF_ILLUMINANT_E, 1.0 / 3.0, 1.0 / 3.0}};
    for (size_t r = 0; r < sizeof ref / sizeof ref[0]; r++) {
        assert_int_equal(bf_color_weights(wl, 95, BF_COLOR_XYZ, ref[r].ill, w, NULL), BF_OK);
        apply(w, 95, one, X);
        ts_assert_near(X[1], 1.0, 0.0, 1e-14, "a flat 1 has Y = 1");
        double s = X[0] + X[1] + X[2];
        /* E: the CMFs' own sums differ by 3e-4 relative (CIE 015 quotes x = y = 0.33333
         * at 5 digits only for the 1 nm table). */
        double tol = ref[r].ill == BF_ILLUMINANT_E ? 1e-4 : 3e-5;
        ts_assert_near(X[0] / s, ref[r].x, 0.0, tol, "white x");
        ts_assert_near(X[1] / s, ref[r].y, 0.0, tol, "white y");
    }
}

static void test_flat_is_neutral(void **state)
{
    (void)state;
    double wl[NW], v[NW], w[3 * NW], rgb[3];
    grid(wl);
    for (bf_illuminant ill = BF_ILLUMINANT_D65; ill <= BF_ILLUMINANT_D50; ill++)
        for (bf_color c = BF_COLOR_SRGB; c <= BF_COLOR_ACESCG; c++) {
            assert_int_equal(bf_color_weights(wl, NW, c, ill, w, NULL), BF_OK);
            for (int i = 0; i < NW; i++)
                v[i] = 0.18; /* an 18 % grey card */
            apply(w, NW, v, rgb);
            for (int k = 0; k < 3; k++)
                ts_assert_near(rgb[k], 0.18, 0.0, 1e-14, "flat grey -> neutral grey");
        }
}

/* The XYZ -> RGB matrices (D65 data, D65 sRGB: adaptation nearly the identity) against
 * their published forms: IEC 61966-2-1 Amendment 1 (4 decimals) and ACES TB-2014-004
 * (AP1, ACES white; after Bradford from D65, so compared on a neutral and a primary). */
static void test_srgb_matrix(void **state)
{
    (void)state;
    /* Three narrow spectra give three independent XYZ; their sRGB must be the
     * published matrix applied to their XYZ. */
    double w_xyz[3 * NW], w_rgb[3 * NW];
    d65_weights(BF_COLOR_SRGB, w_xyz, w_rgb);
    static const double M[9] = {3.2406, -1.5372, -0.4986, -0.9689, 1.8758, 0.0415, 0.0557, -0.2040, 1.0570};
    for (int probe = 0; probe < 3; probe++) {
        double v[NW] = {0}, X[3], rgb[3];
        for (int i = 0; i < 5; i++)
            v[probe * 10 + i] = 0.5;
        apply(w_xyz, NW, v, X);
        apply(w_rgb, NW, v, rgb);
        for (int k = 0; k < 3; k++) {
            double ref = M[3 * k] * X[0] + M[3 * k + 1] * X[1] + M[3 * k + 2] * X[2];
            ts_assert_near(rgb[k], ref, 0.0, 2e-4, "sRGB vs IEC 61966-2-1");
        }
    }
}

/* ColorChecker patches (BabelColor average spectra, 380-730 nm every 10 nm) under D50
 * against BabelColor's published x, y, Y (4 decimals): within one unit of the last
 * published digit (measured: 5.6e-5 at most; the rounding alone is 5e-5). */
static void test_colorchecker(void **state)
{
    (void)state;
    char path[512];
    snprintf(path, sizeof path, "%s/colorchecker/babelcolor_average.csv", BRDFIT_TEST_DATA);
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    char line[2048];
    assert_non_null(fgets(line, sizeof line, fp)); /* header */
    double wl[36], w[3 * 36];
    for (int i = 0; i < 36; i++)
        wl[i] = 380.0 + 10.0 * i;
    assert_int_equal(bf_color_weights(wl, 36, BF_COLOR_XYZ, BF_ILLUMINANT_D50, w, NULL), BF_OK);
    int patches = 0;
    while (fgets(line, sizeof line, fp)) {
        char *p = strchr(strchr(line, ',') + 1, ',') + 1; /* past patch, name */
        double ref[3], v[36], X[3];
        for (int k = 0; k < 3; k++)
            ref[k] = strtod(p, &p), p++;
        for (int i = 0; i < 36; i++)
            v[i] = strtod(p, &p), p++;
        apply(w, 36, v, X);
        double s = X[0] + X[1] + X[2];
        const double tol = 1e-4;
        ts_assert_near(X[0] / s, ref[0], 0.0, tol, "ColorChecker x (D50)");
        ts_assert_near(X[1] / s, ref[1], 0.0, tol, "ColorChecker y (D50)");
        ts_assert_near(X[1], ref[2], 0.0, tol, "ColorChecker Y (D50)");
        patches++;
    }
    fclose(fp);
    assert_int_equal(patches, 7);
}

/* ACEScg: a D65 grey stays grey, and the XYZ of the ACES white maps through the AP1
 * matrix of ACES TB-2014-004 (XYZ -> AP1: 1.6410234 -0.3248033 -0.2364247 ...). The
 * probe: a spectrum's ACEScg from D65 equals TB-2014-004's matrix applied to its XYZ
 * after Bradford D65 -> ACES white, the adaptation worked out here independently. */
static void test_acescg(void **state)
{
    (void)state;
    double w_xyz[3 * NW], w_ap1[3 * NW];
    d65_weights(BF_COLOR_ACESCG, w_xyz, w_ap1);
    static const double M[9] = {1.6410234, -0.3248033, -0.2364247, -0.6636629, 1.6153316,
                                0.0167563, 0.0117219,  -0.0082844, 0.9883949};
    static const double B[9] = {0.8951, 0.2664, -0.1614, -0.7502, 1.7135, 0.0367, 0.0389, -0.0685, 1.0296};
    static const double Bi[9] = {0.9869929, -0.1470543, 0.1599627, 0.4323053, 0.5183603,
                                 0.0492912, -0.0085287, 0.0400428, 0.9684867};
    double one[NW], ws[3], wd[3] = {0.32168 / 0.33767, 1.0, (1.0 - 0.32168 - 0.33767) / 0.33767};
    for (int i = 0; i < NW; i++)
        one[i] = 1.0;
    apply(w_xyz, NW, one, ws);
    double cs[3], cd[3];
    for (int k = 0; k < 3; k++) {
        cs[k] = B[3 * k] * ws[0] + B[3 * k + 1] * ws[1] + B[3 * k + 2] * ws[2];
        cd[k] = B[3 * k] * wd[0] + B[3 * k + 1] * wd[1] + B[3 * k + 2] * wd[2];
    }
    double v[NW] = {0};
    for (int i = 20; i < NW; i++)
        v[i] = 0.7; /* a red */
    double X[3], got[3], lms[3], Xa[3];
    apply(w_xyz, NW, v, X);
    apply(w_ap1, NW, v, got);
    for (int k = 0; k < 3; k++)
        lms[k] = (B[3 * k] * X[0] + B[3 * k + 1] * X[1] + B[3 * k + 2] * X[2]) * cd[k] / cs[k];
    for (int k = 0; k < 3; k++)
        Xa[k] = Bi[3 * k] * lms[0] + Bi[3 * k + 1] * lms[1] + Bi[3 * k + 2] * lms[2];
    for (int k = 0; k < 3; k++)
        ts_assert_near(got[k], M[3 * k] * Xa[0] + M[3 * k + 1] * Xa[1] + M[3 * k + 2] * Xa[2], 0.0, 2e-6,
                       "ACEScg vs TB-2014-004");
}

static void test_errors_and_names(void **state)
{
    (void)state;
    double w[12];
    bf_error err;
    const double one[1] = {550}, dup[3] = {500, 600, 500}, uv[2] = {200, 300}, bad[2] = {500, NAN};
    assert_int_equal(bf_color_weights(one, 1, BF_COLOR_SRGB, BF_ILLUMINANT_D65, w, &err), BF_ERR_ARG);
    assert_int_equal(bf_color_weights(dup, 3, BF_COLOR_SRGB, BF_ILLUMINANT_D65, w, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "500 nm appears twice"));
    assert_int_equal(bf_color_weights(uv, 2, BF_COLOR_XYZ, BF_ILLUMINANT_D65, w, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "outside the visible"));
    assert_int_equal(bf_color_weights(bad, 2, BF_COLOR_XYZ, BF_ILLUMINANT_D65, w, &err), BF_ERR_ARG);
    assert_int_equal(bf_color_weights(dup, 2, BF_COLOR_NONE, BF_ILLUMINANT_D65, w, &err), BF_ERR_ARG);
    bf_color c = BF_COLOR_NONE;
    bf_illuminant ill = BF_ILLUMINANT_D65;
    assert_int_equal(bf_color_parse("sRGB", &c, &err), BF_OK);
    assert_int_equal(c, BF_COLOR_SRGB);
    assert_int_equal(bf_color_parse("none", &c, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "srgb, acescg, xyz"));
    assert_int_equal(bf_illuminant_parse("A", &ill, &err), BF_OK);
    assert_int_equal(ill, BF_ILLUMINANT_A);
    assert_int_equal(bf_illuminant_parse("d75", &ill, &err), BF_ERR_ARG);
    assert_string_equal(bf_color_name(BF_COLOR_ACESCG), "acescg");
    assert_string_equal(bf_illuminant_name(BF_ILLUMINANT_E), "e");
}

/* Through bf_samples_prep: unsorted wavelength names, the channel names it gives, and
 * the refusals (no wavelengths, bands with colour, an illuminant alone). */
static void test_prep_color(void **state)
{
    (void)state;
    const int C = 4;
    bf_samples *s = NULL;
    bf_samples_new(2, C, &s, NULL);
    const char *names[4] = {"650nm", "450", "550 nm", "700"};
    for (int c = 0; c < C; c++) {
        bf_samples_set_channel_name(s, c, names[c], NULL);
        for (size_t i = 0; i < 2; i++)
            s->value[i * (size_t)C + (size_t)c] = 0.25 * (double)(i + 1);
    }
    bf_prep p = {.color = BF_COLOR_SRGB, .illuminant = BF_ILLUMINANT_A};
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[0], "r");
    assert_string_equal(s->channel_names[2], "b");
    for (int k = 0; k < 3; k++) {
        ts_assert_near(s->value[k], 0.25, 0.0, 1e-14, "flat sample 0");
        ts_assert_near(s->value[3 + k], 0.5, 0.0, 1e-14, "flat sample 1");
    }
    bf_samples_free(s);

    bf_error err;
    bf_samples_new(1, 5, &s, NULL); /* channels c0..c4: no wavelengths */
    p = (bf_prep){.color = BF_COLOR_XYZ};
    assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "cannot make XYZ"));
    p = (bf_prep){.color = BF_COLOR_SRGB, .to_bands = 1};
    assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_ARG);
    p = (bf_prep){.to_bands = 1, .illuminant = BF_ILLUMINANT_E};
    assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "illuminant (e)"));
    assert_int_equal(s->channels, 5);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_white_points), cmocka_unit_test(test_flat_is_neutral),
        cmocka_unit_test(test_srgb_matrix),  cmocka_unit_test(test_colorchecker),
        cmocka_unit_test(test_acescg),       cmocka_unit_test(test_errors_and_names),
        cmocka_unit_test(test_prep_color),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
