/* The shared entries (--share) fitted jointly with the subsample's pixels (photo_run.h):
 * Levenberg-Marquardt on every unknown at once, each step solved by the Schur complement
 * as bundle adjustment does. Per pixel p, the damped normal equations over its own
 * unknowns (free entries, normal) and its cluster's shared entries are
 *     [A_pp A_ps] [d_p]     [g_p]
 *     [A_sp A_ss] [d_s] = - [g_s];
 * the pixels' blocks are eliminated,
 *     S = sum_p (A_ss - A_sp A_pp^-1 A_ps),   r = sum_p (g_s - A_sp A_pp^-1 g_p),
 * S d_s = -r gives the shared step of each cluster, and each pixel's step follows:
 *     d_p = -A_pp^-1 (g_p + A_ps d_s).
 * Alternating the two (solve the pixels, then the shared entries) crawls along the valley
 * that couples them (a roughness against the normals' tilt: 15% off after 24 steps); the
 * joint step goes down it. Sums are kept per fixed chunk and added in chunk order, so the
 * result does not depend on the threads. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/parallel.h"
#include "photo_run.h"

#define JOINT_STEPS 30  /* accepted steps at most */
#define JOINT_STOP 1e-7 /* relative cost decrease that ends it */
#define JOINT_CHUNK 16  /* pixels per chunk */

typedef struct joint {
    photo_run *run;
    const photo_band *b;
    const int *label;
    double *x, *n;        /* per pixel: P, 3 (the current point) */
    double *tx, *tn;      /* the trial point */
    double *A, *g, *cost; /* per pixel: m*m, m, 1 (at the current point) */
    double *L, *Y, *z;    /* per pixel: np*np, np*ns, np (for the current lambda) */
    double *tcost;        /* per pixel, at the trial point */
    unsigned char *bad;   /* per pixel: its block not positive definite */
    double *S, *r;        /* per chunk: nclusters * (ns*ns + ns) */
    double *S_sum;        /* nclusters * (ns*ns + ns): the chunks' added */
    double *ds;           /* nclusters * ns: the shared steps */
    double *trial_shared; /* nclusters * ns */
    int np, ns, m;
    double lambda;
    size_t nchunks;
} joint;

static void range(const joint *j, size_t c, size_t *p0, size_t *p1)
{
    *p0 = c * JOINT_CHUNK;
    *p1 = *p0 + JOINT_CHUNK < j->b->npix ? *p0 + JOINT_CHUNK : j->b->npix;
}

/* J'J, J'r and the cost of every pixel of a chunk at the current point. */
static void sums_chunk(void *ctx, size_t c)
{
    joint *j = ctx;
    photo_run *run = j->run;
    const bf_stack *s = run->s;
    size_t p0, p1;
    range(j, c, &p0, &p1);
    photo_buffers bb;
    photo_problem pr = photo_run_problem(run, 1);
    if (!photo_buffers_new(run, &bb)) {
        for (size_t p = p0; p < p1; p++)
            j->bad[p] = 1, j->cost[p] = 0.0;
        photo_buffers_free(&bb);
        return;
    }
    photo_lights pl = {bb.l, bb.e, {0}};
    for (size_t p = p0; p < p1; p++) {
        photo_lights_at(s, j->b->pixel[p] % s->width, j->b->pixel[p] / s->width, &pl);
        photo_pixel_at at = {j->b->v + p * (size_t)run->K * (size_t)run->C, &pl, j->x + p * (size_t)run->P,
                             j->n + 3 * p};
        photo_joint_block blk = {j->A + p * (size_t)j->m * (size_t)j->m, j->g + p * (size_t)j->m, &j->cost[p]};
        photo_joint_sums(&pr, run->shared, j->ns, &at, bb.w, &blk);
    }
    photo_buffers_free(&bb);
}

/* The pixels' damped blocks eliminated: the chunk's part of S and r for each cluster. */
static void schur_chunk(void *ctx, size_t c)
{
    joint *j = ctx;
    int np = j->np, ns = j->ns, m = j->m, nc = j->run->nclusters;
    size_t p0, p1;
    range(j, c, &p0, &p1);
    double *S = j->S + c * (size_t)nc * (size_t)(ns * ns + ns);
    memset(S, 0, (size_t)nc * (size_t)(ns * ns + ns) * sizeof *S);
    for (size_t p = p0; p < p1; p++) {
        const double *A = j->A + p * (size_t)m * (size_t)m, *g = j->g + p * (size_t)m;
        double *L = j->L + p * (size_t)np * (size_t)np, *Y = j->Y + p * (size_t)np * (size_t)ns,
               *z = j->z + p * (size_t)np;
        for (int a = 0; a < np; a++) {
            z[a] = g[a];
            for (int b = 0; b < np; b++)
                L[a * np + b] = A[a * m + b];
        }
        photo_damp(L, np, j->lambda);
        j->bad[p] = np > 0 && !photo_chol(L, np);
        if (j->bad[p])
            continue; /* left out of this step: its unknowns stay */
        if (np > 0)
            photo_chol_solve(L, np, z);
        double col[PHOTO_MAX_PARAMS + 2];
        for (int k = 0; k < ns; k++) {
            for (int a = 0; a < np; a++)
                col[a] = A[a * m + np + k];
            if (np > 0)
                photo_chol_solve(L, np, col);
            for (int a = 0; a < np; a++)
                Y[a * ns + k] = col[a];
        }
        double *Sc = S + (size_t)j->label[p] * (size_t)(ns * ns + ns), *rc = Sc + ns * ns;
        for (int k = 0; k < ns; k++) {
            double t = g[np + k];
            for (int a = 0; a < np; a++)
                t -= A[(np + k) * m + a] * z[a];
            rc[k] += t;
            for (int l = 0; l < ns; l++) {
                double u = A[(np + k) * m + np + l];
                for (int a = 0; a < np; a++)
                    u -= A[(np + k) * m + a] * Y[a * ns + l];
                Sc[k * ns + l] += u;
            }
        }
    }
}

/* Each pixel's step for the clusters' shared steps, its trial point and cost. */
static void step_chunk(void *ctx, size_t c)
{
    joint *j = ctx;
    photo_run *run = j->run;
    const bf_stack *s = run->s;
    int np = j->np, ns = j->ns, P = run->P;
    size_t p0, p1;
    range(j, c, &p0, &p1);
    photo_buffers bb;
    photo_problem pr = photo_run_problem(run, 1);
    if (!photo_buffers_new(run, &bb)) {
        for (size_t p = p0; p < p1; p++)
            j->tcost[p] = INFINITY;
        photo_buffers_free(&bb);
        return;
    }
    photo_lights pl = {bb.l, bb.e, {0}};
    for (size_t p = p0; p < p1; p++) {
        const double *x = j->x + p * (size_t)P, *n = j->n + 3 * p, *ds = j->ds + (size_t)j->label[p] * (size_t)ns;
        double *tx = j->tx + p * (size_t)P, *tn = j->tn + 3 * p, d[PHOTO_MAX_PARAMS + 2] = {0};
        if (!j->bad[p]) {
            const double *Y = j->Y + p * (size_t)np * (size_t)ns, *z = j->z + p * (size_t)np;
            for (int a = 0; a < np; a++) {
                double t = z[a];
                for (int k = 0; k < ns; k++)
                    t += Y[a * ns + k] * ds[k];
                d[a] = -t;
            }
        }
        photo_pixel_step(&pr, x, n, d, tx, tn);
        for (int k = 0; k < ns; k++)
            tx[run->shared[k]] = j->trial_shared[(size_t)j->label[p] * (size_t)ns + (size_t)k];
        photo_lights_at(s, j->b->pixel[p] % s->width, j->b->pixel[p] / s->width, &pl);
        j->tcost[p] = photo_cost(&pr, j->b->v + p * (size_t)run->K * (size_t)run->C, &pl, tx, tn, bb.w);
    }
    photo_buffers_free(&bb);
}

static double total(const double *c, size_t n)
{
    double t = 0.0;
    for (size_t p = 0; p < n; p++)
        t += c[p];
    return t;
}

/* The joint's arrays for its n pixels (j->np, j->ns, j->m and j->nchunks set); 0 when out
 * of memory. */
static int joint_new(joint *j, size_t n)
{
    int ns = j->ns, nc = j->run->nclusters, P = j->run->P;
    size_t m = (size_t)j->m, np = (size_t)j->np, sz = (size_t)nc * (size_t)(ns * ns + ns);
    j->tx = malloc(n * (size_t)P * sizeof *j->tx);
    j->tn = malloc(n * 3 * sizeof *j->tn);
    j->A = malloc(n * m * m * sizeof *j->A);
    j->g = malloc(n * m * sizeof *j->g);
    j->cost = malloc(n * sizeof *j->cost);
    j->L = malloc(n * (np * np + 1) * sizeof *j->L);
    j->Y = malloc(n * (np * (size_t)ns + 1) * sizeof *j->Y);
    j->z = malloc(n * (np + 1) * sizeof *j->z);
    j->tcost = malloc(n * sizeof *j->tcost);
    j->bad = calloc(n, 1);
    j->S = malloc(j->nchunks * sz * sizeof *j->S);
    j->S_sum = malloc(sz * sizeof *j->S_sum);
    j->ds = malloc((size_t)nc * (size_t)ns * sizeof *j->ds);
    j->trial_shared = malloc((size_t)nc * (size_t)ns * sizeof *j->trial_shared);
    return j->tx && j->tn && j->A && j->g && j->cost && j->L && j->Y && j->z && j->tcost && j->bad && j->S &&
           j->S_sum && j->ds && j->trial_shared;
}

static void joint_free(joint *j)
{
    free(j->tx);
    free(j->tn);
    free(j->A);
    free(j->g);
    free(j->cost);
    free(j->L);
    free(j->Y);
    free(j->z);
    free(j->tcost);
    free(j->bad);
    free(j->S);
    free(j->S_sum);
    free(j->ds);
    free(j->trial_shared);
}

/* Each cluster's shared step for the current lambda (S d_s = -r, the chunks' parts added in
 * chunk order) and its trial values; 0 when a cluster's S is not positive definite. */
static int shared_steps(joint *j, const photo_problem *pr)
{
    photo_run *run = j->run;
    int ns = j->ns, nc = run->nclusters, P = run->P;
    size_t sz = (size_t)nc * (size_t)(ns * ns + ns);
    double *S = j->S_sum, *ds = j->ds;
    bf_parallel_for(j->nchunks, run->threads, schur_chunk, j);
    memset(S, 0, sz * sizeof *S);
    for (size_t c = 0; c < j->nchunks; c++) /* in chunk order */
        for (size_t i = 0; i < sz; i++)
            S[i] += j->S[c * sz + i];
    int ok = 1;
    for (int cl = 0; cl < nc && ok; cl++) {
        double *Sc = S + (size_t)cl * (size_t)(ns * ns + ns), *rc = Sc + ns * ns;
        photo_damp(Sc, ns, j->lambda);
        ok = photo_chol(Sc, ns);
        if (ok) {
            for (int k = 0; k < ns; k++)
                ds[cl * ns + k] = -rc[k];
            photo_chol_solve(Sc, ns, ds + cl * ns);
        }
        for (int k = 0; k < ns && ok; k++) {
            int e = run->shared[k];
            j->trial_shared[cl * ns + k] =
                photo_shared_step(pr, e, run->start[(size_t)cl * (size_t)P + (size_t)e], ds[cl * ns + k]);
        }
    }
    return ok;
}

/* The trial point becomes the current one: the pixels' and the clusters' shared entries. */
static void accept_trial(joint *j)
{
    photo_run *run = j->run;
    size_t n = j->b->npix;
    int ns = j->ns, P = run->P;
    memcpy(j->x, j->tx, n * (size_t)P * sizeof *j->x);
    memcpy(j->n, j->tn, n * 3 * sizeof *j->n);
    for (int cl = 0; cl < run->nclusters; cl++)
        for (int k = 0; k < ns; k++)
            run->start[(size_t)cl * (size_t)P + (size_t)run->shared[k]] = j->trial_shared[cl * ns + k];
}

void photo_joint_refine(photo_run *run, const photo_band *b, const int *label, double *x, double *normal)
{
    size_t n = b->npix;
    int ns = run->nshared, P = run->P;
    if (!n || !ns)
        return;
    joint j = {.run = run, .b = b, .label = label, .x = x, .n = normal, .ns = ns, .lambda = 1e-3};
    for (int e = 0; e < P; e++)
        j.np += run->pixel_free[e];
    j.np += run->o->normals == BF_NORMALS_FIT ? 2 : 0;
    j.m = j.np + ns;
    j.nchunks = (n + JOINT_CHUNK - 1) / JOINT_CHUNK;
    photo_problem pr = photo_run_problem(run, 1);
    if (joint_new(&j, n)) {
        bf_parallel_for(j.nchunks, run->threads, sums_chunk, &j);
        double cost = total(j.cost, n);
        for (int it = 0; it < JOINT_STEPS && !(run->o->cancel && *run->o->cancel); it++) {
            int accepted = 0;
            while (!accepted && j.lambda < 1e10) {
                if (!shared_steps(&j, &pr)) {
                    j.lambda *= 10.0;
                    continue;
                }
                bf_parallel_for(j.nchunks, run->threads, step_chunk, &j);
                double trial = total(j.tcost, n);
                if (trial < cost) {
                    accepted = 1;
                    accept_trial(&j);
                    j.lambda = fmax(j.lambda / 3.0, 1e-9);
                    double rel = (cost - trial) / fmax(cost, 1e-300);
                    bf_parallel_for(j.nchunks, run->threads, sums_chunk, &j);
                    cost = total(j.cost, n);
                    if (rel < JOINT_STOP)
                        it = JOINT_STEPS;
                } else
                    j.lambda *= 4.0;
            }
            if (!accepted)
                break;
        }
    }
    joint_free(&j);
}
