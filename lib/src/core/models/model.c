/* Configured models: spec parsing, parameter tables, bounds checks, evaluation. */
#include "models/family.h"
#include "registry.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int count_values(const bf_option_info *o)
{
    int n = 0;
    while (o->values[n])
        n++;
    return n;
}

static int count_options(const bf_family *f)
{
    int n = 0;
    while (f->info.options && f->info.options[n].name)
        n++;
    return n;
}

/* Applies one "key=value" to m. */
static bf_status apply_option(bf_model *m, const char *kv, size_t len, int *seen, bf_error *err)
{
    const bf_family *f = m->family;
    const char *eq = memchr(kv, '=', len);
    if (!eq || eq == kv || eq == kv + len - 1)
        return bf_fail(err, BF_ERR_ARG, "model %s: option '%.*s' is not key=value", f->info.name, (int)len, kv);
    size_t klen = (size_t)(eq - kv), vlen = len - klen - 1;
    const char *val = eq + 1;

    if (klen == 4 && strncmp(kv, "mono", 4) == 0) {
        if (vlen >= sizeof m->mono)
            return bf_fail(err, BF_ERR_ARG, "model %s: mono value '%.*s' is too long", f->info.name, (int)vlen, val);
        if (seen[BF_MAX_OPTIONS + 1]++)
            return bf_fail(err, BF_ERR_ARG, "model %s: option mono given twice", f->info.name);
        memcpy(m->mono, val, vlen);
        m->mono[vlen] = '\0';
        return BF_OK;
    }
    if (klen == 5 && strncmp(kv, "lobes", 5) == 0) {
        if (!f->info.lobes)
            return bf_fail(err, BF_ERR_ARG, "model %s does not accept lobes", f->info.name);
        char buf[16];
        if (vlen >= sizeof buf)
            vlen = sizeof buf - 1;
        memcpy(buf, val, vlen);
        buf[vlen] = '\0';
        char *end;
        long k = strtol(buf, &end, 10);
        if (*end || k < 1 || k > BF_MAX_LOBES)
            return bf_fail(err, BF_ERR_ARG, "model %s: lobes must be an integer from 1 to %d, got '%s'", f->info.name,
                           BF_MAX_LOBES, buf);
        if (seen[BF_MAX_OPTIONS]++)
            return bf_fail(err, BF_ERR_ARG, "model %s: option lobes given twice", f->info.name);
        m->lobes = (int)k;
        return BF_OK;
    }
    int no = count_options(f);
    for (int o = 0; o < no; o++) {
        const bf_option_info *oi = &f->info.options[o];
        if (strlen(oi->name) != klen || strncmp(oi->name, kv, klen) != 0)
            continue;
        if (seen[o]++)
            return bf_fail(err, BF_ERR_ARG, "model %s: option %s given twice", f->info.name, oi->name);
        for (int v = 0; oi->values[v]; v++) {
            if (strlen(oi->values[v]) == vlen && strncmp(oi->values[v], val, vlen) == 0) {
                m->opt[o] = v;
                return BF_OK;
            }
        }
        char allowed[128] = "";
        for (int v = 0; oi->values[v]; v++) {
            strncat(allowed, v ? "|" : "", sizeof allowed - strlen(allowed) - 1);
            strncat(allowed, oi->values[v], sizeof allowed - strlen(allowed) - 1);
        }
        return bf_fail(err, BF_ERR_ARG, "model %s: option %s has no value '%.*s' (one of %s)", f->info.name, oi->name,
                       (int)vlen, val, allowed);
    }
    return bf_fail(err, BF_ERR_ARG, "model %s has no option '%.*s'", f->info.name, (int)klen, kv);
}

static void make_canonical_spec(bf_model *m)
{
    const bf_family *f = m->family;
    size_t cap = sizeof m->spec, len;
    snprintf(m->spec, cap, "%s", f->info.name);
    int no = count_options(f);
    for (int o = 0; o < no; o++) {
        if (f->info.options[o].quiet_default && m->opt[o] == 0)
            continue;
        len = strlen(m->spec);
        snprintf(m->spec + len, cap - len, "%c%s=%s", strchr(m->spec, ':') ? ',' : ':', f->info.options[o].name,
                 f->info.options[o].values[m->opt[o]]);
    }
    if (f->info.lobes) {
        len = strlen(m->spec);
        snprintf(m->spec + len, cap - len, "%clobes=%d", strchr(m->spec, ':') ? ',' : ':', m->lobes);
    }
    if (m->mono[0]) {
        len = strlen(m->spec);
        snprintf(m->spec + len, cap - len, "%cmono=%s", strchr(m->spec, ':') ? ',' : ':', m->mono);
    }
}

/* Which colour parameters mono=WHAT ties (tie[i] = 1); rewrites m->mono canonically:
 * "specular" or "all" when the set is one of those, else the names joined by '+'. */
static bf_status mono_resolve(bf_model *m, unsigned char *tie, bf_error *err)
{
    const char *fam = m->family->info.name;
    int first = -1, ncolor = 0;
    for (int i = 0; i < m->nparam; i++)
        if (m->param[i].color) {
            ncolor++;
            if (first < 0)
                first = i;
        }
    int all = !strcmp(m->mono, "all"), spec = !strcmp(m->mono, "specular");
    if (all || spec) {
        for (int i = 0; i < m->nparam; i++)
            tie[i] = m->param[i].color && (all || m->param[i].role != BF_ROLE_DIFFUSE);
    } else {
        for (const char *p = m->mono; *p;) {
            size_t len = strcspn(p, "+");
            char name[BF_NAME_LEN];
            snprintf(name, sizeof name, "%.*s", (int)(len < sizeof name ? len : sizeof name - 1), p);
            int i = bf_model_find_param(m, name);
            if (i < 0 || len >= sizeof name)
                return bf_fail(err, BF_ERR_ARG, "model %s: mono names '%.*s', which is not one of its parameters", fam,
                               (int)len, p);
            if (!m->param[i].color)
                return bf_fail(err, BF_ERR_ARG, "model %s: mono names %s, which is not a colour parameter", fam, name);
            tie[i] = 1;
            p += len;
            if (*p == '+' && !*++p)
                return bf_fail(err, BF_ERR_ARG, "model %s: mono=%s ends with '+'", fam, m->mono);
        }
    }
    int ntie = 0, is_spec = 1;
    for (int i = 0; i < m->nparam; i++) {
        ntie += tie[i];
        if (m->param[i].color && tie[i] != (m->param[i].role != BF_ROLE_DIFFUSE))
            is_spec = 0;
    }
    if (ntie == 0)
        return bf_fail(err, BF_ERR_ARG, "model %s: mono=%s ties nothing (its only colour parameter is %s)", fam,
                       m->mono, first >= 0 ? m->param[first].name : "none");
    if (ntie == ncolor)
        snprintf(m->mono, sizeof m->mono, "all");
    else if (is_spec)
        snprintf(m->mono, sizeof m->mono, "specular");
    else {
        m->mono[0] = '\0';
        for (int i = 0; i < m->nparam; i++)
            if (tie[i]) {
                size_t len = strlen(m->mono);
                snprintf(m->mono + len, sizeof m->mono - len, "%s%s", len ? "+" : "", m->param[i].name);
            }
    }
    return BF_OK;
}

/* Applies mono: the tied parameters become one value; the evaluator keeps the untied
 * model as `inner` and a map from its vector onto this one (only needed for C > 1). */
static bf_status mono_apply(bf_model *m, bf_error *err)
{
    unsigned char tie[BF_MAX_PARAMS] = {0};
    bf_status rc = mono_resolve(m, tie, err);
    if (rc != BF_OK)
        return rc;
    const int C = m->channels;
    bf_model *in = NULL;
    if (C > 1) {
        if (!(in = malloc(sizeof *in)))
            return bf_fail(err, BF_ERR_NOMEM, "out of memory");
        *in = *m;
        for (int i = 0; i < in->nparam; i++)
            in->param[i].name = in->names[i];
        in->mono[0] = '\0';
    }
    m->nfree = 0;
    for (int i = 0; i < m->nparam; i++) {
        if (tie[i]) {
            m->param[i].color = 0;
            m->param[i].mono = 1;
        }
        m->offset[i] = m->nfree;
        m->nfree += m->param[i].color ? C : 1;
    }
    if (!in)
        return BF_OK;
    if (!(m->xmap = malloc((size_t)in->nfree * sizeof *m->xmap))) {
        free(in);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    for (int i = 0; i < in->nparam; i++)
        for (int c = 0; c < (in->param[i].color ? C : 1); c++)
            m->xmap[in->offset[i] + c] = m->offset[i] + (m->param[i].color ? c : 0);
    m->inner = in;
    return BF_OK;
}

bf_status bf_model_new(const char *spec, int channels, bf_model **out, bf_error *err)
{
    *out = NULL;
    if (!spec || !*spec)
        return bf_fail(err, BF_ERR_ARG, "empty model name");
    if (channels < 1 || channels > BF_MAX_CHANNELS)
        return bf_fail(err, BF_ERR_ARG, "channel count must be from 1 to %d, got %d", BF_MAX_CHANNELS, channels);
    const char *colon = strchr(spec, ':');
    size_t nlen = colon ? (size_t)(colon - spec) : strlen(spec);
    const bf_family *f = bf_registry_find(spec, nlen);
    if (!f)
        return bf_fail(err, BF_ERR_ARG, "unknown model '%.*s' (see brdfit models)", (int)nlen, spec);
    bf_model *m = calloc(1, sizeof *m);
    if (!m)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    m->family = f;
    m->channels = channels;
    m->lobes = 1;
    m->reciprocal = 1;
    int seen[BF_MAX_OPTIONS + 2] = {0}; /* the family's options, lobes, mono */
    bf_status rc = BF_OK;
    if (colon) {
        const char *p = colon + 1;
        for (;;) {
            const char *comma = strchr(p, ',');
            size_t len = comma ? (size_t)(comma - p) : strlen(p);
            if ((rc = apply_option(m, p, len, seen, err)) != BF_OK)
                break;
            if (!comma)
                break;
            p = comma + 1;
        }
    }
    if (rc == BF_OK && (rc = f->configure(m, err)) == BF_OK && m->mono[0])
        rc = mono_apply(m, err);
    if (rc != BF_OK) {
        bf_model_free(m);
        return rc;
    }
    make_canonical_spec(m);
    *out = m;
    return BF_OK;
}

void bf_model_free(bf_model *m)
{
    if (!m)
        return;
    free(m->inner);
    free(m->xmap);
    free(m);
}

/* Positional: one call per row of a family's parameter table (family.h). */
bf_status bf_model_add_param_open(bf_model *m, const char *name, int color, double lo, int lo_open, double hi,
                                  int hi_open, double def, bf_scale scale, int lobe, bf_param_role role, bf_error *err)
{
    if (m->nparam >= BF_MAX_PARAMS)
        return bf_fail(err, BF_ERR_ARG, "model %s: too many parameters", m->family->info.name);
    int i = m->nparam++;
    if (lobe > 0 && m->lobes > 1)
        snprintf(m->names[i], BF_NAME_LEN, "%s_%d", name, lobe);
    else
        snprintf(m->names[i], BF_NAME_LEN, "%s", name);
    bf_param_info *p = &m->param[i];
    p->name = m->names[i];
    p->color = color;
    p->lo = lo;
    p->hi = hi;
    p->lo_open = lo_open;
    p->hi_open = hi_open;
    p->def = def;
    p->scale = scale;
    p->lobe = lobe;
    p->role = role;
    m->offset[i] = m->nfree;
    m->nfree += color ? m->channels : 1;
    if (lobe > 0 && lobe <= BF_MAX_LOBES) {
        if (m->lobe_first[lobe] == 0 && color)
            m->lobe_first[lobe] = i;
        else {
            m->lobe_nscalar[lobe]++;
            m->lobe_chroma[lobe] |= color;
        }
    }
    return BF_OK;
}

/* Positional, as bf_model_add_param_open. */
bf_status bf_model_add_param(bf_model *m, const char *name, int color, double lo, double hi, double def, bf_scale scale,
                             int lobe, bf_param_role role, bf_error *err)
{
    return bf_model_add_param_open(m, name, color, lo, 0, hi, 0, def, scale, lobe, role, err);
}

bf_status bf_model_add_rows(bf_model *m, const bf_param_row *rows, int n, bf_error *err)
{
    for (int k = 0; k < n; k++) {
        bf_status rc = bf_model_add_param(m, rows[k].name, rows[k].color, rows[k].lo, 1.0, rows[k].def, BF_SCALE_LINEAR,
                                          0, rows[k].role, err);
        if (rc != BF_OK)
            return rc;
    }
    return BF_OK;
}

const char *bf_param_role_name(bf_param_role role)
{
    static const char *const names[] = {
        [BF_ROLE_NONE] = "none",
        [BF_ROLE_DIFFUSE] = "diffuse",
        [BF_ROLE_DIFFUSE_SHAPE] = "diffuse_shape",
        [BF_ROLE_WEIGHT] = "weight",
        [BF_ROLE_ROUGHNESS] = "roughness",
        [BF_ROLE_PERCEPTUAL_ROUGHNESS] = "perceptual_roughness",
        [BF_ROLE_EXPONENT] = "exponent",
        [BF_ROLE_FALLOFF] = "falloff",
        [BF_ROLE_SLOPE_SPREAD] = "slope_spread",
        [BF_ROLE_F0] = "f0",
        [BF_ROLE_IOR] = "ior",
        [BF_ROLE_EDGE_TINT] = "edge_tint",
        [BF_ROLE_ORIENTATION] = "orientation",
        [BF_ROLE_SHAPE] = "shape",
    };
    return (unsigned)role < sizeof names / sizeof names[0] ? names[role] : "none";
}

int bf_model_opt(const bf_model *m, const char *key)
{
    int no = count_options(m->family);
    for (int o = 0; o < no; o++)
        if (strcmp(m->family->info.options[o].name, key) == 0)
            return m->opt[o];
    return -1;
}

const char *bf_model_name(const bf_model *m)
{
    return m->family->info.name;
}
const bf_family_info *bf_model_family(const bf_model *m)
{
    return &m->family->info;
}
const char *bf_model_spec(const bf_model *m)
{
    return m->spec;
}
int bf_model_channels(const bf_model *m)
{
    return m->channels;
}
int bf_model_lobes(const bf_model *m)
{
    return m->lobes;
}
int bf_model_reciprocal(const bf_model *m)
{
    return m->reciprocal;
}
int bf_model_energy_conserving(const bf_model *m)
{
    return m->energy_conserving;
}
int bf_model_nparams(const bf_model *m)
{
    return m->nparam;
}
int bf_model_nvalues(const bf_model *m)
{
    return m->nfree;
}

const char *bf_model_option(const bf_model *m, const char *key)
{
    if (strcmp(key, "mono") == 0)
        return m->mono[0] ? m->mono : NULL;
    int v = bf_model_opt(m, key);
    if (v < 0) {
        if (strcmp(key, "lobes") == 0 && m->family->info.lobes) {
            static const char *const digits[] = {"0", "1", "2", "3", "4", "5", "6", "7", "8"};
            return digits[m->lobes];
        }
        return NULL;
    }
    int no = count_options(m->family);
    for (int o = 0; o < no; o++)
        if (strcmp(m->family->info.options[o].name, key) == 0)
            return v < count_values(&m->family->info.options[o]) ? m->family->info.options[o].values[v] : NULL;
    return NULL;
}

const bf_param_info *bf_model_param(const bf_model *m, int i)
{
    return (i >= 0 && i < m->nparam) ? &m->param[i] : NULL;
}

int bf_model_param_offset(const bf_model *m, int i)
{
    return (i >= 0 && i < m->nparam) ? m->offset[i] : -1;
}

int bf_model_find_param(const bf_model *m, const char *name)
{
    for (int i = 0; i < m->nparam; i++)
        if (strcmp(m->param[i].name, name) == 0)
            return i;
    return -1;
}

const char *bf_model_entry_name(const bf_model *m, int k, char *buf, size_t size)
{
    for (int i = m->nparam - 1; i >= 0; i--) {
        if (k < m->offset[i])
            continue;
        if (m->param[i].color && m->channels > 1)
            snprintf(buf, size, "%s[%d]", m->param[i].name, k - m->offset[i]);
        else
            snprintf(buf, size, "%s", m->param[i].name);
        return buf;
    }
    snprintf(buf, size, "entry %d", k);
    return buf;
}

void bf_model_defaults(const bf_model *m, double *x)
{
    for (int i = 0; i < m->nparam; i++) {
        int n = m->param[i].color ? m->channels : 1;
        for (int c = 0; c < n; c++)
            x[m->offset[i] + c] = m->param[i].def;
    }
}

bf_status bf_model_check(const bf_model *m, const double *x, bf_error *err)
{
    for (int i = 0; i < m->nparam; i++) {
        const bf_param_info *p = &m->param[i];
        int n = p->color ? m->channels : 1;
        for (int c = 0; c < n; c++) {
            double v = x[m->offset[i] + c];
            char where[48] = "";
            if (p->color && m->channels > 1)
                snprintf(where, sizeof where, "[%d]", c);
            if (!isfinite(v))
                return bf_fail(err, BF_ERR_RANGE, "parameter %s%s is %g", p->name, where, v);
            if (v < p->lo || (p->lo_open && v == p->lo) || v > p->hi || (p->hi_open && v == p->hi))
                return bf_fail(err, BF_ERR_RANGE, "parameter %s%s = %.17g is outside %c%.17g, %.17g%c", p->name, where,
                               v, p->lo_open ? '(' : '[', p->lo, p->hi, p->hi_open ? ')' : ']');
        }
    }
    return BF_OK;
}

/* A model with tied (mono) parameters: the untied model on the expanded vector, and its
 * Jacobian columns summed onto the tied entries, a chunk of samples at a time. The
 * expanded vector and a chunk's untied gradient live on the stack (a chunk is cut to
 * fit MONO_STACK doubles; the values of a sample do not depend on the chunks); only
 * models with over MONO_STACK untied entries times channels use the heap. Out of memory
 * (no error path here) gives NaN, which every caller treats as a failed step. */
enum { MONO_STACK = 2048 }; /* doubles: 16 KiB each for the vector and the gradient */

static void eval_mono(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                      double *grad)
{
    const bf_model *in = m->inner;
    const size_t C = (size_t)m->channels, P = (size_t)m->nfree, Pi = (size_t)in->nfree;
    size_t chunk = grad ? MONO_STACK / (C * Pi) : 0;
    if (chunk < 1)
        chunk = 1;
    if (chunk > i1 - i0)
        chunk = i1 - i0;
    double xs[MONO_STACK], gs[MONO_STACK];
    double *xi = Pi <= MONO_STACK ? xs : malloc(Pi * sizeof *xi);
    double *gi = !grad ? NULL : chunk * C * Pi <= MONO_STACK ? gs : malloc(chunk * C * Pi * sizeof *gi);
    if (!xi || (grad && !gi)) {
        for (size_t r = 0; r < (i1 - i0) * C; r++) {
            values[r] = NAN;
            for (size_t k = 0; grad && k < P; k++)
                grad[r * P + k] = NAN;
        }
    } else {
        for (size_t k = 0; k < Pi; k++)
            xi[k] = x[m->xmap[k]];
        if (!grad)
            in->family->eval(in, xi, g, i0, i1, values, NULL);
        for (size_t a = i0; grad && a < i1; a += chunk) {
            size_t b = a + chunk < i1 ? a + chunk : i1;
            in->family->eval(in, xi, g, a, b, values + (a - i0) * C, gi);
            for (size_t r = 0; r < (b - a) * C; r++) {
                double *out = grad + ((a - i0) * C + r) * P;
                const double *gr = gi + r * Pi;
                memset(out, 0, P * sizeof *out);
                for (size_t k = 0; k < Pi; k++)
                    out[m->xmap[k]] += gr[k];
            }
        }
    }
    if (xi != xs)
        free(xi);
    if (gi != gs)
        free(gi);
}

static void eval_stored(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                        double *grad)
{
    if (m->inner)
        eval_mono(m, x, g, i0, i1, values, grad);
    else
        m->family->eval(m, x, g, i0, i1, values, grad);
}

void bf_model_eval_range(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1, double *values,
                         double *grad)
{
    if (i1 > g->n)
        i1 = g->n;
    if (i0 >= i1)
        return;
    if (bf_geometry_stored(g)) {
        eval_stored(m, x, g, i0, i1, values, grad);
        return;
    }
    /* A generated geometry: a block of it at a time (families read stored arrays). */
    const size_t C = (size_t)m->channels, P = (size_t)m->nfree;
    bf_geometry_block b;
    for (size_t a = i0; a < i1; a += BF_GEOMETRY_BLOCK) {
        size_t cnt = i1 - a < BF_GEOMETRY_BLOCK ? i1 - a : BF_GEOMETRY_BLOCK;
        const bf_geometry *v = bf_geometry_view(g, a, cnt, &b);
        eval_stored(m, x, v, 0, cnt, values + (a - i0) * C, grad ? grad + (a - i0) * C * P : NULL);
    }
}

void bf_model_eval(const bf_model *m, const double *x, const bf_geometry *g, double *values, double *grad)
{
    bf_model_eval_range(m, x, g, 0, g->n, values, grad);
}
