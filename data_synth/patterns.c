/* Direction patterns: where the synthetic samples sit. Angles are produced in degrees,
 * the unit of bf_samples. */
#include "synth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static const char *const pattern_names[] = {"uniform", "cosine", "stratified", "random", "gonio", "merl"};
#define NPATTERNS (int)(sizeof pattern_names / sizeof pattern_names[0])

int bf_synth_pattern_from_name(const char *name)
{
    for (int p = 0; p < NPATTERNS; p++)
        if (strcmp(name, pattern_names[p]) == 0)
            return p;
    return -1;
}

const char *bf_synth_pattern_name(bf_synth_pattern p)
{
    return (int)p >= 0 && (int)p < NPATTERNS ? pattern_names[p] : "unknown";
}

int bf_synth_pattern_fixed_count(bf_synth_pattern p)
{
    return p == BF_SYNTH_GONIO || p == BF_SYNTH_MERL;
}

static double deg(double rad)
{
    return rad * (180.0 / M_PI);
}

/* Above the horizon exactly as bf_geometry sees a polar angle in degrees: it converts
 * with the same factor and takes a cosine below 1e-15 as zero. */
static int above(double theta_deg)
{
    return cos(theta_deg * (M_PI / 180.0)) >= 1e-15;
}

/* One direction (theta, phi in degrees) of a random pattern; redrawn in the (1e-15
 * likely) case that it lands on the horizon. */
static void draw_direction(bf_synth_pattern p, bf_synth_rng *r, double *theta, double *phi)
{
    do {
        const double u = bf_synth_uniform(r);
        if (p == BF_SYNTH_UNIFORM) /* cos theta uniform on (0, 1] */
            *theta = deg(acos(1.0 - u));
        else if (p == BF_SYNTH_COSINE) /* pdf 2 cos theta sin theta: cos^2 uniform */
            *theta = deg(acos(sqrt(1.0 - u)));
        else /* random: theta itself uniform on [0, 90) */
            *theta = 90.0 * u;
        *phi = 360.0 * bf_synth_uniform(r);
    } while (!above(*theta));
}

/* ---- stratified --------------------------------------------------------------- */

void bf_synth_strata(size_t n, size_t dims[4])
{
    size_t f[4] = {1, 1, 1, 1};
    /* Prime factors in ascending order, then dealt out from the largest. */
    size_t primes[64], np = 0;
    for (size_t m = n, q = 2; m > 1 && np < 64;) {
        if (q * q > m) {
            primes[np++] = m;
            break;
        }
        if (m % q == 0) {
            primes[np++] = q;
            m /= q;
        } else {
            q++;
        }
    }
    for (size_t k = np; k-- > 0;) {
        int smallest = 0;
        for (int d = 1; d < 4; d++)
            if (f[d] < f[smallest])
                smallest = d;
        f[smallest] *= primes[k];
    }
    /* Sort descending: the two largest counts go to the azimuths. */
    for (int a = 0; a < 4; a++)
        for (int b = a + 1; b < 4; b++)
            if (f[b] > f[a]) {
                size_t t = f[a];
                f[a] = f[b];
                f[b] = t;
            }
    dims[0] = f[2]; /* cos theta_i */
    dims[1] = f[0]; /* phi_i */
    dims[2] = f[3]; /* cos theta_o */
    dims[3] = f[1]; /* phi_o */
}

/* Jittered cell a of A in cos theta: cos in (a/A, (a+1)/A], never 0. */
static double stratum_theta(size_t a, size_t A, bf_synth_rng *r)
{
    double theta;
    do
        theta = deg(acos(((double)a + 1.0 - bf_synth_uniform(r)) / (double)A));
    while (!above(theta));
    return theta;
}

static void stratified(bf_samples *s, bf_synth_rng *r)
{
    size_t dims[4];
    bf_synth_strata(s->n, dims);
    for (size_t j = 0; j < s->n; j++) {
        /* Mixed radix: phi_o varies fastest, cos theta_i slowest. */
        size_t idx[4], rest = j;
        for (int d = 3; d >= 0; d--) {
            idx[d] = rest % dims[d];
            rest /= dims[d];
        }
        s->theta_i[j] = stratum_theta(idx[0], dims[0], r);
        s->phi_i[j] = 360.0 * ((double)idx[1] + bf_synth_uniform(r)) / (double)dims[1];
        s->theta_o[j] = stratum_theta(idx[2], dims[2], r);
        s->phi_o[j] = 360.0 * ((double)idx[3] + bf_synth_uniform(r)) / (double)dims[3];
    }
}

/* ---- gonio ----------------------------------------------------------------------- */

#define GONIO_MIN_STEP 1e-3

static int gonio_ok(const bf_synth_gonio *g)
{
    if (!g || !g->incidence || g->n_incidence < 1 || !(g->step >= GONIO_MIN_STEP && g->step <= 90.0))
        return 0;
    for (int k = 0; k < g->n_incidence; k++)
        if (!(g->incidence[k] >= 0.0 && g->incidence[k] < 90.0))
            return 0;
    return 1;
}

/* Largest K with K step < 90. */
static size_t inplane_k(double step)
{
    size_t K = (size_t)ceil(90.0 / step);
    while (K > 0 && (double)K * step >= 90.0)
        K--;
    while ((double)(K + 1) * step < 90.0)
        K++;
    return K;
}

/* theta_i is one of the in-plane angles k step. */
static int on_inplane_grid(double theta_i, double step)
{
    return nearbyint(theta_i / step) * step == theta_i;
}

/* Fills (or, with s NULL, only counts) the gonio pairs. */
static size_t gonio_fill(const bf_synth_gonio *g, bf_samples *s)
{
    const size_t K = inplane_k(g->step);
    size_t n = 0;
    for (int q = 0; q < g->n_incidence; q++) {
        const double ti = g->incidence[q];
        for (size_t k = 0; k < 2 * K + 1; k++) {
            const double t = ((double)k - (double)K) * g->step; /* exact: integer times step */
            if (s) {
                s->theta_i[n] = ti;
                s->phi_i[n] = 0.0;
                s->theta_o[n] = fabs(t);
                s->phi_o[n] = t > 0.0 ? 180.0 : 0.0;
            }
            n++;
        }
        if (ti == 0.0)
            continue; /* the cone through the mirror direction is the normal alone */
        const int skip_plane = on_inplane_grid(ti, g->step);
        for (size_t j = 0; (double)j * g->step < 360.0; j++) {
            const double po = (double)j * g->step;
            if (skip_plane && (po == 0.0 || po == 180.0))
                continue;
            if (s) {
                s->theta_i[n] = ti;
                s->phi_i[n] = 0.0;
                s->theta_o[n] = ti;
                s->phi_o[n] = po;
            }
            n++;
        }
    }
    return n;
}

size_t bf_synth_gonio_count(const bf_synth_gonio *g)
{
    return gonio_ok(g) ? gonio_fill(g, NULL) : 0;
}

/* ---- merl -------------------------------------------------------------------------- */

static int merl_above(int32_t cell)
{
    double ti, pi_, to, po;
    bf_merl_cell_directions(cell, &ti, &pi_, &to, &po);
    return above(ti) && above(to);
}

/* ---- dispatch ---------------------------------------------------------------------- */

bf_status bf_synth_directions(bf_synth_pattern p, size_t count, const bf_synth_gonio *gonio, bf_synth_rng *r,
                              int channels, bf_samples **out, bf_error *err)
{
    *out = NULL;
    size_t n = count;
    switch (p) {
    case BF_SYNTH_UNIFORM:
    case BF_SYNTH_COSINE:
    case BF_SYNTH_STRATIFIED:
    case BF_SYNTH_RANDOM:
        if (count < 1)
            return bf_fail(err, BF_ERR_ARG, "pattern %s needs a sample count of at least 1", bf_synth_pattern_name(p));
        break;
    case BF_SYNTH_GONIO:
        if (!gonio_ok(gonio))
            return bf_fail(err, BF_ERR_ARG,
                           "pattern gonio needs incidence angles in [0, 90) and a step in [%g, 90] degrees",
                           GONIO_MIN_STEP);
        n = gonio_fill(gonio, NULL);
        break;
    case BF_SYNTH_MERL:
        n = 0;
        for (int32_t c = 0; c < BF_MERL_CELLS; c++)
            n += (size_t)merl_above(c);
        break;
    default: return bf_fail(err, BF_ERR_ARG, "unknown pattern %d", (int)p);
    }

    /* MERL cells stay cells (no angle arrays): the same directions and geometry as the
     * table read back. */
    bf_samples *s;
    bf_status rc =
        p == BF_SYNTH_MERL ? bf_samples_new_cells(n, channels, &s, err) : bf_samples_new(n, channels, &s, err);
    if (rc != BF_OK)
        return rc;
    switch (p) {
    case BF_SYNTH_STRATIFIED: stratified(s, r); break;
    case BF_SYNTH_GONIO: gonio_fill(gonio, s); break;
    case BF_SYNTH_MERL: {
        size_t i = 0;
        for (int32_t c = 0; c < BF_MERL_CELLS; c++)
            if (merl_above(c))
                s->merl->cell[i++] = c;
        break;
    }
    default: /* uniform, cosine, random: incident then outgoing direction per pair */
        for (size_t i = 0; i < n; i++) {
            draw_direction(p, r, &s->theta_i[i], &s->phi_i[i]);
            draw_direction(p, r, &s->theta_o[i], &s->phi_o[i]);
        }
        break;
    }
    *out = s;
    return BF_OK;
}
