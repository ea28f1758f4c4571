/* The per-pixel solve (photo_impl.h): Levenberg-Marquardt on one pixel's samples,
 *   r_kc = E_kc f_c(x; l_k, v) max(0, n . l_k) - v_kc,
 * over the pixel's free model entries, each in the optimizer's scale (log for widths and
 * exponents), and the normal's two angles. The model's gradient is analytic
 * (bf_model_eval); the normal's derivatives are forward differences of the prediction
 * (two more evaluations a step; the model's interface gives no derivative by direction,
 * and central differences cost two more for no gain in the solves' accuracy). Saturated
 * samples (NaN) and dark outliers (far below the prediction after a first solve: cast
 * shadows) are left out. A sample in shadow at the current normal (n . l <= 0) stays in
 * the cost, predicted 0 and pulling nothing: were it left out, the solve could lower the
 * cost by tilting the normal until a lit sample's n . l reaches 0 (the cost must not jump
 * with the normal). Such samples are counted as shadowed. Bounds are kept by projection. The scratch holds everything, so a solve allocates nothing. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "models/scale.h"
#include "photo_impl.h"

#define NORMAL_STEP 1e-5 /* radians: the forward differences of the normal */
#define MAX_UNKNOWNS (PHOTO_MAX_PARAMS + 2)
#define RELATIVE_STOP 1e-7 /* two steps in a row that lower the cost by less end the solve */
#define STEP_STOP 1e-8     /* as does a step this small (optimizer scale, radians) */
#define DARK_FACTOR 0.5    /* a dark outlier is below this fraction of the prediction */
#define DARK_SIGMAS 4.0    /* and below it by this many of the pixel's residual RMS */

struct photo_scratch {
    int K, C, P;
    bf_geometry g;
    double *geo;         /* 11 * K: the geometry's arrays */
    double *f, *grad;    /* K*C, K*C*P */
    double *pred[3];     /* K*C each: at the point, and at the normal moved along t, b */
    unsigned char *dark; /* K */
    double *jtj, *jtr;   /* MAX_UNKNOWNS^2, MAX_UNKNOWNS */
};

photo_scratch *photo_scratch_new(int K, int C, int P)
{
    photo_scratch *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->K = K;
    w->C = C;
    w->P = P;
    size_t kc = (size_t)K * (size_t)C;
    w->geo = malloc(11 * (size_t)K * sizeof *w->geo);
    w->f = malloc(kc * sizeof *w->f);
    w->grad = malloc(kc * (size_t)P * sizeof *w->grad);
    for (int i = 0; i < 3; i++)
        w->pred[i] = malloc(kc * sizeof *w->pred[i]);
    w->dark = calloc((size_t)K, 1);
    w->jtj = malloc(MAX_UNKNOWNS * MAX_UNKNOWNS * sizeof *w->jtj);
    w->jtr = malloc(MAX_UNKNOWNS * sizeof *w->jtr);
    int ok = w->geo && w->f && w->grad && w->dark && w->jtj && w->jtr;
    for (int i = 0; i < 3; i++)
        ok = ok && w->pred[i];
    if (!ok) {
        photo_scratch_free(w);
        return NULL;
    }
    double *a = w->geo;
    w->g.n = (size_t)K;
    w->g.lx = a;
    w->g.ly = a + K;
    w->g.lz = a + 2 * K;
    w->g.vx = a + 3 * K;
    w->g.vy = a + 4 * K;
    w->g.vz = a + 5 * K;
    w->g.hx = a + 6 * K;
    w->g.hy = a + 7 * K;
    w->g.hz = a + 8 * K;
    w->g.vh = a + 9 * K;
    w->g.sin2h = a + 10 * K;
    w->g.cell = NULL;
    return w;
}

void photo_scratch_free(photo_scratch *w)
{
    if (!w)
        return;
    free(w->geo);
    free(w->f);
    free(w->grad);
    for (int i = 0; i < 3; i++)
        free(w->pred[i]);
    free(w->dark);
    free(w->jtj);
    free(w->jtr);
    free(w);
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The tangent frame at n: t is the world's x axis projected on the tangent plane (the y
 * axis where n is near x), b = n x t. Anisotropic models see their x along t. */
void photo_frame(const double n[3], double t[3], double b[3])
{
    double ax[3] = {1.0, 0.0, 0.0};
    if (fabs(n[0]) > 0.9) {
        ax[0] = 0.0;
        ax[1] = 1.0;
    }
    double d = dot3(ax, n), len = 0.0;
    for (int i = 0; i < 3; i++) {
        t[i] = ax[i] - d * n[i];
        len += t[i] * t[i];
    }
    len = sqrt(len);
    for (int i = 0; i < 3; i++)
        t[i] /= len;
    b[0] = n[1] * t[2] - n[2] * t[1];
    b[1] = n[2] * t[0] - n[0] * t[2];
    b[2] = n[0] * t[1] - n[1] * t[0];
}

static double zero_tiny(double c)
{
    return fabs(c) < 1e-15 ? 0.0 : c;
}

/* The local geometry of every sample at normal n. */
static void fill_geometry(photo_scratch *w, const photo_lights *pl, const double n[3])
{
    double t[3], b[3];
    photo_frame(n, t, b);
    const bf_geometry *g = &w->g;
    double vx = dot3(t, pl->v), vy = dot3(b, pl->v), vz = zero_tiny(dot3(n, pl->v));
    for (int k = 0; k < w->K; k++) {
        const double *l = pl->l + 3 * k;
        double lx = dot3(t, l), ly = dot3(b, l), lz = zero_tiny(dot3(n, l));
        double hx = lx + vx, hy = ly + vy, hz = lz + vz, hl = sqrt(hx * hx + hy * hy + hz * hz);
        if (hl > 0.0) {
            hx /= hl;
            hy /= hl;
            hz /= hl;
        }
        g->lx[k] = lx;
        g->ly[k] = ly;
        g->lz[k] = lz;
        g->vx[k] = vx;
        g->vy[k] = vy;
        g->vz[k] = vz;
        g->hx[k] = hx;
        g->hy[k] = hy;
        g->hz[k] = hz;
        g->vh[k] = vx * hx + vy * hy + vz * hz;
        g->sin2h[k] = hx * hx + hy * hy;
    }
}

/* Predictions E f max(0, n.l) into pred (and the model's gradient into w->grad when
 * want_grad). */
static void predict(const photo_problem *pr, const photo_lights *pl, const double *x, const double n[3],
                    photo_scratch *w, double *pred, int want_grad)
{
    fill_geometry(w, pl, n);
    bf_model_eval(pr->model, x, &w->g, w->f, want_grad ? w->grad : NULL);
    int C = pr->C;
    for (int k = 0; k < pr->K; k++) {
        double lz = fmax(w->g.lz[k], 0.0);
        for (int c = 0; c < C; c++)
            pred[k * C + c] = pl->e[k * C + c] * w->f[k * C + c] * lz;
    }
}

void photo_predict(const photo_problem *pr, const photo_lights *pl, const double *x, const double n[3],
                   photo_scratch *w, double *pred)
{
    predict(pr, pl, x, n, w, pred, 0);
}

static void rotated(const double n[3], double a, double bb, double out[3])
{
    double t[3], b[3];
    photo_frame(n, t, b);
    double len = 0.0;
    for (int i = 0; i < 3; i++) {
        out[i] = n[i] + a * t[i] + bb * b[i];
        len += out[i] * out[i];
    }
    len = sqrt(len);
    for (int i = 0; i < 3; i++)
        out[i] /= len;
}

/* A sample is used when measured and not a dark outlier (shadowed ones too: above). */
static int used(const float *v, const photo_scratch *w, int k, int C)
{
    return !isnan(v[k * C]) && !w->dark[k];
}

static double cost_of(const photo_problem *pr, const float *v, photo_scratch *w, const double *pred)
{
    double s = 0.0;
    int C = pr->C;
    for (int k = 0; k < pr->K; k++)
        if (used(v, w, k, C))
            for (int c = 0; c < C; c++) {
                double r = pred[k * C + c] - v[k * C + c];
                s += r * r;
            }
    return s;
}

/* The unknowns: free entries (idx) then the normal's two angles. */
typedef struct unknowns {
    int n, nx;
    int idx[PHOTO_MAX_PARAMS];
} unknowns;

/* J'J and J'r at (x, n) into w->jtj, w->jtr; returns the cost. */
static double sums(const photo_problem *pr, const float *v, const photo_lights *pl, const double *x, const double n[3],
                   const unknowns *u, photo_scratch *w)
{
    int C = pr->C, P = pr->P, nu = u->n;
    if (pr->fit_normal) {
        static const double dir[2][2] = {{1, 0}, {0, 1}};
        for (int i = 0; i < 2; i++) {
            double m[3];
            rotated(n, NORMAL_STEP * dir[i][0], NORMAL_STEP * dir[i][1], m);
            predict(pr, pl, x, m, w, w->pred[1 + i], 0);
        }
    }
    predict(pr, pl, x, n, w, w->pred[0], 1);
    memset(w->jtj, 0, (size_t)nu * (size_t)nu * sizeof *w->jtj);
    memset(w->jtr, 0, (size_t)nu * sizeof *w->jtr);
    double dxdz[PHOTO_MAX_PARAMS], row[MAX_UNKNOWNS], cost = 0.0;
    for (int j = 0; j < u->nx; j++)
        dxdz[j] = bf_scale_dxdz(pr->scale[u->idx[j]], x[u->idx[j]]);
    for (int k = 0; k < pr->K; k++) {
        if (!used(v, w, k, C))
            continue;
        double lz = fmax(w->g.lz[k], 0.0);
        for (int c = 0; c < C; c++) {
            int q = k * C + c;
            double r = w->pred[0][q] - v[q], el = pl->e[q] * lz;
            const double *gr = w->grad + (size_t)q * (size_t)P;
            for (int j = 0; j < u->nx; j++)
                row[j] = el * gr[u->idx[j]] * dxdz[j];
            if (pr->fit_normal) {
                row[u->nx] = (w->pred[1][q] - w->pred[0][q]) / NORMAL_STEP;
                row[u->nx + 1] = (w->pred[2][q] - w->pred[0][q]) / NORMAL_STEP;
            }
            cost += r * r;
            for (int a = 0; a < nu; a++) {
                w->jtr[a] += row[a] * r;
                for (int b = 0; b <= a; b++)
                    w->jtj[a * nu + b] += row[a] * row[b];
            }
        }
    }
    for (int a = 0; a < nu; a++)
        for (int b = 0; b < a; b++)
            w->jtj[b * nu + a] = w->jtj[a * nu + b];
    return cost;
}

int photo_chol(double *L, int n)
{
    for (int j = 0; j < n; j++) { /* Cholesky, in place (lower) */
        double s = L[j * n + j];
        for (int k = 0; k < j; k++)
            s -= L[j * n + k] * L[j * n + k];
        if (!(s > 0.0))
            return 0;
        L[j * n + j] = sqrt(s);
        for (int i = j + 1; i < n; i++) {
            double t = L[i * n + j];
            for (int k = 0; k < j; k++)
                t -= L[i * n + k] * L[j * n + k];
            L[i * n + j] = t / L[j * n + j];
        }
    }
    return 1;
}

void photo_chol_solve(const double *L, int n, double *b)
{
    for (int i = 0; i < n; i++) {
        double t = b[i];
        for (int k = 0; k < i; k++)
            t -= L[i * n + k] * b[k];
        b[i] = t / L[i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double t = b[i];
        for (int k = i + 1; k < n; k++)
            t -= L[k * n + i] * b[k];
        b[i] = t / L[i * n + i];
    }
}

void photo_damp(double *A, int n, double lambda)
{
    double maxd = 0.0;
    for (int i = 0; i < n; i++)
        maxd = fmax(maxd, A[i * n + i]);
    for (int i = 0; i < n; i++)
        A[i * n + i] += lambda * fmax(A[i * n + i], 1e-9 * maxd) + 1e-14 * maxd;
}

int photo_damped_solve(const double *A, const double *g, int n, double lambda, double *d)
{
    double L[MAX_UNKNOWNS * MAX_UNKNOWNS], maxd = 0.0;
    for (int i = 0; i < n; i++)
        maxd = fmax(maxd, A[i * n + i]);
    if (!(maxd > 0.0))
        return 0;
    memcpy(L, A, (size_t)n * (size_t)n * sizeof *L);
    photo_damp(L, n, lambda);
    if (!photo_chol(L, n))
        return 0;
    for (int i = 0; i < n; i++)
        d[i] = -g[i];
    photo_chol_solve(L, n, d);
    return 1;
}

/* Entry e moved by dz in the optimizer's scale, kept inside its bounds (the driver has
 * moved open bounds inside by a hair). */
static double step_entry(const photo_problem *pr, int e, double x, double dz)
{
    bf_scale sc = pr->scale[e];
    double y = bf_scale_to_x(sc, bf_scale_to_z(sc, x) + dz);
    if (!(y >= pr->lo[e]))
        y = pr->lo[e];
    if (!(y <= pr->hi[e]))
        y = pr->hi[e];
    return y;
}

/* One pixel's solve: what every step of lm reads. */
typedef struct pixel_solve {
    const photo_problem *pr;
    const float *v;
    const photo_lights *pl;
    const unknowns *u;
    photo_scratch *w;
} pixel_solve;

/* The damped step d at x over the unknowns (w->jtj, w->jtr), 0 for the entries held on a
 * bound; *na counts the others. 0 when none is free or the damped system is not positive
 * definite. */
static int active_step(const pixel_solve *ps, const double *x, double lambda, double *d, int *na)
{
    const photo_problem *pr = ps->pr;
    const unknowns *u = ps->u;
    const photo_scratch *w = ps->w;
    int nu = u->n;
    /* Entries on a bound that the gradient pushes outwards stay there this step (an
     * active set): a step projected back onto the bound would not be a descent. */
    int act[MAX_UNKNOWNS];
    *na = 0;
    for (int j = 0; j < nu; j++) {
        int e = j < u->nx ? u->idx[j] : -1;
        int held = e >= 0 && ((x[e] <= pr->lo[e] && w->jtr[j] > 0.0) || (x[e] >= pr->hi[e] && w->jtr[j] < 0.0));
        if (!held)
            act[(*na)++] = j;
    }
    double A[MAX_UNKNOWNS * MAX_UNKNOWNS], g[MAX_UNKNOWNS], da[MAX_UNKNOWNS];
    for (int a = 0; a < *na; a++) {
        g[a] = w->jtr[act[a]];
        for (int b = 0; b < *na; b++)
            A[a * *na + b] = w->jtj[act[a] * nu + act[b]];
    }
    if (!*na || !photo_damped_solve(A, g, *na, lambda, da))
        return 0;
    memset(d, 0, (size_t)nu * sizeof *d);
    for (int a = 0; a < *na; a++)
        d[act[a]] = da[a];
    return 1;
}

static void lm(const pixel_solve *ps, double *x, double n[3], photo_pixel_out *out)
{
    const photo_problem *pr = ps->pr;
    const float *v = ps->v;
    const photo_lights *pl = ps->pl;
    const unknowns *u = ps->u;
    photo_scratch *w = ps->w;
    int nu = u->n, P = pr->P;
    double cost = sums(pr, v, pl, x, n, u, w), lambda = 1e-3;
    double xt[PHOTO_MAX_PARAMS], nt[3], d[MAX_UNKNOWNS];
    int small = 0;
    for (int it = 0; it < pr->max_iterations && nu > 0; it++) {
        out->iterations++;
        int na;
        if (!active_step(ps, x, lambda, d, &na)) {
            if (!na || (lambda *= 10.0) > 1e12)
                break;
            continue;
        }
        memcpy(xt, x, (size_t)P * sizeof *xt);
        for (int j = 0; j < u->nx; j++)
            xt[u->idx[j]] = step_entry(pr, u->idx[j], x[u->idx[j]], d[j]);
        if (pr->fit_normal)
            rotated(n, d[u->nx], d[u->nx + 1], nt);
        else
            memcpy(nt, n, sizeof nt);
        predict(pr, pl, xt, nt, w, w->pred[0], 0);
        double trial = cost_of(pr, v, w, w->pred[0]);
        if (trial < cost) {
            double rel = (cost - trial) / fmax(cost, 1e-300);
            memcpy(x, xt, (size_t)P * sizeof *x);
            memcpy(n, nt, sizeof nt);
            lambda = fmax(lambda / 3.0, 1e-9);
            cost = sums(pr, v, pl, x, n, u, w);
            small = rel < RELATIVE_STOP ? small + 1 : 0;
            double dmax = 0.0;
            for (int j = 0; j < nu; j++)
                dmax = fmax(dmax, fabs(d[j]));
            if (small >= 2 || dmax < STEP_STOP)
                break;
        } else if ((lambda *= 4.0) > 1e12)
            break;
    }
    out->cost = cost;
}

void photo_solve_pixel(const photo_problem *pr, const float *v, const photo_lights *pl, double *x, double n[3],
                       photo_scratch *w, photo_pixel_out *out)
{
    memset(out, 0, sizeof *out);
    unknowns u = {0};
    for (int e = 0; e < pr->P; e++)
        if (pr->free_entry[e])
            u.idx[u.nx++] = e;
    u.n = u.nx + (pr->fit_normal ? 2 : 0);
    int K = pr->K, C = pr->C;
    memset(w->dark, 0, (size_t)K);
    pixel_solve ps = {pr, v, pl, &u, w};
    lm(&ps, x, n, out);
    /* Dark outliers: samples far below the fitted prediction (a cast shadow, a defect),
     * then one more solve without them. */
    predict(pr, pl, x, n, w, w->pred[0], 0);
    size_t m = 0;
    for (int k = 0; k < K; k++)
        m += used(v, w, k, C);
    double sigma = m ? sqrt(out->cost / (double)(m * (size_t)C)) : 0.0;
    int dark = 0;
    for (int k = 0; k < K; k++) {
        if (!used(v, w, k, C))
            continue;
        double p = 0.0, q = 0.0;
        for (int c = 0; c < C; c++) {
            p += w->pred[0][k * C + c];
            q += v[k * C + c];
        }
        if (q < DARK_FACTOR * p && (p - q) / C > DARK_SIGMAS * sigma) {
            w->dark[k] = 1;
            dark++;
        }
    }
    if (dark)
        lm(&ps, x, n, out);
    fill_geometry(w, pl, n);
    for (int k = 0; k < K; k++) {
        if (isnan(v[k * C]))
            continue;
        if (w->dark[k])
            out->dark++;
        else if (!(w->g.lz[k] > 0.0))
            out->shadowed++;
        else
            out->used++;
    }
    out->ok = isfinite(out->cost);
}

int photo_local_angles(const double n[3], const double l[3], const double v[3], double ang[4])
{
    double t[3], b[3];
    photo_frame(n, t, b);
    double lz = dot3(n, l), vz = dot3(n, v);
    if (!(lz > 0.0 && vz > 0.0))
        return 0;
    ang[0] = acos(fmin(lz, 1.0)) * 180.0 / M_PI;
    ang[1] = atan2(dot3(b, l), dot3(t, l)) * 180.0 / M_PI;
    ang[2] = acos(fmin(vz, 1.0)) * 180.0 / M_PI;
    ang[3] = atan2(dot3(b, v), dot3(t, v)) * 180.0 / M_PI;
    return 1;
}

/* The joint unknowns of a pixel: its free entries, its normal's two angles (when
 * fitted), then the shared entries. */
static void joint_unknowns(const photo_problem *pr, const int *shared, int ns, unknowns *u, int *npix)
{
    memset(u, 0, sizeof *u);
    for (int e = 0; e < pr->P; e++)
        if (pr->free_entry[e])
            u->idx[u->nx++] = e;
    *npix = u->nx + (pr->fit_normal ? 2 : 0);
    for (int j = 0; j < ns; j++)
        u->idx[u->nx++] = shared[j];
    u->n = u->nx + (pr->fit_normal ? 2 : 0);
}

int photo_joint_sums(const photo_problem *pr, const int *shared, int ns, const photo_pixel_at *at, photo_scratch *w,
                     photo_joint_block *out)
{
    double *A = out->A, *g = out->g;
    unknowns u;
    int np;
    joint_unknowns(pr, shared, ns, &u, &np);
    memset(w->dark, 0, (size_t)pr->K);
    *out->cost = sums(pr, at->v, at->pl, at->x, at->n, &u, w);
    /* sums orders (free entries, shared entries, normal): reorder to (free, normal, shared). */
    int nu = u.n, nf = np - (pr->fit_normal ? 2 : 0), order[MAX_UNKNOWNS];
    for (int a = 0; a < nf; a++)
        order[a] = a;
    if (pr->fit_normal) {
        order[nf] = u.nx;
        order[nf + 1] = u.nx + 1;
    }
    for (int j = 0; j < ns; j++)
        order[np + j] = nf + j;
    for (int a = 0; a < nu; a++) {
        g[a] = w->jtr[order[a]];
        for (int b = 0; b < nu; b++)
            A[a * nu + b] = w->jtj[order[a] * nu + order[b]];
    }
    return np;
}

void photo_pixel_step(const photo_problem *pr, const double *x, const double n[3], const double *d, double *xo,
                      double no[3])
{
    memcpy(xo, x, (size_t)pr->P * sizeof *xo);
    int j = 0;
    for (int e = 0; e < pr->P; e++)
        if (pr->free_entry[e])
            xo[e] = step_entry(pr, e, x[e], d[j++]);
    if (pr->fit_normal)
        rotated(n, d[j], d[j + 1], no);
    else
        memcpy(no, n, 3 * sizeof *no);
}

double photo_shared_step(const photo_problem *pr, int e, double x, double dz)
{
    return step_entry(pr, e, x, dz);
}

double photo_cost(const photo_problem *pr, const float *v, const photo_lights *pl, const double *x, const double n[3],
                  photo_scratch *w)
{
    memset(w->dark, 0, (size_t)pr->K);
    predict(pr, pl, x, n, w, w->pred[0], 0);
    return cost_of(pr, v, w, w->pred[0]);
}
