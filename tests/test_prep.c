/* Preprocessing: channel selection, spectral to RGB and luminance, the drops and their
 * counts, and the seeded stratified subsample. Hand-built sample sets; each sample's
 * weight holds its original index, so the kept samples can be named exactly. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/prep.h"
#include "support.h"

/* n samples of C channels, all at (30, 0, 40, 180) degrees; value[i*C+c] = 10 i + c;
 * weight[i] = i (a marker that bf_samples_keep carries along). */
static bf_samples *make(size_t n, int C)
{
    bf_samples *s = NULL;
    bf_samples_new(n, C, &s, NULL);
    assert_non_null(s);
    assert_int_equal(bf_samples_add_weights(s, NULL), BF_OK);
    for (size_t i = 0; i < n; i++) {
        s->theta_i[i] = 30;
        s->phi_i[i] = 0;
        s->theta_o[i] = 40;
        s->phi_o[i] = 180;
        s->weight[i] = (double)i;
        for (int c = 0; c < C; c++)
            s->value[i * (size_t)C + (size_t)c] = 10.0 * (double)i + c;
    }
    return s;
}

/* In-plane pair with the given half and difference angles (degrees): L at theta_h +
 * theta_d on one side of N, V at theta_d - theta_h on the other. */
static void set_half_diff(bf_samples *s, size_t i, double th, double td)
{
    s->theta_i[i] = td + th;
    s->phi_i[i] = 0;
    s->theta_o[i] = td - th;
    s->phi_o[i] = 180;
}

static void give_origin(bf_samples *s)
{
    s->merl = calloc(1, sizeof *s->merl);
    s->merl->raw = calloc(3 * (size_t)BF_MERL_CELLS, sizeof *s->merl->raw);
    s->merl->cell = calloc(s->n + 1, sizeof *s->merl->cell);
    for (size_t i = 0; i < s->n; i++)
        s->merl->cell[i] = (int32_t)i;
}

static void assert_kept(const bf_samples *s, const size_t *want, size_t n)
{
    assert_int_equal(s->n, n);
    for (size_t i = 0; i < n; i++)
        assert_true(s->weight[i] == (double)want[i]);
}

/* ---- Channel selection ------------------------------------------------------------ */

static void test_select_names_and_indices(void **state)
{
    (void)state;
    bf_samples *s = make(2, 3);
    give_origin(s);
    bf_prep p = {.channels = "b, 0"};
    bf_prep_report r;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_int_equal(s->channels, 2);
    assert_string_equal(s->channel_names[0], "b");
    assert_string_equal(s->channel_names[1], "r");
    assert_true(s->value[0] == 2 && s->value[1] == 0 && s->value[2] == 12 && s->value[3] == 10);
    assert_null(s->merl->raw); /* channels changed: the raw table no longer describes the data */
    assert_int_equal(r.read, 2);
    assert_int_equal(r.kept, 2);
    bf_samples_free(s);

    /* Every channel in its own order changes nothing, so a MERL table can be written back. */
    s = make(2, 3);
    give_origin(s);
    p.channels = "r,1,b";
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_non_null(s->merl);
    assert_int_equal(s->channels, 3);
    assert_true(s->value[4] == 11);
    bf_samples_free(s);
}

static void test_select_spectral(void **state)
{
    (void)state;
    bf_samples *s = make(1, 5);
    s->wavelength = malloc(5 * sizeof *s->wavelength);
    for (int c = 0; c < 5; c++) {
        char name[8];
        snprintf(name, sizeof name, "%d", 400 + 50 * c);
        assert_int_equal(bf_samples_set_channel_name(s, c, name, NULL), BF_OK);
        s->wavelength[c] = 400 + 50 * c;
    }
    /* "600" is a name (channel 4); "1" is no name, so an index (450 nm). */
    bf_prep p = {.channels = "600,1"};
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_int_equal(s->channels, 2);
    assert_string_equal(s->channel_names[0], "600");
    assert_string_equal(s->channel_names[1], "450");
    assert_true(s->wavelength[0] == 600 && s->wavelength[1] == 450);
    assert_true(s->value[0] == 4 && s->value[1] == 1);
    bf_samples_free(s);
}

static void test_select_errors(void **state)
{
    (void)state;
    const char *bad[] = {"x", "3", "r,r", "r,,g", "r,0", ""};
    const char *says[] = {"'x'", "'3'", "twice", "empty", "twice", "empty"};
    for (int k = 0; k < 6; k++) {
        bf_samples *s = make(2, 3);
        bf_prep p = {.channels = bad[k]};
        bf_error err;
        assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_ARG);
        if (!strstr(err.msg, says[k]))
            fail_msg("'%s': message '%s' lacks %s", bad[k], err.msg, says[k]);
        assert_null(strchr(err.msg, '\n'));
        assert_int_equal(s->channels, 3); /* nothing changed */
        assert_true(s->value[5] == 12);
        bf_samples_free(s);
    }
    bf_samples *s = make(1, 3);
    bf_prep p = {.channels = "q"};
    bf_error err;
    bf_samples_prep(s, &p, NULL, &err);
    assert_non_null(strstr(err.msg, "r, g, b")); /* names the channels there are */
    bf_samples_free(s);
}

/* ---- Spectral to RGB, luminance ----------------------------------------------------- */

/* Spectral set: channel c at wavelength w0 + 10 c, value (i + 1) * wavelength. */
static bf_samples *make_spectral(int C, double w0, int set_wavelengths)
{
    bf_samples *s = make(2, C);
    if (set_wavelengths)
        s->wavelength = malloc((size_t)C * sizeof *s->wavelength);
    for (int c = 0; c < C; c++) {
        char name[16];
        snprintf(name, sizeof name, "%g", w0 + 10 * c);
        bf_samples_set_channel_name(s, c, name, NULL);
        if (set_wavelengths)
            s->wavelength[c] = w0 + 10 * c;
        for (size_t i = 0; i < 2; i++)
            s->value[i * (size_t)C + (size_t)c] = (double)(i + 1) * (w0 + 10 * c);
    }
    return s;
}

static void assert_rgb(bf_samples *s, double r, double g, double b)
{
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[0], "r");
    assert_string_equal(s->channel_names[1], "g");
    assert_string_equal(s->channel_names[2], "b");
    assert_null(s->wavelength);
    for (size_t i = 0; i < s->n; i++) {
        double k = (double)(i + 1);
        ts_assert_rel(s->value[3 * i + 0], k * r, 1e-15, "r");
        ts_assert_rel(s->value[3 * i + 1], k * g, 1e-15, "g");
        ts_assert_rel(s->value[3 * i + 2], k * b, 1e-15, "b");
    }
}

static void test_rgb_by_wavelength(void **state)
{
    (void)state;
    bf_prep p = {.to_bands = 1};
    /* 400..700 nm as Cornell: b = 400..490 (mean 445), g = 500..590 (545), r = 600..700 (650). */
    bf_samples *s = make_spectral(31, 400, 1);
    give_origin(s);
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_rgb(s, 650, 545, 445);
    assert_null(s->merl->raw);
    bf_samples_free(s);
    /* 380..720: the channels outside 400-700 nm count in no band. */
    s = make_spectral(35, 380, 1);
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_rgb(s, 650, 545, 445);
    bf_samples_free(s);
    /* No wavelength array, but numeric channel names (a CSV with wavelength headers). */
    s = make_spectral(31, 400, 0);
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_rgb(s, 650, 545, 445);
    bf_samples_free(s);
    s = make(1, 4);
    const char *names[4] = {"450nm", "550", "650 nm", "750"};
    for (int c = 0; c < 4; c++)
        bf_samples_set_channel_name(s, c, names[c], NULL);
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_true(s->value[0] == 2 && s->value[1] == 1 && s->value[2] == 0);
    bf_samples_free(s);
}

static void test_rgb_by_index_groups(void **state)
{
    (void)state;
    /* 7 channels c0..c6 (value = index for sample 0): b = {0,1}, g = {2,3}, r = {4,5,6}. */
    bf_samples *s = make(2, 7);
    bf_prep p = {.to_bands = 1};
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_int_equal(s->channels, 3);
    assert_true(s->value[0] == 5.0 && s->value[1] == 2.5 && s->value[2] == 0.5);
    assert_true(s->value[3] == 15.0 && s->value[4] == 12.5 && s->value[5] == 10.5);
    bf_samples_free(s);
}

static void test_rgb_errors(void **state)
{
    (void)state;
    bf_prep p = {.to_bands = 1};
    bf_error err;
    bf_samples *s = make(1, 3); /* already r, g, b */
    assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "spectral"));
    bf_samples_free(s);
    s = make_spectral(10, 300, 1); /* 300-390 nm: no band covered */
    assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "600-700 nm"));
    assert_non_null(strstr(err.msg, "300-390 nm"));
    assert_int_equal(s->channels, 10);
    bf_samples_free(s);
}

static void test_luminance(void **state)
{
    (void)state;
    bf_prep p = {.to_luminance = 1};
    bf_samples *s = make(2, 3); /* r, g, b = 10i, 10i+1, 10i+2 */
    give_origin(s);
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_int_equal(s->channels, 1);
    assert_string_equal(s->channel_names[0], "luminance");
    ts_assert_rel(s->value[0], 0.7152 + 2 * 0.0722, 1e-15, "Rec. 709 Y");
    ts_assert_rel(s->value[1], 10 * 0.2126 + 11 * 0.7152 + 12 * 0.0722, 1e-15, "Rec. 709 Y");
    assert_null(s->merl->raw);
    bf_samples_free(s);
    /* Weights follow the names, not the order. */
    s = make(1, 3);
    bf_samples_set_channel_name(s, 0, "B", NULL);
    bf_samples_set_channel_name(s, 2, "R", NULL);
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    ts_assert_rel(s->value[0], 0.7152 + 2 * 0.2126, 1e-15, "Rec. 709 Y, b,g,r order");
    bf_samples_free(s);
    /* Anything else without wavelengths: the mean of the channels. */
    s = make(2, 4); /* channels named c0..c3: values 10i + c */
    for (int c = 0; c < 4; c++) {
        char name[8];
        snprintf(name, sizeof name, "c%d", c);
        bf_samples_set_channel_name(s, c, name, NULL);
    }
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_string_equal(s->channel_names[0], "mean");
    ts_assert_rel(s->value[0], 1.5, 1e-15, "mean");
    ts_assert_rel(s->value[1], 11.5, 1e-15, "mean");
    bf_samples_free(s);
    /* One channel: unchanged. */
    s = make(2, 1);
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    assert_string_equal(s->channel_names[0], "value");
    assert_true(s->value[1] == 10);
    bf_samples_free(s);
    /* Spectral -> RGB -> Rec. 709 luminance. */
    s = make_spectral(31, 400, 1);
    p.to_bands = 1;
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    ts_assert_rel(s->value[0], 0.2126 * 650 + 0.7152 * 545 + 0.0722 * 445, 1e-15, "spectral Y");
    bf_samples_free(s);
}

/* Spectral data with wavelengths: --luminance is CIE Y under the illuminant, the Y of
 * --color xyz, and a flat spectrum v gives v (the reflectance normalisation). */
static void test_luminance_spectral(void **state)
{
    (void)state;
    static const bf_illuminant ills[] = {BF_ILLUMINANT_D65, BF_ILLUMINANT_E, BF_ILLUMINANT_A, BF_ILLUMINANT_D50};
    for (size_t k = 0; k < sizeof ills / sizeof ills[0]; k++) {
        bf_prep lum = {.to_luminance = 1, .illuminant = ills[k]}, xyz = {.color = BF_COLOR_XYZ, .illuminant = ills[k]};
        bf_samples *a = make_spectral(41, 380, 1), *b = make_spectral(41, 380, 1), *flat = make_spectral(41, 380, 0);
        for (int c = 0; c < 41; c++)
            flat->value[c] = flat->value[41 + c] = 0.18;
        assert_int_equal(bf_samples_prep(a, &lum, NULL, NULL), BF_OK);
        assert_int_equal(bf_samples_prep(b, &xyz, NULL, NULL), BF_OK);
        assert_int_equal(bf_samples_prep(flat, &lum, NULL, NULL), BF_OK);
        assert_int_equal(a->channels, 1);
        assert_string_equal(a->channel_names[0], "luminance");
        for (int i = 0; i < 2; i++) {
            ts_assert_rel(a->value[i], b->value[3 * i + 1], 1e-14, "luminance = Y of XYZ");
            ts_assert_rel(flat->value[i], 0.18, 1e-13, "flat 18% -> 0.18");
        }
        /* value (i + 1) * wavelength: Y is a weighted mean of 380..780, nearer the
         * green (555 nm) than the ends. */
        assert_true(a->value[0] > 450 && a->value[0] < 650);
        bf_samples_free(a);
        bf_samples_free(b);
        bf_samples_free(flat);
    }
    /* An illuminant with data that is not spectral: an error. */
    bf_prep p = {.to_luminance = 1, .illuminant = BF_ILLUMINANT_A};
    bf_samples *s = make(2, 3);
    bf_error err;
    assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_ARG);
    assert_non_null(strstr(err.msg, "applies only to a colour conversion or the luminance of spectral data"));
    bf_samples_free(s);
}

/* ---- Drops ---------------------------------------------------------------------------- */

/* Ten samples, two channels, each with one reason to go (or none); see the comments. */
static bf_samples *make_mixed(void)
{
    bf_samples *s = make(10, 2);
    for (size_t i = 0; i < 10; i++)
        s->value[2 * i] = s->value[2 * i + 1] = 0.5;
    s->theta_i[1] = 90;          /* 1: on the horizon */
    s->theta_o[2] = 95;          /* 2: below it */
    s->theta_i[3] = 89.99;       /* 3: grazing but above: kept */
    s->value[2 * 4 + 1] = NAN;   /* 4: NaN */
    s->value[2 * 5] = -INFINITY; /* 5: Inf (and below the horizon: counted once) */
    s->theta_i[5] = 95;
    s->theta_i[6] = 70;          /* 6: above max theta 60 (as is 3) */
    s->value[2 * 7] = -0.01;     /* 7: negative */
    s->value[2 * 8 + 1] = -0.02; /* 8: negative and above max theta 60 */
    s->theta_o[8] = 80;
    s->theta_i[9] = nextafter(90.0, 0.0); /* 9: cos < 1e-15: the geometry's horizon */
    return s;
}

static void test_drops(void **state)
{
    (void)state;
    /* The horizon test agrees with the geometry, to the last bit below 90 degrees. */
    bf_samples *s = make_mixed();
    const bf_geometry *g = NULL;
    bf_samples_geometry(s, &g, NULL);
    assert_false(bf_geometry_valid(g, 9));
    assert_true(bf_geometry_valid(g, 3));
    bf_prep_report r;
    bf_prep p = {.max_theta = 60};
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_kept(s, (size_t[]){0, 7}, 2);
    assert_int_equal(r.read, 10);
    assert_int_equal(r.below_horizon, 3);
    assert_int_equal(r.nonfinite, 2);
    assert_int_equal(r.above_max_theta, 3);
    assert_int_equal(r.negative, 1);
    assert_int_equal(r.subsampled_out, 0);
    assert_int_equal(r.kept, 2);
    assert_true(s->value[2] == -0.01); /* kept as data */
    assert_null(s->geom);              /* samples changed: geometry recomputed on use */
    bf_samples_free(s);

    s = make_mixed();
    p.negative = BF_NEGATIVE_DROP;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_kept(s, (size_t[]){0}, 1);
    assert_int_equal(r.negative, 1);
    assert_int_equal(r.kept, 1);
    bf_samples_free(s);

    s = make_mixed();
    p.negative = BF_NEGATIVE_CLAMP;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_kept(s, (size_t[]){0, 7}, 2);
    assert_int_equal(r.negative, 1);
    assert_true(s->value[2] == 0.0 && s->value[3] == 0.5); /* only the negative channel */
    bf_samples_free(s);

    /* No max theta: 6 and 8 stay; both negatives counted. */
    s = make_mixed();
    p = (bf_prep){0};
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_kept(s, (size_t[]){0, 3, 6, 7, 8}, 5);
    assert_int_equal(r.negative, 2);
    assert_int_equal(r.above_max_theta, 0);
    assert_int_equal(r.below_horizon + r.nonfinite + r.kept, r.read);
    bf_samples_free(s);

    /* NULL options: the same defaults. */
    s = make_mixed();
    assert_int_equal(bf_samples_prep(s, NULL, NULL, NULL), BF_OK);
    assert_int_equal(s->n, 5);
    bf_samples_free(s);
}

static void test_drops_keep_origin_cells(void **state)
{
    (void)state;
    /* Dropping samples (not channels) keeps the MERL origin, with their cells invalid. */
    bf_samples *s = make_mixed();
    give_origin(s);
    assert_int_equal(bf_samples_prep(s, NULL, NULL, NULL), BF_OK);
    assert_non_null(s->merl);
    assert_int_equal(s->merl->cell[1], 3);
    assert_true(s->merl->raw[1] == -1.0 && s->merl->raw[BF_MERL_CELLS + 2] == -1.0);
    assert_true(s->merl->raw[3] == 0.0);
    bf_samples_free(s);
}

static void test_no_sample_left(void **state)
{
    (void)state;
    bf_samples *s = make(4, 1);
    for (size_t i = 0; i < 4; i++)
        s->theta_o[i] = 90;
    bf_error err;
    assert_int_equal(bf_samples_prep(s, NULL, NULL, &err), BF_ERR_RANGE);
    assert_non_null(strstr(err.msg, "no sample left"));
    assert_non_null(strstr(err.msg, "4 below the horizon"));
    bf_samples_free(s);

    s = make(3, 1);
    for (size_t i = 0; i < 3; i++)
        s->value[i] = -1;
    bf_prep p = {.negative = BF_NEGATIVE_DROP};
    assert_int_equal(bf_samples_prep(s, &p, NULL, &err), BF_ERR_RANGE);
    assert_non_null(strstr(err.msg, "3 negative (dropped)"));
    bf_samples_free(s);

    s = make(0, 1);
    assert_int_equal(bf_samples_prep(s, NULL, NULL, &err), BF_ERR_RANGE);
    bf_samples_free(s);
}

/* ---- Stratified subsample ----------------------------------------------------------- */

/* Strata the tests place samples in: (theta_h, theta_d) = (1, 10), (20, 30), (40, 47),
 * (5, 60) degrees fall in sqrt-theta_h bins 1, 7, 10, 3 and theta_d bins 0, 2, 4, 5. */
static const double strata[4][2] = {{1, 10}, {20, 30}, {40, 47}, {5, 60}};

/* counts[k] samples in stratum k, interleaved; weight = index; stratum of sample i in
 * which[i] (caller frees). */
static bf_samples *make_strata(const size_t *counts, int K, int **which)
{
    size_t n = 0, left[4];
    for (int k = 0; k < K; k++)
        n += left[k] = counts[k];
    bf_samples *s = make(n, 1);
    *which = malloc(n * sizeof **which);
    size_t i = 0;
    while (i < n)
        for (int k = 0; k < K; k++)
            if (left[k]) {
                left[k]--;
                /* small offsets keep samples distinct without leaving the stratum */
                set_half_diff(s, i, strata[k][0] + 1e-3 * (double)(i % 7), strata[k][1] + 1e-3 * (double)(i % 5));
                (*which)[i++] = k;
            }
    return s;
}

/* Kept count per stratum, after checking that the kept samples keep their order. */
static void kept_per_stratum(const bf_samples *s, const int *which, size_t *got, int K)
{
    for (int k = 0; k < K; k++)
        got[k] = 0;
    for (size_t i = 0; i < s->n; i++) {
        if (i > 0)
            assert_true(s->weight[i] > s->weight[i - 1]);
        got[which[(size_t)s->weight[i]]]++;
    }
}

static void test_subsample_quotas(void **state)
{
    (void)state;
    /* 7, 5, 3 of 15 to 4: exact shares 1.87, 1.33, 0.8 -> floors 1, 1, 0; the two
     * largest remainders (0.87, 0.8) get the two left: 2, 1, 1. */
    int *which;
    size_t counts[3] = {7, 5, 3}, got[3];
    bf_samples *s = make_strata(counts, 3, &which);
    bf_prep p = {.subsample = 4, .seed = 1};
    bf_prep_report r;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_int_equal(s->n, 4);
    assert_int_equal(r.subsampled_out, 11);
    assert_int_equal(r.kept, 4);
    kept_per_stratum(s, which, got, 3);
    assert_int_equal(got[0], 2);
    assert_int_equal(got[1], 1);
    assert_int_equal(got[2], 1);
    bf_samples_free(s);
    free(which);

    /* 500, 300, 137, 63 of 1000 to 100: one each, then 96 in proportion to 499, 299,
     * 136, 62 of 996: 48.10, 28.82, 13.11, 5.98 -> 48, 28, 13, 5 and the two largest
     * remainders: 1 + 48, 1 + 29, 1 + 13, 1 + 6. */
    size_t counts4[4] = {500, 300, 137, 63}, got4[4];
    s = make_strata(counts4, 4, &which);
    p.subsample = 100;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_int_equal(s->n, 100);
    kept_per_stratum(s, which, got4, 4);
    assert_int_equal(got4[0], 49);
    assert_int_equal(got4[1], 30);
    assert_int_equal(got4[2], 14);
    assert_int_equal(got4[3], 7);
    bf_samples_free(s);
    free(which);

    /* Any N: exactly N kept, every stratum within rounding of its share (one each
     * first when N >= 4, then proportional to what is left). */
    for (size_t N = 1; N < 1000; N += 37) {
        s = make_strata(counts4, 4, &which);
        p.subsample = N;
        assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
        assert_int_equal(s->n, N);
        kept_per_stratum(s, which, got4, 4);
        for (int k = 0; k < 4; k++) {
            double share = N >= 4 ? 1.0 + (double)(N - 4) * (double)(counts4[k] - 1) / 996.0
                                  : (double)N * (double)counts4[k] / 1000.0;
            assert_true((double)got4[k] >= floor(share) && (double)got4[k] <= ceil(share));
        }
        bf_samples_free(s);
        free(which);
    }
}

/* A stratum of one sample among a thousand (a highlight caught once) survives a
 * subsample to 10, where its proportional share (0.01) would round to nothing. */
static void test_subsample_keeps_rare_strata(void **state)
{
    (void)state;
    int *which;
    size_t counts[3] = {600, 399, 1}, got[3];
    bf_samples *s = make_strata(counts, 3, &which);
    bf_prep p = {.subsample = 10, .seed = 3};
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    kept_per_stratum(s, which, got, 3);
    assert_int_equal(got[2], 1);
    assert_int_equal(got[0] + got[1], 9);
    bf_samples_free(s);
    free(which);
}

static size_t *subsample_markers(uint64_t seed, size_t N)
{
    int *which;
    size_t counts[4] = {500, 300, 137, 63};
    bf_samples *s = make_strata(counts, 4, &which);
    bf_prep p = {.subsample = N, .seed = seed};
    assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
    size_t *m = malloc(N * sizeof *m);
    for (size_t i = 0; i < N; i++)
        m[i] = (size_t)s->weight[i];
    bf_samples_free(s);
    free(which);
    return m;
}

static void test_subsample_deterministic(void **state)
{
    (void)state;
    size_t *a = subsample_markers(42, 100), *b = subsample_markers(42, 100);
    size_t *c = subsample_markers(43, 100), *d = subsample_markers(0, 100);
    assert_memory_equal(a, b, 100 * sizeof *a);
    assert_memory_not_equal(a, c, 100 * sizeof *a);
    assert_memory_not_equal(a, d, 100 * sizeof *a);
    free(a);
    free(b);
    free(c);
    free(d);
}

/* Within a stratum every sample is equally likely: 12 samples, quota 3, 3000 seeds:
 * each is kept 750 times on average (sd 23.7); allow 5 sd. */
static void test_subsample_uniform(void **state)
{
    (void)state;
    size_t hits[12] = {0};
    for (uint64_t seed = 0; seed < 3000; seed++) {
        bf_samples *s = make(12, 1);
        bf_prep p = {.subsample = 3, .seed = seed};
        assert_int_equal(bf_samples_prep(s, &p, NULL, NULL), BF_OK);
        assert_int_equal(s->n, 3);
        for (size_t i = 0; i < 3; i++)
            hits[(size_t)s->weight[i]]++;
        bf_samples_free(s);
    }
    for (int i = 0; i < 12; i++)
        if (fabs((double)hits[i] - 750.0) > 5 * 23.7)
            fail_msg("sample %d kept %zu times of 3000, expected 750", i, hits[i]);
}

static void test_subsample_more_than_available(void **state)
{
    (void)state;
    /* N at or above what is left after the drops keeps everything. */
    bf_samples *s = make_mixed();
    bf_prep p = {.subsample = 5};
    bf_prep_report r;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_kept(s, (size_t[]){0, 3, 6, 7, 8}, 5);
    assert_int_equal(r.subsampled_out, 0);
    bf_samples_free(s);
    s = make_mixed();
    p.subsample = 1000;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_int_equal(r.kept, 5);
    bf_samples_free(s);
    /* Subsampling runs on what the drops left: 4 of the 5. */
    s = make_mixed();
    p.subsample = 4;
    assert_int_equal(bf_samples_prep(s, &p, &r, NULL), BF_OK);
    assert_int_equal(r.subsampled_out, 1);
    assert_int_equal(r.kept, 4);
    assert_int_equal(r.below_horizon + r.nonfinite + r.subsampled_out + r.kept, r.read);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_select_names_and_indices),
        cmocka_unit_test(test_select_spectral),
        cmocka_unit_test(test_select_errors),
        cmocka_unit_test(test_rgb_by_wavelength),
        cmocka_unit_test(test_rgb_by_index_groups),
        cmocka_unit_test(test_rgb_errors),
        cmocka_unit_test(test_luminance),
        cmocka_unit_test(test_luminance_spectral),
        cmocka_unit_test(test_drops),
        cmocka_unit_test(test_drops_keep_origin_cells),
        cmocka_unit_test(test_no_sample_left),
        cmocka_unit_test(test_subsample_quotas),
        cmocka_unit_test(test_subsample_keeps_rare_strata),
        cmocka_unit_test(test_subsample_deterministic),
        cmocka_unit_test(test_subsample_uniform),
        cmocka_unit_test(test_subsample_more_than_available),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
