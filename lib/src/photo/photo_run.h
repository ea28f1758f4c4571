/* Internal: the state of one bf_photo_fit run and the steps' functions, shared by
 * photo_fit.c (bands and pixels), photo_start.c (start, clusters), photo_joint.c (shared
 * entries) and photo_run.c (their common helpers). */
#ifndef BF_PHOTO_RUN_H
#define BF_PHOTO_RUN_H

#include "photo_impl.h"

typedef struct photo_run {
    const bf_stack *s;
    const bf_photo_options *o;
    const char *spec;
    bf_model *model;
    int P, K, C, threads;
    double scale;
    double lo[PHOTO_MAX_PARAMS], hi[PHOTO_MAX_PARAMS];
    bf_scale pscale[PHOTO_MAX_PARAMS];
    unsigned char pixel_free[PHOTO_MAX_PARAMS]; /* entries each pixel fits */
    int nshared;
    int shared[PHOTO_MAX_PARAMS];
    const float *given_normals; /* BF_NORMALS_FILE: width*height*3, world frame */
    /* Per cluster: the start (P each) and the mean robust albedo (C each). */
    int nclusters;
    double *start, *centroid, *cluster_albedo;
    /* Scratch for single-threaded steps (K*3, K*C). */
    double *lbuf, *ebuf;
} photo_run;

/* One thread's buffers for a run's pixels: the solve's scratch, each image's light (K*3)
 * and irradiance (K*C), the predictions (K*C). photo_buffers_free takes a half-made one. */
typedef struct photo_buffers {
    photo_scratch *w;
    double *l, *e, *pred;
} photo_buffers;
int photo_buffers_new(const photo_run *run, photo_buffers *b);
void photo_buffers_free(photo_buffers *b);
/* The run's per-pixel problem, solves of at most max_iterations. */
photo_problem photo_run_problem(const photo_run *run, int max_iterations);

/* The normal a pixel starts from when normals are given or flat (world frame); n is left
 * as it is when they are fitted. */
void photo_given_normal(const photo_run *run, int x, int y, double n[3]);

/* Every stride-th masked pixel of rows [y0, y1), at most max of them (y*width + x,
 * malloc'd into *out): their count, or (size_t)-1 when out of memory. */
size_t photo_subsample(const unsigned char *mask, int y0, int y1, int width, size_t max, int32_t **out);
void photo_start_lambert(photo_run *run, const photo_band *b, double *normal, double *albedo);
double photo_auto_scale(const double *albedo, size_t n, int C);
int photo_nearest(const double *centroids, int k, const double *a, int C);
void photo_kmeans(const double *albedo, size_t n, int C, int k, uint64_t seed, double *centroids, int *label);
bf_status photo_cluster_start(photo_run *run, const photo_band *b, const double *normal, const int *label, int cl,
                              double *x, bf_error *err);
/* The shared entries (run->start's, per cluster) and the subsample's pixels (x: P each,
 * normal: 3 each, world) fitted jointly (photo_joint.c). */
void photo_joint_refine(photo_run *run, const photo_band *b, const int *label, double *x, double *normal);
/* The pixel's start: its cluster's, with the diffuse colour scaled by the pixel's albedo
 * against the cluster's mean. */
void photo_pixel_start(const photo_run *run, int cluster, const double *albedo, double *x);

#endif
