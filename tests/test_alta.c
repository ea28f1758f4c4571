/* ALTA text data: the MERL pink-felt slice from ALTA's repository, every supported
 * input parametrisation against the directions it defines, the value units, '#VS'
 * intervals, header leniency, and every kind of bad input. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include "brdfit/formats.h"
#include "brdfit/samples.h"
#include "support.h"

static bf_samples *read_text(const char *name, const char *text)
{
    ts_write_file(ts_tmp_path(name), text, strlen(text));
    bf_samples *s = NULL;
    bf_error err = {0};
    if (bf_samples_read_alta(ts_tmp_path(name), &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    return s;
}

static void assert_close(double got, double want, double tol, const char *what, size_t i)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s (sample %zu): %.17g, want %.17g", what, i, got, want);
}

/* Azimuths agree modulo 360 degrees. */
static void assert_phi(double got, double want, double tol, const char *what, size_t i)
{
    double d = remainder(got - want, 360.0);
    if (!(fabs(d) <= tol))
        fail_msg("%s (sample %zu): %.17g, want %.17g (mod 360)", what, i, got, want);
}

/* Rusinkiewicz angles (radians) of sample i, from its directions: theta_h, phi_h,
 * theta_d and phi_d of L (L brought into the half-vector frame). */
static void half_diff_of(const bf_samples *s, size_t i, double *th, double *ph, double *td, double *pd)
{
    double L[3], V[3], H[3];
    ts_dirs_deg(s->theta_i[i], s->phi_i[i], s->theta_o[i], s->phi_o[i], L, V);
    double len = sqrt(pow(L[0] + V[0], 2) + pow(L[1] + V[1], 2) + pow(L[2] + V[2], 2));
    for (int k = 0; k < 3; k++)
        H[k] = (L[k] + V[k]) / len;
    /* atan2 keeps the precision that acos loses near 0; phi_h is 0 with H on the normal */
    double hr = hypot(H[0], H[1]);
    *th = atan2(hr, H[2]);
    *ph = hr > 1e-12 ? atan2(H[1], H[0]) : 0.0;
    /* rotate L by -phi_h about the normal, then by -theta_h about the binormal */
    double x = L[0] * cos(*ph) + L[1] * sin(*ph), y = -L[0] * sin(*ph) + L[1] * cos(*ph), z = L[2];
    double dx = x * cos(*th) - z * sin(*th), dz = x * sin(*th) + z * cos(*th);
    *td = atan2(hypot(dx, y), dz);
    *pd = atan2(y, dx);
}

/* Two sample sets describe the same configurations up to a rotation about the normal:
 * the same cosines and V.H. */
static void assert_same_geometry(bf_samples *a, bf_samples *b, double tol)
{
    assert_int_equal(a->n, b->n);
    const bf_geometry *ga = ts_samples_geometry(a), *gb = ts_samples_geometry(b);
    assert_non_null(ga);
    assert_non_null(gb);
    for (size_t i = 0; i < a->n; i++) {
        assert_close(gb->lz[i], ga->lz[i], tol, "N.L", i);
        assert_close(gb->vz[i], ga->vz[i], tol, "N.V", i);
        assert_close(gb->hz[i], ga->hz[i], tol, "N.H", i);
        assert_close(gb->vh[i], ga->vh[i], tol, "V.H", i);
    }
}

/* ---- The real file ------------------------------------------------------------- */

/* pink-felt-1d.alta: '#DIM 1 3', COS_TH, RGB_COLOR, 90 tab-separated rows with a
 * trailing tab. An independent fscanf reading gives the expected numbers. */
static void test_pink_felt(void **state)
{
    (void)state;
    const char *path = BRDFIT_TEST_DATA "/alta/pink-felt-1d.alta";
    bf_samples *s = NULL;
    bf_error err = {0};
    if (bf_samples_read_with(path, NULL, &s, &err) != BF_OK) /* by extension */
        fail_msg("%s", err.msg);
    assert_int_equal(s->n, 90);
    assert_int_equal(s->channels, 3);
    assert_string_equal(s->channel_names[0], "r");
    assert_string_equal(s->channel_names[1], "g");
    assert_string_equal(s->channel_names[2], "b");
    assert_null(s->wavelength);
    assert_null(s->weight);
    FILE *fp = fopen(path, "r");
    assert_non_null(fp);
    char line[512];
    size_t i = 0;
    while (fgets(line, sizeof line, fp)) {
        double c, r, g, b;
        if (line[0] == '#')
            continue;
        assert_int_equal(sscanf(line, "%lf %lf %lf %lf", &c, &r, &g, &b), 4);
        assert_true(i < s->n);
        /* COS_TH: theta_d = 0, so L = V = H at theta_h = acos(c), phi = 0 */
        assert_close(s->theta_i[i], acos(c) * 180 / M_PI, 1e-11, "theta_i", i);
        assert_true(s->theta_o[i] == s->theta_i[i]);
        assert_true(s->phi_i[i] == 0.0 && s->phi_o[i] == 0.0);
        assert_true(s->value[3 * i] == r && s->value[3 * i + 1] == g && s->value[3 * i + 2] == b);
        i++;
    }
    fclose(fp);
    assert_int_equal(i, 90);
    /* First row: 0.999984567305837  0.109704419970512 0.0794405192136765 0.0616232864558697 */
    assert_true(s->value[0] == 0.109704419970512 && s->value[2] == 0.0616232864558697);
    assert_close(s->theta_i[0], acos(0.999984567305837) * 180 / M_PI, 1e-11, "first theta_h", 0);
    ts_assert_rel(s->theta_i[89], 84.0, 0.01, "last theta_h (about 84 degrees)");
    bf_samples_free(s);
}

/* ---- Parametrisations ---------------------------------------------------------- */

/* Header for nin = n coordinates in parametrisation `in` and one value in 1/sr. */
#define H(in, n) "#DIM " #n " 1\n#PARAM_IN " in "\n#PARAM_OUT INV_STERADIAN\n"

static const double rusin[][3] = {
    {0.3, 0.5, 1.1}, {0.7, 0.2, -2.0}, {0.05, 1.2, 3.0}, {0.0, 0.4, 0.6}, {1.2, 0.9, 0.0}, {0.3, 0.5, 0.0},
};
#define NR (sizeof rusin / sizeof rusin[0])

static bf_samples *read_rusin(void)
{
    char text[2048] = H("RUSIN_TH_TD_PD", 3);
    for (size_t i = 0; i < NR; i++)
        snprintf(text + strlen(text), sizeof text - strlen(text), "%.17g %.17g %.17g %zu\n", rusin[i][0], rusin[i][1],
                 rusin[i][2], i);
    return read_text("rusin.alta", text);
}

/* RUSIN_TH_TD_PD gives back its angles, with the difference vector being L (the MERL
 * convention of docs/formats.md), not V as ALTA labels it. */
static void test_rusin_convention(void **state)
{
    (void)state;
    bf_samples *s = read_rusin();
    assert_int_equal(s->n, NR);
    for (size_t i = 0; i < NR; i++) {
        double th, ph, td, pd;
        half_diff_of(s, i, &th, &ph, &td, &pd);
        assert_close(th, rusin[i][0], 1e-12, "theta_h", i);
        assert_close(td, rusin[i][1], 1e-12, "theta_d", i);
        if (rusin[i][1] > 0)
            assert_close(remainder(pd - rusin[i][2], 2 * M_PI), 0.0, 1e-12, "phi_d of L", i);
        assert_true(s->value[i] == (double)i);
    }
    /* theta_h 0.3, theta_d 0.5, phi_d 0: L at theta 0.8 in the plane of H, V at 0.2 on
     * the other side of the normal. */
    const size_t k = NR - 1;
    assert_close(s->theta_i[k], 0.8 * 180 / M_PI, 1e-12, "theta_i", k);
    assert_close(s->phi_i[k], 0.0, 1e-12, "phi_i", k);
    assert_close(s->theta_o[k], 0.2 * 180 / M_PI, 1e-12, "theta_o", k);
    assert_phi(s->phi_o[k], 180.0, 1e-12, "phi_o", k);
    /* theta_h + theta_d > 90 degrees: L below the horizon is data, kept */
    assert_true(s->theta_i[4] > 90.0);
    bf_samples_free(s);
}

/* RUSIN_TH_TD_PD rows at MERL cell centres name the directions the MERL reader gives
 * those cells: one convention for both formats. */
static void test_rusin_matches_merl(void **state)
{
    (void)state;
    const int32_t cells[] = {0, 1 + 180 * 3 + 16200 * 2, 179 + 180 * 45 + 16200 * 30, 90 + 180 * 89 + 16200 * 89,
                             7 + 180 * 10 + 16200 * 60};
    const size_t n = sizeof cells / sizeof cells[0];
    char text[2048] = H("RUSIN_TH_TD_PD", 3);
    for (size_t c = 0; c < n; c++) {
        int k = cells[c] % 180, j = cells[c] / 180 % 90, i = cells[c] / 16200;
        double th = pow((i + 0.5) / 90, 2) * M_PI / 2, td = (j + 0.5) / 90 * M_PI / 2, pd = (k + 0.5) / 180 * M_PI;
        snprintf(text + strlen(text), sizeof text - strlen(text), "%.17g %.17g %.17g 1\n", th, td, pd);
    }
    bf_samples *s = read_text("merlcells.alta", text);
    for (size_t c = 0; c < n; c++) {
        double ti, pi_, to, po;
        bf_merl_cell_directions(cells[c], &ti, &pi_, &to, &po);
        assert_close(s->theta_i[c], ti, 1e-11, "theta_i", c);
        assert_close(s->theta_o[c], to, 1e-11, "theta_o", c);
        assert_phi(s->phi_i[c], pi_, 1e-10, "phi_i", c);
        assert_phi(s->phi_o[c], po, 1e-10, "phi_o", c);
        assert_int_equal(bf_merl_cell_of(s->theta_i[c], s->phi_i[c], s->theta_o[c], s->phi_o[c]), cells[c]);
    }
    bf_samples_free(s);
}

/* A CARTESIAN row [V, L] and a SPHERICAL_TL_PL_TV_PV row of the same directions read
 * back as the same geometry as the RUSIN_TH_TD_PD rows. */
static void test_cartesian_and_spherical(void **state)
{
    (void)state;
    bf_samples *r = read_rusin();
    char cart[4096] = H("CARTESIAN", 6), sph[4096] = H("SPHERICAL_TL_PL_TV_PV", 4);
    for (size_t i = 0; i < NR; i++) {
        double L[3], V[3];
        ts_dirs_deg(r->theta_i[i], r->phi_i[i], r->theta_o[i], r->phi_o[i], L, V);
        snprintf(cart + strlen(cart), sizeof cart - strlen(cart), "%.17g %.17g %.17g\t%.17g %.17g %.17g\t%zu\n", V[0],
                 V[1], V[2], L[0], L[1], L[2], i);
        snprintf(sph + strlen(sph), sizeof sph - strlen(sph), "%.17g %.17g %.17g %.17g %zu\n", r->theta_i[i] * DEG,
                 r->phi_i[i] * DEG, r->theta_o[i] * DEG, r->phi_o[i] * DEG, i);
    }
    bf_samples *c = read_text("cart.alta", cart), *s = read_text("sph.alta", sph);
    for (size_t i = 0; i < NR; i++) {
        assert_close(c->theta_i[i], r->theta_i[i], 1e-12, "CARTESIAN theta_i", i);
        assert_close(c->theta_o[i], r->theta_o[i], 1e-12, "CARTESIAN theta_o", i);
        assert_phi(c->phi_i[i], r->phi_i[i], 1e-11, "CARTESIAN phi_i", i);
        assert_phi(c->phi_o[i], r->phi_o[i], 1e-11, "CARTESIAN phi_o", i);
        assert_close(s->theta_i[i], r->theta_i[i], 1e-12, "SPHERICAL theta_i", i);
        assert_close(s->phi_i[i], r->phi_i[i], 1e-12, "SPHERICAL phi_i", i);
        assert_close(s->theta_o[i], r->theta_o[i], 1e-12, "SPHERICAL theta_o", i);
        assert_close(s->phi_o[i], r->phi_o[i], 1e-12, "SPHERICAL phi_o", i);
        assert_true(c->value[i] == (double)i && s->value[i] == (double)i);
    }
    assert_same_geometry(r, c, 1e-14);
    assert_same_geometry(r, s, 1e-14);
    bf_samples_free(r);
    bf_samples_free(c);
    bf_samples_free(s);
}

/* The reduced half/difference forms: RUSIN_TH_TD fixes phi_d at pi/2 (ALTA's
 * params.cpp), COS_TH_TD at 0, COS_TH and RUSIN_VH have theta_d = 0 (L = V = H);
 * RUSIN_TH_PH_TD_PD rotates the pair by phi_h about the normal. */
static void test_reduced_half_diff(void **state)
{
    (void)state;
    double th, ph, td, pd;
    bf_samples *s = read_text("thtd.alta", H("RUSIN_TH_TD", 2) "0.3 0.5 1\n");
    half_diff_of(s, 0, &th, &ph, &td, &pd);
    assert_close(th, 0.3, 1e-12, "theta_h", 0);
    assert_close(td, 0.5, 1e-12, "theta_d", 0);
    assert_close(pd, M_PI / 2, 1e-12, "phi_d", 0);
    bf_samples_free(s);

    char text[512];
    snprintf(text, sizeof text, H("COS_TH_TD", 2) "%.17g %.17g 1\n", cos(0.3), cos(0.5));
    s = read_text("costhtd.alta", text);
    assert_close(s->theta_i[0], 0.8 * 180 / M_PI, 1e-12, "theta_i", 0);
    assert_close(s->theta_o[0], 0.2 * 180 / M_PI, 1e-12, "theta_o", 0);
    assert_phi(s->phi_o[0] - s->phi_i[0], 180.0, 1e-12, "phi_o - phi_i", 0);
    bf_samples_free(s);

    snprintf(text, sizeof text, H("COS_TH", 1) "%.17g 1\n-0.5 2\n", cos(0.3));
    s = read_text("costh.alta", text);
    assert_close(s->theta_i[0], 0.3 * 180 / M_PI, 1e-12, "theta_i", 0);
    assert_true(s->theta_o[0] == s->theta_i[0] && s->phi_i[0] == 0.0 && s->phi_o[0] == 0.0);
    assert_close(s->theta_i[1], 120.0, 1e-12, "theta_h beyond 90 degrees (data below the horizon)", 1);
    bf_samples_free(s);

    snprintf(text, sizeof text, H("RUSIN_VH", 3) "%.17g %.17g %.17g 1\n", sin(0.3) * cos(1.0), sin(0.3) * sin(1.0),
             cos(0.3));
    s = read_text("vh.alta", text);
    assert_close(s->theta_i[0], 0.3 * 180 / M_PI, 1e-12, "theta_i", 0);
    assert_close(s->phi_i[0], 180 / M_PI, 1e-12, "phi_i", 0);
    assert_true(s->theta_o[0] == s->theta_i[0] && s->phi_o[0] == s->phi_i[0]);
    bf_samples_free(s);

    bf_samples *r = read_rusin();
    char text4[2048] = H("RUSIN_TH_PH_TD_PD", 4);
    for (size_t i = 0; i < NR; i++)
        snprintf(text4 + strlen(text4), sizeof text4 - strlen(text4), "%.17g 0.7 %.17g %.17g %zu\n", rusin[i][0],
                 rusin[i][1], rusin[i][2], i);
    s = read_text("thphtdpd.alta", text4);
    for (size_t i = 0; i < NR; i++) {
        assert_close(s->theta_i[i], r->theta_i[i], 1e-12, "theta_i", i);
        assert_close(s->theta_o[i], r->theta_o[i], 1e-12, "theta_o", i);
        if (r->theta_i[i] > 1e-6)
            assert_phi(s->phi_i[i], r->phi_i[i] + 0.7 * 180 / M_PI, 1e-10, "phi_i rotated by phi_h", i);
        if (r->theta_o[i] > 1e-6)
            assert_phi(s->phi_o[i], r->phi_o[i] + 0.7 * 180 / M_PI, 1e-10, "phi_o rotated by phi_h", i);
    }
    bf_samples_free(r);
    bf_samples_free(s);
}

/* The isotropic light/view forms name L and V explicitly: ISOTROPIC_TV_TL_DPHI is
 * (theta_v, theta_l, phi_l) with phi_v = 0, ISOTROPIC_TL_TV_PROJ_DPHI is (theta_l,
 * theta_v cos dphi, theta_v sin dphi) with phi_l = 0 (ALTA's params::to_cartesian). */
static void test_isotropic_forms(void **state)
{
    (void)state;
    bf_samples *a = read_text("tvtl.alta", H("ISOTROPIC_TV_TL_DPHI", 3) "0.4 0.9 2 5\n");
    assert_close(a->theta_o[0], 0.4 * 180 / M_PI, 1e-12, "theta_o", 0);
    assert_true(a->phi_o[0] == 0.0);
    assert_close(a->theta_i[0], 0.9 * 180 / M_PI, 1e-12, "theta_i", 0);
    assert_close(a->phi_i[0], 2 * 180 / M_PI, 1e-12, "phi_i", 0);
    char text[512];
    snprintf(text, sizeof text, H("ISOTROPIC_TL_TV_PROJ_DPHI", 3) "0.9 %.17g %.17g 5\n0.2 0 0 6\n", 0.4 * cos(-2.0),
             0.4 * sin(-2.0));
    bf_samples *b = read_text("proj.alta", text);
    assert_close(b->theta_i[0], 0.9 * 180 / M_PI, 1e-12, "theta_i", 0);
    assert_true(b->phi_i[0] == 0.0);
    assert_close(b->theta_o[0], 0.4 * 180 / M_PI, 1e-12, "theta_o", 0);
    assert_close(b->phi_o[0], -2 * 180 / M_PI, 1e-12, "phi_o", 0);
    assert_true(b->theta_o[1] == 0.0 && b->phi_o[1] == 0.0); /* V on the normal */
    bf_samples *c = read_text("sph1.alta", H("SPHERICAL_TL_PL_TV_PV", 4) "0.9 2 0.4 0 5\n");
    const unsigned char first[2] = {1, 0};
    assert_int_equal(bf_samples_keep(b, first, NULL), BF_OK);
    assert_same_geometry(c, a, 1e-14);
    assert_same_geometry(c, b, 1e-14);
    bf_samples_free(a);
    bf_samples_free(b);
    bf_samples_free(c);
}

/* ---- Values -------------------------------------------------------------------- */

static void test_outputs(void **state)
{
    (void)state;
    const char *row = "0.1 0 0.2 3 ";
    char text[512];
    struct {
        const char *out;
        int n;
        const char *names[3];
    } cases[] = {
        {"INV_STERADIAN", 1, {"value"}},   {"INV_STERADIAN", 2, {"c0", "c1"}}, {"INV_STERADIAN", 3, {"c0", "c1", "c2"}},
        {"RGB_COLOR", 3, {"r", "g", "b"}}, {"XYZ_COLOR", 3, {"X", "Y", "Z"}},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        snprintf(text, sizeof text, "#DIM 4 %d\n#PARAM_IN SPHERICAL_TL_PL_TV_PV\n#PARAM_OUT %s\n%s", cases[k].n,
                 cases[k].out, row);
        for (int c = 0; c < cases[k].n; c++)
            snprintf(text + strlen(text), sizeof text - strlen(text), "%g ", -0.5 + c);
        strcat(text, "\n");
        bf_samples *s = read_text("out.alta", text);
        assert_int_equal(s->channels, cases[k].n);
        for (int c = 0; c < cases[k].n; c++) {
            assert_string_equal(s->channel_names[c], cases[k].names[c]);
            assert_true(s->value[c] == -0.5 + c); /* negative values are data */
        }
        bf_samples_free(s);
    }
}

/* INV_STERADIAN_COSINE_FACTOR holds f cos(theta_v), V the outgoing direction (ALTA's
 * params.h: "weighted by the cosine factor of the output direction"). */
static void test_cosine_factor(void **state)
{
    (void)state;
    char text[1024];
    snprintf(text, sizeof text,
             "#DIM 4 2\n#PARAM_IN SPHERICAL_TL_PL_TV_PV\n#PARAM_OUT INV_STERADIAN_COSINE_FACTOR\n"
             "0.2 0 %.17g 3.14159 0.25 -0.1\n%.17g 0 0.2 3.14159 0.25 1\n"
             "0.2 0 %.17g 0 0.3 1\n0.2 0 2.0 0 0.3 1\n",
             acos(0.5), acos(0.5), M_PI / 2);
    bf_samples *s = read_text("cosf.alta", text);
    ts_assert_rel(s->value[0], 0.5, 1e-14, "f = 0.25 / cos(60 deg)");
    ts_assert_rel(s->value[1], -0.2, 1e-14, "f = -0.1 / cos(60 deg)");
    ts_assert_rel(s->value[2], 0.25 / cos(0.2), 1e-14, "divided by cos theta_v, not cos theta_l");
    /* on and below the horizon nothing to divide by: kept as read, dropped later */
    assert_true(s->value[4] == 0.3 && s->value[6] == 0.3);
    bf_samples_free(s);
}

/* '#VS 1' adds a half-width, '#VS 2' a lower and upper bound, for the first value
 * (ALTA's reader) or every value: read, checked, not used. */
static void test_vertical_segments(void **state)
{
    (void)state;
    bf_samples *s = read_text("vs1.alta", "#DIM 1 3\n#PARAM_IN COS_TH\n#PARAM_OUT RGB_COLOR\n#VS 1\n"
                                          "0.9 1 2 3 0.1\n0.8 4 5 6 0.1 0.2 0.3\n");
    assert_int_equal(s->n, 2);
    assert_true(s->value[3] == 4 && s->value[5] == 6);
    assert_null(s->weight);
    bf_samples_free(s);
    s = read_text("vs2.alta", "#DIM 1 1\n#VS 2\n#PARAM_IN COS_TH\n#PARAM_OUT INV_STERADIAN\n0.9 1 0.8 1.2\n");
    assert_int_equal(s->n, 1);
    assert_true(s->value[0] == 1);
    bf_samples_free(s);
}

/* ALTA's own header habits: '#ALTA HEADER BEGIN/END', '#CMD', '# ' comments, a bare
 * '#'; blank lines, tabs, trailing tabs, CRLF; '#' lines after the data are comments. */
static void test_header_leniency(void **state)
{
    (void)state;
    bf_samples *s = read_text("lenient.alta", "\n#ALTA HEADER BEGIN\n# a comment: #DIM 9 9\n#\n#CMD --fit x\r\n"
                                              "#DIM 2 1\r\n#PARAM_IN  RUSIN_TH_TD\t\r\n#PARAM_OUT\tINV_STERADIAN\r\n"
                                              "#FORMAT text\n#ALTA HEADER END\n\n0.1\t0.2\t-0.5\t\r\n"
                                              "   # indented comment\n#DIM 9 9\n\n0.2 0.3 1e-3\n");
    assert_int_equal(s->n, 2);
    assert_int_equal(s->channels, 1);
    assert_true(s->value[0] == -0.5 && s->value[1] == 1e-3);
    bf_samples_free(s);
    /* Rounding past a bound is clamped: theta_d written 1.5708 (pi/2 + 4e-6) reads as
     * pi/2 (at which V = -L) */
    s = read_text("clamp.alta", H("RUSIN_TH_TD_PD", 3) "0.2 1.5708 0.5 1\n0.2 1.5707963267948966 0.5 1\n");
    assert_true(s->theta_i[0] == s->theta_i[1] && s->phi_i[0] == s->phi_i[1]);
    assert_true(s->theta_o[0] == s->theta_o[1] && s->phi_o[0] == s->phi_o[1]);
    assert_close(s->theta_i[0] + s->theta_o[0], 180.0, 1e-12, "V = -L", 0);
    bf_samples_free(s);
}

/* ---- Bad input ----------------------------------------------------------------- */

static void expect_error_len(const char *name, const char *text, size_t len, int code, const char *fragment)
{
    ts_expect_read_error(bf_samples_read_alta, name, text, len, code, fragment);
}

static void expect_error(const char *name, const char *text, int code, const char *fragment)
{
    expect_error_len(name, text, strlen(text), code, fragment);
}

#define RGB "#DIM 1 3\n#PARAM_IN COS_TH\n#PARAM_OUT RGB_COLOR\n"

static void test_bad_input(void **state)
{
    (void)state;
    const int P = BF_ERR_PARSE, R = BF_ERR_RANGE;
    expect_error("empty.alta", "", P, ": empty file");
    expect_error("nodim.alta", "#PARAM_IN COS_TH\n#PARAM_OUT RGB_COLOR\n0.5 1 2 3\n", P, ":3: missing #DIM");
    expect_error("noin.alta", "#DIM 1 3\n#PARAM_OUT RGB_COLOR\n0.5 1 2 3\n", P, ":3: missing #PARAM_IN");
    expect_error("noout.alta", "#DIM 1 3\n#PARAM_IN COS_TH\n\n0.5 1 2 3\n", P, ":4: missing #PARAM_OUT");
    expect_error("comments.alta", "# only a comment\n", P, ":1: missing #DIM");
    expect_error("unknownin.alta", "#DIM 1 3\n#PARAM_IN FOO\n", P, ":2: unknown #PARAM_IN 'FOO'");
    expect_error("stark.alta", "#DIM 2 1\n#PARAM_IN STARK_2D\n", P, ":2: #PARAM_IN STARK_2D is not supported");
    expect_error("unknownout.alta", "#DIM 1 3\n#PARAM_OUT BAR\n", P, ":2: unknown #PARAM_OUT 'BAR'");
    expect_error("energy.alta", "#PARAM_OUT ENERGY\n", P, ":1: #PARAM_OUT ENERGY values are not a BRDF");
    expect_error("twonames.alta", "#PARAM_IN COS_TH COS_TH_TD\n", P, ":1: #PARAM_IN needs one name");
    expect_error("dimin.alta", "#DIM 2 3\n#PARAM_IN COS_TH\n#PARAM_OUT RGB_COLOR\n0.5 1 2 3\n", P,
                 ":1: #DIM gives 2 input coordinates but COS_TH has 1");
    expect_error("dimout.alta", "#DIM 1 2\n#PARAM_IN COS_TH\n#PARAM_OUT RGB_COLOR\n0.5 1 2\n", P,
                 ":1: #DIM gives 2 output values but RGB_COLOR has 3");
    expect_error("dim1.alta", "#DIM 1\n", P, ":1: #DIM needs two positive integers");
    expect_error("dimab.alta", "#DIM a b\n", P, ":1: #DIM needs two positive integers");
    expect_error("dim0.alta", "#DIM 1 0\n", P, ":1: #DIM needs two positive integers");
    expect_error("dim7.alta", "#DIM 7 1\n", P, ":1: #DIM needs two positive integers");
    expect_error("dim3.alta", "#DIM 1 3 4\n", P, ":1: #DIM needs two positive integers");
    expect_error("dimtwice.alta", "#DIM 1 3\n#DIM 1 3\n", P, ":2: #DIM given twice (first on line 1)");
    expect_error("vs3.alta", "#VS 3\n", P, ":1: #VS must be 0, 1 or 2");
    expect_error("binary.alta", "#FORMAT binary\n", P, ":1: ALTA '#FORMAT binary' data is not supported");
    expect_error("short.alta", RGB "0.5 1 2 3\n0.5 1 2\n", P, ":5: expected 4 numbers (#DIM 1 3), found 3");
    expect_error("long.alta", RGB "0.5 1 2 3 4\n", P, ":4: expected 4 numbers (#DIM 1 3), found 5");
    expect_error("vsshort.alta", RGB "#VS 1\n0.5 1 2 3 0.1 0.2\n", P,
                 ":5: expected 4 numbers (#DIM 1 3) and the #VS 1 interval (5 or 7 in all), found 6");
    expect_error("word.alta", RGB "0.5 1 x 3\n", P, ":4: number 3: 'x' is not a number");
    expect_error("comma.alta", RGB "0.5,1,2,3\n", P, ":4: number 1: '0.5,1,2,3' is not a number");
    expect_error("nan.alta", RGB "0.5 1 2 NaN\n", R, ":4: number 4: NaN is not a finite number");
    expect_error("inf.alta", RGB "inf 1 2 3\n", R, ":4: number 1: inf is not a finite number");
    expect_error("vsnan.alta", RGB "#VS 1\n0.5 1 2 3 nan\n", R, ":5: number 5: nan is not a finite number");
    expect_error("cos.alta", RGB "1.5 1 2 3\n", R, ":4: COS_TH: cos theta_h = 1.5 is outside [-1, 1]");
    expect_error("td.alta", H("RUSIN_TH_TD_PD", 3) "0.3 1.7 0 1\n", R,
                 ":4: RUSIN_TH_TD_PD: theta_d = 1.7 is outside [0, pi/2]");
    expect_error("th.alta", H("RUSIN_TH_TD_PD", 3) "-0.3 0.7 0 1\n", R,
                 ":4: RUSIN_TH_TD_PD: theta_h = -0.3 is outside [0, pi]");
    expect_error("tl.alta", H("SPHERICAL_TL_PL_TV_PV", 4) "0.1 0 3.5 0 1\n", R,
                 ":4: SPHERICAL_TL_PL_TV_PV: theta_v = 3.5 is outside [0, pi]");
    expect_error("proj.alta", H("ISOTROPIC_TL_TV_PROJ_DPHI", 3) "0.1 3 2 1\n", R,
                 "ISOTROPIC_TL_TV_PROJ_DPHI: theta_v (the length of the projected pair)");
    expect_error("unit.alta", H("CARTESIAN", 6) "0 0 2 0 0 1 1\n", R,
                 ":4: CARTESIAN: V (numbers 1-3) has length 2, not 1");
    expect_error("unitl.alta", H("CARTESIAN", 6) "0 0 1 0 0 0 1\n", R, ":4: CARTESIAN: L (numbers 4-6) has length 0");
    expect_error("norows.alta", RGB "# nothing\n", P, ":4: no data rows after the header");
    static const char nul[] = RGB "0.5 1 2\0 3\n";
    expect_error_len("nul.alta", nul, sizeof nul - 1, P, ":4: binary data");
    bf_samples *s = NULL;
    bf_error err = {0};
    assert_int_equal(bf_samples_read_alta(ts_tmp_path("missing.alta"), &s, &err), BF_ERR_IO);
    assert_null(s);
    assert_non_null(strstr(err.msg, "missing.alta: cannot open"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_pink_felt),
        cmocka_unit_test(test_rusin_convention),
        cmocka_unit_test(test_rusin_matches_merl),
        cmocka_unit_test(test_cartesian_and_spherical),
        cmocka_unit_test(test_reduced_half_diff),
        cmocka_unit_test(test_isotropic_forms),
        cmocka_unit_test(test_outputs),
        cmocka_unit_test(test_cosine_factor),
        cmocka_unit_test(test_vertical_segments),
        cmocka_unit_test(test_header_leniency),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests_name("alta", tests, NULL, NULL);
}
