/* Reading and preparing data in one call (brdfit/load.h), in the one order every front
 * end uses. */
#include "brdfit/load.h"

#include "base/cancel.h"
#include "base/sized.h"
#include "brdfit/scene.h"
#include "run_options.h"

#include <string.h>

bf_status bf_samples_read(const char *path, const bf_options *o, bf_samples **out, bf_error *err)
{
    if (!o)
        return bf_samples_read_with(path, NULL, out, err);
    options_reading rd;
    options_read_get(o, &rd);
    return bf_samples_read_with(path, &rd.read, out, err);
}

BF_SIZED_INIT_ZERO(bf_load_report)

/* The scene goes between preprocessing's drops and its subsampling: prep without the
 * subsample, the scene, then prep again with only the subsample (nothing else is left to
 * drop), so that a subsample of N means N samples inside the scene. */
static bf_status apply_scene(const char *path, const char *scene, const bf_prep *p, bf_samples *s, bf_load_report *r,
                             bf_error *err)
{
    bf_error e;
    bf_scene *sc = NULL;
    bf_status rc = bf_scene_read(scene, &sc, err);
    if (rc != BF_OK)
        return rc;
    r->scene = 1;
    r->scene_in = s->n;
    rc = bf_scene_apply(sc, s, &r->scene_kept, &e);
    bf_scene_free(sc);
    if (rc != BF_OK)
        return bf_fail(err, rc, "%s: scene %s: %s", path, scene, e.msg);
    bf_prep sub = {.subsample = p->subsample, .seed = p->seed};
    bf_prep_report r2;
    if ((rc = bf_samples_prep(s, &sub, &r2, &e)) != BF_OK)
        return bf_fail(err, rc, "%s: %s", path, e.msg);
    r->subsampled_out = r2.subsampled_out;
    return BF_OK;
}

/* Stopped by o's cancel flag between steps (the readers watch it within theirs). */
static bf_status cancelled(const char *name, const bf_options *o, bf_error *err)
{
    if (bf_cancel_is_set(o->cancel))
        return bf_fail(err, BF_ERR_CANCELLED, "%s: cancelled", name);
    return BF_OK;
}

/* The preprocessing, the scene and the subsample of o applied to s, counted into r. */
static bf_status prepare(const char *name, const bf_options *o, bf_samples *s, bf_load_report *r, bf_error *err)
{
    bf_prep p, first;
    options_prep_get(o, &p);
    const char *scene = options_scene(o);
    first = p;
    if (scene)
        first.subsample = 0;
    bf_prep_report pr;
    bf_error e;
    bf_status rc = bf_samples_prep(s, &first, &pr, &e);
    if (rc != BF_OK)
        return bf_fail(err, rc, "%s: %s", name, e.msg);
    r->below_horizon = pr.below_horizon;
    r->nonfinite = pr.nonfinite;
    r->negative = pr.negative;
    r->above_max_theta = pr.above_max_theta;
    r->subsampled_out = pr.subsampled_out;
    if ((rc = cancelled(name, o, err)) != BF_OK)
        return rc;
    if (scene && (rc = apply_scene(name, scene, &p, s, r, err)) != BF_OK)
        return rc;
    return cancelled(name, o, err);
}

bf_status bf_samples_prepare(bf_samples *s, const bf_options *o, bf_load_report *report, bf_error *err)
{
    bf_load_report r;
    bf_load_report_init(&r);
    if (!s || !o)
        return bf_fail(err, BF_ERR_ARG, "prepare: no samples or no options");
    if (report && bf_sized_check(report, sizeof *report, "bf_load_report", err) != BF_OK)
        return BF_ERR_ARG;
    bf_status rc = bf_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    r.read = s->n;
    r.channels_read = s->channels;
    if ((rc = cancelled("samples", o, err)) == BF_OK)
        rc = prepare("samples", o, s, &r, err);
    r.kept = s->n;
    if (report)
        bf_sized_copy(report, &r, sizeof r);
    return rc;
}

bf_status bf_samples_load(const char *path, const bf_options *o, bf_samples **out, bf_load_report *report,
                          bf_error *err)
{
    bf_load_report r;
    bf_load_report_init(&r);
    *out = NULL;
    if (!o)
        return bf_fail(err, BF_ERR_ARG, "load: no options");
    if (report && bf_sized_check(report, sizeof *report, "bf_load_report", err) != BF_OK)
        return BF_ERR_ARG;
    bf_status rc = bf_options_check(o, err);
    if (rc != BF_OK)
        return rc;
    options_reading rd;
    options_read_get(o, &rd);
    bf_samples *s = NULL;
    if ((rc = bf_samples_read_with(path, &rd.read, &s, err)) != BF_OK)
        return rc;
    r.read = s->n;
    r.channels_read = s->channels;
    if ((rc = cancelled(path, o, err)) == BF_OK)
        rc = prepare(path, o, s, &r, err);
    r.kept = s->n;
    if (report)
        bf_sized_copy(report, &r, sizeof r);
    if (rc != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}
