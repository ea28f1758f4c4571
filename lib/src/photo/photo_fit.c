/* bf_photo_fit (photo.h): the whole run.
 *  1. The model, its bounds and scales; which entries each pixel fits and which are
 *     shared (--share), the mask and the rows (a tile's band).
 *  2. The start (photo_start.c) on an evenly spread subsample of the pixels: robust
 *     Lambertian normals and albedos, the automatic scale, the clusters, each cluster's
 *     model fit pooled over its pixels, and the shared entries' joint solve
 *     (photo_joint.c).
 *  3. The pixels, band by band (as many rows as keep the band's samples within
 *     band_bytes), in fixed chunks on every thread and three passes: each pixel's solve
 *     (photo_solve.c), the restarts of pixels that stand apart from their row
 *     neighbours, then the outputs, the Lambertian baseline and per chunk the sums of
 *     the relit errors, added in chunk order so the result does not depend on the
 *     thread count. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/parallel.h"
#include "brdfit/clock.h"
#include "brdfit/image.h"
#include "models/scale.h"
#include "photo_run.h"

#define START_PIXELS 2048  /* the subsample of the start */
#define MAX_ITERATIONS 100 /* per pixel solve */
#define DEFAULT_BAND_BYTES ((size_t)1 << 30)

void bf_photo_result_free(bf_photo_result *r)
{
    if (!r)
        return;
    bf_model_free(r->model);
    free(r->mask);
    free(r->normals);
    free(r->params);
    free(r->error);
    free(r->lambert_normals);
    free(r->lambert_albedo);
    free(r->cluster);
    free(r->shared);
    free(r->image_rms);
    free(r->image_lambert_rms);
    free(r->image_samples);
    for (int i = 0; i < BF_PHOTO_MAX_RELIT; i++) {
        free(r->relit_measured[i]);
        free(r->relit_model[i]);
    }
    free(r);
}

/* ---- setup ---- */

static bf_status setup(photo_run *run, bf_error *err)
{
    const bf_stack *s = run->s;
    const bf_photo_options *o = run->o;
    bf_status rc = bf_model_new(run->spec, s->channels, &run->model, err);
    if (rc != BF_OK)
        return rc;
    run->P = bf_model_nvalues(run->model);
    if (run->P > PHOTO_MAX_PARAMS)
        return bf_fail(err, BF_ERR_ARG, "%s: %d model entries: per-pixel fits take at most %d", run->spec, run->P,
                       PHOTO_MAX_PARAMS);
    int np = bf_model_nparams(run->model);
    for (int i = 0; i < np; i++) {
        const bf_param_info *pi = bf_model_param(run->model, i);
        int off = bf_model_param_offset(run->model, i), cnt = pi->color ? run->C : 1;
        for (int c = 0; c < cnt; c++) {
            int e = off + c;
            double lo = pi->lo, hi = pi->hi, hair = 1e-6 * (hi - lo);
            run->lo[e] = pi->lo_open ? lo + hair : lo;
            run->hi[e] = pi->hi_open ? hi - hair : hi;
            bf_scale sc = pi->scale;
            if (sc == BF_SCALE_LOG && !(run->lo[e] > 0.0))
                sc = run->lo[e] == 0.0 ? BF_SCALE_LOG1P : BF_SCALE_LINEAR;
            if (sc == BF_SCALE_LOG1P && !(run->lo[e] >= 0.0))
                sc = BF_SCALE_LINEAR;
            run->pscale[e] = sc;
            run->pixel_free[e] = 1;
        }
    }
    if (o->share && *o->share) {
        char *list = strdup(o->share), *save = NULL;
        if (!list)
            return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", photo_option_name(o, "share"));
        for (char *t = strtok_r(list, ",", &save); t && rc == BF_OK; t = strtok_r(NULL, ",", &save)) {
            int i = bf_model_find_param(run->model, t);
            if (i < 0) {
                rc = bf_fail(err, BF_ERR_ARG, "%s: %s has no parameter '%s' (brdfit models)",
                             photo_option_name(o, "share"), bf_model_name(run->model), t);
                break;
            }
            const bf_param_info *pi = bf_model_param(run->model, i);
            int off = bf_model_param_offset(run->model, i), cnt = pi->color ? run->C : 1;
            for (int c = 0; c < cnt; c++)
                if (run->pixel_free[off + c]) {
                    run->pixel_free[off + c] = 0;
                    run->shared[run->nshared++] = off + c;
                }
        }
        free(list);
        if (rc != BF_OK)
            return rc;
        if (run->nshared > BF_PHOTO_MAX_SHARED)
            return bf_fail(err, BF_ERR_ARG, "%s: %d entries, at most %d", photo_option_name(o, "share"), run->nshared,
                           BF_PHOTO_MAX_SHARED);
    }
    run->lbuf = malloc((size_t)run->K * 3 * sizeof *run->lbuf);
    run->ebuf = malloc((size_t)run->K * (size_t)run->C * sizeof *run->ebuf);
    if (!run->lbuf || !run->ebuf)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    return BF_OK;
}

static bf_status load_given_normals(photo_run *run, float **out, bf_error *err)
{
    const bf_stack *s = run->s;
    bf_image img;
    bf_image_init(&img);
    bf_status rc = bf_image_read(run->o->normals_file, &img, err);
    if (rc != BF_OK)
        return rc;
    if (img.width != s->width || img.height != s->height || img.channels < 3) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: %dx%d pixels of %d channels; the stack's normals need %dx%d of 3",
                     run->o->normals_file, img.width, img.height, img.channels, s->width, s->height);
        bf_image_clear(&img);
        return rc;
    }
    size_t n = (size_t)s->width * (size_t)s->height;
    float *w = malloc(n * 3 * sizeof *w);
    if (!w) {
        bf_image_clear(&img);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", run->o->normals_file);
    }
    for (size_t i = 0; i < n; i++) {
        double c[3], d[3], len = 0.0;
        for (int k = 0; k < 3; k++) {
            c[k] = img.pixels[i * (size_t)img.channels + (size_t)k];
            len += c[k] * c[k];
        }
        len = sqrt(len);
        if (!(len > 0.0) || !isfinite(len)) {
            c[0] = c[1] = 0.0;
            c[2] = 1.0;
            len = 1.0;
        }
        for (int k = 0; k < 3; k++)
            c[k] /= len;
        photo_to_world(s, c, d);
        for (int k = 0; k < 3; k++)
            w[3 * i + (size_t)k] = (float)d[k];
    }
    bf_image_clear(&img);
    *out = w;
    return BF_OK;
}

/* ---- the start ---- */

typedef struct shared_job {
    photo_run *run;
    const photo_band *b;
    double *normal, *x; /* per subsample pixel */
    const double *albedo;
    const int *label;
} shared_job;

/* Per-pixel solves of the subsample with the shared entries at their cluster's values. */
static void solve_sub_chunk(void *ctx, size_t p)
{
    shared_job *j = ctx;
    photo_run *run = j->run;
    const bf_stack *s = run->s;
    int K = run->K, C = run->C;
    photo_buffers bb;
    if (photo_buffers_new(run, &bb)) {
        photo_lights pl = {bb.l, bb.e, {0}};
        photo_lights_at(s, j->b->pixel[p] % s->width, j->b->pixel[p] / s->width, &pl);
        photo_problem pr = photo_run_problem(run, MAX_ITERATIONS);
        double *x = j->x + p * (size_t)run->P;
        for (int i = 0; i < run->nshared; i++)
            x[run->shared[i]] = run->start[(size_t)j->label[p] * (size_t)run->P + (size_t)run->shared[i]];
        photo_pixel_out po;
        photo_solve_pixel(&pr, j->b->v + p * (size_t)K * (size_t)C, &pl, x, j->normal + 3 * p, bb.w, &po);
    }
    photo_buffers_free(&bb);
}

/* Every stride-th pixel of b (at most max), copied; kc values per pixel. */
static bf_status band_pick(const photo_band *b, size_t kc, size_t max, photo_band *out, bf_error *err)
{
    memset(out, 0, sizeof *out);
    size_t stride = b->npix > max ? (b->npix + max - 1) / max : 1, n = (b->npix + stride - 1) / stride;
    out->y0 = b->y0;
    out->y1 = b->y1;
    out->pixel = malloc((n ? n : 1) * sizeof *out->pixel);
    out->v = malloc((n ? n : 1) * kc * sizeof *out->v);
    if (!out->pixel || !out->v) {
        photo_band_free(out);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    for (size_t p = 0; p < b->npix; p += stride) {
        out->pixel[out->npix] = b->pixel[p];
        memcpy(out->v + out->npix * kc, b->v + p * kc, kc * sizeof *out->v);
        out->npix++;
    }
    return BF_OK;
}

static bf_status fit_start(photo_run *run, photo_band *b, bf_photo_result *r, bf_error *err)
{
    const bf_stack *s = run->s;
    const bf_photo_options *o = run->o;
    size_t n = b->npix;
    int C = run->C, k = o->clusters > 1 ? o->clusters : 1;
    double *normal = malloc((n ? n : 1) * 3 * sizeof *normal),
           *albedo = malloc((n ? n : 1) * (size_t)C * sizeof *albedo);
    int *label = calloc(n ? n : 1, sizeof *label);
    run->start = calloc((size_t)k * (size_t)run->P, sizeof *run->start);
    run->centroid = calloc((size_t)k * (size_t)C, sizeof *run->centroid);
    run->cluster_albedo = calloc((size_t)k * (size_t)C, sizeof *run->cluster_albedo);
    bf_status rc = BF_OK;
    if (!normal || !albedo || !label || !run->start || !run->centroid || !run->cluster_albedo)
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", s->path);
    if (rc == BF_OK) {
        photo_start_lambert(run, b, normal, albedo);
        /* The automatic scale from the unscaled albedos; then everything scaled. */
        if (run->scale == 0.0)
            run->scale = photo_auto_scale(albedo, n, C);
        size_t nv = n * (size_t)run->K * (size_t)C;
        for (size_t i = 0; i < nv; i++)
            b->v[i] = (float)(b->v[i] * run->scale);
        for (size_t i = 0; i < n * (size_t)C; i++)
            albedo[i] *= run->scale;
        run->nclusters = k;
        if (k > 1 && n >= (size_t)k)
            photo_kmeans(albedo, n, C, k, o->seed, run->centroid, label);
        else {
            run->nclusters = 1;
            for (int c = 0; c < C; c++) {
                double sum = 0.0;
                for (size_t p = 0; p < n; p++)
                    sum += albedo[p * (size_t)C + (size_t)c];
                run->centroid[c] = n ? sum / (double)n : 0.0;
            }
        }
        memcpy(run->cluster_albedo, run->centroid, (size_t)run->nclusters * (size_t)C * sizeof *run->centroid);
    }
    for (int cl = 0; rc == BF_OK && cl < run->nclusters; cl++)
        rc = photo_cluster_start(run, b, normal, label, cl, run->start + (size_t)cl * (size_t)run->P, err);
    if (rc == BF_OK && run->nshared > 0 && n > 0) {
        double *x = malloc(n * (size_t)run->P * sizeof *x);
        if (!x)
            rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", s->path);
        for (size_t p = 0; rc == BF_OK && p < n; p++)
            photo_pixel_start(run, label[p], albedo + p * (size_t)C, x + p * (size_t)run->P);
        /* The pixels solved with the shared entries at the pooled fit's values, then
         * everything together. */
        shared_job j = {run, b, normal, x, albedo, label};
        if (!(o->cancel && *o->cancel))
            bf_parallel_for(n, run->threads, solve_sub_chunk, &j);
        if (rc == BF_OK && !(o->cancel && *o->cancel))
            photo_joint_refine(run, b, label, x, normal);
        free(x);
    }
    if (rc == BF_OK) {
        r->nclusters = run->nclusters;
        r->nshared = run->nshared;
        memcpy(r->shared_entry, run->shared, (size_t)run->nshared * sizeof *run->shared);
        r->shared = calloc((size_t)run->nclusters * (size_t)(run->nshared ? run->nshared : 1), sizeof *r->shared);
        if (!r->shared)
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
        for (int cl = 0; rc == BF_OK && cl < run->nclusters; cl++)
            for (int i = 0; i < run->nshared; i++)
                r->shared[cl * run->nshared + i] = run->start[(size_t)cl * (size_t)run->P + (size_t)run->shared[i]];
    }
    free(normal);
    free(albedo);
    free(label);
    return rc;
}

/* ---- the pixels ---- */

typedef struct chunk_sums {
    bf_photo_counts counts;
    size_t iterations, restarted;
    double *img; /* per image: model sum of squares, Lambert sum of squares, samples */
} chunk_sums;

/* A band's pixel solutions: model vector, normal (world), cost, cluster and counts. */
typedef struct band_solution {
    double *x, *n, *cost;
    int *cluster;
    photo_pixel_out *out;
} band_solution;

typedef struct pixel_job {
    photo_run *run;
    bf_photo_result *r;
    const photo_band *b;
    size_t chunk;               /* pixels per chunk */
    chunk_sums *sums;           /* per chunk */
    band_solution first, final; /* the first solves; after the restarts */
    atomic_size_t done;
    pthread_t caller;
    int cancelled;
} pixel_job;

static void chunk_range(const pixel_job *j, size_t ci, size_t *p0, size_t *p1)
{
    *p0 = ci * j->chunk;
    *p1 = *p0 + j->chunk < j->b->npix ? *p0 + j->chunk : j->b->npix;
}

/* Pass 1: every pixel from its start (the robust Lambertian normal, its cluster's model). */
static void solve_chunk(void *ctx, size_t ci)
{
    pixel_job *j = ctx;
    photo_run *run = j->run;
    const bf_stack *s = run->s;
    if (run->o->cancel && *run->o->cancel) {
        j->cancelled = 1;
        return;
    }
    int K = run->K, C = run->C, P = run->P;
    size_t p0, p1;
    chunk_range(j, ci, &p0, &p1);
    photo_buffers cb;
    photo_problem pr = photo_run_problem(run, MAX_ITERATIONS);
    if (photo_buffers_new(run, &cb)) {
        photo_lights pl = {cb.l, cb.e, {0}};
        for (size_t p = p0; p < p1; p++) {
            int px = j->b->pixel[p] % s->width, py = j->b->pixel[p] / s->width;
            const float *v = j->b->v + p * (size_t)K * (size_t)C;
            double *x = j->first.x + p * (size_t)P, *n = j->first.n + 3 * p, albr[3];
            photo_lights_at(s, px, py, &pl);
            if (!photo_lambert_robust(v, &pl, K, C, n, albr)) {
                n[0] = n[1] = 0.0;
                n[2] = 1.0;
            }
            photo_given_normal(run, px, py, n);
            int cl = run->nclusters > 1 ? photo_nearest(run->centroid, run->nclusters, albr, C) : 0;
            photo_pixel_start(run, cl, albr, x);
            photo_solve_pixel(&pr, v, &pl, x, n, cb.w, &j->first.out[p]);
            j->first.cost[p] = j->first.out[p].cost;
            j->first.cluster[p] = cl;
        }
    } else
        for (size_t p = p0; p < p1; p++)
            j->first.out[p].ok = 0, j->first.cost[p] = INFINITY;
    photo_buffers_free(&cb);
    atomic_fetch_add(&j->done, p1 - p0);
    if (run->o->progress && pthread_equal(pthread_self(), j->caller))
        run->o->progress(run->o->progress_user, (double)atomic_load(&j->done));
}

static double angle_between(const double *a, const double *b)
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    return acos(fmax(-1.0, fmin(1.0, d)));
}

/* Pass 2: a pixel whose normal stands apart from both its row neighbours' (which agree
 * with each other) is solved again from each neighbour's solution, and the lowest cost
 * kept: a solve from the Lambertian start can end in a local minimum where a highlight
 * misleads it. Only the first solves are read, and only the same row's pixels (in every
 * band and tile alike), so the result depends neither on the threads nor on the tiling. */
#define RESTART_ANGLE (2.0 * M_PI / 180.0) /* apart by more than this */
static void restart_chunk(void *ctx, size_t ci)
{
    pixel_job *j = ctx;
    photo_run *run = j->run;
    const bf_stack *s = run->s;
    int K = run->K, C = run->C, P = run->P;
    size_t p0, p1;
    chunk_range(j, ci, &p0, &p1);
    const band_solution *f = &j->first;
    band_solution *g = &j->final;
    for (size_t p = p0; p < p1; p++) {
        memcpy(g->x + p * (size_t)P, f->x + p * (size_t)P, (size_t)P * sizeof *g->x);
        memcpy(g->n + 3 * p, f->n + 3 * p, 3 * sizeof *g->n);
        g->cost[p] = f->cost[p];
        g->cluster[p] = f->cluster[p];
        g->out[p] = f->out[p];
    }
    if (run->o->normals != BF_NORMALS_FIT || (run->o->cancel && *run->o->cancel))
        return;
    photo_buffers cb;
    if (!photo_buffers_new(run, &cb)) {
        photo_buffers_free(&cb);
        return;
    }
    photo_problem pr = photo_run_problem(run, MAX_ITERATIONS);
    photo_lights pl = {cb.l, cb.e, {0}};
    const int32_t *pix = j->b->pixel;
    for (size_t p = p0; p < p1; p++) {
        /* The row neighbours at distance d on both sides (present and in the same row):
         * the pixel stands apart when its normal is farther from both than twice their
         * own difference (a smooth surface's change) and than RESTART_ANGLE. Distance 2
         * catches a pair of bad pixels side by side. */
        int suspect = 0;
        size_t from[4];
        int nfrom = 0;
        for (size_t d = 1; d <= 2; d++) {
            if (p < d || p + d >= j->b->npix || pix[p - d] != pix[p] - (int32_t)d ||
                pix[p + d] != pix[p] + (int32_t)d || pix[p] / s->width != pix[p - d] / s->width ||
                pix[p] / s->width != pix[p + d] / s->width)
                continue;
            const double *np = f->n + 3 * p, *na = f->n + 3 * (p - d), *nb = f->n + 3 * (p + d);
            double apart = fmax(RESTART_ANGLE, 2.0 * angle_between(na, nb));
            if (angle_between(np, na) > apart && angle_between(np, nb) > apart) {
                suspect = 1;
                from[nfrom++] = p - d;
                from[nfrom++] = p + d;
            }
        }
        if (!suspect)
            continue;
        const float *v = j->b->v + p * (size_t)K * (size_t)C;
        photo_lights_at(s, pix[p] % s->width, pix[p] / s->width, &pl);
        for (int i = 0; i < nfrom; i++) {
            size_t q = from[i];
            double x[PHOTO_MAX_PARAMS], n[3];
            memcpy(x, f->x + q * (size_t)P, (size_t)P * sizeof *x);
            memcpy(n, f->n + 3 * q, sizeof n);
            photo_pixel_out po;
            photo_solve_pixel(&pr, v, &pl, x, n, cb.w, &po);
            po.iterations += g->out[p].iterations;
            if (po.ok && po.cost < g->cost[p] * (1.0 - 1e-9)) {
                memcpy(g->x + p * (size_t)P, x, (size_t)P * sizeof *x);
                memcpy(g->n + 3 * p, n, sizeof n);
                g->cost[p] = po.cost;
                g->out[p] = po;
            } else
                g->out[p].iterations = po.iterations;
        }
        g->out[p].restarted = 1;
    }
    photo_buffers_free(&cb);
}

/* Pass 3: the outputs of every pixel, the Lambertian baseline, the counts and the relit
 * errors' sums of the chunk. */
static void output_chunk(void *ctx, size_t ci)
{
    pixel_job *j = ctx;
    photo_run *run = j->run;
    bf_photo_result *r = j->r;
    const bf_stack *s = run->s;
    int K = run->K, C = run->C, P = run->P;
    size_t p0, p1;
    chunk_range(j, ci, &p0, &p1);
    chunk_sums *cs = &j->sums[ci];
    photo_buffers cb;
    if (!photo_buffers_new(run, &cb)) {
        cs->counts.failed += p1 - p0;
        photo_buffers_free(&cb);
        return;
    }
    photo_problem pr = photo_run_problem(run, MAX_ITERATIONS);
    photo_lights pl = {cb.l, cb.e, {0}};
    const band_solution *g = &j->final;
    for (size_t p = p0; p < p1; p++) {
        int px = j->b->pixel[p] % s->width, py = j->b->pixel[p] / s->width;
        size_t at = (size_t)j->b->pixel[p];
        const float *v = j->b->v + p * (size_t)K * (size_t)C;
        const double *x = g->x + p * (size_t)P, *n = g->n + 3 * p;
        const photo_pixel_out *po = &g->out[p];
        double alb[3], nl[3];
        photo_lights_at(s, px, py, &pl);
        photo_lambert(v, &pl, K, C, nl, alb);
        cs->iterations += (size_t)po->iterations;
        cs->restarted += (size_t)po->restarted;
        if (!po->ok)
            cs->counts.failed++;
        cs->counts.pixels++;
        cs->counts.samples += po->used;
        cs->counts.shadowed += po->shadowed;
        cs->counts.dark += po->dark;
        photo_predict(&pr, &pl, x, n, cb.w, cb.pred);
        /* Relit errors over every measured sample (the same set for both fits), in the
         * stack's values. */
        double inv = 1.0 / run->scale, ss = 0.0;
        size_t m = 0;
        for (int k = 0; k < K; k++) {
            if (isnan(v[k * C]))
                continue;
            const double *lk = cb.l + 3 * k;
            double s_nl = fmax(0.0, nl[0] * lk[0] + nl[1] * lk[1] + nl[2] * lk[2]);
            for (int c = 0; c < C; c++) {
                double dm = (cb.pred[k * C + c] - v[k * C + c]) * inv;
                double dl = (alb[c] / M_PI * cb.e[k * C + c] * s_nl - v[k * C + c]) * inv;
                cs->img[3 * k] += dm * dm;
                cs->img[3 * k + 1] += dl * dl;
                ss += dm * dm;
                m++;
            }
            cs->img[3 * k + 2] += C;
            for (int i = 0; i < r->nrelit; i++)
                if (r->relit_index[i] == k)
                    for (int c = 0; c < C; c++) {
                        r->relit_measured[i][at * (size_t)C + (size_t)c] = (float)(v[k * C + c] * inv);
                        r->relit_model[i][at * (size_t)C + (size_t)c] = (float)(cb.pred[k * C + c] * inv);
                    }
        }
        r->error[at] = m ? (float)sqrt(ss / (double)m) : 0.0f;
        double nc[3], lc[3];
        photo_to_camera(s, n, nc);
        photo_to_camera(s, nl, lc);
        for (int i = 0; i < 3; i++) {
            r->normals[3 * at + (size_t)i] = (float)nc[i];
            r->lambert_normals[3 * at + (size_t)i] = (float)lc[i];
        }
        for (int c = 0; c < C; c++)
            r->lambert_albedo[at * (size_t)C + (size_t)c] = (float)(alb[c] * inv);
        for (int q = 0; q < P; q++)
            r->params[at * (size_t)P + (size_t)q] = (float)x[q];
        if (r->cluster)
            r->cluster[at] = g->cluster[p];
        r->mask[at] = 1;
    }
    photo_buffers_free(&cb);
}

static void band_solution_free(band_solution *b)
{
    free(b->x);
    free(b->n);
    free(b->cost);
    free(b->cluster);
    free(b->out);
}

static int band_solution_new(band_solution *b, size_t n, int P)
{
    n = n ? n : 1;
    b->x = malloc(n * (size_t)P * sizeof *b->x);
    b->n = malloc(n * 3 * sizeof *b->n);
    b->cost = malloc(n * sizeof *b->cost);
    b->cluster = malloc(n * sizeof *b->cluster);
    b->out = calloc(n, sizeof *b->out);
    return b->x && b->n && b->cost && b->cluster && b->out;
}

/* The bands: rows whose masked pixels' samples fit in band_bytes each. */
static int next_band(const photo_run *run, const unsigned char *mask, int y, int y_end, size_t bytes)
{
    const bf_stack *s = run->s;
    size_t per = (size_t)run->K * (size_t)run->C * sizeof(float), used = 0;
    int y1 = y;
    while (y1 < y_end) {
        size_t row = 0;
        for (int x = 0; x < s->width; x++)
            row += mask[(size_t)y1 * (size_t)s->width + (size_t)x] != 0;
        if (y1 > y && used + row * per > bytes)
            break;
        used += row * per;
        y1++;
    }
    return y1;
}

static void progress_scaled(void *ctx, double done);

typedef struct progress_ctx {
    const bf_photo_options *o;
    double base, total;
} progress_ctx;

static void progress_scaled(void *ctx, double done)
{
    progress_ctx *pc = ctx;
    pc->o->progress(pc->o->progress_user, pc->total > 0 ? (pc->base + done) / pc->total : 1.0);
}

/* The masked pixels of rows [y, y1) and their samples, scaled. */
static bf_status band_read(const photo_run *run, const unsigned char *mask, int y, int y1, photo_band *band,
                           bf_error *err)
{
    const bf_stack *s = run->s;
    int32_t *pix = NULL;
    size_t np = photo_subsample(mask, y, y1, s->width, (size_t)-1 / 2, &pix);
    if (np == (size_t)-1)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    photo_band_pixels at = {pix, np, y, y1};
    bf_status rc = photo_band_load(s, &at, run->threads, band, err);
    free(pix);
    if (rc != BF_OK)
        return rc;
    size_t nv = band->npix * (size_t)run->K * (size_t)run->C;
    for (size_t i = 0; i < nv; i++)
        band->v[i] = (float)(band->v[i] * run->scale);
    return BF_OK;
}

/* The chunks' counts and sums into the result, in chunk order. */
static void add_chunk_sums(const photo_run *run, const chunk_sums *sums, size_t nchunks, bf_photo_result *r)
{
    for (size_t c = 0; c < nchunks; c++) {
        bf_photo_counts *a = &r->counts;
        const bf_photo_counts *bb = &sums[c].counts;
        a->pixels += bb->pixels;
        a->failed += bb->failed;
        a->samples += bb->samples;
        a->shadowed += bb->shadowed;
        a->dark += bb->dark;
        r->iterations += sums[c].iterations;
        r->restarted += sums[c].restarted;
        for (int k = 0; k < run->K; k++) {
            r->image_rms[k] += sums[c].img[3 * k];
            r->image_lambert_rms[k] += sums[c].img[3 * k + 1];
            r->image_samples[k] += (size_t)sums[c].img[3 * k + 2];
        }
    }
}

/* The three passes over a band's chunks, the progress told through pc (the band's part of
 * the run's). */
static bf_status band_passes(photo_run *run, bf_photo_result *r, const photo_band *b, size_t chunk, chunk_sums *sums,
                             progress_ctx *pc, bf_error *err)
{
    const bf_photo_options *o = run->o;
    size_t nchunks = (b->npix + chunk - 1) / chunk;
    bf_status rc = BF_OK;
    bf_photo_options oo = *o;
    if (o->progress) {
        oo.progress = progress_scaled;
        oo.progress_user = pc;
    }
    run->o = &oo;
    pixel_job j = {.run = run, .r = r, .b = b, .chunk = chunk, .sums = sums, .caller = pthread_self()};
    atomic_init(&j.done, 0);
    if (!band_solution_new(&j.first, b->npix, run->P) || !band_solution_new(&j.final, b->npix, run->P))
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu pixels' solutions", b->npix);
    if (rc == BF_OK) {
        bf_parallel_for(nchunks, run->threads, solve_chunk, &j);
        if (!j.cancelled)
            bf_parallel_for(nchunks, run->threads, restart_chunk, &j);
        if (!j.cancelled && !(o->cancel && *o->cancel))
            bf_parallel_for(nchunks, run->threads, output_chunk, &j);
    }
    band_solution_free(&j.first);
    band_solution_free(&j.final);
    run->o = o;
    add_chunk_sums(run, sums, nchunks, r);
    if (j.cancelled)
        r->cancelled = 1;
    return rc;
}

/* One band's pixels: its counts, its chunks' sums and the passes. */
static bf_status fit_band(photo_run *run, bf_photo_result *r, const photo_band *b, size_t done_pixels, size_t total,
                          bf_error *err)
{
    for (int k = 0; k < run->K; k++) {
        r->counts.saturated += b->saturated[k];
        r->counts.invalid += b->invalid[k];
    }
    /* Chunks: at least 16 pixels, at most 1024 chunks a band. */
    size_t chunk = b->npix / 1024 + 16, nchunks = (b->npix + chunk - 1) / chunk;
    chunk_sums *sums = calloc(nchunks ? nchunks : 1, sizeof *sums);
    double *img = calloc((nchunks ? nchunks : 1) * 3 * (size_t)run->K, sizeof *img);
    if (!sums || !img) {
        free(sums);
        free(img);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    for (size_t c = 0; c < nchunks; c++)
        sums[c].img = img + c * 3 * (size_t)run->K;
    progress_ctx pc = {run->o, (double)done_pixels, (double)total};
    bf_status rc = band_passes(run, r, b, chunk, sums, &pc, err);
    free(sums);
    free(img);
    return rc;
}

static bf_status fit_bands(photo_run *run, const unsigned char *mask, bf_photo_result *r, size_t total,
                           photo_band *first, bf_error *err)
{
    size_t bytes = run->o->band_bytes ? run->o->band_bytes : DEFAULT_BAND_BYTES;
    size_t done_pixels = 0;
    bf_status rc = BF_OK;
    for (int y = r->y0; y < r->y1 && rc == BF_OK;) {
        int y1 = next_band(run, mask, y, r->y1, bytes);
        photo_band band, *b = &band;
        if (first && first->y0 == y && first->y1 == y1)
            b = first; /* the start's band is this band: already read and scaled */
        else if ((rc = band_read(run, mask, y, y1, &band, err)) != BF_OK)
            return rc;
        size_t band_pixels = b->npix;
        rc = fit_band(run, r, b, done_pixels, total, err);
        if (b != first)
            photo_band_free(&band);
        done_pixels += band_pixels;
        y = y1;
        if (r->cancelled)
            break;
    }
    return rc;
}

static int online_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}

/* One bf_photo_fit: the run, the options it reads, the result and what the phases share. */
typedef struct fit_state {
    photo_run run;
    bf_photo_options o; /* a whole struct of this version */
    bf_photo_result *r;
    unsigned char *mask; /* width*height; the tile's rows only once the start is made */
    float *given;        /* BF_NORMALS_FILE: the normals, world frame */
    photo_band first;    /* the start's pixels, kept when they are the whole image in one band */
    int32_t *sub;        /* the start's subsample */
    size_t total;        /* pixels to fit */
} fit_state;

/* The result's maps, the tile's rows and the relit images kept. */
static bf_status result_new(fit_state *f, bf_error *err)
{
    const bf_stack *s = f->run.s;
    const bf_photo_options *o = f->run.o;
    bf_photo_result *r = f->r;
    size_t WH = (size_t)s->width * (size_t)s->height;
    r->width = s->width;
    r->height = s->height;
    r->channels = s->channels;
    r->nimages = s->nimages;
    r->threads = f->run.threads;
    r->nvalues = f->run.P;
    r->y0 = o->tile_count > 0 ? (int)((long)s->height * o->tile_index / o->tile_count) : 0;
    r->y1 = o->tile_count > 0 ? (int)((long)s->height * (o->tile_index + 1) / o->tile_count) : s->height;
    r->mask = calloc(WH, 1);
    r->normals = calloc(WH * 3, sizeof *r->normals);
    r->params = calloc(WH * (size_t)f->run.P, sizeof *r->params);
    r->error = calloc(WH, sizeof *r->error);
    r->lambert_normals = calloc(WH * 3, sizeof *r->lambert_normals);
    r->lambert_albedo = calloc(WH * (size_t)s->channels, sizeof *r->lambert_albedo);
    r->image_rms = calloc((size_t)s->nimages, sizeof *r->image_rms);
    r->image_lambert_rms = calloc((size_t)s->nimages, sizeof *r->image_lambert_rms);
    r->image_samples = calloc((size_t)s->nimages, sizeof *r->image_samples);
    if (o->clusters > 1)
        r->cluster = malloc(WH * sizeof *r->cluster);
    int ok = r->mask && r->normals && r->params && r->error && r->lambert_normals && r->lambert_albedo &&
             r->image_rms && r->image_lambert_rms && r->image_samples && (o->clusters <= 1 || r->cluster);
    r->nrelit = o->relit_images < 0 ? 0 : o->relit_images > BF_PHOTO_MAX_RELIT ? BF_PHOTO_MAX_RELIT : o->relit_images;
    if (r->nrelit > s->nimages)
        r->nrelit = s->nimages;
    for (int i = 0; i < r->nrelit && ok; i++) {
        /* Spread over the stack: the first, the last and evenly between. */
        r->relit_index[i] = r->nrelit > 1 ? (int)((long)i * (s->nimages - 1) / (r->nrelit - 1)) : 0;
        r->relit_measured[i] = calloc(WH * (size_t)s->channels, sizeof(float));
        r->relit_model[i] = calloc(WH * (size_t)s->channels, sizeof(float));
        ok = r->relit_measured[i] && r->relit_model[i];
    }
    if (r->cluster)
        for (size_t i = 0; i < WH; i++)
            r->cluster[i] = -1;
    if (!ok)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory for the %dx%d outputs", s->path, s->width, s->height);
    return BF_OK;
}

/* The start's pixels: an evenly spread subsample of the whole image's mask, whatever the
 * tile, so that every tile starts alike and tiles merge into the whole run. */
static bf_status start(fit_state *f, bf_error *err)
{
    photo_run *run = &f->run;
    const bf_stack *s = run->s;
    const bf_photo_options *o = run->o;
    size_t WH = (size_t)s->width * (size_t)s->height, all = 0;
    for (size_t i = 0; i < WH; i++)
        all += f->mask[i] != 0;
    size_t bytes = o->band_bytes ? o->band_bytes : DEFAULT_BAND_BYTES;
    int whole = f->r->y0 == 0 && f->r->y1 == s->height && next_band(run, f->mask, 0, s->height, bytes) >= s->height;
    size_t ns = photo_subsample(f->mask, 0, s->height, s->width, whole ? all : START_PIXELS, &f->sub);
    bf_status rc;
    if (ns == (size_t)-1)
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    else if (!ns)
        rc = bf_fail(err, BF_ERR_ARG, "%s: no pixel to fit (the mask is empty)", s->path);
    else {
        photo_band_pixels at = {f->sub, ns, 0, s->height};
        rc = photo_band_load(s, &at, run->threads, &f->first, err);
    }
    photo_band pick = {0};
    if (rc == BF_OK)
        rc = band_pick(&f->first, (size_t)run->K * (size_t)run->C, START_PIXELS, &pick, err);
    if (rc == BF_OK)
        rc = fit_start(run, &pick, f->r, err);
    photo_band_free(&pick);
    if (rc == BF_OK && whole) { /* the whole image in one band, read once */
        size_t nv = f->first.npix * (size_t)run->K * (size_t)run->C;
        for (size_t i = 0; i < nv; i++)
            f->first.v[i] = (float)(f->first.v[i] * run->scale);
    } else
        photo_band_free(&f->first);
    return rc;
}

/* Outside the tile's rows nothing is fitted: the mask cut to them, the pixels counted. */
static bf_status tile_rows(fit_state *f, bf_error *err)
{
    const bf_stack *s = f->run.s;
    bf_photo_result *r = f->r;
    size_t W = (size_t)s->width, WH = W * (size_t)s->height;
    for (size_t i = 0; i < WH; i++) {
        int y = (int)(i / W);
        if (y < r->y0 || y >= r->y1)
            f->mask[i] = 0;
        else if (!f->mask[i])
            r->counts.masked++;
        f->total += f->mask[i] != 0;
    }
    if (!f->total)
        return bf_fail(err, BF_ERR_ARG, "%s: no pixel to fit in rows %d to %d (the tile's band)", s->path, r->y0,
                       r->y1 - 1);
    return BF_OK;
}

/* The relit errors' sums as RMS, per image and over all. */
static void relit_rms(bf_photo_result *r, int K)
{
    double sm = 0.0, sl = 0.0;
    size_t n = 0;
    for (int k = 0; k < K; k++) {
        sm += r->image_rms[k];
        sl += r->image_lambert_rms[k];
        n += r->image_samples[k];
        r->image_rms[k] = r->image_samples[k] ? sqrt(r->image_rms[k] / (double)r->image_samples[k]) : 0.0;
        r->image_lambert_rms[k] =
            r->image_samples[k] ? sqrt(r->image_lambert_rms[k] / (double)r->image_samples[k]) : 0.0;
    }
    r->relit_rms = n ? sqrt(sm / (double)n) : 0.0;
    r->lambert_rms = n ? sqrt(sl / (double)n) : 0.0;
}

static void fit_state_free(fit_state *f)
{
    photo_band_free(&f->first);
    free(f->sub);
    free(f->mask);
    free(f->given);
    bf_model_free(f->run.model);
    free(f->run.start);
    free(f->run.centroid);
    free(f->run.cluster_albedo);
    free(f->run.lbuf);
    free(f->run.ebuf);
}

bf_status bf_photo_fit(const bf_stack *s, const bf_photo_options *o, bf_photo_result **out, bf_error *err)
{
    *out = NULL;
    double t0 = bf_now_seconds();
    if (!s)
        return bf_fail(err, BF_ERR_ARG, "fit-images: no stack");
    bf_status checked = bf_photo_options_check(o, err);
    if (checked != BF_OK)
        return checked;
    if (o->tile_count > s->height)
        return bf_fail(err, BF_ERR_ARG, "%s %d/%d: out of range (the image has %d rows)", photo_option_name(o, "tile"),
                       o->tile_index + 1, o->tile_count, s->height);
    fit_state f = {0};
    /* The run reads (and copies) a whole struct of this version: an older caller's is
     * shorter, its missing tail the defaults. */
    bf_photo_options_init(&f.o);
    memcpy(&f.o, o, o->size < sizeof f.o ? o->size : sizeof f.o);
    f.o.size = sizeof f.o;
    o = &f.o;
    f.run = (photo_run){.s = s, .o = o, .spec = o->model, .K = s->nimages, .C = s->channels};
    f.run.threads = o->threads > 0 ? o->threads : online_threads();
    f.run.scale = o->scale_given ? o->scale : s->scale;
    f.r = calloc(1, sizeof *f.r);
    bf_status rc = f.r ? setup(&f.run, err) : bf_fail(err, BF_ERR_NOMEM, "out of memory");
    if (rc == BF_OK)
        rc = result_new(&f, err);
    if (rc == BF_OK)
        rc = photo_mask_load(s, &f.mask, err);
    if (rc == BF_OK && o->normals == BF_NORMALS_FILE && (rc = load_given_normals(&f.run, &f.given, err)) == BF_OK)
        f.run.given_normals = f.given;
    if (rc == BF_OK)
        rc = start(&f, err);
    if (rc == BF_OK)
        rc = tile_rows(&f, err);
    if (rc == BF_OK && !(o->cancel && *o->cancel)) {
        f.r->scale = f.run.scale;
        rc = fit_bands(&f.run, f.mask, f.r, f.total, f.first.npix ? &f.first : NULL, err);
    }
    if (rc == BF_OK && o->cancel && *o->cancel)
        f.r->cancelled = 1;
    if (rc == BF_OK) {
        relit_rms(f.r, s->nimages);
        f.r->model = f.run.model;
        f.run.model = NULL;
        f.r->seconds = bf_now_seconds() - t0;
    }
    fit_state_free(&f);
    if (rc != BF_OK) {
        bf_photo_result_free(f.r);
        return rc;
    }
    *out = f.r;
    return BF_OK;
}
