/* A photo_fit run's helpers that its steps share (photo_fit.c, photo_start.c,
 * photo_joint.c; photo_run.h): the given normals, a pixel's start, one thread's
 * buffers and the per-pixel problem. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "photo_run.h"

void photo_given_normal(const photo_run *run, int x, int y, double n[3])
{
    const bf_stack *s = run->s;
    if (run->o->normals == BF_NORMALS_FLAT) {
        n[0] = n[1] = 0.0;
        n[2] = 1.0;
    } else if (run->o->normals == BF_NORMALS_FILE) {
        const float *g = run->given_normals + 3 * ((size_t)y * (size_t)s->width + (size_t)x);
        for (int i = 0; i < 3; i++)
            n[i] = g[i];
    }
}

void photo_pixel_start(const photo_run *run, int cluster, const double *albedo, double *x)
{
    memcpy(x, run->start + (size_t)cluster * (size_t)run->P, (size_t)run->P * sizeof *x);
    int np = bf_model_nparams(run->model);
    for (int i = 0; i < np; i++) {
        const bf_param_info *pi = bf_model_param(run->model, i);
        if (pi->role != BF_ROLE_DIFFUSE)
            continue;
        int off = bf_model_param_offset(run->model, i), cnt = pi->color ? run->C : 1;
        for (int c = 0; c < cnt; c++) {
            int e = off + c;
            if (!run->pixel_free[e])
                continue;
            double mean = run->cluster_albedo[(size_t)cluster * (size_t)run->C + (size_t)(pi->color ? c : 0)];
            double ratio = mean > 0.0 ? albedo[pi->color ? c : 0] / mean : 1.0;
            double v = x[e] * (isfinite(ratio) ? ratio : 1.0);
            x[e] = fmin(fmax(v, run->lo[e]), run->hi[e]);
        }
    }
}

int photo_buffers_new(const photo_run *run, photo_buffers *b)
{
    b->w = photo_scratch_new(run->K, run->C, run->P);
    b->l = malloc((size_t)run->K * 3 * sizeof *b->l);
    b->e = malloc((size_t)run->K * (size_t)run->C * sizeof *b->e);
    b->pred = malloc((size_t)run->K * (size_t)run->C * sizeof *b->pred);
    return b->w && b->l && b->e && b->pred;
}

void photo_buffers_free(photo_buffers *b)
{
    photo_scratch_free(b->w);
    free(b->l);
    free(b->e);
    free(b->pred);
}

photo_problem photo_run_problem(const photo_run *run, int max_iterations)
{
    photo_problem pr = {
        run->model, run->K,  run->C,      run->P,        run->pixel_free, run->o->normals == BF_NORMALS_FIT,
        run->lo,    run->hi, run->pscale, max_iterations};
    return pr;
}
