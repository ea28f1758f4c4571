/* A fitted material as a renderer's file: glTF 2.0, a Blender 3.4 script, a Mitsuba 3
 * scene (docs/export.md). A result in the target's native model (gltf,
 * blender_principled, mitsuba_principled) maps exactly; any other is converted by
 * fitting the native model to the source's values over a fixed grid of direction pairs,
 * and the conversion's error goes into the file. `brdfit export` is this and a command
 * line. Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_EXPORT_H
#define BRDFIT_EXPORT_H

#include <stddef.h>
#include <stdio.h>

#include "brdfit/error.h"
#include "brdfit/fit.h"
#include "brdfit/metrics.h"
#include "brdfit/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A material in a target's native model. Callers set it up with
 * bf_export_material_init; bf_export_prepare fills what lies within its size
 * (docs/api.md). */
typedef struct bf_export_material {
    size_t size;           /* sizeof, set by bf_export_material_init */
    const bf_model *model; /* the target's native model, 1 or 3 channels (not owned) */
    const double *x;       /* its parameters (not owned) */
    const char *source;    /* the source's model spec (not owned) */
    int converted;         /* 0: the source itself; 1: fitted to the source's values */
    size_t directions;     /* conversion: the direction pairs fitted */
    bf_metrics metrics;    /* conversion: the fit's metrics (the source's values as data) */
} bf_export_material;

/* An empty material (no model) with its size set. */
BF_API void bf_export_material_init_size(bf_export_material *e, size_t size);
static inline void bf_export_material_init(bf_export_material *e)
{
    bf_export_material_init_size(e, sizeof *e);
}

/* The direction pairs a conversion fits: theta_i and theta_o 2.5 .. 87.5 by 5 degrees,
 * phi_o 0 .. 350 by 10, and for an anisotropic source phi_i 0 .. 150 by 30. */
#define BF_EXPORT_PAIRS_ISOTROPIC 11664

/* The library's table (bf_export_target_get): read through the pointer (docs/api.md). */
typedef struct bf_export_target {
    const char *name;    /* "gltf", "blender", "mitsuba" (brdfit export --to) */
    const char *model;   /* its native model family */
    const char *summary; /* what the file is, one line */
    /* Writes e (in this target's model) to fp: BF_OK, or an error (out of memory). */
    bf_status (*write)(const bf_export_material *e, FILE *fp, bf_error *err);
} bf_export_target;

/* The targets, in a fixed order; by name (NULL: none of that name). */
BF_API int bf_export_target_count(void);
BF_API const bf_export_target *bf_export_target_get(int i);
BF_API const bf_export_target *bf_export_target_find(const char *name);

/* Whether source model src can go to target t: BF_OK, or BF_ERR_ARG with why (colours of
 * other than 1 or 3 channels; an anisotropic or multi-lobe source unless convert_any: the
 * targets hold one isotropic lobe). */
BF_API bf_status bf_export_check(const bf_export_target *t, const bf_model *src, int convert_any, bf_error *err);

/* Puts (src, xs) into t's native model as *e (set up by bf_export_material_init): the
 * source itself when its family is t->model, else a conversion fit of t->model to src's
 * values (seeded, so the same bytes each time), whose result goes into *fit (set up by
 * bf_fit_result_init; clear it with bf_fit_result_clear once *e is no longer used; it is
 * cleared here on an error).
 * Check first with bf_export_check. */
BF_API bf_status bf_export_prepare(const bf_export_target *t, const bf_model *src, const double *xs,
                                   bf_export_material *e, bf_fit_result *fit, bf_error *err);

/* "conversion over N direction pairs: rmse ..., max_err ... (1/sr)" to fp (no newline). */
BF_API void bf_export_conversion_note(const bf_export_material *e, FILE *fp);

/* Writes e with t's writer to path ("-": standard output), atomically (brdfit/io.h's
 * bf_outfile: a failed write leaves no file). */
BF_API bf_status bf_export_write(const bf_export_target *t, const bf_export_material *e, const char *path,
                                 bf_error *err);
/* The file's text, into *out (freed with bf_free): what bf_export_write writes. */
BF_API bf_status bf_export_text(const bf_export_target *t, const bf_export_material *e, char **out, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
