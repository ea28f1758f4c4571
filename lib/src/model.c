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
static int apply_option(bf_model *m, const char *kv, size_t len, int *seen, bf_error *err)
{
    const bf_family *f = m->family;
    const char *eq = memchr(kv, '=', len);
    if (!eq || eq == kv || eq == kv + len - 1)
        return bf_fail(err, BF_ERR_ARG, "model %s: option '%.*s' is not key=value",
                       f->info.name, (int)len, kv);
    size_t klen = (size_t)(eq - kv), vlen = len - klen - 1;
    const char *val = eq + 1;

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
            return bf_fail(err, BF_ERR_ARG, "model %s: lobes must be an integer from 1 to %d, got '%s'",
                           f->info.name, BF_MAX_LOBES, buf);
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
        return bf_fail(err, BF_ERR_ARG, "model %s: option %s has no value '%.*s' (one of %s)",
                       f->info.name, oi->name, (int)vlen, val, allowed);
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
        len = strlen(m->spec);
        snprintf(m->spec + len, cap - len, "%c%s=%s", o ? ',' : ':', f->info.options[o].name,
                 f->info.options[o].values[m->opt[o]]);
    }
    if (f->info.lobes) {
        len = strlen(m->spec);
        snprintf(m->spec + len, cap - len, "%clobes=%d", no ? ',' : ':', m->lobes);
    }
}

bf_model *bf_model_create(const char *spec, int channels, bf_error *err)
{
    if (!spec || !*spec) {
        bf_fail(err, BF_ERR_ARG, "empty model name");
        return NULL;
    }
    if (channels < 1) {
        bf_fail(err, BF_ERR_ARG, "channel count must be at least 1, got %d", channels);
        return NULL;
    }
    const char *colon = strchr(spec, ':');
    size_t nlen = colon ? (size_t)(colon - spec) : strlen(spec);
    const bf_family *f = bf_registry_find(spec, nlen);
    if (!f) {
        bf_fail(err, BF_ERR_ARG, "unknown model '%.*s' (see brdfit models)", (int)nlen, spec);
        return NULL;
    }
    bf_model *m = calloc(1, sizeof *m);
    if (!m) {
        bf_fail(err, BF_ERR_NOMEM, "out of memory");
        return NULL;
    }
    m->family = f;
    m->channels = channels;
    m->lobes = 1;
    m->reciprocal = 1;
    int seen[BF_MAX_OPTIONS + 1] = {0};
    if (colon) {
        const char *p = colon + 1;
        for (;;) {
            const char *comma = strchr(p, ',');
            size_t len = comma ? (size_t)(comma - p) : strlen(p);
            if (apply_option(m, p, len, seen, err) != BF_OK) {
                free(m);
                return NULL;
            }
            if (!comma)
                break;
            p = comma + 1;
        }
    }
    if (f->configure(m, err) != BF_OK) {
        free(m);
        return NULL;
    }
    make_canonical_spec(m);
    return m;
}

void bf_model_free(bf_model *m) { free(m); }

int bf_model_add_param_open(bf_model *m, const char *name, int colour, double lo, int lo_open,
                            double hi, int hi_open, double def, bf_scale scale, int lobe,
                            bf_error *err)
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
    p->colour = colour;
    p->lo = lo;
    p->hi = hi;
    p->lo_open = lo_open;
    p->hi_open = hi_open;
    p->def = def;
    p->scale = scale;
    p->lobe = lobe;
    m->offset[i] = m->nfree;
    m->nfree += colour ? m->channels : 1;
    if (lobe > 0 && lobe <= BF_MAX_LOBES) {
        if (m->lobe_first[lobe] == 0 && colour)
            m->lobe_first[lobe] = i;
        else
            m->lobe_nscalar[lobe]++;
    }
    return BF_OK;
}

int bf_model_add_param(bf_model *m, const char *name, int colour, double lo, double hi,
                       double def, bf_scale scale, int lobe, bf_error *err)
{
    return bf_model_add_param_open(m, name, colour, lo, 0, hi, 0, def, scale, lobe, err);
}

int bf_model_opt(const bf_model *m, const char *key)
{
    int no = count_options(m->family);
    for (int o = 0; o < no; o++)
        if (strcmp(m->family->info.options[o].name, key) == 0)
            return m->opt[o];
    return -1;
}

const char *bf_model_name(const bf_model *m) { return m->family->info.name; }
const char *bf_model_spec(const bf_model *m) { return m->spec; }
int bf_model_channels(const bf_model *m) { return m->channels; }
int bf_model_lobes(const bf_model *m) { return m->lobes; }
int bf_model_reciprocal(const bf_model *m) { return m->reciprocal; }
int bf_model_energy_conserving(const bf_model *m) { return m->energy_conserving; }
int bf_model_nparams(const bf_model *m) { return m->nparam; }
int bf_model_nfree(const bf_model *m) { return m->nfree; }

const char *bf_model_option(const bf_model *m, const char *key)
{
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
            return v < count_values(&m->family->info.options[o])
                       ? m->family->info.options[o].values[v] : NULL;
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

void bf_model_defaults(const bf_model *m, double *x)
{
    for (int i = 0; i < m->nparam; i++) {
        int n = m->param[i].colour ? m->channels : 1;
        for (int c = 0; c < n; c++)
            x[m->offset[i] + c] = m->param[i].def;
    }
}

int bf_model_check(const bf_model *m, const double *x, bf_error *err)
{
    for (int i = 0; i < m->nparam; i++) {
        const bf_param_info *p = &m->param[i];
        int n = p->colour ? m->channels : 1;
        for (int c = 0; c < n; c++) {
            double v = x[m->offset[i] + c];
            char where[48] = "";
            if (p->colour && m->channels > 1)
                snprintf(where, sizeof where, "[%d]", c);
            if (!isfinite(v))
                return bf_fail(err, BF_ERR_RANGE, "parameter %s%s is %g", p->name, where, v);
            if (v < p->lo || (p->lo_open && v == p->lo) || v > p->hi || (p->hi_open && v == p->hi))
                return bf_fail(err, BF_ERR_RANGE, "parameter %s%s = %.17g is outside %c%.17g, %.17g%c",
                               p->name, where, v, p->lo_open ? '(' : '[', p->lo, p->hi,
                               p->hi_open ? ')' : ']');
        }
    }
    return BF_OK;
}

void bf_model_eval_range(const bf_model *m, const double *x, const bf_geometry *g,
                         size_t i0, size_t i1, double *values, double *grad)
{
    if (i1 > g->n)
        i1 = g->n;
    if (i0 >= i1)
        return;
    m->family->eval(m, x, g, i0, i1, values, grad);
}

void bf_model_eval(const bf_model *m, const double *x, const bf_geometry *g,
                   double *values, double *grad)
{
    bf_model_eval_range(m, x, g, 0, g->n, values, grad);
}
