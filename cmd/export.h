/* brdfit export: what the target writers share. The material is always in the target's
 * native model (gltf, blender_principled, mitsuba_principled) with 1 or 3 channels; export.c gets it there,
 * exactly or by a conversion fit, and each writer maps it to the renderer's file. */
#ifndef BRDFIT_EXPORT_H
#define BRDFIT_EXPORT_H

#include <stdio.h>

#include "brdfit/metrics.h"
#include "brdfit/model.h"

typedef struct export_material {
    const bf_model *m;       /* the target's native model */
    const double *x;         /* its parameters */
    const char *source;      /* the result file's model spec */
    int converted;           /* 0: exact mapping; 1: fitted to the source's values */
    size_t directions;       /* conversion: direction pairs fitted */
    bf_metrics metrics;      /* conversion: the fit's metrics (source values as data) */
} export_material;

/* Channel c (0..2) of the named parameter: a scalar's value, a colour's channel c (its
 * only channel when the model has one). The name must be the model's. */
double export_param(const export_material *e, const char *name, int c);

/* "Conversion over N direction pairs: rmse ..., max_err ..." (no newline), as export
 * reports it and the script and XML writers repeat it. */
void export_conversion_note(const export_material *e, FILE *fp);

/* The glTF 2.0 document (a sphere carrying the material), the Blender Python script
 * (material and preview scene) and the Mitsuba 3 scene XML to fp. glTF returns 0, or -1 out of memory. */
int export_write_gltf(const export_material *e, FILE *fp);
void export_write_blender(const export_material *e, FILE *fp);
void export_write_mitsuba(const export_material *e, FILE *fp);

#endif
