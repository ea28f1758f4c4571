/* Materials from photographs: a stack of images of one object, each under one known
 * light, and per-pixel fits of a normal and a model's parameters to it (photometric
 * stereo with a BRDF). docs/images.md gives the formats, conventions and outputs.
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_PHOTO_H
#define BRDFIT_PHOTO_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/error.h"
#include "brdfit/model.h"
#include "brdfit/options.h"
#include "brdfit/solve.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One image of a stack and its light. Frozen (docs/api.md): an array element. */
typedef struct bf_stack_image {
    char *file;    /* as it is opened (the stack's folder prepended) */
    int point;     /* 0: directional light `dir`; 1: point light at `pos` (1/r^2) */
    double dir[3]; /* unit, from the surface towards the light (world frame) */
    double pos[3];
    double intensity[3]; /* per channel (a grey stack uses [0]) */
    double exposure;     /* divides the image's values */
} bf_stack_image;

typedef enum bf_stack_camera_type { BF_CAMERA_ORTHOGRAPHIC = 0, BF_CAMERA_PINHOLE } bf_stack_camera_type;

/* Frozen (docs/api.md): embedded in bf_stack. */
typedef struct bf_stack_camera {
    bf_stack_camera_type type;
    double pixel_size, center[3]; /* orthographic */
    double fx, fy, cx, cy;        /* pinhole intrinsics in pixels */
    double rotation[9];           /* camera to world, row-major */
    double position[3];           /* pinhole centre in the world */
} bf_stack_camera;

typedef enum bf_transfer { BF_TRANSFER_LINEAR = 0, BF_TRANSFER_SRGB, BF_TRANSFER_GAMMA } bf_transfer;

typedef enum bf_stack_layout { BF_STACK_DILIGENT = 0, BF_STACK_JSON } bf_stack_layout;

/* Made by bf_stack_read, freed by bf_stack_free: read through the pointer, may gain
 * fields at the end (docs/api.md). */
typedef struct bf_stack {
    char *path; /* the folder or JSON file it was read from */
    bf_stack_layout layout;
    int nimages;
    bf_stack_image *images;
    bf_stack_camera camera;
    char *mask; /* NULL: every pixel */
    bf_transfer transfer;
    double gamma;       /* BF_TRANSFER_GAMMA */
    double black_level; /* subtracted from linear values */
    double saturation;  /* linear values >= it are saturated; +Inf: none */
    double scale;       /* 0: automatic (docs/images.md), else the given value */
    /* Of every image (checked alike when read): */
    int width, height, channels; /* channels 1 or 3 */
    int bits, is_float;
} bf_stack;

/* Reads a DiLiGenT folder (a path that is a folder) or a JSON stack file, and the header
 * of every image and of the mask (sizes and channel counts must agree). Errors name the
 * file, the line where there is one, and the problem. */
BF_API bf_status bf_stack_read(const char *path, bf_stack **out, bf_error *err);
BF_API void bf_stack_free(bf_stack *s);

/* Where the normals come from. */
typedef enum bf_photo_normals {
    BF_NORMALS_FIT = 0, /* fitted per pixel with the model's parameters */
    BF_NORMALS_FILE,    /* read from an image of unit vectors in the camera frame */
    BF_NORMALS_FLAT     /* the sample's plane: the world's +z */
} bf_photo_normals;

/* The options' ranges (bf_photo_options_check). */
#define BF_PHOTO_MAX_CLUSTERS 64
#define BF_PHOTO_MAX_THREADS 1024
#define BF_PHOTO_MAX_TILES 1000000

/* Callers set it up with bf_photo_options_init (size: docs/api.md). */
typedef struct bf_photo_options {
    size_t size;       /* sizeof, set by bf_photo_options_init */
    const char *model; /* a registry spec */
    bf_photo_normals normals;
    const char *normals_file;   /* BF_NORMALS_FILE */
    const char *share;          /* NULL, or parameter names joined by ',' fitted once per cluster */
    int clusters;               /* material clusters for shared parameters (0, 1: one; at most
                                   BF_PHOTO_MAX_CLUSTERS) */
    int scale_given;            /* 1: `scale` overrides the stack's */
    double scale;               /* 0: automatic; else from 1e-30 to 1e30 */
    int tile_index, tile_count; /* a band of the image (0-based index of count); count 0: all */
    int threads;                /* 0: every online core; at most BF_PHOTO_MAX_THREADS */
    size_t band_bytes;          /* memory for one band's samples; 0: 1 GiB */
    int relit_images;           /* relit comparisons kept (0: none; at most BF_PHOTO_MAX_RELIT) */
    uint64_t seed;              /* the clusters' and shared fit's subsample */
    /* Called now and then with the fraction of pixels done (0..1). */
    void (*progress)(void *user, double done);
    void *progress_user;
    const bf_cancel_flag *cancel; /* non-zero: stop (bf_photo_result.cancelled) */
    /* How messages name the options: as `brdfit fit-images` writes them ("--tile 3/40:
     * ...", "-m: ..."; the default) or as keywords ("tile 3/40: ...", "model: ...") for
     * APIs: model, normals, share, clusters, scale, tile, relit, seed, threads. */
    bf_option_spelling spelling;
} bf_photo_options;

/* Sets the size and the defaults: model "walter", 3 relit images, the rest 0. */
BF_API void bf_photo_options_init_size(bf_photo_options *o, size_t size);
static inline void bf_photo_options_init(bf_photo_options *o)
{
    bf_photo_options_init_size(o, sizeof *o);
}

#define BF_PHOTO_MAX_RELIT 8
#define BF_PHOTO_MAX_SHARED 32

/* The options against their ranges, before any image is read: the model spec (a
 * registry model), the shared names (its parameters), a file for BF_NORMALS_FILE,
 * clusters, scale, the tile (1 <= I <= N, N at most BF_PHOTO_MAX_TILES), threads and
 * relit_images (0 to BF_PHOTO_MAX_RELIT). BF_ERR_ARG with a one-line message naming the
 * option as o->spelling says. bf_photo_fit checks them too. */
BF_API bf_status bf_photo_options_check(const bf_photo_options *o, bf_error *err);

/* The options that brdfit fit-images takes as text, parsed in one place: the tile "I/N"
 * (band I of N, from 1), the normals "fit", "flat" or an image file (o keeps the pointer
 * to text as normals_file: it must outlive o's use), the scale "auto" (the stack's rule)
 * or a number. BF_ERR_ARG, o unchanged, for a value they do not take, with the message
 * the check gives ("bad value '3/2' for --tile (I/N with 1 <= I <= N)"). */
BF_API bf_status bf_photo_options_set_tile(bf_photo_options *o, const char *text, bf_error *err);
BF_API bf_status bf_photo_options_set_normals(bf_photo_options *o, const char *text, bf_error *err);
BF_API bf_status bf_photo_options_set_scale(bf_photo_options *o, const char *text, bf_error *err);

/* Counts of samples (pixel x image) and pixels. Frozen (docs/api.md): embedded in
 * bf_photo_result. */
typedef struct bf_photo_counts {
    size_t pixels;   /* fitted (inside the mask and the tile) */
    size_t masked;   /* pixels outside the mask (in the tile) */
    size_t failed;   /* pixels whose fit did not finish (kept at the start) */
    size_t samples;  /* used in the fits */
    size_t shadowed; /* n.l <= 0 at the fitted normal */
    size_t dark;     /* dark outliers: far below what the fit predicts (cast shadows) */
    size_t saturated;
    size_t invalid; /* NaN or infinite values */
} bf_photo_counts;

/* Made by bf_photo_fit, freed by bf_photo_result_free: read through the pointer, may
 * gain fields at the end (docs/api.md). */
typedef struct bf_photo_result {
    int width, height, channels;
    int y0, y1;             /* the rows fitted (a tile's band; else 0, height) */
    bf_model *model;        /* configured for `channels` (owned) */
    int nvalues;            /* P: bf_model_nvalues */
    double scale;           /* as used */
    unsigned char *mask;    /* width * height: 1 where fitted */
    float *normals;         /* width * height * 3, camera frame, 0 outside */
    float *params;          /* width * height * P: the model vector of each pixel */
    float *error;           /* width * height: RMS relit error of the pixel's samples */
    float *lambert_normals; /* width * height * 3: the Lambertian baseline's */
    float *lambert_albedo;  /* width * height * channels */
    int *cluster;           /* width * height, -1 outside; NULL without clusters */
    int nclusters;          /* 1 without */
    int nshared;            /* shared model-vector entries */
    int shared_entry[BF_PHOTO_MAX_SHARED];
    double *shared; /* nclusters * nshared values */
    bf_photo_counts counts;
    /* Relit error (RMS over the used samples, in the stack's linear values), of the model
     * and of the Lambertian baseline, overall and per image (nimages each). */
    int nimages;
    double relit_rms, lambert_rms;
    double *image_rms, *image_lambert_rms;
    size_t *image_samples;
    /* Relit comparisons: measured and relit images (width * height * channels each, in the
     * stack's linear values) for a few lights spread over the stack. */
    int nrelit;
    int relit_index[BF_PHOTO_MAX_RELIT];
    float *relit_measured[BF_PHOTO_MAX_RELIT], *relit_model[BF_PHOTO_MAX_RELIT];
    size_t iterations; /* of the per-pixel solves, all together */
    size_t restarted;  /* pixels solved again from a row neighbour's solution */
    int threads;
    double seconds;
    int cancelled; /* 1: o->cancel stopped the run; nothing is to be written */
} bf_photo_result;

/* Fits o->model to every pixel of the stack (of the tile). A run stopped by o->cancel
 * returns BF_OK with r->cancelled set (bf_photo_write refuses it). */
BF_API bf_status bf_photo_fit(const bf_stack *s, const bf_photo_options *o, bf_photo_result **out, bf_error *err);
BF_API void bf_photo_result_free(bf_photo_result *r);

/* Writes the outputs (docs/images.md) into the folder dir, whole or not at all: an
 * existing dir is replaced only when it is empty or holds a previous run's outputs.
 * command_line (may be NULL) is recorded in fit.json. */
BF_API bf_status bf_photo_write(const bf_photo_result *r, const bf_stack *s, const bf_photo_options *o, const char *dir,
                                const char *command_line, bf_error *err);
/* The text bf_photo_write puts in fit.json (docs/images.md: the model, the stack, the
 * options, counts, relit errors, shared values, the files it writes, timing), in memory:
 * *out, freed with bf_free. */
BF_API bf_status bf_photo_result_json(const bf_photo_result *r, const bf_stack *s, const bf_photo_options *o,
                                      const char *command_line, char **out, bf_error *err);
/* The outputs of the `--tile I/N` runs of one stack (the folders of tiles 1..N, in any
 * order) merged into the outputs of the whole image in dir, as one run would have
 * written them (the tiles start alike: photo.h's fits of a tile depend on its rows only
 * through the pixels in them). */
BF_API bf_status bf_photo_merge(const char *const *dirs, int n, const char *dir, const char *command_line,
                                bf_error *err);

/* Whether dir could be written (before a long fit). */
BF_API bf_status bf_photo_check_output(const char *dir, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
