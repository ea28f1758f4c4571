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
 * allocation per sample, the trigonometry once per sample for both orientations, and
 * asin and exp only for configurations within a pair's light band. */
#include "brdfit/scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { CHUNK = 256 };

typedef struct pair {
    double lt;          /* light polar angle (rad) */
    double vx, vy, vz;  /* rotated view direction (unit) */
    double vt;          /* view polar angle (rad), for the views-only case */
    double w;           /* product of the weights */
} pair;

typedef struct prepared {
    bf_range lr, vr;    /* degrees, as the samples hold their angles */
    pair *p;
    int np;
    int lights, views;  /* which lists the scene has */
    double inv2r2;      /* 1 / (2 radius^2), radians */
    double amax2;       /* (3 radius)^2: the kernel's support */
    double cmax2;       /* the squared chord of that angle, to skip asin beyond it */
} prepared;

static const double DEG = M_PI / 180.0;

static int prepare(const bf_scene *sc, prepared *q, bf_error *err)
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
    return BF_OK;
}

/* One chunk's configurations in one orientation: light polar angle tl and view polar
 * angle tv (degrees, for the ranges), tlr (radians), and the view rotated so that the
 * light has azimuth 0 (unit vectors, only when the scene has lights and views). */
typedef struct oriented {
    const double *tl, *tv, *tlr, *tvr, *vx, *vy, *vz;
} oriented;

static void orient(const prepared *q, size_t m, const oriented *o, double *out)
{
    for (size_t i = 0; i < m; i++)
        out[i] = o->tl[i] >= q->lr.lo && o->tl[i] <= q->lr.hi && o->tv[i] >= q->vr.lo && o->tv[i] <= q->vr.hi
                     ? 1.0
                     : 0.0;
    if (q->np == 0)
        return;
    double acc[CHUNK] = {0};
    for (int k = 0; k < q->np; k++) {
        const pair *p = &q->p[k];
        if (q->lights && q->views) {
            for (size_t i = 0; i < m; i++) {
                double a = o->tlr[i] - p->lt, a2 = a * a;
                /* Most configurations miss a pair's light band: no asin or exp for them. */
                if (out[i] == 0.0 || a2 > q->amax2)
                    continue;
                double dx = o->vx[i] - p->vx, dy = o->vy[i] - p->vy, dz = o->vz[i] - p->vz;
                /* Angle from the chord: accurate at small angles, unlike acos of a dot. */
                double c2 = dx * dx + dy * dy + dz * dz;
                if (c2 > q->cmax2)
                    continue;
                double c = 0.5 * sqrt(c2);
                double b = 2.0 * asin(c < 1.0 ? c : 1.0), b2 = b * b;
                if (b2 <= q->amax2)
                    acc[i] += p->w * exp(-(a2 + b2) * q->inv2r2);
            }
        } else {
            const double *t = q->lights ? o->tlr : o->tvr;
            const double t0 = q->lights ? p->lt : p->vt;
            for (size_t i = 0; i < m; i++) {
                double a = t[i] - t0, a2 = a * a;
                acc[i] += a2 <= q->amax2 ? p->w * exp(-a2 * q->inv2r2) : 0.0;
            }
        }
    }
    for (size_t i = 0; i < m; i++)
        out[i] *= acc[i];
}

int bf_scene_weights(const bf_scene *sc, bf_samples *s, double *w, bf_error *err)
{
    prepared q;
    int rc = prepare(sc, &q, err);
    if (rc != BF_OK)
        return rc;
    const int rotate = q.lights && q.views;
    double sw[CHUNK], tir[CHUNK], tor[CHUNK];
    double dx[CHUNK], dy[CHUNK], dz[CHUNK], rx[CHUNK], ry[CHUNK], rz[CHUNK], abuf[4 * CHUNK];
    for (size_t i0 = 0; i0 < s->n; i0 += CHUNK) {
        const size_t m = s->n - i0 < CHUNK ? s->n - i0 : CHUNK;
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
        orient(&q, m, &direct, w + i0);
        if (!sc->reciprocal)
            continue;
        /* Light and view swapped: the same configuration seen the other way round. */
        const oriented swapped = {to, ti, tor, tir, rx, ry, rz};
        orient(&q, m, &swapped, sw);
        for (size_t i = 0; i < m; i++)
            w[i0 + i] = sw[i] > w[i0 + i] ? sw[i] : w[i0 + i];
    }
    free(q.p);
    return BF_OK;
}

int bf_scene_apply(const bf_scene *sc, bf_samples *s, size_t *kept, bf_error *err)
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
    int rc = bf_scene_weights(sc, s, w, err);
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
