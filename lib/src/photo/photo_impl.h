/* Internal: the pieces of bf_photo_fit (photo.h), one file each:
 *  - photo_band.c:    a band of rows of every image, for the masked pixels only;
 *  - photo_light.c:   per pixel, each image's light direction and irradiance and the view;
 *  - photo_lambert.c: the Lambertian least-squares baseline and the robust start;
 *  - photo_solve.c:   the per-pixel (and shared) Levenberg-Marquardt solve;
 *  - photo_fit.c:     the whole run: start, clusters, shared parameters, bands, counts;
 *  - photo_options.c: the options' defaults, ranges and parsers. */
#ifndef BF_PHOTO_IMPL_H
#define BF_PHOTO_IMPL_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/photo.h"

/* bf_photo_options as the first version had it (before `spelling`): the least size the
 * library takes; `spelling` is read only when the caller's size holds it. */
#define PHOTO_OPTIONS_MIN_SIZE offsetof(bf_photo_options, spelling)
#define PHOTO_OPTIONS_SPELLING_SIZE (offsetof(bf_photo_options, spelling) + sizeof(bf_option_spelling))
/* How messages name an option (a keyword: "tile", "model", ...): "--tile" and "-m" as
 * the command line writes them, or the keyword, as o->spelling says. */
const char *photo_option_name(const bf_photo_options *o, const char *keyword);

/* A band of rows [y0, y1): its masked pixels and their values, image-major per pixel:
 * v[(p*K + k)*C + c], linear, exposure divided out, black level subtracted, times the
 * fit's scale; NaN where the sample is saturated or not finite. */
typedef struct photo_band {
    int y0, y1;
    size_t npix;
    int32_t *pixel; /* y*width + x of each */
    float *v;
    size_t *saturated, *invalid; /* per image */
} photo_band;

/* The pixels a band is read for: y*width + x each, all in rows [y0, y1). */
typedef struct photo_band_pixels {
    const int32_t *pixel;
    size_t npix;
    int y0, y1;
} photo_band_pixels;
/* The listed pixels, read from every image on up to `threads` threads. */
bf_status photo_band_load(const bf_stack *s, const photo_band_pixels *at, int threads, photo_band *b, bf_error *err);
void photo_band_free(photo_band *b);
/* The mask as width*height bytes (1: fitted). */
bf_status photo_mask_load(const bf_stack *s, unsigned char **mask, bf_error *err);

/* Pixel geometry in the world frame: each image's direction towards the light (unit)
 * and its irradiance per channel (a point light's intensity / r^2), and the view. */
typedef struct photo_lights {
    double *l; /* K * 3 */
    double *e; /* K * C */
    double v[3];
} photo_lights;
void photo_lights_at(const bf_stack *s, int x, int y, photo_lights *pl);
/* Camera frame <-> world frame (the camera's rotation). */
void photo_to_camera(const bf_stack *s, const double w[3], double c[3]);
void photo_to_world(const bf_stack *s, const double c[3], double w[3]);

/* The classic baseline: the grey values' least-squares normal over every sample (NaN
 * excluded) and the per-channel albedo at it. Returns 0 when undetermined. */
int photo_lambert(const float *v, const photo_lights *pl, int K, int C, double n[3], double *albedo);
/* The same, leaving out samples in shadow at the current normal and bright outliers
 * (highlights): the start of the model's fit. */
int photo_lambert_robust(const float *v, const photo_lights *pl, int K, int C, double n[3], double *albedo);

/* Per-pixel solve: at most this many model entries (a 3-channel model has far fewer). */
#define PHOTO_MAX_PARAMS 64
typedef struct photo_problem {
    const bf_model *model;
    int K, C, P;
    const unsigned char *free_entry; /* P: 1 where the pixel's solve moves the entry */
    int fit_normal;
    const double *lo, *hi; /* P: bounds */
    const bf_scale *scale; /* P: the optimizer's scale per entry */
    int max_iterations;
} photo_problem;

/* Scratch for one thread's solves (photo_scratch_new for K, C, P). */
typedef struct photo_scratch photo_scratch;
photo_scratch *photo_scratch_new(int K, int C, int P);
void photo_scratch_free(photo_scratch *w);

typedef struct photo_pixel_out {
    double cost;     /* sum of squared residuals over the used samples */
    size_t used;     /* samples used */
    size_t shadowed; /* n.l <= 0 at the final normal */
    size_t dark;     /* dark outliers left out */
    int iterations;
    int restarted; /* solved again from a neighbour's solution (photo_fit.c) */
    int ok;
} photo_pixel_out;

/* Fits x (P entries, in/out) and n (unit, world, in/out) to one pixel's K samples. */
void photo_solve_pixel(const photo_problem *pr, const float *v, const photo_lights *pl, double *x, double n[3],
                       photo_scratch *w, photo_pixel_out *out);
/* The model's prediction at x, n for every sample (K*C values into pred). */
void photo_predict(const photo_problem *pr, const photo_lights *pl, const double *x, const double n[3],
                   photo_scratch *w, double *pred);

/* One pixel's samples, its lights and the point (x, n) where its sums are taken. */
typedef struct photo_pixel_at {
    const float *v; /* K*C */
    const photo_lights *pl;
    const double *x, *n; /* P entries; unit, world */
} photo_pixel_at;
/* Where one pixel's block of the joint normal equations goes. */
typedef struct photo_joint_block {
    double *A, *g, *cost;
} photo_joint_block;
/* The joint problem of shared entries and pixels (photo_joint.c). For one pixel at
 * (at->x, at->n): J'J (out->A, m x m) and J'r (out->g, m) over its unknowns, ordered its
 * free entries, its normal's two angles (when fitted), then the `ns` shared entries;
 * *out->cost its cost. Returns the count of the pixel's own unknowns (m minus ns). */
int photo_joint_sums(const photo_problem *pr, const int *shared, int ns, const photo_pixel_at *at, photo_scratch *w,
                     photo_joint_block *out);
/* (x, n) moved by d over the pixel's own unknowns (that order), bounds kept, into (xo, no). */
void photo_pixel_step(const photo_problem *pr, const double *x, const double n[3], const double *d, double *xo,
                      double no[3]);
/* Entry e moved by dz in its optimizer scale, within its bounds. */
double photo_shared_step(const photo_problem *pr, int e, double x, double dz);
/* The pixel's cost at (x, n) (no dark outliers left out). */
double photo_cost(const photo_problem *pr, const float *v, const photo_lights *pl, const double *x, const double n[3],
                  photo_scratch *w);
/* Cholesky in place (lower; 0 when not positive definite), its solve in place, and the
 * Marquardt damping A + lambda diag(A) (with a floor). */
int photo_chol(double *L, int n);
void photo_chol_solve(const double *L, int n, double *b);
void photo_damp(double *A, int n, double lambda);

/* The tangent frame at n (t: the world's x projected on the tangent plane, or y where n
 * is near x; b = n x t): anisotropic models see their x along t. */
void photo_frame(const double n[3], double t[3], double b[3]);
/* theta_i, phi_i, theta_o, phi_o in degrees of l and v at normal n; 0 when either is
 * below the horizon. */
int photo_local_angles(const double n[3], const double l[3], const double v[3], double ang[4]);

/* Solves (A + lambda diag(A)) d = -g for a small symmetric A (n x n, row-major); 0 when
 * not positive definite. */
int photo_damped_solve(const double *A, const double *g, int n, double lambda, double *d);

#endif
