/* --fix NAME=VALUE and --bound NAME=LO:HI: parsing, and applying them to the model's
 * bounds.
 *
 * Bounds may only be narrowed. The model's bounds are the limits where its formulas hold
 * (roughness > 0, f0 in [0, 1], exponents >= 0) and they are already wide where a
 * parameter absorbs a normalisation (rho_s up to 1e5 in Brady and ABC), so a wider bound
 * could only let the fit reach values the model does not define. A fixed value must lie
 * inside the model's bounds, open ends excluded. An override bound equal to an open
 * model bound stays open (nudged in like the model's own). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "objective_state.h"

/* Parses "NAME" or "NAME[c]" from text up to '='; *rest points after the '='. */
static bf_status parse_target(const char *what, const char *text, bf_override *out, const char **rest, bf_error *err)
{
    const char *eq = strchr(text, '=');
    if (!eq)
        return bf_fail(err, BF_ERR_ARG, "%s '%s': expected NAME=%s", what, text,
                       strcmp(what, "fix") == 0 ? "VALUE" : "LO:HI");
    const char *br = memchr(text, '[', (size_t)(eq - text));
    const char *name_end = br ? br : eq;
    size_t len = (size_t)(name_end - text);
    if (len == 0)
        return bf_fail(err, BF_ERR_ARG, "%s '%s': no parameter name before '='", what, text);
    if (len >= sizeof out->name)
        return bf_fail(err, BF_ERR_ARG, "%s '%s': parameter name too long", what, text);
    memcpy(out->name, text, len);
    out->name[len] = '\0';
    out->channel = -1;
    if (br) {
        char *end;
        errno = 0;
        long c = strtol(br + 1, &end, 10);
        if (end == br + 1 || *end != ']' || end + 1 != eq || errno || c < 0 || c > 1000000)
            return bf_fail(err, BF_ERR_ARG, "%s '%s': bad channel index (expected NAME[c] with c >= 0)", what, text);
        out->channel = (int)c;
    }
    *rest = eq + 1;
    return BF_OK;
}

/* A number filling [s, e) exactly; finite unless allow_inf. */
static int parse_number(const char *s, const char *e, int allow_inf, double *v)
{
    if (s == e)
        return 0;
    char buf[64];
    size_t len = (size_t)(e - s);
    if (len >= sizeof buf)
        return 0;
    memcpy(buf, s, len);
    buf[len] = '\0';
    char *end;
    *v = strtod(buf, &end);
    if (end != buf + len || isnan(*v) || (!allow_inf && isinf(*v)))
        return 0;
    return 1;
}

bf_status bf_override_parse_fix(const char *text, bf_override *out, bf_error *err)
{
    const char *rest;
    bf_status rc;
    if (!text)
        return bf_fail(err, BF_ERR_ARG, "fix: no text");
    memset(out, 0, sizeof *out);
    if ((rc = parse_target("fix", text, out, &rest, err)))
        return rc;
    if (!parse_number(rest, rest + strlen(rest), 0, &out->value))
        return bf_fail(err, BF_ERR_ARG, "fix '%s': value '%s' is not a finite number", text, rest);
    out->fix = 1;
    out->lo = out->hi = out->value;
    return BF_OK;
}

bf_status bf_override_parse_bound(const char *text, bf_override *out, bf_error *err)
{
    const char *rest;
    bf_status rc;
    if (!text)
        return bf_fail(err, BF_ERR_ARG, "bound: no text");
    memset(out, 0, sizeof *out);
    if ((rc = parse_target("bound", text, out, &rest, err)))
        return rc;
    const char *colon = strchr(rest, ':');
    if (!colon)
        return bf_fail(err, BF_ERR_ARG, "bound '%s': expected NAME=LO:HI", text);
    if (!parse_number(rest, colon, 1, &out->lo))
        return bf_fail(err, BF_ERR_ARG, "bound '%s': lower bound is not a number", text);
    if (!parse_number(colon + 1, colon + 1 + strlen(colon + 1), 1, &out->hi))
        return bf_fail(err, BF_ERR_ARG, "bound '%s': upper bound is not a number", text);
    if (!(out->lo < out->hi))
        return bf_fail(err, BF_ERR_ARG, "bound '%s': lower bound %g is not below upper bound %g%s", text, out->lo,
                       out->hi, out->lo == out->hi ? " (use fix for a single value)" : "");
    out->fix = 0;
    return BF_OK;
}

/* The closed interval the optimizer may use for parameter p: an open end is moved in by
 * 1e-9 of the range (the model is undefined at the end itself, e.g. Brady's a = 0). */
static double closed_lo(const bf_param_info *p)
{
    return p->lo_open ? p->lo + 1e-9 * (p->hi - p->lo) : p->lo;
}

static double closed_hi(const bf_param_info *p)
{
    return p->hi_open ? p->hi - 1e-9 * (p->hi - p->lo) : p->hi;
}

static void target_text(const bf_override *ov, char *buf, size_t size)
{
    if (ov->channel >= 0)
        snprintf(buf, size, "%s[%d]", ov->name, ov->channel);
    else
        snprintf(buf, size, "%s", ov->name);
}

static void interval_text(const bf_param_info *p, char *buf, size_t size)
{
    snprintf(buf, size, "%c%g, %g%c", p->lo_open ? '(' : '[', p->lo, p->hi, p->hi_open ? ')' : ']');
}

/* The bounds override ov gives its parameter p (lo == hi for a fix), or an error. */
static bf_status override_interval(const bf_override *ov, const bf_param_info *p, double *lo, double *hi, bf_error *err)
{
    char tgt[80], range[96];
    target_text(ov, tgt, sizeof tgt);
    interval_text(p, range, sizeof range);
    if (ov->fix) {
        double x = ov->value;
        if (!isfinite(x) || x < p->lo || x > p->hi || (p->lo_open && x == p->lo) || (p->hi_open && x == p->hi))
            return bf_fail(err, BF_ERR_RANGE, "fix %s: value %g is outside the model's bounds %s", tgt, x, range);
        *lo = *hi = x;
        return BF_OK;
    }
    if (isnan(ov->lo) || isnan(ov->hi) || !(ov->lo < ov->hi))
        return bf_fail(err, BF_ERR_ARG, "bound %s: lower bound %g is not below upper bound %g", tgt, ov->lo, ov->hi);
    if (ov->lo < p->lo || ov->hi > p->hi)
        return bf_fail(err, BF_ERR_RANGE,
                       "bound %s: %g:%g is outside the model's bounds %s (bounds may only be narrowed)", tgt, ov->lo,
                       ov->hi, range);
    *lo = ov->lo == p->lo ? closed_lo(p) : ov->lo;
    *hi = ov->hi == p->hi ? closed_hi(p) : ov->hi;
    if (!(*lo < *hi))
        return bf_fail(err, BF_ERR_RANGE, "bound %s: %g:%g leaves no room inside the model's bounds %s", tgt, ov->lo,
                       ov->hi, range);
    return BF_OK;
}

bf_status bf_overrides_check(const bf_model *m, int channels, const bf_override *ovs, int nov, bf_error *err)
{
    for (int v = 0; v < nov; v++) {
        const bf_override *ov = &ovs[v];
        const char *what = ov->fix ? "fix" : "bound";
        char tgt[80];
        target_text(ov, tgt, sizeof tgt);
        int i = bf_model_find_param(m, ov->name);
        if (i < 0)
            return bf_fail(err, BF_ERR_ARG, "%s %s: model %s has no parameter '%s'", what, tgt, bf_model_name(m),
                           ov->name);
        const bf_param_info *p = bf_model_param(m, i);
        if (ov->channel >= 0 && !p->color)
            return bf_fail(err, BF_ERR_ARG, "%s %s: %s is one scalar for every channel, it takes no channel index",
                           what, tgt, ov->name);
        if (channels > 0 && ov->channel >= channels)
            return bf_fail(err, BF_ERR_ARG, "%s %s: channel %d out of range (the data have %d channel%s)", what, tgt,
                           ov->channel, channels, channels == 1 ? "" : "s");
        double lo, hi;
        bf_status rc = override_interval(ov, p, &lo, &hi, err);
        if (rc != BF_OK)
            return rc;
        /* Two overrides of one entry: the later would silently win. */
        for (int u = 0; u < v; u++) {
            const bf_override *w = &ovs[u];
            if (strcmp(w->name, ov->name) || (w->channel >= 0 && ov->channel >= 0 && w->channel != ov->channel))
                continue;
            char prev[80];
            target_text(w, prev, sizeof prev);
            return bf_fail(err, BF_ERR_ARG, "%s %s and %s %s both set %s: give one", w->fix ? "fix" : "bound", prev,
                           what, tgt, ov->channel >= 0 ? tgt : prev);
        }
    }
    return BF_OK;
}

bf_status bf_obj_apply_overrides(bf_objective *o, const bf_override *ovs, int nov, bf_error *err)
{
    const bf_model *m = o->model;
    bf_status rc = bf_overrides_check(m, o->C, ovs, nov, err);
    if (rc != BF_OK)
        return rc;
    int np = bf_model_nparams(m);
    for (int i = 0; i < np; i++) {
        const bf_param_info *p = bf_model_param(m, i);
        int off = bf_model_param_offset(m, i), cnt = p->color ? o->C : 1;
        for (int c = 0; c < cnt; c++) {
            o->lo[off + c] = closed_lo(p);
            o->hi[off + c] = closed_hi(p);
            o->fixed[off + c] = 0;
            o->fixval[off + c] = 0.0;
        }
    }
    for (int v = 0; v < nov; v++) {
        const bf_override *ov = &ovs[v];
        const int i = bf_model_find_param(m, ov->name);
        const bf_param_info *p = bf_model_param(m, i);
        const int off = bf_model_param_offset(m, i);
        double lo, hi;
        override_interval(ov, p, &lo, &hi, NULL); /* checked above */
        int c0 = ov->channel >= 0 ? ov->channel : 0;
        int c1 = ov->channel >= 0 ? ov->channel + 1 : (p->color ? o->C : 1);
        for (int c = c0; c < c1; c++) {
            int k = off + c;
            o->fixed[k] = (unsigned char)ov->fix;
            o->fixval[k] = ov->fix ? ov->value : 0.0;
            o->lo[k] = lo;
            o->hi[k] = hi;
        }
    }
    return BF_OK;
}
