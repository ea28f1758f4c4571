/* What a fit should be doubted for (fit.h, bf_fit_result.warnings), each warning naming
 * the parameter and the number:
 *  - a free parameter on a bound (or within 1e-9 of its range of one);
 *  - a parameter the data do not determine: standard error undefined, or at least half
 *    of its range, or larger than the value itself; a pair of parameters correlated
 *    beyond 0.999;
 *  - directional albedo above 1 (the fitted BRDF reflects more than it receives), by the
 *    quadrature of bf_fit_max_albedo;
 *  - a lobe narrower than the data's sampling near the specular peak: fewer than
 *    LOBE_MIN_SAMPLES samples within its half width at half maximum in theta_h;
 *  - a solve that stopped on its iteration or time limit, or failed;
 *  - criteria left undefined by a robust loss.
 * Each warning carries its kind (fit.h, bf_warning_kind): decisions read the kind, never
 * the text. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "diagnostics.h"
#include "lobe_order.h"
#include "models/lobes.h"

#define AT_BOUND_REL 1e-9 /* of the parameter's range */
#define CORRELATED 0.999
#define ALBEDO_LIMIT 1.001 /* above 1 by more than the quadrature's error */
#define LOBE_MIN_SAMPLES 10

/* The names of bf_warning_kind, in its order: stored in files, so never renamed. */
static const char *const kind_names[BF_WARN_KINDS] = {
    [BF_WARN_OTHER] = "other",
    [BF_WARN_AT_BOUND] = "at_bound",
    [BF_WARN_UNDETERMINED] = "undetermined",
    [BF_WARN_CORRELATED] = "correlated",
    [BF_WARN_INACTIVE] = "inactive",
    [BF_WARN_ALBEDO] = "albedo_above_one",
    [BF_WARN_NARROW_LOBE] = "narrow_lobe",
    [BF_WARN_ONE_START] = "one_start",
    [BF_WARN_SOLVER_LIMIT] = "solver_limit",
    [BF_WARN_FAILED] = "failed",
    [BF_WARN_CANCELLED] = "cancelled",
    [BF_WARN_NO_CRITERIA] = "criteria_undefined",
    [BF_WARN_TRUNCATED] = "truncated",
    [BF_WARN_REFERENCE_BETTER] = "reference_better",
};

const char *bf_warning_kind_name(bf_warning_kind k)
{
    return (int)k >= 0 && (int)k < BF_WARN_KINDS ? kind_names[k] : "unknown";
}

bf_status bf_warning_kind_parse(const char *name, bf_warning_kind *out, bf_error *err)
{
    char list[320] = "";
    for (int k = 0; k < BF_WARN_KINDS; k++) {
        if (name && !strcmp(name, kind_names[k])) {
            *out = (bf_warning_kind)k;
            return BF_OK;
        }
        /* Blanks alone between the names: with reference_better the list would pass a
         * message's BF_ERROR_MAX_CHARS with commas too. */
        size_t len = strlen(list);
        snprintf(list + len, sizeof list - len, "%s%s", k ? " " : "", kind_names[k]);
    }
    return bf_fail(err, BF_ERR_ARG, "unknown warning kind '%s' (%s)", name ? name : "", list);
}

void bf_fit_warn(bf_fit_result *r, bf_warning_kind kind, const char *fmt, ...)
{
    if (r->nwarnings >= BF_FIT_MAX_WARNINGS) {
        /* The last slot says that more were left out (and what it said is lost with its
         * kind). */
        snprintf(r->warnings[BF_FIT_MAX_WARNINGS - 1], sizeof r->warnings[0], "%s",
                 "more warnings than shown (the list is cut here)");
        r->warning_kind[BF_FIT_MAX_WARNINGS - 1] = BF_WARN_TRUNCATED;
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    r->warning_kind[r->nwarnings] = kind;
    vsnprintf(r->warnings[r->nwarnings++], sizeof r->warnings[0], fmt, ap);
    va_end(ap);
}

/* What is wrong with one entry, if anything. */
enum { ENTRY_OK = 0, ENTRY_AT_LOWER, ENTRY_AT_UPPER, ENTRY_NO_SE, ENTRY_HUGE_SE, ENTRY_KINDS };

static int entry_kind(double x, double se, double lo, double hi)
{
    const double range = hi - lo;
    if (x - lo <= AT_BOUND_REL * range)
        return ENTRY_AT_LOWER;
    if (hi - x <= AT_BOUND_REL * range)
        return ENTRY_AT_UPPER; /* at a bound its standard error says little more */
    if (isnan(se))
        return ENTRY_NO_SE;
    return se >= 0.5 * range || se > fabs(x) ? ENTRY_HUGE_SE : ENTRY_OK;
}

static void warn_entry(bf_fit_result *r, const char *name, int kind, double x, double se, double lo, double hi)
{
    switch (kind) {
    case ENTRY_AT_LOWER: bf_fit_warn(r, BF_WARN_AT_BOUND, "%s = %.6g is at its lower bound %.6g", name, x, lo); break;
    case ENTRY_AT_UPPER: bf_fit_warn(r, BF_WARN_AT_BOUND, "%s = %.6g is at its upper bound %.6g", name, x, hi); break;
    case ENTRY_NO_SE:
        bf_fit_warn(r, BF_WARN_UNDETERMINED, "%s = %.6g is not determined by the data (no standard error)", name, x);
        break;
    case ENTRY_HUGE_SE:
        bf_fit_warn(r, BF_WARN_UNDETERMINED, "%s = %.6g +- %.2g is not determined by the data", name, x, se);
        break;
    default: break;
    }
}

/* Appends text to buf (size), cutting at its end. */
static void append(char *buf, size_t size, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static void append(char *buf, size_t size, const char *fmt, ...)
{
    size_t len = strlen(buf);
    if (len + 1 >= size)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf + len, size - len, fmt, ap);
    va_end(ap);
}

/* Entries without effect, one line per parameter that silences them ("clearcoat_gloss
 * has no effect while clearcoat = 0 is at its lower bound"), or for those nothing
 * silences ("sheen_tint has no effect on these data"). A silencing parameter's own place
 * on its bound is said there, once: reported[k] marks its entries for check_entries. */
static void check_inactive(const bf_fit_result *r, const double *lo, const double *hi, unsigned char *reported,
                           bf_fit_result *w)
{
    const bf_model *m = r->model;
    const int np = bf_model_nparams(m), C = bf_model_channels(m);
    if (!r->inactive || !r->inactive_gate)
        return;
    for (int g = -1; g < np; g++) {
        char names[BF_FIT_WARNING_LEN] = "";
        int count = 0;
        for (int i = 0; i < np; i++) {
            const int off = bf_model_param_offset(m, i), n = bf_model_param(m, i)->color ? C : 1;
            int in = 0;
            for (int k = off; k < off + n; k++)
                in += !r->fixed[k] && r->inactive[k] && r->inactive_gate[k] == g;
            if (!in)
                continue;
            append(names, sizeof names, "%s%s", count ? ", " : "", bf_model_param(m, i)->name);
            if (in < n) { /* some channels only: name them */
                append(names, sizeof names, " (channel%s", in > 1 ? "s" : "");
                int c = 0;
                for (int k = off; k < off + n; k++)
                    if (!r->fixed[k] && r->inactive[k] && r->inactive_gate[k] == g)
                        append(names, sizeof names, "%s%d", c++ ? ", " : " ", k - off);
                append(names, sizeof names, ")");
            }
            count++;
        }
        if (!count)
            continue;
        if (g < 0) {
            bf_fit_warn(w, BF_WARN_INACTIVE, "%s %s no effect on these data (inactive: not counted in k)", names,
                        count > 1 ? "have" : "has");
            continue;
        }
        const bf_param_info *gp = bf_model_param(m, g);
        const int off = bf_model_param_offset(m, g), n = gp->color ? C : 1;
        char where[96] = "";
        int lower = 0, upper = 0;
        for (int k = off; k < off + n; k++) {
            if (r->fixed[k])
                continue;
            const double range = hi[k] - lo[k];
            if (r->x[k] - lo[k] <= AT_BOUND_REL * range)
                lower++, reported[k] = 1;
            else if (hi[k] - r->x[k] <= AT_BOUND_REL * range)
                upper++, reported[k] = 1;
        }
        if (lower + upper == 0)
            snprintf(where, sizeof where, "while %s has its fitted value", gp->name);
        else if (n == 1)
            snprintf(where, sizeof where, "while %s = %.6g is at its %s bound", gp->name, r->x[off],
                     lower ? "lower" : "upper");
        else
            snprintf(where, sizeof where, "while %s is at its %s bound %.6g in %s", gp->name, lower ? "lower" : "upper",
                     lower ? lo[off] : hi[off], lower + upper == n ? "every channel" : "some channels");
        /* Inactive, though it may also say where the silencing parameter's bound is. */
        bf_fit_warn(w, BF_WARN_INACTIVE, "%s %s no effect %s (inactive: not counted in k)", names,
                    count > 1 ? "have" : "has", where);
    }
}

/* Bounds and standard errors per parameter, one line per parameter and kind of problem:
 * a single entry by its name and value, several channels of a colour parameter by
 * their numbers ("rho_d: channels 1, 2 at the lower bound 0"); a spectral parameter (more
 * than three channels) by how many and the first. Inactive entries and a silencing
 * parameter's bound are said by check_inactive instead. */
static void check_entries(const bf_objective *o, bf_fit_result *r)
{
    const bf_model *m = r->model;
    const int P = bf_model_nvalues(m), C = bf_model_channels(m);
    double *lo = malloc((size_t)P * sizeof *lo), *hi = malloc((size_t)P * sizeof *hi);
    unsigned char *reported = calloc((size_t)P + 1, 1);
    if (!lo || !hi || !reported) {
        free(lo);
        free(hi);
        free(reported);
        return;
    }
    bf_objective_bounds(o, lo, hi);
    check_inactive(r, lo, hi, reported, r);
    char name[64];
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        const int off = bf_model_param_offset(m, i), n = p->color ? C : 1;
        int count[ENTRY_KINDS] = {0}, first[ENTRY_KINDS];
        char chans[ENTRY_KINDS][64];
        for (int kind = 0; kind < ENTRY_KINDS; kind++)
            chans[kind][0] = '\0';
        for (int k = off; k < off + n; k++) {
            if (r->fixed[k] || reported[k] || (r->inactive && r->inactive[k]))
                continue;
            const int kind = entry_kind(r->x[k], r->stderr_[k], lo[k], hi[k]);
            if (count[kind]++ == 0)
                first[kind] = k;
            append(chans[kind], sizeof chans[kind], "%s%d", count[kind] > 1 ? ", " : "", k - off);
        }
        for (int kind = ENTRY_OK + 1; kind < ENTRY_KINDS; kind++) {
            const int k = first[kind];
            if (count[kind] == 0)
                continue;
            if (count[kind] == 1) {
                warn_entry(r, bf_model_entry_name(m, k, name, sizeof name), kind, r->x[k], r->stderr_[k], lo[k], hi[k]);
            } else if (n > 3) {
                bf_model_entry_name(m, k, name, sizeof name);
                if (kind == ENTRY_AT_LOWER || kind == ENTRY_AT_UPPER)
                    bf_fit_warn(r, BF_WARN_AT_BOUND, "%s is at its %s bound %.6g in %d of %d channels (the first %s)",
                                p->name, kind == ENTRY_AT_LOWER ? "lower" : "upper",
                                kind == ENTRY_AT_LOWER ? lo[k] : hi[k], count[kind], n, name);
                else if (kind == ENTRY_NO_SE)
                    bf_fit_warn(r, BF_WARN_UNDETERMINED,
                                "%s is not determined by the data in %d of %d channels (no standard error; "
                                "%s = %.6g)",
                                p->name, count[kind], n, name, r->x[k]);
                else
                    bf_fit_warn(r, BF_WARN_UNDETERMINED,
                                "%s is not determined by the data in %d of %d channels (%s = %.6g +- %.2g)", p->name,
                                count[kind], n, name, r->x[k], r->stderr_[k]);
            } else if ((kind == ENTRY_AT_LOWER || kind == ENTRY_AT_UPPER) && count[kind] == n) {
                bf_fit_warn(r, BF_WARN_AT_BOUND, "%s is at its %s bound %.6g in every channel", p->name,
                            kind == ENTRY_AT_LOWER ? "lower" : "upper", kind == ENTRY_AT_LOWER ? lo[k] : hi[k]);
            } else if (kind == ENTRY_AT_LOWER || kind == ENTRY_AT_UPPER) {
                bf_fit_warn(r, BF_WARN_AT_BOUND, "%s: channels %s at the %s bound %.6g", p->name, chans[kind],
                            kind == ENTRY_AT_LOWER ? "lower" : "upper", kind == ENTRY_AT_LOWER ? lo[k] : hi[k]);
            } else {
                bf_fit_warn(r, BF_WARN_UNDETERMINED, "%s: channels %s not determined by the data (%s)", p->name,
                            chans[kind],
                            kind == ENTRY_NO_SE ? "no standard error"
                                                : "standard error larger than the value or half the range");
            }
        }
    }
    free(lo);
    free(hi);
    free(reported);
}

/* Pairs of free entries correlated beyond CORRELATED, one warning per pair of parameters
 * (a colour parameter's channels are one parameter): "rho_s and f0 are correlated in 3
 * channels", not three lines; a single pair of entries is named as it is. */
static int param_of_entry(const bf_model *m, int k)
{
    for (int i = bf_model_nparams(m) - 1; i >= 0; i--)
        if (bf_model_param_offset(m, i) <= k)
            return i;
    return 0;
}

static void check_correlations(const bf_objective *o, const double *corr, bf_fit_result *r)
{
    const bf_model *m = r->model;
    const int np = bf_model_nparams(m);
    int *count = calloc((size_t)np * (size_t)np, sizeof *count),
        *first = malloc((size_t)np * (size_t)np * 2 * sizeof *first);
    double *worst = calloc((size_t)np * (size_t)np, sizeof *worst);
    if (!count || !first || !worst || !corr) {
        free(count);
        free(first);
        free(worst);
        return;
    }
    /* Per pair of parameters (the lower index first), the count of correlated entry pairs,
     * the first of them, and the largest correlation in magnitude (with its sign). */
    for (int a = 0; a < o->nz; a++)
        for (int b = 0; b < a; b++) {
            const double c = corr[a * o->nz + b];
            if (!(fabs(c) > CORRELATED))
                continue;
            int pa = param_of_entry(m, o->kidx[a]), pb = param_of_entry(m, o->kidx[b]);
            int lo = pa < pb ? pa : pb, hi = pa < pb ? pb : pa, at = lo * np + hi;
            if (count[at]++ == 0) {
                first[2 * at] = o->kidx[b];
                first[2 * at + 1] = o->kidx[a];
            }
            if (fabs(c) > fabs(worst[at]))
                worst[at] = c;
        }
    char name[64], other[64];
    for (int pa = 0; pa < np; pa++)
        for (int pb = pa; pb < np; pb++) {
            const int at = pa * np + pb;
            if (!count[at])
                continue;
            if (count[at] == 1) {
                bf_model_entry_name(m, first[2 * at], other, sizeof other);
                bf_model_entry_name(m, first[2 * at + 1], name, sizeof name);
                bf_fit_warn(r, BF_WARN_CORRELATED,
                            "%s and %s are correlated (r = %.4f): the data hardly tell them apart", other, name,
                            worst[at]);
            } else if (pa == pb) {
                bf_fit_warn(r, BF_WARN_CORRELATED,
                            "%s: its channels are correlated with each other (%d pairs, r up to %.4f): the data "
                            "hardly tell them apart",
                            bf_model_param(m, pa)->name, count[at], worst[at]);
            } else {
                const int colors = bf_model_param(m, pa)->color + bf_model_param(m, pb)->color;
                bf_fit_warn(r, BF_WARN_CORRELATED,
                            "%s and %s are correlated in %d %s (r up to %.4f): the data hardly tell them apart",
                            bf_model_param(m, pa)->name, bf_model_param(m, pb)->name, count[at],
                            colors == 1 ? "channels" : "pairs of channels", worst[at]);
            }
        }
    free(count);
    free(first);
    free(worst);
}

/* ---- Albedo ---------------------------------------------------------------------------
 * The directional albedo a(L) = integral of f(L, V) cos theta_o dV over the hemisphere,
 * integrated over the half vector: V = reflect(L, H), dV = 4 (L.H) dH, with theta_h on
 * the nodes of a Gauss-Legendre rule in u = sqrt(theta_h / (pi/2)) (dense near the mirror
 * direction, where a narrow lobe lives, as MERL's table is) and phi_h uniform. Every V
 * of the hemisphere comes from exactly one H with L.H > 0. */
enum { ALB_NU = 96, ALB_NPHI = 128, ALB_NTHETA = 9, ALB_NPHI_I = 4 };

/* Gauss-Legendre nodes and weights on [0, 1] (Newton on the Legendre polynomial). */
static void gauss_legendre(int n, double *x, double *w)
{
    for (int i = 0; i < n; i++) {
        double z = cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 1.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = z;
            for (int k = 2; k <= n; k++) {
                double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = n * (z * p1 - p0) / (z * z - 1.0);
            double dz = p1 / dp;
            z -= dz;
            if (fabs(dz) < 1e-15)
                break;
        }
        x[i] = 0.5 * (1.0 - z);
        w[i] = 1.0 / ((1.0 - z * z) * dp * dp);
    }
}

bf_status bf_fit_max_albedo(const bf_model *m, const double *x, double *albedo, double *theta_deg, int *channel,
                            bf_error *err)
{
    const int C = bf_model_channels(m);
    /* An isotropic model's albedo does not depend on the azimuth of L. */
    const int aniso = bf_model_family(m)->anisotropic;
    const int nphi_i = aniso ? ALB_NPHI_I : 1;
    const size_t nh = (size_t)ALB_NU * ALB_NPHI;
    double u[ALB_NU], wu[ALB_NU];
    gauss_legendre(ALB_NU, u, wu);
    double *L = malloc(nh * 3 * sizeof *L), *V = malloc(nh * 3 * sizeof *V);
    double *wt = malloc(nh * sizeof *wt), *f = malloc(nh * (size_t)C * sizeof *f);
    if (!L || !V || !wt || !f) {
        free(L), free(V), free(wt), free(f);
        return bf_fail(err, BF_ERR_NOMEM, "albedo: out of memory");
    }
    *albedo = -INFINITY;
    *theta_deg = 0.0;
    *channel = 0;
    bf_status rc = BF_OK;
    for (int t = 0; t < ALB_NTHETA && rc == BF_OK; t++) {
        const double ti = (t + 0.5) / ALB_NTHETA * (M_PI / 2); /* 5 .. 85 degrees */
        for (int pi_i = 0; pi_i < nphi_i && rc == BF_OK; pi_i++) {
            const double pli = pi_i * (M_PI / 2) / ALB_NPHI_I; /* azimuths for anisotropic lobes */
            const double l[3] = {sin(ti) * cos(pli), sin(ti) * sin(pli), cos(ti)};
            size_t n = 0;
            for (int a = 0; a < ALB_NU; a++) {
                const double th = u[a] * u[a] * (M_PI / 2), dth = 2.0 * u[a] * (M_PI / 2) * wu[a];
                for (int b = 0; b < ALB_NPHI; b++) {
                    const double ph = (b + 0.5) * (2.0 * M_PI / ALB_NPHI);
                    const double h[3] = {sin(th) * cos(ph), sin(th) * sin(ph), cos(th)};
                    const double lh = l[0] * h[0] + l[1] * h[1] + l[2] * h[2];
                    const double v[3] = {2.0 * lh * h[0] - l[0], 2.0 * lh * h[1] - l[1], 2.0 * lh * h[2] - l[2]};
                    if (!(lh > 0.0) || !(v[2] > 1e-12))
                        continue;
                    memcpy(L + 3 * n, l, sizeof l);
                    memcpy(V + 3 * n, v, sizeof v);
                    /* f cos theta_o dV with dV = 4 (L.H) sin theta_h dtheta_h dphi_h. */
                    wt[n] = v[2] * 4.0 * lh * sin(th) * dth * (2.0 * M_PI / ALB_NPHI);
                    n++;
                }
            }
            bf_geometry *g = NULL;
            if ((rc = bf_geometry_from_vectors(n, L, V, &g, err)) != BF_OK)
                break;
            bf_model_eval(m, x, g, f, NULL);
            bf_geometry_free(g);
            for (int c = 0; c < C; c++) {
                double a = 0.0;
                for (size_t q = 0; q < n; q++)
                    a += f[q * (size_t)C + (size_t)c] * wt[q];
                if (a > *albedo) {
                    *albedo = a;
                    *theta_deg = ti * (180.0 / M_PI);
                    *channel = c;
                }
            }
        }
    }
    free(L), free(V), free(wt), free(f);
    return rc;
}

/* ---- Lobe width against the data's sampling ------------------------------------------ */

/* Samples above the horizon with theta_h below w. */
static size_t samples_within(bf_samples *s, double w)
{
    const bf_geometry *g = NULL;
    if (bf_samples_geometry(s, &g, NULL) != BF_OK)
        return (size_t)-1;
    const double s2 = sin(w) * sin(w);
    size_t n = 0;
    bf_geometry_block gb;
    for (size_t ib = 0; ib < s->n; ib += BF_GEOMETRY_BLOCK) {
        size_t cnt = s->n - ib < BF_GEOMETRY_BLOCK ? s->n - ib : BF_GEOMETRY_BLOCK;
        const bf_geometry *gv = bf_geometry_view(g, ib, cnt, &gb);
        for (size_t q = 0; q < cnt; q++)
            n += bf_geometry_valid(gv, q) && gv->sin2h[q] < s2;
    }
    return n;
}

static void check_lobes(bf_samples *s, bf_fit_result *r)
{
    const int *map;
    const bf_model *um = bf_model_untied(r->model, &map);
    bf_lobe_layout lay;
    if (!bf_model_lobe_layout(um, &lay) || lay.lobes == 0)
        return;
    const int P = bf_model_nvalues(um);
    double *xu = malloc((size_t)P * sizeof *xu);
    if (!xu)
        return;
    for (int k = 0; k < P; k++)
        xu[k] = r->x[map ? map[k] : k];
    for (int k = 0; k < lay.lobes; k++) {
        const double w = bf_fit_lobe_hwhm(um, xu, k);
        if (!(w > 0.0))
            continue;
        const size_t n = samples_within(s, w);
        if (n < LOBE_MIN_SAMPLES)
            bf_fit_warn(r, BF_WARN_NARROW_LOBE,
                        "lobe %d is %.3g deg wide (half width at half maximum in theta_h), and only %zu "
                        "sample%s within it: the data do not resolve the highlight",
                        k + 1, w * (180.0 / M_PI), n, n == 1 ? " lies" : "s lie");
    }
    free(xu);
}

/* ---- Everything ------------------------------------------------------------------------ */

int bf_fit_result_unsure(const bf_fit_result *r)
{
    for (int w = 0; r && w < r->nwarnings; w++)
        if (r->warning_kind[w] == BF_WARN_ONE_START)
            return 1;
    return 0;
}

void bf_fit_diagnose(const bf_objective *o, bf_samples *s, const bf_fit_options *opt, const double *corr,
                     bf_fit_result *r)
{
    const bf_solution *sol = &r->solution;
    if (!r->ok)
        bf_fit_warn(r, BF_WARN_FAILED, "the fit failed: %s", sol->termination);
    else if (sol->stop == BF_STOP_ITERATIONS || sol->stop == BF_STOP_TIME)
        bf_fit_warn(r, BF_WARN_SOLVER_LIMIT, "the solver stopped on its limit after %d iteration%s, before converging",
                    sol->iterations, sol->iterations == 1 ? "" : "s");
    if (r->ok && r->starts > 1 && r->starts_at_best == 1)
        bf_fit_warn(r, BF_WARN_ONE_START,
                    "the best optimum was reached from 1 of %d starts: a better one may have been missed "
                    "(--accuracy best searches harder)",
                    r->starts);
    bf_fit_diagnose_model(o, s, opt, corr, r);
}

void bf_fit_diagnose_model(const bf_objective *o, bf_samples *s, const bf_fit_options *opt, const double *corr,
                           bf_fit_result *r)
{
    if (opt->solver.loss.kind != BF_LOSS_NONE)
        bf_fit_warn(r, BF_WARN_NO_CRITERIA,
                    "AIC, AICc and BIC are undefined: a robust loss minimises no Gaussian likelihood");
    check_entries(o, r);
    check_correlations(o, corr, r);
    double a, t;
    int c;
    if (bf_fit_max_albedo(r->model, r->x, &a, &t, &c, NULL) == BF_OK && a > ALBEDO_LIMIT) {
        char ch[40] = "";
        if (bf_model_channels(r->model) > 1)
            snprintf(ch, sizeof ch, " in channel %d", c);
        bf_fit_warn(r, BF_WARN_ALBEDO,
                    "the albedo reaches %.4g at theta_i = %.0f deg%s: the fitted BRDF reflects more light than it "
                    "receives",
                    a, t, ch);
    }
    check_lobes(s, r);
}
