/* A scene: the light and view directions a renderer will actually use. Fitting and
 * selecting models for a scene restricts (and weights) the samples to those directions,
 * so that error is spent, and reported, where the scene can see it.
 *
 * JSON (every key optional; angles in degrees; see docs/scenes.md):
 *   {
 *     "description": "product shot: camera within 60 degrees, lights from above",
 *     "light": {"theta": [0, 45]},          range of incidence angles (default [0, 90])
 *     "view":  {"theta": [0, 60]},          range of view angles (default [0, 90])
 *     "lights": [{"theta": 30, "phi": 0, "weight": 2}, ...],   explicit directions
 *     "views":  [{"theta": 0, "phi": 0, "weight": 1}, ...],
 *     "radius": 5,                          kernel width for explicit directions
 *     "reciprocal": true                    a sample also counts with light and view swapped
 *   }
 * A sample (L, V) gets weight
 *   w = in_ranges(L, V) * Kl(L) * Kv(V)      (explicit lists absent: that factor is 1)
 * where Kl(L) = sum over lights of weight * exp(-a^2 / (2 radius^2)), a the angle between
 * L and the light direction (0 beyond 3 radius), and the same for views. Explicit
 * directions are compared after rotating each configuration about the normal so that its
 * light has azimuth 0 and folding the view's relative azimuth into [0, 180] degrees
 * (isotropic materials: only |phi_o - phi_i| matters, and measured sets often hold one
 * sign of it only, as MERL's phi_d does); sample and scene alike. So with both lists the product is taken per (light, view) pair, each pair
 * rotated by its own light's azimuth, and summed over pairs:
 *   Kl Kv = sum_(l,v) w_l w_v exp(-(a_L^2 + a_V^2) / (2 radius^2))
 * With one list only, a direction's azimuth has no meaning after the rotation: only its
 * polar angle counts. in_ranges bounds are inclusive. With "reciprocal",
 * w = max(w(L, V), w(V, L)).
 * Status codes and ownership follow brdfit/error.h.
 */
#ifndef BRDFIT_SCENE_H
#define BRDFIT_SCENE_H

#include <stddef.h>

#include "brdfit/error.h"
#include "brdfit/prep.h"
#include "brdfit/samples.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Frozen (docs/api.md): an array element of bf_scene. */
typedef struct bf_scene_dir {
    double theta, phi; /* degrees */
    double weight;     /* > 0 */
} bf_scene_dir;

typedef struct bf_scene {
    char *description;    /* NULL if none (owned) */
    bf_range light_theta; /* degrees, within [0, 90] */
    bf_range view_theta;
    bf_scene_dir *lights; /* nlights entries (owned), may be 0 */
    bf_scene_dir *views;
    int nlights, nviews;
    double radius;  /* degrees, > 0 (default 5) */
    int reciprocal; /* default 1 */
} bf_scene;

/* Reads a scene file; errors name the file, the line and the problem (unknown key,
 * wrong type, angle out of range, lo > hi, weight <= 0, radius <= 0). */
BF_API bf_status bf_scene_read(const char *path, bf_scene **out, bf_error *err);
/* The same from text in memory (path names it in messages). */
BF_API bf_status bf_scene_parse(const char *text, const char *path, bf_scene **out, bf_error *err);
BF_API void bf_scene_free(bf_scene *sc);

/* w[i] >= 0 for each of s's n samples, as above (0: outside the scene). */
BF_API bf_status bf_scene_weights(const bf_scene *sc, bf_samples *s, double *w, bf_error *err);

/* Restricts s in place to the scene: drops samples of weight 0 and gives the rest their
 * scene weight in s->scene_weight (kept apart from the data's own weights), scaled so
 * that it averages 1 over the kept samples. When every kept sample has the same scene
 * weight (a ranges-only scene) no scene weights are added: the scene only selects.
 * kept (may be NULL) gets the count. BF_ERR_ARG when no sample lies in the scene; s is
 * then unchanged. */
BF_API bf_status bf_scene_apply(const bf_scene *sc, bf_samples *s, size_t *kept, bf_error *err);

#ifdef __cplusplus
}
#endif
#endif
