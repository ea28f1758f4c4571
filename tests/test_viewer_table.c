/* The report viewer's tables (lib/src/report/html/viewer_table.c): the grid's nodes,
 * a model tabulated at them (the model's own values, none below the horizon), a MERL
 * table's cells interpolated at them, and the stored codes decoded as viewer.js decodes
 * them (zlib inflate, byte planes, running sums, log codes) give the values back within
 * half a code step. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include <cmocka.h>

#include "brdfit/geometry.h"
#include "brdfit/merl.h"
#include "brdfit/render.h"
#include "html/viewer_table.h"
#include "support.h"

/* The base64 payload of a data URI, decoded. */
static unsigned char *unbase64(const char *uri, size_t *n)
{
    const char *p = strchr(uri, ',');
    assert_non_null(p);
    p++;
    size_t len = strlen(p);
    unsigned char *out = malloc(len);
    size_t o = 0;
    unsigned v = 0;
    int bits = 0;
    for (size_t q = 0; q < len && p[q] != '='; q++) {
        const char *tab = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
        const char *at = strchr(tab, p[q]);
        assert_non_null(at);
        v = v << 6 | (unsigned)(at - tab);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out[o++] = (unsigned char)(v >> bits & 0xff);
        }
    }
    *n = o;
    return out;
}

/* viewer.js's decoding of {"lo", "step", "data"}: channels x count values. */
static double *decode(const cJSON *o, int channels, size_t count, size_t run)
{
    size_t zn, total = (size_t)channels * count;
    unsigned char *z = unbase64(cJSON_GetObjectItem(o, "data")->valuestring, &zn);
    uLongf pn = (uLongf)(2 * total);
    unsigned char *planes = malloc(pn);
    assert_int_equal(uncompress(planes, &pn, z, (uLong)zn), Z_OK);
    assert_int_equal(pn, 2 * total);
    uint16_t *codes = malloc(total * sizeof *codes);
    for (size_t q = 0; q < total; q++)
        codes[q] = (uint16_t)(planes[q] << 8 | planes[total + q]);
    for (size_t q = 1; q < total; q++)
        if (q % run)
            codes[q] = (uint16_t)(codes[q] + codes[q - 1]);
    double *v = malloc(total * sizeof *v);
    const cJSON *lo = cJSON_GetObjectItem(o, "lo"), *step = cJSON_GetObjectItem(o, "step");
    for (size_t q = 0; q < total; q++) {
        int c = (int)(q / count);
        double l = cJSON_GetArrayItem(lo, c)->valuedouble, s = cJSON_GetArrayItem(step, c)->valuedouble;
        v[q] = codes[q] == 0 ? NAN : codes[q] == 1 ? 0.0 : exp(l + (codes[q] - 2) * s);
    }
    free(z);
    free(planes);
    free(codes);
    return v;
}

static void test_nodes(void **state)
{
    (void)state;
    double th, td, pd;
    viewer_node_angles(0, 0, 0, &th, &td, &pd);
    assert_true(th == 0.0 && td == 0.0 && pd == 0.0);
    viewer_node_angles(VIEWER_NH - 1, VIEWER_ND - 1, VIEWER_NP - 1, &th, &td, &pd);
    assert_float_equal(th, M_PI / 2, 1e-15);
    assert_float_equal(td, M_PI / 2, 1e-15);
    assert_float_equal(pd, M_PI / 2, 1e-15);
    /* Square-root spacing: the first step in theta_h is tiny, the last large. */
    viewer_node_angles(1, 0, 0, &th, &td, &pd);
    assert_float_equal(th, M_PI / 2 / ((VIEWER_NH - 1.0) * (VIEWER_NH - 1.0)), 1e-15);
}

/* A walter model: the table holds its values at the nodes, NaN exactly below the horizon,
 * and the codes give them back within half a log step. */
static void test_model_round_trip(void **state)
{
    (void)state;
    bf_model *m = ts_model("walter", 3);
    const double x[8] = {0.5, 0.3, 0.1, 0.6, 0.6, 0.6, 0.05, 0.04};
    assert_int_equal(bf_model_nvalues(m), 8);
    double *v = malloc(3 * VIEWER_NODES * sizeof *v);
    bf_error err;
    assert_int_equal(viewer_table_model(m, x, v, &err), BF_OK);
    size_t none = 0;
    for (size_t q = 0; q < VIEWER_NODES; q++) {
        int i = (int)(q % VIEWER_NH), j = (int)(q / VIEWER_NH % VIEWER_ND), k = (int)(q / (VIEWER_NH * VIEWER_ND));
        double th, td, pd, L[3], V[3], f[3];
        viewer_node_angles(i, j, k, &th, &td, &pd);
        bf_halfdiff_dirs(th, td, pd, L, V);
        bf_geometry *g;
        assert_int_equal(bf_geometry_from_vectors(1, L, V, &g, &err), BF_OK);
        bf_model_eval(m, x, g, f, NULL);
        if (!bf_geometry_valid(g, 0)) {
            assert_true(isnan(v[q]));
            none++;
        } else {
            for (int c = 0; c < 3; c++)
                assert_float_equal(v[(size_t)c * VIEWER_NODES + q], f[c], 1e-12 * fabs(f[c]));
        }
        bf_geometry_free(g);
    }
    assert_true(none > 0 && none < VIEWER_NODES / 2);

    cJSON *o = viewer_encode(v, 3, VIEWER_NODES, VIEWER_NH, &err);
    assert_non_null(o);
    double *back = decode(o, 3, VIEWER_NODES, VIEWER_NH);
    for (size_t q = 0; q < 3 * VIEWER_NODES; q++) {
        if (isnan(v[q])) {
            assert_true(isnan(back[q]));
            continue;
        }
        double s = cJSON_GetArrayItem(cJSON_GetObjectItem(o, "step"), (int)(q / VIEWER_NODES))->valuedouble;
        assert_true(fabs(log(back[q] / v[q])) <= 0.5 * s + 1e-12);
    }
    /* Smooth tables shrink: under a third of the 16-bit codes' size. */
    size_t zn;
    free(unbase64(cJSON_GetObjectItem(o, "data")->valuestring, &zn));
    assert_true(zn < 2 * 3 * VIEWER_NODES / 3);
    free(back);
    cJSON_Delete(o);
    free(v);
    bf_model_free(m);
}

/* Zeros and no values keep their own codes; a constant channel is exact. */
static void test_special_values(void **state)
{
    (void)state;
    const double v[8] = {0.0, -1.0, NAN, 2.0, 2.0, 2.0, 2.0, 2.0};
    bf_error err;
    cJSON *o = viewer_encode(v, 2, 4, 4, &err);
    assert_non_null(o);
    double *back = decode(o, 2, 4, 4);
    assert_true(back[0] == 0.0 && back[1] == 0.0 && isnan(back[2]));
    for (int q = 3; q < 8; q++)
        assert_float_equal(back[q], 2.0, 1e-12);
    free(back);
    cJSON_Delete(o);
}

/* A MERL table's cells at the nodes: interpolated between the centres, phi_d periodic. */
static void test_merl(void **state)
{
    (void)state;
    bf_samples *s;
    bf_error err;
    const size_t n = BF_MERL_PD;
    assert_int_equal(bf_samples_new_cells(n, 3, &s, &err), BF_OK);
    /* The cells at theta_h index 0 (the peak column) and theta_d index 0, every phi_d: a
     * ramp 10 + k in phi_d's index k (channel c adds c). */
    for (size_t q = 0; q < n; q++) {
        s->merl->cell[q] = (int32_t)q;
        for (int c = 0; c < 3; c++)
            s->value[q * 3 + (size_t)c] = 10.0 + (double)q + c;
    }
    double *v = malloc(3 * VIEWER_NODES * sizeof *v);
    assert_int_equal(viewer_table_merl(s, v, &err), BF_OK);
    /* Node (0, 0, 0): phi_d 0 lies half way between the centres of cells 179 and 0 (phi_d
     * repeats every 180 degrees). */
    assert_float_equal(v[0], (10.0 + 189.0) / 2, 1e-9);
    assert_float_equal(v[2 * VIEWER_NODES], (12.0 + 191.0) / 2, 1e-9);
    /* Node (0, 0, 1): phi_d 90/11 degrees, 7.68 cells from cell 0's centre. */
    const double w = 90.0 / (VIEWER_NP - 1) - 0.5;
    assert_float_equal(v[VIEWER_NH * VIEWER_ND], 10.0 + w, 1e-9);
    /* A node whose cells were not read has no value. */
    assert_true(isnan(v[VIEWER_NH / 2]));
    free(v);
    bf_samples_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nodes),
        cmocka_unit_test(test_model_round_trip),
        cmocka_unit_test(test_special_values),
        cmocka_unit_test(test_merl),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
