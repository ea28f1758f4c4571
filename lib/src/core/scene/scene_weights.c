/* Scene weights of samples, and restricting a sample set to a scene (scene.h).
 *
 * Each sample configuration is rotated about the normal so that its light has azimuth 0:
 * L' = (theta_i, 0), V' = (theta_o, phi_o - phi_i); each scene pair (light l, view v)
 * the same way: l' = (theta_l, 0), v' = (theta_v, phi_v - phi_l). The angle between L'
 * and l' is then |theta_i - theta_l|, and the pair's kernel product is
 *   w_l w_v exp(-(a_L^2 + a_V^2) / (2 radius^2))   (0 when a_L or a_V exceeds 3 radius)
 * summed over every (light, view) pair. With lights only (or views only) a direction's
 * azimuth means nothing for an isotropic material once the configuration is rotated, so
 * only its polar angle counts. The work runs over fixed chunks with stack scratch: no
 * allocation per sample, the trigonometry once per sample for both orientations.
 *
 * The pairs are indexed in a grid over (pair light polar angle, rotated view x, y) whose
 * cells are as wide as the kernel's support, so a sample looks only at the pairs in the
 * 3 x 3 x 3 cells around it instead of every pair. The sum runs in cell order (fixed
 * by the scene alone), so the weights are the same on every run and thread count. */
#include "brdfit/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "base/parallel.h"

enum { CHUNK = 256 };

typedef struct pair {
    double lt;         /* light polar angle (rad) */
    double vx, vy, vz; /* rotated view direction (unit) */
    double vt;         /* view polar angle (rad), for the views-only case */
    double w;          /* product of the weights */
} pair;

typedef struct prepared {
    bf_range lr, vr; /* degrees, as the samples hold their angles */
    pair *p;
    int np;
    /* The grid: n1 x n2 x n3 cells of width h1 (polar angle) and h2 (view x and y);
     * cell c holds pairs by_cell[start[c] .. start[c + 1]) (copies, in cell order, so a
     * sample reads them contiguously). */
    int n1, n2, n3;
    double h1, h2;
    int *start;
    pair *by_cell;
    int lights, views; /* which lists the scene has */
    double inv2r2;     /* 1 / (2 radius^2), radians */
    double amax2;      /* (3 radius)^2: the kernel's support */
    double cmax2;      /* the squared chord of that angle, to skip asin beyond it */
} prepared;

static const double DEG = M_PI / 180.0;

/* Cell coordinates, clamped into the grid. */
static int cell_of(double v, double lo, double h, int n)
{
    double c = floor((v - lo) / h);
    return c < 0.0 ? 0 : c >= n ? n - 1 : (int)c;
}

/* The grid over the pairs (see the top). Dimensions are capped so that a tiny radius
 * cannot ask for more cells than pairs are worth; wider cells only cost more checks. */
static bf_status build_grid(prepared *q, bf_error *err)
{
    enum { MAX_DIM = 128 };
    const int both = q->lights && q->views;
    q->h1 = sqrt(q->amax2);
    q->h2 = sqrt(q->cmax2);
    double h1 = q->h1 > 0.5 * M_PI / MAX_DIM ? q->h1 : 0.5 * M_PI / MAX_DIM;
    double h2 = q->h2 > 2.0 / MAX_DIM ? q->h2 : 2.0 / MAX_DIM;
    q->h1 = h1;
    q->h2 = h2;
    q->n1 = (int)ceil(0.5 * M_PI / h1) + 1;
    q->n2 = both ? (int)ceil(2.0 / h2) + 1 : 1;
    q->n3 = both ? (int)ceil(1.0 / h2) + 1 : 1;
    const size_t ncell = (size_t)q->n1 * (size_t)q->n2 * (size_t)q->n3;
    q->start = calloc(ncell + 1, sizeof *q->start);
    q->by_cell = malloc((size_t)q->np * sizeof *q->by_cell);
    int *cell = malloc((size_t)q->np * sizeof *cell);
    if (!q->start || !q->by_cell || !cell) {
        free(cell);
        return bf_fail(err, BF_ERR_NOMEM, "scene: out of memory for %d direction pairs", q->np);
    }
    for (int k = 0; k < q->np; k++) {
        const pair *p = &q->p[k];
        const double t = q->lights ? p->lt : p->vt;
        int c = cell_of(t, 0.0, q->h1, q->n1);
        if (both)
            c = (c * q->n2 + cell_of(p->vx, -1.0, q->h2, q->n2)) * q->n3 + cell_of(p->vy, 0.0, q->h2, q->n3);
        cell[k] = c;
        q->start[c + 1]++;
    }
    for (size_t c = 0; c < ncell; c++)
        q->start[c + 1] += q->start[c];
    int *fill = malloc((ncell + 1) * sizeof *fill);
    if (!fill) {
        free(cell);
        return bf_fail(err, BF_ERR_NOMEM, "scene: out of memory for %d direction pairs", q->np);
    }
    memcpy(fill, q->start, (ncell + 1) * sizeof *fill);
    for (int k = 0; k < q->np; k++) /* ascending k within a cell */
        q->by_cell[fill[cell[k]]++] = q->p[k];
    free(fill);
    free(cell);
    return BF_OK;
}

static void release(prepared *q)
{
    free(q->p);
    free(q->start);
    free(q->by_cell);
}

static bf_status prepare(const bf_scene *sc, prepared *q, bf_error *err)
{
    memset(q, 0, sizeof *q);
    q->lr = sc->light_theta;
    q->vr = sc->view_theta;
    q->lights = sc->nlights > 0;
    q->views = sc->nviews > 0;
    double r = sc->radius * DEG;
    if (!(r > 0.0) || !isfinite(r))
        return bf_fail(err, BF_ERR_ARG, "scene: radius %g must be > 0", sc->radius);
    q->inv2r2 = 1.0 / (2.0 * r * r);
    q->amax2 = 9.0 * r * r;
    double half = 1.5 * r < 0.5 * M_PI ? 1.5 * r : 0.5 * M_PI;
    q->cmax2 = 4.0 * sin(half) * sin(half) * (1.0 + 1e-12);
    if (!q->lights && !q->views)
        return BF_OK;
    int nl = q->lights ? sc->nlights : 1, nv = q->views ? sc->nviews : 1;
    q->np = nl * nv;
    if (!(q->p = calloc((size_t)q->np, sizeof *q->p)))
        return bf_fail(err, BF_ERR_NOMEM, "scene: out of memory");
    for (int a = 0; a < nl; a++)
        for (int b = 0; b < nv; b++) {
            pair *p = &q->p[a * nv + b];
            const bf_scene_dir *l = q->lights ? &sc->lights[a] : NULL, *v = q->views ? &sc->views[b] : NULL;
            p->w = (l ? l->weight : 1.0) * (v ? v->weight : 1.0);
            p->lt = l ? l->theta * DEG : 0.0;
            if (v) {
                double t = v->theta * DEG, ph = (v->phi - (l ? l->phi : 0.0)) * DEG;
                p->vt = t;
                p->vx = sin(t) * cos(ph);
                p->vy = fabs(sin(t) * sin(ph)); /* relative azimuth folded: see scene.h */
                p->vz = cos(t);
            }
        }
    return build_grid(q, err);
}

/* One chunk's configurations in one orientation: light polar angle tl and view polar
 * angle tv (degrees, for the ranges), tlr (radians), and the view rotated so that the
 * light has azimuth 0 (unit vectors, only when the scene has lights and views). */
typedef struct oriented {
    const double *tl, *tv, *tlr, *tvr, *vx, *vy, *vz;
} oriented;

/* The kernel sum of pair k at configuration i of o (0 outside its support). */
static inline double pair_kernel(const prepared *q, const pair *p, const oriented *o, size_t i)
{
    if (q->lights && q->views) {
        double a = o->tlr[i] - p->lt, a2 = a * a;
        if (a2 > q->amax2)
            return 0.0;
        double dx = o->vx[i] - p->vx, dy = o->vy[i] - p->vy, dz = o->vz[i] - p->vz;
        /* Angle from the chord: accurate at small angles, unlike acos of a dot. */
        double c2 = dx * dx + dy * dy + dz * dz;
        if (c2 > q->cmax2)
            return 0.0;
        double c = 0.5 * sqrt(c2);
        double b = 2.0 * asin(c < 1.0 ? c : 1.0), b2 = b * b;
        return b2 <= q->amax2 ? p->w * exp(-(a2 + b2) * q->inv2r2) : 0.0;
    }
    double a = (q->lights ? o->tlr[i] - p->lt : o->tvr[i] - p->vt), a2 = a * a;
    return a2 <= q->amax2 ? p->w * exp(-a2 * q->inv2r2) : 0.0;
}

static void orient(const prepared *q, size_t m, const oriented *o, double *out)
{
    for (size_t i = 0; i < m; i++)
        out[i] =
            o->tl[i] >= q->lr.lo && o->tl[i] <= q->lr.hi && o->tv[i] >= q->vr.lo && o->tv[i] <= q->vr.hi ? 1.0 : 0.0;
    if (q->np == 0)
        return;
    const int both = q->lights && q->views;
    for (size_t i = 0; i < m; i++) {
        if (out[i] == 0.0)
            continue;
        const double t = q->lights ? o->tlr[i] : o->tvr[i];
        const int c1 = cell_of(t, 0.0, q->h1, q->n1);
        const int c2 = both ? cell_of(o->vx[i], -1.0, q->h2, q->n2) : 0;
        const int c3 = both ? cell_of(o->vy[i], 0.0, q->h2, q->n3) : 0;
        /* The pairs of the neighbouring cells: every pair within the kernel's support
         * lies in one of them (cells are as wide as the support). */
        double acc = 0.0;
        for (int a = c1 > 0 ? c1 - 1 : 0; a <= c1 + 1 && a < q->n1; a++)
            for (int b = c2 > 0 ? c2 - 1 : 0; b <= c2 + 1 && b < q->n2; b++)
                for (int c = c3 > 0 ? c3 - 1 : 0; c <= c3 + 1 && c < q->n3; c++) {
                    const int cell = (a * q->n2 + b) * q->n3 + c;
                    for (int k = q->start[cell]; k < q->start[cell + 1]; k++)
                        acc += pair_kernel(q, &q->by_cell[k], o, i);
                }
        out[i] *= acc;
    }
}

typedef struct weights_job {
    const bf_scene *sc;
    const prepared *q;
    bf_samples *s;
    double *w;
} weights_job;

/* The weights of one chunk of samples (both orientations when reciprocal). */
static void weights_chunk(void *ctx, size_t chunk)
{
    const weights_job *job = ctx;
    const prepared *q = job->q;
    bf_samples *s = job->s;
    double *w = job->w;
    const int rotate = q->lights && q->views;
    double sw[CHUNK], tir[CHUNK], tor[CHUNK];
    double dx[CHUNK], dy[CHUNK], dz[CHUNK], rx[CHUNK], ry[CHUNK], rz[CHUNK], abuf[4 * CHUNK];
    const size_t i0 = chunk * CHUNK, m = s->n - i0 < CHUNK ? s->n - i0 : CHUNK;
    const double *dir[4];
    bf_samples_angle_block(s, i0, m, abuf, dir);
    const double *ti = dir[0], *pi_ = dir[1], *to = dir[2], *po = dir[3];
    for (size_t i = 0; i < m; i++) {
        tir[i] = ti[i] * DEG;
        tor[i] = to[i] * DEG;
    }
    if (rotate) /* V rotated by -phi_i, and L rotated by -phi_o for the swapped view */
        for (size_t i = 0; i < m; i++) {
            double d = (po[i] - pi_[i]) * DEG, cd = cos(d), sd = sin(d);
            double so = sin(tor[i]), si = sin(tir[i]);
            dx[i] = so * cd;
            dy[i] = fabs(so * sd);
            dz[i] = cos(tor[i]);
            rx[i] = si * cd;
            ry[i] = fabs(si * sd);
            rz[i] = cos(tir[i]);
        }
    const oriented direct = {ti, to, tir, tor, dx, dy, dz};
    orient(q, m, &direct, w + i0);
    if (!job->sc->reciprocal)
        return;
    /* Light and view swapped: the same configuration seen the other way round. */
    const oriented swapped = {to, ti, tor, tir, rx, ry, rz};
    orient(q, m, &swapped, sw);
    for (size_t i = 0; i < m; i++)
        w[i0 + i] = sw[i] > w[i0 + i] ? sw[i] : w[i0 + i];
}

bf_status bf_scene_weights(const bf_scene *sc, bf_samples *s, double *w, bf_error *err)
{
    prepared q;
    bf_status rc = prepare(sc, &q, err);
    if (rc != BF_OK) {
        release(&q);
        return rc;
    }
    /* Every sample's weight is its own: any thread count gives the same values. */
    weights_job job = {sc, &q, s, w};
    long cores = sysconf(_SC_NPROCESSORS_ONLN);
    bf_parallel_for((s->n + CHUNK - 1) / CHUNK, cores > 0 ? (int)cores : 1, weights_chunk, &job);
    release(&q);
    return BF_OK;
}

bf_status bf_scene_apply(const bf_scene *sc, bf_samples *s, size_t *kept, bf_error *err)
{
    if (kept)
        *kept = 0;
    const size_t n = s->n;
    double *w = malloc((n + 1) * sizeof *w);
    unsigned char *keep = malloc(n + 1);
    if (!w || !keep) {
        free(w);
        free(keep);
        return bf_fail(err, BF_ERR_NOMEM, "scene: out of memory for %zu samples", n);
    }
    bf_status rc = bf_scene_weights(sc, s, w, err);
    size_t k = 0;
    double sum = 0.0;
    int equal = 1;
    double first = 0.0;
    for (size_t i = 0; rc == BF_OK && i < n; i++) {
        keep[i] = w[i] > 0.0; /* NaN angles give 0 through the range test */
        if (!keep[i])
            continue;
        if (k == 0)
            first = w[i];
        equal &= w[i] == first;
        w[k++] = w[i]; /* compacted in the order bf_samples_keep keeps */
        sum += w[i];
    }
    if (rc == BF_OK && k == 0)
        rc = bf_fail(err, BF_ERR_ARG,
                     "no sample lies in the scene (%zu samples; scene: light theta %g..%g, view theta %g..%g%s)", n,
                     sc->light_theta.lo, sc->light_theta.hi, sc->view_theta.lo, sc->view_theta.hi,
                     sc->nlights || sc->nviews ? ", explicit directions" : "");
    if (rc == BF_OK && k < n)
        rc = bf_samples_keep(s, keep, err);
    /* Weights change only where the scene weighs samples differently: a ranges-only
     * scene selects, and leaves unweighted data unweighted. */
    /* Scene weights stay apart from the data's own (a scene's metrics use them alone);
     * a ranges-only scene only selects, and a second scene multiplies the first's. */
    if (rc == BF_OK && !equal) {
        int fresh = s->scene_weight == NULL;
        if (fresh && !(s->scene_weight = malloc((k + 1) * sizeof *s->scene_weight)))
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory for %zu scene weights", k);
        const double scale = (double)k / sum;
        for (size_t i = 0; rc == BF_OK && i < k; i++)
            s->scene_weight[i] = w[i] * scale * (fresh ? 1.0 : s->scene_weight[i]);
    }
    free(w);
    free(keep);
    if (rc == BF_OK && kept)
        *kept = k;
    return rc;
}
