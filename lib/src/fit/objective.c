/* The objective: model + samples + residual form -> a bf_problem over the internal
 * vector z (free entries only, in their internal scale; see parametrisation.c).
 *
 * Residual r = i*C + c (sample-major, as bf_model_eval lays out values), so the model's
 * Jacobian rows map directly onto the problem's. For each residual:
 *   res = sqrt(w_i) form(f, m, cos theta_i)                 (forms: objective_state.h)
 *   d res / d z_j = sqrt(w_i) form'(f) d f / d x_k  dx_k / dz_j,  k the entry of z_j
 * with w_i the product of the sample's own weight (use_weights; negative weights count
 * as 0), its solid-angle weight (solid_angle) and its scene weight (always, when a scene
 * gave one). Samples below the horizon (cos theta_i
 * <= 0 or cos theta_o <= 0) have residual 0 and a zero Jacobian row: the model is 0 there
 * whatever was measured, and nres must stay n*C (preprocessing normally drops them).
 *
 * The relative form's floor is per channel: delta_c = 1e-3 mean |m| over that channel's
 * samples above the horizon (1e-3 where they are all 0), so near-zero measurements do not
 * blow the residual up while bright and dark channels are each judged relative to
 * themselves. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "base/big_alloc.h"
#include "objective_state.h"
#include "base/parallel.h"
#include "base/sized.h"

/* Model-gradient scratch per block of samples: about 128 KiB whatever C and P are, and
 * at most one geometry block (generated geometries are made a block at a time). */
#define BLOCK_DOUBLES 16384

static size_t block_samples(const bf_objective *o, int with_grad)
{
    size_t b = BLOCK_DOUBLES / ((size_t)o->C * (with_grad ? (size_t)o->P + 1 : 1));
    if (b < 1)
        b = 1;
    return b < BF_GEOMETRY_BLOCK ? b : BF_GEOMETRY_BLOCK;
}

/* The residual of sample i, channel c (value f, geometry view gv at sample j) and dr/df. */
static inline double residual_of(const bf_objective *o, size_t i, size_t c, double f, double cs, double *drdf)
{
    const size_t r = i * (size_t)o->C + c;
    const double mm = o->samples->value[r];
    const double t = o->meas_t ? o->meas_t[r] : bf_obj_form_meas(o->residual, mm, cs);
    return bf_obj_form_t(o->residual, f, mm, cs, o->delta[c], t, drdf);
}

int bf_obj_eval_x(const bf_objective *o, const double *x, const bf_obj_cols *cols, size_t r0, size_t r1, double *res,
                  double *jac)
{
    const int ncols = cols->n, *idx = cols->idx;
    const double *colscale = cols->scale;
    const size_t C = (size_t)o->C, P = (size_t)o->P, nres = o->n * C;
    if (r1 > nres)
        r1 = nres;
    if (r0 >= r1)
        return 0;
    size_t first = r0 / C, end = (r1 + C - 1) / C;
    size_t chunk = block_samples(o, jac != NULL);
    if (chunk > end - first)
        chunk = end - first;
    bf_obj_ws *ws = bf_obj_ws_get(o->ws);
    double *vals = ws ? bf_obj_ws_buf(ws, BF_WS_VALS, chunk * C * sizeof *vals) : NULL;
    double *grad = jac && ws ? bf_obj_ws_buf(ws, BF_WS_GRAD, chunk * C * P * sizeof *grad) : NULL;
    if (!vals || (jac && !grad)) {
        bf_obj_ws_put(o->ws, ws);
        return -1;
    }
    bf_geometry_block gb;
    for (size_t ib = first; ib < end; ib += chunk) {
        size_t ie = ib + chunk < end ? ib + chunk : end;
        const bf_geometry *gv = bf_geometry_view(o->geom, ib, ie - ib, &gb);
        bf_model_eval_range(o->model, x, gv, 0, ie - ib, vals, jac ? grad : NULL);
        for (size_t i = ib; i < ie; i++) {
            size_t c0 = i == first ? r0 - i * C : 0;
            size_t c1 = (i + 1) * C > r1 ? r1 - i * C : C;
            int valid = bf_geometry_valid(gv, i - ib);
            double w = o->sw ? o->sw[i] : 1.0, cs = gv->lz[i - ib];
            for (size_t c = c0; c < c1; c++) {
                size_t r = i * C + c, row = r - r0;
                double *jr = jac ? jac + row * (size_t)ncols : NULL;
                if (!valid) {
                    res[row] = 0.0;
                    if (jr)
                        memset(jr, 0, (size_t)ncols * sizeof *jr);
                    continue;
                }
                double d;
                size_t li = (i - ib) * C + c;
                res[row] = w * residual_of(o, i, c, vals[li], cs, &d);
                if (jr) {
                    const double *gr = grad + li * P, s = w * d;
                    for (int j = 0; j < ncols; j++)
                        jr[j] = s * gr[idx[j]] * colscale[j];
                }
            }
        }
    }
    bf_obj_ws_put(o->ws, ws);
    return 0;
}

/* z -> x and the chain rule dx/dz as column scales. The vectors are small: on the stack
 * for every model of the registry. */
static int with_model_vector(const bf_objective *o, const double *z, double **x, double **colscale, double *stack,
                             size_t stack_len)
{
    size_t need = (size_t)o->P + (size_t)o->nz + 1;
    *x = need <= stack_len ? stack : malloc(need * sizeof **x);
    if (!*x)
        return -1;
    *colscale = *x + o->P;
    bf_objective_to_model(o, z, *x);
    for (int j = 0; j < o->nz; j++)
        (*colscale)[j] = bf_scale_dxdz(o->scale[o->kidx[j]], (*x)[o->kidx[j]]);
    return 0;
}

/* The problem's eval. Concurrent calls for disjoint ranges share nothing mutable. */
static int problem_eval(void *ctx, const double *z, size_t r0, size_t r1, double *res, double *jac)
{
    const bf_objective *o = ctx;
    double stack[256], *x, *colscale;
    if (with_model_vector(o, z, &x, &colscale, stack, 256))
        return -1;
    int bad = bf_obj_eval_x(o, x, &(bf_obj_cols){o->nz, o->kidx, colscale}, r0, r1, res, jac); /* solve.h: 0 or -1 */
    if (x != stack)
        free(x);
    return bad;
}

/* The problem's fused pass (solve.h). */
static int problem_normal(void *ctx, const double *z, const bf_loss *loss, int threads, double *ssq, double *jtr,
                          double *jtj)
{
    const bf_objective *o = ctx;
    double stack[256], *x, *colscale;
    if (with_model_vector(o, z, &x, &colscale, stack, 256))
        return -1;
    const bf_obj_pass req = {loss, threads, {o->nz, o->kidx, colscale}, 0};
    int bad = bf_obj_normal_x(o, x, &req, &(bf_obj_pass_out){ssq, jtr, jtj, NULL}); /* solve.h: 0 or -1 */
    if (x != stack)
        free(x);
    return bad;
}

/* Energy conservation as c(z) <= 0: c = max over channels of the sum of that channel's
 * colour parameters (rho_d + every lobe's rho_s ...) minus 1, the albedo bound these
 * weights express for normalised lobes. The gradient is the maximising channel's (a
 * subgradient where channels tie), through the parametrisation; fixed entries count in
 * the sum but have no gradient. */
static double problem_constraint(void *ctx, const double *z, double *grad)
{
    const bf_objective *o = ctx;
    double xs[64], *x = o->P <= 64 ? xs : malloc((size_t)o->P * sizeof *x);
    if (!x)
        return INFINITY;
    bf_objective_to_model(o, z, x);
    int best = 0;
    double bsum = -INFINITY;
    for (int c = 0; c < o->C; c++) {
        double sum = 0.0;
        for (int q = 0; q < o->ncolor; q++)
            sum += x[o->color_off[q] + c * o->color_step[q]];
        if (sum > bsum) {
            bsum = sum;
            best = c;
        }
    }
    if (grad) {
        for (int j = 0; j < o->nz; j++)
            grad[j] = 0.0;
        for (int q = 0; q < o->ncolor; q++) {
            int k = o->color_off[q] + best * o->color_step[q];
            if (o->zpos[k] >= 0)
                grad[o->zpos[k]] = bf_scale_dxdz(o->scale[k], x[k]);
        }
    }
    if (x != xs)
        free(x);
    return bsum - 1.0;
}

void bf_objective_free(bf_objective *o)
{
    if (!o)
        return;
    bf_obj_ws_list_free(o->ws);
    free(o->lo);
    free(o->hi);
    free(o->fixed);
    free(o->fixval);
    free(o->scale);
    free(o->zpos);
    free(o->kidx);
    free(o->zlo);
    free(o->zhi);
    free(o->sw);
    free(o->delta);
    free(o->meas_t);
    free(o->color_off);
    free(o->color_step);
    free(o);
}

/* Combined per-sample weights (sample weights, solid angle), as square roots. */
static bf_status setup_weights(bf_objective *o, const bf_objective_options *opt, bf_error *err)
{
    bf_samples *s = o->samples;
    int use_w = opt->use_weights && s->weight;
    if (!use_w && !opt->solid_angle && !s->scene_weight)
        return BF_OK;
    if (!(o->sw = bf_big_malloc((o->n + 1) * sizeof *o->sw)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for the objective's weights");
    for (size_t i = 0; i < o->n; i++)
        o->sw[i] = 1.0;
    if (opt->solid_angle) {
        bf_status rc = bf_obj_solid_angle_weights(s, o->geom, o->sw, err);
        if (rc)
            return rc;
    }
    for (size_t i = 0; i < o->n; i++) {
        double w = o->sw[i] * (use_w ? s->weight[i] : 1.0) * (s->scene_weight ? s->scene_weight[i] : 1.0);
        o->sw[i] = w > 0.0 && isfinite(w) ? sqrt(w) : 0.0;
    }
    return BF_OK;
}

/* One pass over the samples (fixed chunks on the objective's threads, summed in chunk
 * order): the samples above the horizon (nvalid), per channel the relative form's floor
 * from the mean |m| over them, and the log and cbrt forms' measurement terms (their
 * log1p or cbrt would be a third of every evaluation; without the memory for them each
 * evaluation computes them itself). */
enum { SCAN_CHUNK = 16384 }; /* samples */

typedef struct scan_job {
    bf_objective *o;
    size_t *nvalid; /* per chunk */
    size_t *npos;   /* per chunk: valid samples with a positive weight */
    double *logw;   /* per chunk: sum of ln w over them (one per sample; times C later) */
    double *wsum;   /* per chunk: sum of w over them (likewise) */
    double *sum;    /* per chunk, C: sum |m| over valid samples */
} scan_job;

static void scan_chunk(void *ctx, size_t chunk)
{
    scan_job *j = ctx;
    bf_objective *o = j->o;
    const size_t C = (size_t)o->C;
    const double *value = o->samples->value;
    size_t i1 = (chunk + 1) * SCAN_CHUNK < o->n ? (chunk + 1) * SCAN_CHUNK : o->n, nvalid = 0, npos = 0;
    double logw = 0.0, wsum = 0.0;
    double sum[64] = {0}, *sp = C <= 64 ? sum : j->sum + chunk * C; /* on the stack when it fits */
    bf_geometry_block gb;
    for (size_t ib = chunk * SCAN_CHUNK; ib < i1; ib += BF_GEOMETRY_BLOCK) {
        size_t cnt = i1 - ib < BF_GEOMETRY_BLOCK ? i1 - ib : BF_GEOMETRY_BLOCK;
        const bf_geometry *gv = bf_geometry_view(o->geom, ib, cnt, &gb);
        for (size_t q = 0; q < cnt; q++) {
            const double *v = value + (ib + q) * C;
            if (o->meas_t)
                for (size_t c = 0; c < C; c++)
                    o->meas_t[(ib + q) * C + c] = bf_obj_form_meas(o->residual, v[c], gv->lz[q]);
            if (!bf_geometry_valid(gv, q))
                continue;
            nvalid++;
            for (size_t c = 0; c < C; c++)
                sp[c] += fabs(v[c]);
            const double sw = o->sw ? o->sw[ib + q] : 1.0; /* sqrt of the weight */
            if (sw > 0.0) {
                npos++;
                logw += 2.0 * log(sw);
                wsum += sw * sw;
            }
        }
    }
    j->nvalid[chunk] = nvalid;
    j->npos[chunk] = npos;
    j->logw[chunk] = logw;
    j->wsum[chunk] = wsum;
    if (sp == sum)
        memcpy(j->sum + chunk * C, sum, C * sizeof *sum);
}

static int scan_samples(bf_objective *o)
{
    const size_t C = (size_t)o->C, nchunks = (o->n + SCAN_CHUNK - 1) / SCAN_CHUNK;
    if ((o->residual == BF_RESIDUAL_LOG || o->residual == BF_RESIDUAL_CBRT))
        o->meas_t = bf_big_malloc(o->n * C * sizeof *o->meas_t + 1); /* NULL: computed as needed */
    scan_job j = {o,
                  calloc(nchunks + 1, sizeof(size_t)),
                  calloc(nchunks + 1, sizeof(size_t)),
                  calloc(nchunks + 1, sizeof(double)),
                  calloc(nchunks + 1, sizeof(double)),
                  calloc(nchunks * C + 1, sizeof(double))};
    double *sum = calloc(C, sizeof *sum);
    if (!j.nvalid || !j.npos || !j.logw || !j.wsum || !j.sum || !sum) {
        free(j.nvalid);
        free(j.npos);
        free(j.logw);
        free(j.wsum);
        free(j.sum);
        free(sum);
        return -1;
    }
    bf_parallel_for(nchunks, o->threads, scan_chunk, &j);
    for (size_t k = 0; k < nchunks; k++) {
        o->npos += j.npos[k] * C;
        o->sum_log_w += j.logw[k] * (double)C;
        o->wsum += j.wsum[k] * (double)C;
        o->nvalid += j.nvalid[k];
        for (size_t c = 0; c < C; c++)
            sum[c] += j.sum[k * C + c];
    }
    for (size_t c = 0; c < C; c++) {
        double d = o->nvalid ? 1e-3 * sum[c] / (double)o->nvalid : 0.0;
        o->delta[c] = d > 0.0 && isfinite(d) ? d : 1e-3;
    }
    free(j.nvalid);
    free(j.npos);
    free(j.logw);
    free(j.wsum);
    free(j.sum);
    free(sum);
    return 0;
}

/* bf_objective_options with the library's defaults (a whole struct of this version). */
static void objective_options_defaults(bf_objective_options *o)
{
    o->use_weights = 1; /* bf_fit's default: a data set's own weights count */
}

BF_SIZED_INIT(bf_objective_options, objective_options_defaults)

bf_status bf_objective_new(const bf_model *m, bf_samples *s, const bf_objective_options *opt, bf_objective **out,
                           bf_error *err)
{
    *out = NULL;
    /* NULL keeps its meaning from before the size: a zeroed struct's (no weights). */
    static const bf_objective_options defaults = {.size = sizeof(bf_objective_options)};
    if (!opt)
        opt = &defaults;
    /* The first version is today's struct: nothing smaller is one. */
    if (bf_sized_check(opt, sizeof *opt, "bf_objective_options", err) != BF_OK)
        return BF_ERR_ARG;
    if (!m || !s)
        return bf_fail(err, BF_ERR_ARG, "objective: no model or no samples");
    if (bf_model_channels(m) != s->channels)
        return bf_fail(err, BF_ERR_ARG, "model %s has %d channel%s but the samples have %d", bf_model_name(m),
                       bf_model_channels(m), bf_model_channels(m) == 1 ? "" : "s", s->channels);
    if ((int)opt->residual < 0 || opt->residual > BF_RESIDUAL_RELATIVE)
        return bf_fail(err, BF_ERR_ARG, "objective: unknown residual form %d", (int)opt->residual);
    if (opt->noverrides > 0 && !opt->overrides)
        return bf_fail(err, BF_ERR_ARG, "objective: %d overrides but no array", opt->noverrides);
    const bf_geometry *g;
    bf_status rc = bf_samples_geometry(s, &g, err);
    if (rc != BF_OK)
        return rc;
    bf_objective *o = calloc(1, sizeof *o);
    if (!o)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for the objective");
    o->model = m;
    o->samples = s;
    o->geom = g;
    o->residual = opt->residual;
    o->threads = opt->threads;
    o->n = s->n;
    o->C = s->channels;
    o->P = bf_model_nvalues(m);
    size_t P1 = (size_t)o->P + 1, np = (size_t)bf_model_nparams(m) + 1;
    o->lo = malloc(P1 * sizeof *o->lo);
    o->hi = malloc(P1 * sizeof *o->hi);
    o->fixed = calloc(P1, 1);
    o->fixval = calloc(P1, sizeof *o->fixval);
    o->scale = calloc(P1, sizeof *o->scale);
    o->zpos = malloc(P1 * sizeof *o->zpos);
    o->kidx = malloc(P1 * sizeof *o->kidx);
    o->zlo = malloc(P1 * sizeof *o->zlo);
    o->zhi = malloc(P1 * sizeof *o->zhi);
    o->delta = malloc((size_t)o->C * sizeof *o->delta);
    o->color_off = malloc(np * sizeof *o->color_off);
    o->color_step = malloc(np * sizeof *o->color_step);
    o->ws = bf_obj_ws_list_new();
    if (!o->ws || !o->lo || !o->hi || !o->fixed || !o->fixval || !o->scale || !o->zpos || !o->kidx || !o->zlo ||
        !o->zhi || !o->delta || !o->color_off || !o->color_step) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for the objective");
        goto fail;
    }
    if ((rc = bf_obj_apply_overrides(o, opt->overrides, opt->noverrides, err)) != BF_OK)
        goto fail;
    bf_obj_setup_scale(o);

    if ((rc = setup_weights(o, opt, err)) != BF_OK)
        goto fail;
    if (scan_samples(o)) {
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for the objective");
        goto fail;
    }
    if (o->nvalid == 0) {
        rc = bf_fail(err, BF_ERR_ARG, "no samples above the horizon to fit (%zu samples)", o->n);
        goto fail;
    }

    for (int i = 0; i < bf_model_nparams(m); i++)
        if (bf_model_param(m, i)->color || bf_model_param(m, i)->mono) {
            o->color_step[o->ncolor] = bf_model_param(m, i)->color;
            o->color_off[o->ncolor++] = bf_model_param_offset(m, i);
        }

    bf_problem_init(&o->problem);
    o->problem.nres = o->n * (size_t)o->C;
    o->problem.npar = o->nz;
    o->problem.lo = o->zlo;
    o->problem.hi = o->zhi;
    o->problem.eval = problem_eval;
    o->problem.normal = problem_normal;
    o->problem.user = o;
    o->problem.constraint = o->ncolor > 0 ? problem_constraint : NULL;
    *out = o;
    return BF_OK;
fail:
    bf_objective_free(o);
    return rc;
}

const bf_problem *bf_objective_problem(const bf_objective *o)
{
    return &o->problem;
}
int bf_objective_nz(const bf_objective *o)
{
    return o->nz;
}
int bf_objective_fixed(const bf_objective *o, int k)
{
    return k >= 0 && k < o->P && o->fixed[k];
}

void bf_objective_bounds(const bf_objective *o, double *lo, double *hi)
{
    for (int k = 0; k < o->P; k++) {
        lo[k] = o->fixed[k] ? o->fixval[k] : o->lo[k];
        hi[k] = o->fixed[k] ? o->fixval[k] : o->hi[k];
    }
}
