/* Internal: what the export writers share (gltf.c, blender.c, mitsuba.c; targets.c has the
 * targets and the write; the conversion is lib/src/study/export/convert.c). The material is always in the target's native model with
 * 1 or 3 channels; each writer maps it to the renderer's file. */
#ifndef BF_EXPORT_IMPL_H
#define BF_EXPORT_IMPL_H

#include <stdio.h>

#include "brdfit/export.h"

/* Channel c (0..2) of the named parameter: a scalar's value, a colour's channel c (its
 * only channel when the model has one). The name must be the model's. */
double bf_export_param(const bf_export_material *e, const char *name, int c);

/* The glTF 2.0 document (a sphere carrying the material), the Blender Python script
 * (material and preview scene) and the Mitsuba 3 scene XML, to fp. */
bf_status bf_export_write_gltf(const bf_export_material *e, FILE *fp, bf_error *err);
bf_status bf_export_write_blender(const bf_export_material *e, FILE *fp, bf_error *err);
bf_status bf_export_write_mitsuba(const bf_export_material *e, FILE *fp, bf_error *err);

#endif
