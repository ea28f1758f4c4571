/* A fit whose channels are independent problems, one fit per channel (fit_channels.h). */
#include "fit_channels.h"

#include "diagnostics.h"
#include "models/family.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int bf_fit_channels_separable(const bf_objective *obj)
{
    const bf_model *m = obj->model;
    if (!m->family->channels_independent || obj->C < 2)
        return 0;
    for (int i = 0; i < bf_model_nparams(m); i++)
        if (!bf_model_param(m, i)->color && !bf_objective_fixed(obj, bf_model_param_offset(m, i)))
            return 0; /* a free scalar (mono ties included) couples the channels */
    return 1;
}

int bf_fit_channels_entry(const bf_model *m, const bf_model *m1, int c, int k1)
{
    for (int i = bf_model_nparams(m1) - 1; i >= 0; i--) {
        const int off1 = bf_model_param_offset(m1, i);
        if (k1 >= off1)
            return bf_model_param_offset(m, i) + (bf_model_param(m, i)->color ? c : 0) + (k1 - off1);
    }
    return -1;
}

/* Channel c of s as a sample set of its own: the same directions (or MERL cells),
 * weights and scene weights, channel c's values, name and wavelength. */
static bf_status channel_samples(const bf_samples *s, int c, bf_samples **out, bf_error *err)
{
    const size_t n = s->n, C = (size_t)s->channels;
    bf_samples *o;
    bf_status rc = s->theta_i ? bf_samples_new(n, 1, &o, err) : bf_samples_new_cells(n, 1, &o, err);
    if (rc != BF_OK)
        return rc;
    rc = bf_samples_set_channel_name(o, 0, s->channel_names[c], err);
    if (rc == BF_OK && s->weight)
        rc = bf_samples_add_weights(o, err);
    if (rc == BF_OK && s->merl && !o->merl && !(o->merl = calloc(1, sizeof *o->merl)))
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for a channel's samples");
    if (rc == BF_OK && s->merl && !o->merl->cell && !(o->merl->cell = malloc((n + 1) * sizeof *o->merl->cell)))
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for a channel's samples");
    if (rc == BF_OK && s->wavelength && !(o->wavelength = malloc(sizeof *o->wavelength)))
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for a channel's samples");
    if (rc == BF_OK && s->scene_weight && !(o->scene_weight = malloc((n + 1) * sizeof *o->scene_weight)))
        rc = bf_fail(err, BF_ERR_NOMEM, "fit: out of memory for a channel's samples");
    if (rc != BF_OK) {
        bf_samples_free(o);
        return rc;
    }
    if (s->theta_i) {
        memcpy(o->theta_i, s->theta_i, n * sizeof *o->theta_i);
        memcpy(o->phi_i, s->phi_i, n * sizeof *o->phi_i);
        memcpy(o->theta_o, s->theta_o, n * sizeof *o->theta_o);
        memcpy(o->phi_o, s->phi_o, n * sizeof *o->phi_o);
    }
    if (s->merl)
        memcpy(o->merl->cell, s->merl->cell, n * sizeof *o->merl->cell);
    if (s->wavelength)
        o->wavelength[0] = s->wavelength[c];
    for (size_t i = 0; i < n; i++)
        o->value[i] = s->value[i * C + (size_t)c];
    if (s->weight)
        memcpy(o->weight, s->weight, n * sizeof *o->weight);
    if (s->scene_weight)
        memcpy(o->scene_weight, s->scene_weight, n * sizeof *o->scene_weight);
    *out = o;
    return BF_OK;
}

/* The overrides of channel c's fit: those of every channel, and channel c's as the
 * only channel's (ov: room for o's). */
static int channel_overrides(const bf_fit_options *o, int c, bf_override *ov)
{
    int n = 0;
    for (int i = 0; i < o->objective.noverrides; i++) {
        const bf_override *v = &o->objective.overrides[i];
        if (v->channel >= 0 && v->channel != c)
            continue;
        ov[n] = *v;
        if (v->channel == c)
            ov[n].channel = 0;
        n++;
    }
    return n;
}

bf_status bf_fit_channels_options(const bf_fit_options *o, const bf_model *m, const bf_model *m1, int c,
                                  bf_fit_options *oc)
{
    oc->objective.noverrides = channel_overrides(o, c, (bf_override *)oc->objective.overrides);
    if (o->start)
        for (int k1 = 0; k1 < bf_model_nvalues(m1); k1++)
            ((double *)oc->start)[k1] = o->start[bf_fit_channels_entry(m, m1, c, k1)];
    return BF_OK;
}

bf_status bf_fit_channels_samples(const bf_samples *s, int c, bf_samples **out, bf_error *err)
{
    return channel_samples(s, c, out, err);
}

/* The search's figures of the channels: the starts and candidates are the option's, as
 * each channel ran them; the starts at the best the least sure channel's; the screen's
 * and presolve's work summed (their samples are one channel's: every channel's set has
 * as many). */
static void merge_counts(const bf_fit_result *ch, int C, bf_fit_result *r)
{
    r->presolve.samples = ch[0].presolve.samples;
    r->screen.samples = ch[0].screen.samples;
    r->starts_at_best = ch[0].starts_at_best;
    for (int c = 0; c < C; c++) {
        if (ch[c].starts > r->starts)
            r->starts = ch[c].starts;
        if (ch[c].starts_at_best < r->starts_at_best)
            r->starts_at_best = ch[c].starts_at_best;
        if (ch[c].candidates > r->candidates)
            r->candidates = ch[c].candidates;
        r->presolve.iterations += ch[c].presolve.iterations;
        r->presolve.evaluations += ch[c].presolve.evaluations;
        r->presolve.seconds += ch[c].presolve.seconds;
        r->screen.iterations += ch[c].screen.iterations;
        r->screen.evaluations += ch[c].screen.evaluations;
        r->screen.seconds += ch[c].screen.seconds;
    }
}

/* The channels' solutions as one: costs and work summed, the worst stop, and why each
 * channel stopped where they differ. */
static void merge_solution(const bf_fit_result *ch, int C, bf_solution *sol)
{
    *sol = ch[0].solution;
    sol->initial_cost = sol->final_cost = sol->seconds = 0.0;
    sol->iterations = sol->evaluations = 0;
    int same = 1;
    for (int c = 0; c < C; c++) {
        const bf_solution *a = &ch[c].solution;
        sol->initial_cost += a->initial_cost;
        sol->final_cost += a->final_cost;
        sol->iterations += a->iterations;
        sol->evaluations += a->evaluations;
        sol->seconds += a->seconds;
        sol->usable = sol->usable && a->usable;
        if (a->stop > sol->stop)
            sol->stop = a->stop;
        same = same && strcmp(a->termination, ch[0].solution.termination) == 0;
    }
    if (same)
        return;
    size_t len = (size_t)snprintf(sol->termination, sizeof sol->termination, "per channel:");
    for (int c = 0; c < C && len < sizeof sol->termination; c++)
        len += (size_t)snprintf(sol->termination + len, sizeof sol->termination - len, "%s %d: %s", c ? ";" : "", c,
                                ch[c].solution.termination);
}

void bf_fit_channels_merge(const bf_fit_result *ch, int C, bf_fit_result *r)
{
    const bf_model *m1 = ch[0].model;
    r->ok = 1;
    for (int c = 0; c < C; c++) {
        r->ok = r->ok && ch[c].ok;
        for (int k1 = 0; k1 < bf_model_nvalues(m1); k1++) {
            const int k = bf_fit_channels_entry(r->model, m1, c, k1);
            r->x[k] = ch[c].x[k1];
            r->inactive[k] = ch[c].inactive[k1];
            r->inactive_gate[k] = ch[c].inactive_gate[k1]; /* a parameter index: the same in both */
        }
    }
    merge_solution(ch, C, &r->solution);
    merge_counts(ch, C, r);
}

void bf_fit_channels_warn(const bf_fit_result *ch, const bf_samples *s, bf_fit_result *r)
{
    for (int c = 0; c < s->channels; c++)
        for (int w = 0; w < ch[c].nwarnings; w++) {
            const bf_warning_kind kind = ch[c].warning_kind[w];
            if (kind == BF_WARN_FAILED || kind == BF_WARN_SOLVER_LIMIT || kind == BF_WARN_ONE_START)
                bf_fit_warn(r, kind, "channel %s: %s", s->channel_names[c], ch[c].warnings[w]);
        }
}
