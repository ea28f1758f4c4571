#include "support.h"

#include "io/read_binary.h"

#include "brdfit/formats.h"
#include "brdfit/prep.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>
#include <dirent.h>
#include <unistd.h>

static int family_selected(const char *name)
{
    const char *sel = getenv("BRDFIT_TEST_MODEL");
    if (!sel || !*sel)
        return 1;
    size_t n = strlen(name);
    for (const char *p = sel; *p;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == n && strncmp(p, name, n) == 0)
            return 1;
        if (!comma)
            break;
        p = comma + 1;
    }
    return 0;
}

static void push(char ***specs, int *n, int *cap, const char *s)
{
    if (*n == *cap) {
        *cap = *cap ? 2 * *cap : 64;
        *specs = realloc(*specs, (size_t)*cap * sizeof **specs);
    }
    (*specs)[(*n)++] = strdup(s);
}

int ts_all_specs(char ***specs)
{
    int n = 0, cap = 0;
    *specs = NULL;
    for (int f = 0; f < bf_family_count(); f++) {
        const bf_family_info *fi = bf_family_get(f);
        if (!family_selected(fi->name))
            continue;
        int no = 0, nv[8], idx[8] = {0};
        while (fi->options && fi->options[no].name) {
            nv[no] = 0;
            while (fi->options[no].values[nv[no]])
                nv[no]++;
            no++;
        }
        for (int lobes = 1; lobes <= (fi->lobes ? 2 : 1); lobes++) {
            memset(idx, 0, sizeof idx);
            for (;;) {
                char buf[256];
                int len = snprintf(buf, sizeof buf, "%s", fi->name);
                for (int o = 0; o < no; o++)
                    len += snprintf(buf + len, sizeof buf - (size_t)len, "%c%s=%s", o ? ',' : ':', fi->options[o].name,
                                    fi->options[o].values[idx[o]]);
                if (fi->lobes)
                    snprintf(buf + len, sizeof buf - (size_t)len, "%clobes=%d", no ? ',' : ':', lobes);
                push(specs, &n, &cap, buf);
                int o = 0;
                while (o < no && ++idx[o] == nv[o])
                    idx[o++] = 0;
                if (o == no)
                    break;
            }
        }
    }
    return n;
}

void ts_free_specs(char **specs, int n)
{
    for (int i = 0; i < n; i++)
        free(specs[i]);
    free(specs);
}

double ts_uniform(ts_rng *r)
{
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return (double)((r->s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}

double ts_param_lo(const bf_param_info *p)
{
    return p->lo_open ? p->lo + 1e-9 * (p->hi - p->lo) : p->lo;
}

double ts_param_hi(const bf_param_info *p)
{
    return p->hi_open ? p->hi - 1e-9 * (p->hi - p->lo) : p->hi;
}

/* A value in [a, b] drawn in the parameter's natural scale. */
static double draw(const bf_param_info *p, ts_rng *r, double a, double b)
{
    double u = ts_uniform(r);
    if (p->scale == BF_SCALE_LOG && a > 0.0)
        return a * pow(b / a, u);
    if (p->scale == BF_SCALE_LOG1P)
        return expm1(log1p(a) + u * (log1p(b) - log1p(a)));
    return a + u * (b - a);
}

void ts_random_params(const bf_model *m, ts_rng *r, int how, double *x)
{
    int C = bf_model_channels(m);
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        int off = bf_model_param_offset(m, i), n = p->color ? C : 1;
        double lo = ts_param_lo(p), hi = ts_param_hi(p);
        for (int c = 0; c < n; c++) {
            double v;
            if (how == TS_PARAMS_ANY) {
                double u = ts_uniform(r);
                v = u < 0.15 ? lo : u < 0.3 ? hi : draw(p, r, lo, hi);
            } else {
                double a = lo, b = hi;
                /* Keep lobes wide enough to integrate on a grid. */
                if (p->scale != BF_SCALE_LINEAR && b > 100.0) /* exponents */
                    b = 100.0;
                if (p->scale == BF_SCALE_LOG && a < 0.1 && b >= 0.3)
                    a = 0.1;
                v = draw(p, r, a, b);
            }
            x[off + c] = v;
        }
    }
    if (how == TS_PARAMS_MODERATE) {
        /* Colour parameters of one channel sum to at most 1 (rho_d + rho_s <= 1). */
        for (int c = 0; c < C; c++) {
            double sum = 0.0;
            for (int i = 0; i < bf_model_nparams(m); i++)
                if (bf_model_param(m, i)->color)
                    sum += x[bf_model_param_offset(m, i) + c];
            if (sum > 1.0)
                for (int i = 0; i < bf_model_nparams(m); i++)
                    if (bf_model_param(m, i)->color)
                        x[bf_model_param_offset(m, i) + c] /= sum;
        }
    }
}

void ts_random_dirs(ts_rng *r, size_t n, double *ti, double *pi_, double *to, double *po)
{
    for (size_t k = 0; k < n; k++) {
        ti[k] = acos(1.0 - ts_uniform(r)) * (89.5 / 90.0);
        pi_[k] = 2.0 * M_PI * ts_uniform(r);
        if (k % 3 == 0) { /* near the mirror direction */
            to[k] = ti[k] + 0.05 * (ts_uniform(r) - 0.5);
            to[k] = fabs(to[k]) > 89.5 * DEG ? 89.5 * DEG : fabs(to[k]);
            po[k] = pi_[k] + M_PI + 0.05 * (ts_uniform(r) - 0.5);
        } else {
            to[k] = acos(1.0 - ts_uniform(r)) * (89.5 / 90.0);
            po[k] = 2.0 * M_PI * ts_uniform(r);
        }
    }
}

double *ts_eval(const bf_model *m, const double *x, const bf_geometry *g)
{
    double *v = malloc((g->n * (size_t)bf_model_channels(m) + 1) * sizeof *v);
    bf_model_eval(m, x, g, v, NULL);
    return v;
}

bf_geometry *ts_geometry_deg(size_t n, const double *ti, const double *pi_, const double *to, const double *po)
{
    double *a = malloc(4 * (n + 1) * sizeof *a);
    for (size_t k = 0; k < n; k++) {
        a[k] = ti[k] * DEG;
        a[n + k] = pi_[k] * DEG;
        a[2 * n + k] = to[k] * DEG;
        a[3 * n + k] = po[k] * DEG;
    }
    bf_geometry *g = NULL;
    bf_geometry_from_angles(n, a, a + n, a + 2 * n, a + 3 * n, &g, NULL);
    free(a);
    return g;
}

double ts_eval1(const bf_model *m, const double *x, double ti, double pi_, double to, double po, int c)
{
    bf_geometry *g = ts_geometry_deg(1, &ti, &pi_, &to, &po);
    double *v = ts_eval(m, x, g);
    double r = v[c];
    free(v);
    bf_geometry_free(g);
    return r;
}

double ts_uniform_ends(ts_rng *r)
{
    double u = ts_uniform(r);
    return u < 0.1 ? 0.0 : u < 0.2 ? 1.0 : ts_uniform(r);
}

void ts_compare_reference(const char *spec, uint64_t seed, ts_draw_fn draw, ts_ref_fn ref, void *ctx, double tol)
{
    static const int chans[] = {1, 3, 5};
    ts_rng rng = {seed};
    for (int ci = 0; ci < 3; ci++) {
        int C = chans[ci];
        bf_model *m = ts_model(spec, C);
        double *x = malloc((size_t)bf_model_nvalues(m) * sizeof *x);
        for (int t = 0; t < 400; t++) {
            draw(&rng, m, x, ctx);
            double ti, pi_, to, po;
            ts_random_pair_deg(&rng, t % 3 == 0, &ti, &pi_, &to, &po);
            for (int c = 0; c < C; c++)
                ts_assert_rel(ts_eval1(m, x, ti, pi_, to, po, c), ref(ctx, C, ti, pi_, to, po, c), tol, spec);
        }
        free(x);
        bf_model_free(m);
    }
}

bf_model *ts_model(const char *spec, int C)
{
    bf_error err;
    bf_model *m;
    if (bf_model_new(spec, C, &m, &err) != BF_OK)
        fail_msg("%s: %s", spec, err.msg);
    return m;
}

unsigned char *ts_read_binary(const char *path, size_t *len)
{
    unsigned char *b;
    bf_error err;
    if (bf_read_binary(path, &b, len, &err) != BF_OK)
        fail_msg("%s", err.msg);
    return b;
}

const bf_geometry *ts_samples_geometry(bf_samples *s)
{
    bf_error err;
    const bf_geometry *g;
    if (bf_samples_geometry(s, &g, &err) != BF_OK)
        fail_msg("geometry: %s", err.msg);
    return g;
}

void ts_assert_rel(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol * fabs(want) + 1e-300))
        fail_msg("%s: got %.17g, want %.17g (rel. error %.3g)", what ? what : "value", got, want,
                 fabs(got - want) / fabs(want));
}

void ts_assert_near(double got, double want, double rel, double abs, const char *what)
{
    if (!(fabs(got - want) <= rel * fabs(want) + abs))
        fail_msg("%s: got %.17g, want %.17g", what ? what : "value", got, want);
}

void ts_random_pair_deg(ts_rng *r, int near_mirror, double *ti, double *pi_, double *to, double *po)
{
    *ti = 85.0 * ts_uniform(r);
    *pi_ = 360.0 * ts_uniform(r);
    if (near_mirror) {
        *to = fabs(*ti + 10.0 * (ts_uniform(r) - 0.5));
        *po = *pi_ + 180.0 + 10.0 * (ts_uniform(r) - 0.5);
    } else {
        *to = 85.0 * ts_uniform(r);
        *po = 360.0 * ts_uniform(r);
    }
}

void ts_dirs_deg(double ti, double pi_, double to, double po, double L[3], double V[3])
{
    double a = ti * DEG, b = pi_ * DEG, c = to * DEG, d = po * DEG;
    L[0] = sin(a) * cos(b);
    L[1] = sin(a) * sin(b);
    L[2] = cos(a);
    V[0] = sin(c) * cos(d);
    V[1] = sin(c) * sin(d);
    V[2] = cos(c);
}

static char tmpdir[64];

static void remove_tmpdir(void)
{
    DIR *d = opendir(tmpdir);
    if (!d)
        return;
    struct dirent *e;
    char p[512];
    while ((e = readdir(d)))
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            snprintf(p, sizeof p, "%s/%s", tmpdir, e->d_name);
            unlink(p);
        }
    closedir(d);
    rmdir(tmpdir);
}

const char *ts_tmpdir(void)
{
    if (!tmpdir[0]) {
        snprintf(tmpdir, sizeof tmpdir, "/tmp/brdfit_test_XXXXXX");
        if (!mkdtemp(tmpdir)) {
            fprintf(stderr, "cannot make a temporary directory\n");
            exit(1);
        }
        atexit(remove_tmpdir);
    }
    return tmpdir;
}

const char *ts_tmp_path(const char *name)
{
    static char buf[8][256];
    static int k;
    k = (k + 1) % 8;
    snprintf(buf[k], sizeof buf[k], "%s/%s", ts_tmpdir(), name);
    return buf[k];
}

void ts_write_file(const char *path, const char *text, size_t len)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(text, 1, len, fp), len);
    fclose(fp);
}

const char *ts_read_file(const char *path)
{
    static char buf[1 << 16];
    FILE *fp = fopen(path, "rb");
    assert_non_null(fp);
    size_t n = fread(buf, 1, sizeof buf - 1, fp);
    fclose(fp);
    buf[n] = '\0';
    return buf;
}

void ts_expect_read_error(ts_reader reader, const char *name, const char *text, size_t len, int code,
                          const char *fragment)
{
    const char *path = ts_tmp_path(name);
    ts_write_file(path, text, len);
    bf_samples *s = (bf_samples *)&s; /* must come back NULL */
    bf_error err = {0};
    int rc = reader(path, &s, &err);
    if (rc == BF_OK)
        fail_msg("%s accepted", name);
    assert_null(s);
    if (rc != code)
        fail_msg("%s: code %d, want %d (%s)", name, rc, code, err.msg);
    if (!strstr(err.msg, fragment) || !strstr(err.msg, path) || strchr(err.msg, '\n'))
        fail_msg("%s: message '%s' lacks the path or '%s'", name, err.msg, fragment);
}

void ts_fit_defaults(bf_fit_options *o)
{
    bf_fit_options_init(o);
    /* The tests' own choices over the library's defaults. */
    o->objective.residual = BF_RESIDUAL_LINEAR;
    o->solver.threads = 0;
    /* The data-driven start alone: the tests of models, objectives and diagnostics see one
     * solve from a known start; the search for the optimum has tests of its own
     * (test_search.c, tests/cli_optimum.sh). */
    o->starts = 1;
}

bf_options *ts_options(bf_task task, const char *words)
{
    bf_options *o = NULL;
    bf_error err;
    if (bf_options_new(task, &o, &err) != BF_OK)
        fail_msg("%s", err.msg);
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", words ? words : "");
    char *save = NULL;
    for (char *w = strtok_r(buf, " ", &save); w; w = strtok_r(NULL, " ", &save)) {
        const bf_option *d = bf_option_find(w, task);
        const char *value = d && d->type != BF_OPTION_FLAG ? strtok_r(NULL, " ", &save) : NULL;
        if (bf_options_set(o, w, value, &err) != BF_OK)
            fail_msg("%s", err.msg);
    }
    return o;
}

bf_samples *ts_read_data(const char *path)
{
    bf_read_options ro;
    memset(&ro, 0, sizeof ro);
    bf_samples *s = NULL;
    bf_error err;
    if (bf_samples_read_with(path, &ro, &s, &err) != BF_OK)
        fail_msg("%s", err.msg);
    return s;
}

bf_samples *ts_read_cornell_rgb(const char *name)
{
    char path[512];
    snprintf(path, sizeof path, "%s/cornell/%s", BRDFIT_EXAMPLES, name);
    bf_samples *s = ts_read_data(path);
    bf_error err;
    bf_prep p;
    memset(&p, 0, sizeof p);
    p.color = BF_COLOR_SRGB;
    if (bf_samples_prep(s, &p, NULL, &err) != BF_OK)
        fail_msg("%s: %s", name, err.msg);
    assert_int_equal(s->channels, 3);
    return s;
}

void ts_fit_ok(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r)
{
    bf_error err;
    if (bf_fit_with(s, spec, o, r, &err) != BF_OK)
        fail_msg("bf_fit %s: %s", spec, err.msg);
    if (!r->ok)
        fail_msg("fit %s failed: %s", spec, r->solution.termination);
}
