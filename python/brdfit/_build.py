"""cffi in API mode over libbrdfit: the declarations below are a subset of the public
headers (brdfit/*.h), and the C compiler checks them against the real ones when the
extension is built, so a header change that breaks them fails the build rather than
corrupting memory. Structs are declared with "...;": only the fields Python touches are
named, and the compiler supplies the layout.

Where the library is: BRDFIT_INCLUDE_DIRS and BRDFIT_LIBRARY_DIRS (os.pathsep-separated;
the CMake target sets them to the build tree), else BRDFIT_PREFIX (an install prefix),
else pkg-config's brdfit. The extension links the shared library with its folder as the
run path, so it finds the same library at run time.
"""
import os
import shlex
import subprocess

from cffi import FFI

CDEF = r"""
typedef enum bf_status { BF_OK = 0, BF_ERR_ARG, BF_ERR_IO, BF_ERR_PARSE, BF_ERR_RANGE, BF_ERR_NOMEM } bf_status;
typedef struct bf_error { bf_status code; char msg[512]; } bf_error;
const char *bf_version(void);
void free(void *);

/* Models (model.h). */
typedef struct bf_geometry bf_geometry;
typedef struct bf_model bf_model;
typedef enum bf_scale { BF_SCALE_LINEAR, BF_SCALE_LOG, BF_SCALE_LOG1P, ... } bf_scale;
typedef struct bf_param_info { const char *name; int colour; double lo, hi, def; ...; } bf_param_info;
char *bf_models_json(void);
bf_status bf_model_new(const char *spec, int channels, bf_model **out, bf_error *err);
void bf_model_free(bf_model *m);
const char *bf_model_spec(const bf_model *m);
const char *bf_model_name(const bf_model *m);
int bf_model_channels(const bf_model *m);
int bf_model_nparams(const bf_model *m);
int bf_model_find_param(const bf_model *m, const char *name);
const bf_param_info *bf_model_param(const bf_model *m, int i);
int bf_model_param_offset(const bf_model *m, int i);
int bf_model_nvalues(const bf_model *m);
const char *bf_model_entry_name(const bf_model *m, int k, char *buf, size_t size);
void bf_model_defaults(const bf_model *m, double *x);
bf_status bf_model_check(const bf_model *m, const double *x, bf_error *err);
void bf_model_eval(const bf_model *m, const double *x, const bf_geometry *g, double *values, double *grad);

/* Geometry (geometry.h). */
bf_status bf_geometry_from_vectors(size_t n, const double *L, const double *V, bf_geometry **out, bf_error *err);
void bf_geometry_free(bf_geometry *g);

/* Samples (samples.h, formats.h, prep.h, scene.h). */
typedef struct bf_samples {
    size_t n; int channels; char **channel_names; double *wavelength;
    double *theta_i, *phi_i, *theta_o, *phi_o; double *value; double *weight; double *scene_weight; ...;
} bf_samples;
bf_status bf_samples_new(size_t n, int channels, bf_samples **out, bf_error *err);
void bf_samples_free(bf_samples *s);
bf_status bf_samples_set_channel_name(bf_samples *s, int c, const char *name, bf_error *err);
bf_status bf_samples_add_weights(bf_samples *s, bf_error *err);
void bf_samples_angle_block(const bf_samples *s, size_t i0, size_t cnt, double *buf, const double *dir[4]);
bf_status bf_samples_geometry(bf_samples *s, const bf_geometry **out, bf_error *err);
bf_status bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_samples **out, bf_error *err);

typedef enum bf_format { BF_FORMAT_AUTO = 0, ... } bf_format;
typedef struct bf_csv_map { const char *angle_cols[4]; int radians; const char *channels; const char *weight_col; ...; } bf_csv_map;
typedef struct bf_read_options { bf_format format; bf_csv_map csv; const char *grid; ...; } bf_read_options;
bf_status bf_samples_read(const char *path, const bf_read_options *opt, bf_samples **out, bf_error *err);
int bf_format_from_name(const char *name);

typedef enum bf_color { BF_COLOR_NONE = 0, BF_COLOR_SRGB, ... } bf_color;
typedef enum bf_illuminant { BF_ILLUMINANT_D65 = 0, ... } bf_illuminant;
typedef enum bf_negative { BF_NEGATIVE_KEEP = 0, BF_NEGATIVE_DROP, BF_NEGATIVE_CLAMP } bf_negative;
int bf_color_from_name(const char *name);
int bf_illuminant_from_name(const char *name);
typedef struct bf_prep {
    const char *channels; int to_bands; bf_color color; bf_illuminant illuminant; int to_luminance;
    double max_theta; bf_negative negative; size_t subsample; uint64_t seed; ...;
} bf_prep;
typedef struct bf_prep_report { size_t read, kept; ...; } bf_prep_report;
bf_status bf_samples_prep(bf_samples *s, const bf_prep *p, bf_prep_report *report, bf_error *err);

typedef struct bf_scene bf_scene;
bf_status bf_scene_read(const char *path, bf_scene **out, bf_error *err);
void bf_scene_free(bf_scene *sc);
bf_status bf_scene_apply(const bf_scene *sc, bf_samples *s, size_t *kept, bf_error *err);

/* Fitting (objective.h, solve.h, fit.h). */
typedef enum bf_residual { BF_RESIDUAL_LINEAR = 0, ... } bf_residual;
typedef struct bf_override { ...; } bf_override;
bf_status bf_residual_parse(const char *name, bf_residual *out, bf_error *err);
const char *bf_residual_name(bf_residual r);
bf_status bf_override_parse_fix(const char *text, bf_override *out, bf_error *err);
bf_status bf_override_parse_bound(const char *text, bf_override *out, bf_error *err);
bf_status bf_overrides_check(const bf_model *m, int channels, const bf_override *ov, int n, bf_error *err);
typedef struct bf_objective_options {
    bf_residual residual; int solid_angle; int use_weights; const bf_override *overrides; int noverrides; ...;
} bf_objective_options;
typedef enum bf_loss_kind { BF_LOSS_NONE = 0, ... } bf_loss_kind;
typedef struct bf_loss { bf_loss_kind kind; ...; } bf_loss;
bf_status bf_loss_parse(const char *text, bf_loss *out, bf_error *err);
typedef enum bf_backend { BF_BACKEND_CERES = 0, BF_BACKEND_NLOPT } bf_backend;
bf_status bf_backend_parse(const char *text, bf_backend *out, bf_error *err);
typedef int (*bf_progress_fn)(void *user, int iteration, double cost);
typedef struct bf_solver_options {
    bf_backend backend; const char *algorithm; const char *local_algorithm; int max_iterations;
    bf_loss loss; int threads; int use_constraint; bf_progress_fn progress; void *progress_user;
    const volatile int *cancel; ...;
} bf_solver_options;
bf_status bf_solver_options_check(const bf_solver_options *o, bf_error *err);
typedef enum bf_stop { BF_STOP_CONVERGED = 0, BF_STOP_ITERATIONS, BF_STOP_TIME, BF_STOP_CANCELLED, BF_STOP_FAILED } bf_stop;
typedef struct bf_solution { bf_stop stop; ...; } bf_solution;
typedef enum bf_fit_accuracy { BF_ACCURACY_NONE = 0, ... } bf_fit_accuracy;
typedef struct bf_fit_options {
    bf_objective_options objective; bf_solver_options solver; int starts; int screen; uint64_t seed;
    long presolve; ...;
} bf_fit_options;
typedef struct bf_fit_result { bf_model *model; double *x; bf_solution solution; int ok; ...; } bf_fit_result;
void bf_fit_options_init(bf_fit_options *o);
bf_status bf_fit_accuracy_parse(const char *name, bf_fit_accuracy *out, bf_error *err);
void bf_fit_options_apply_accuracy(bf_fit_options *o, bf_fit_accuracy acc, unsigned given, size_t *subsample);
enum { BF_FIT_GIVEN_BACKEND, BF_FIT_GIVEN_ALGORITHM, BF_FIT_GIVEN_STARTS, BF_FIT_GIVEN_RESIDUAL,
       BF_FIT_GIVEN_MAX_ITERATIONS, BF_FIT_GIVEN_SUBSAMPLE, BF_FIT_GIVEN_SCREEN, ... };
bf_status bf_fit(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r, bf_error *err);
void bf_fit_result_clear(bf_fit_result *r);
bf_status bf_fit_write_json(const bf_fit_result *r, const char *data_path, const char *out_path, bf_error *err);
bf_status bf_params_read(const char *path, bf_model **model, double **x, bf_error *err);

/* Comparison (compare.h). */
typedef enum bf_compare_metric { BF_CMP_RMSE, BF_CMP_RMSE_LOG, ... } bf_compare_metric;
typedef enum bf_compare_rank_by { BF_RANK_BIC, BF_RANK_CV, ... } bf_compare_rank_by;
typedef struct bf_compare {
    bf_compare_metric metric; bf_compare_rank_by rank_by; int folds; double tolerance; int timing;
    const char *residual; ...;
} bf_compare;
typedef struct bf_compare_run_options { int jobs; ...; } bf_compare_run_options;
bf_status bf_compare_metric_parse(const char *text, bf_compare_metric *out, bf_error *err);
bf_status bf_compare_rank_parse(const char *text, bf_compare_rank_by *out, bf_error *err);
bf_status bf_compare_init(bf_compare *c, int nmaterials, const char *const *data, int nmodels,
                          const char *const *models, bf_error *err);
void bf_compare_clear(bf_compare *c);
bf_status bf_compare_run(bf_compare *c, bf_samples *const *samples, const bf_fit_options *fo,
                         const bf_compare_run_options *ro, bf_error *err);
void bf_compare_rank(bf_compare *c);
bf_status bf_compare_write_json(const bf_compare *c, const char *path, bf_error *err);

/* Export (export.h). */
typedef struct bf_export_target { const char *name; const char *model; ...; } bf_export_target;
typedef struct bf_export_material { int converted; ...; } bf_export_material;
const bf_export_target *bf_export_target_find(const char *name);
bf_status bf_export_check(const bf_export_target *t, const bf_model *src, int convert_any, bf_error *err);
bf_status bf_export_prepare(const bf_export_target *t, const bf_model *src, const double *xs, bf_export_material *e,
                            bf_fit_result *fit, bf_error *err);
bf_status bf_export_write(const bf_export_target *t, const bf_export_material *e, const char *path, bf_error *err);

/* The progress callback, into Python (_progress in brdfit/_core.py). */
extern "Python" int _brdfit_progress(void *user, int iteration, double cost);
"""

SOURCE = r"""
#include <stdlib.h>
#include "brdfit/compare.h"
#include "brdfit/export.h"
#include "brdfit/fit.h"
#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/model.h"
#include "brdfit/prep.h"
#include "brdfit/scene.h"
#include "brdfit/version.h"
"""


def _split(var):
    return [p for p in os.environ.get(var, "").split(os.pathsep) if p]


def _where():
    """The include and library folders of libbrdfit (see the module's docstring)."""
    inc, lib = _split("BRDFIT_INCLUDE_DIRS"), _split("BRDFIT_LIBRARY_DIRS")
    if inc and lib:
        return inc, lib
    prefix = os.environ.get("BRDFIT_PREFIX")
    if prefix:
        libdirs = [os.path.join(prefix, d) for d in ("lib", "lib64", "lib/x86_64-linux-gnu", "lib/aarch64-linux-gnu")]
        return [os.path.join(prefix, "include")], [d for d in libdirs if os.path.isdir(d)]
    try:
        cflags = subprocess.run(["pkg-config", "--cflags-only-I", "brdfit"], check=True, capture_output=True,
                                text=True).stdout
        libs = subprocess.run(["pkg-config", "--libs-only-L", "brdfit"], check=True, capture_output=True,
                              text=True).stdout
    except (OSError, subprocess.CalledProcessError) as e:
        raise SystemExit("brdfit: libbrdfit not found: set BRDFIT_PREFIX to its install prefix, or install "
                         "libbrdfit-dev (pkg-config brdfit): %s" % e)
    inc = [w[2:] for w in shlex.split(cflags) if w.startswith("-I")]
    lib = [w[2:] for w in shlex.split(libs) if w.startswith("-L")]
    return inc, lib or ["/usr/lib/x86_64-linux-gnu"]


ffibuilder = FFI()
ffibuilder.cdef(CDEF)
_inc, _lib = _where()
ffibuilder.set_source("brdfit._brdfit", SOURCE, libraries=["brdfit"], include_dirs=_inc, library_dirs=_lib,
                      runtime_library_dirs=_lib, extra_compile_args=["-std=c11"])

if __name__ == "__main__":
    ffibuilder.compile(verbose=False)
