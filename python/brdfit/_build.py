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
from typing import List, Tuple

from cffi import FFI

CDEF = r"""
typedef enum bf_status { BF_OK = 0, BF_ERR_ARG, BF_ERR_IO, BF_ERR_PARSE, BF_ERR_RANGE, BF_ERR_NOMEM,
                         BF_ERR_CANCELLED } bf_status;
typedef struct bf_error { bf_status code; char msg[512]; } bf_error;
const char *bf_version(void);
const char *bf_status_name(bf_status code);
void bf_free(void *p);

/* Models (model.h). */
typedef struct bf_geometry bf_geometry;
typedef struct bf_model bf_model;
typedef enum bf_scale { BF_SCALE_LINEAR, BF_SCALE_LOG, BF_SCALE_LOG1P, ... } bf_scale;
typedef struct bf_param_info { const char *name; int color; double lo, hi, def; ...; } bf_param_info;
char *bf_models_json(void);
bf_status bf_model_list_split(const char *list, char ***specs, int *n, bf_error *err);
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
void bf_model_eval_range(const bf_model *m, const double *x, const bf_geometry *g, size_t i0, size_t i1,
                         double *values, double *grad);

/* Geometry (geometry.h). */
bf_status bf_geometry_from_vectors(size_t n, const double *L, const double *V, bf_geometry **out, bf_error *err);
void bf_geometry_free(bf_geometry *g);

/* Samples (samples.h, merl.h). */
#define BF_MERL_CELLS ...
typedef struct bf_merl_origin { int32_t *cell; ...; } bf_merl_origin;
typedef struct bf_samples {
    size_t n; int channels; char **channel_names; double *wavelength;
    double *theta_i, *phi_i, *theta_o, *phi_o; double *value; double *weight; double *scene_weight;
    bf_merl_origin *merl; ...;
} bf_samples;
bf_status bf_samples_new(size_t n, int channels, bf_samples **out, bf_error *err);
bf_status bf_samples_new_cells(size_t n, int channels, bf_samples **out, bf_error *err);
bf_status bf_samples_set_channel_name(bf_samples *s, int c, const char *name, bf_error *err);
void bf_samples_free(bf_samples *s);
bf_status bf_samples_add_weights(bf_samples *s, bf_error *err);
void bf_samples_angle_block(const bf_samples *s, size_t i0, size_t cnt, double *buf, const double *dir[4]);
bf_status bf_samples_geometry(bf_samples *s, const bf_geometry **out, bf_error *err);
bf_status bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_samples **out, bf_error *err);

/* Writing data files (formats.h). */
typedef enum bf_format { BF_FORMAT_AUTO = 0, ... } bf_format;
bf_status bf_format_parse(const char *name, bf_format *out, bf_error *err);
bf_status bf_samples_write(const bf_samples *s, const char *path, bf_format f, bf_error *err);

/* Run options (options.h): the table and a set of values. */
typedef enum bf_task { BF_TASK_READ = 1, BF_TASK_FIT = 2, BF_TASK_COMPARE = 4, BF_TASK_SELECT = 8,
                       BF_TASK_TRADEOFF = 16 } bf_task;
typedef enum bf_option_type { BF_OPTION_FLAG = 0, BF_OPTION_INT, BF_OPTION_NUMBER, BF_OPTION_TEXT, BF_OPTION_CHOICE,
                              BF_OPTION_LIST, ... } bf_option_type;
typedef struct bf_option {
    const char *name; const char *group; unsigned tasks; bf_option_type type; const char *arg; const char *help;
    const char *complete; const char *choices; const char *def; double lo, hi; const char *range; ...;
} bf_option;
int bf_option_count(void);
const bf_option *bf_option_get(int i);
const bf_option *bf_option_find(const char *name, unsigned task);
typedef struct bf_options bf_options;
typedef enum bf_option_spelling { BF_SPELL_COMMAND_LINE = 0, BF_SPELL_KEYWORD } bf_option_spelling;
bf_status bf_options_new(bf_task task, bf_options **out, bf_error *err);
void bf_options_free(bf_options *o);
void bf_options_set_spelling(bf_options *o, bf_option_spelling spelling);
bf_status bf_options_set(bf_options *o, const char *name, const char *value, bf_error *err);
bf_status bf_options_get(const bf_options *o, const char *name, char *buf, size_t size, bf_error *err);
bf_status bf_options_check(const bf_options *o, bf_error *err);
bf_status bf_options_check_models(const bf_options *o, const char *const *specs, int n, bf_error *err);
typedef int... sig_atomic_t;
typedef sig_atomic_t bf_cancel_flag;
void bf_options_set_cancel(bf_options *o, const bf_cancel_flag *cancel, const bf_cancel_flag *finish);
typedef enum bf_fit_phase { BF_PHASE_CANDIDATES = 0, BF_PHASE_SCREEN, BF_PHASE_PRESOLVE, BF_PHASE_DATA,
                            BF_PHASE_DONE } bf_fit_phase;
const char *bf_fit_phase_name(bf_fit_phase phase);
typedef struct bf_progress_report {
    size_t size; bf_fit_phase phase; int start; int starts; int iteration; double cost; size_t samples;
    const char *spec; int material; int model; int fold; ...;
} bf_progress_report;
typedef int (*bf_progress_report_fn)(void *user, const bf_progress_report *report);
void bf_options_set_progress_report(bf_options *o, bf_progress_report_fn progress, void *user);
bf_status bf_options_set_start(bf_options *o, const double *x, int n, bf_error *err);

/* Loading (load.h). */
typedef struct bf_load_report {
    size_t size; size_t read; int channels_read; size_t below_horizon, nonfinite, negative, above_max_theta;
    int scene; size_t scene_in, scene_kept, subsampled_out; size_t kept; ...;
} bf_load_report;
void bf_load_report_init(bf_load_report *r);
bf_status bf_samples_load(const char *path, const bf_options *o, bf_samples **out, bf_load_report *report,
                          bf_error *err);
bf_status bf_samples_prepare(bf_samples *s, const bf_options *o, bf_load_report *report, bf_error *err);

/* Fitting (solve.h, fit.h). */
typedef enum bf_stop { BF_STOP_CONVERGED = 0, BF_STOP_ITERATIONS, BF_STOP_TIME, BF_STOP_CANCELLED, BF_STOP_FAILED } bf_stop;
typedef struct bf_solution { bf_stop stop; ...; } bf_solution;
typedef struct bf_fit_result { size_t size; bf_model *model; double *x; bf_solution solution; int ok; double *covariance; ...; }
    bf_fit_result;
void bf_fit_result_init(bf_fit_result *r);
bf_status bf_fit(bf_samples *s, const char *spec, const bf_options *o, bf_fit_result *r, bf_error *err);
void bf_fit_result_clear(bf_fit_result *r);
bf_status bf_fit_result_json(const bf_fit_result *r, const char *data_path, char **out, bf_error *err);
bf_status bf_params_read(const char *path, bf_model **model, double **x, bf_error *err);
bf_status bf_params_parse(const char *text, const char *name, bf_model **model, double **x, bf_error *err);

/* The objective (objective.h, solve.h): a fit's residuals, in the form it was fitted in. */
typedef enum bf_residual { BF_RESIDUAL_LINEAR = 0, ... } bf_residual;
bf_status bf_residual_parse(const char *name, bf_residual *out, bf_error *err);
typedef struct bf_objective_options { size_t size; bf_residual residual; int solid_angle; int use_weights; ...; }
    bf_objective_options;
void bf_objective_options_init(bf_objective_options *o);
typedef struct bf_problem {
    size_t nres; int (*eval)(void *user, const double *x, size_t r0, size_t r1, double *res, double *jac);
    void *user; ...;
} bf_problem;
typedef struct bf_objective bf_objective;
bf_status bf_objective_new(const bf_model *m, bf_samples *s, const bf_objective_options *o, bf_objective **out,
                           bf_error *err);
void bf_objective_free(bf_objective *obj);
const bf_problem *bf_objective_problem(const bf_objective *obj);
int bf_objective_nz(const bf_objective *obj);
void bf_objective_to_internal(const bf_objective *obj, const double *x, double *z);

/* Comparison (compare.h). */
typedef struct bf_compare { int nmaterials, nmodels; int interrupted; ...; } bf_compare;
typedef void (*bf_compare_progress)(void *user, const bf_compare *c, int material, int model, int done, int total);
bf_status bf_compare_new(int nmaterials, const char *const *data, int nmodels, const char *const *models,
                         bf_compare **out, bf_error *err);
void bf_compare_free(bf_compare *c);
bf_status bf_compare_run(bf_compare *c, bf_samples *const *samples, const bf_options *o, bf_compare_progress progress,
                         void *user, bf_error *err);
void bf_compare_rank(bf_compare *c);
bf_status bf_compare_json(const bf_compare *c, char **out, bf_error *err);

/* Selection (select.h). */
typedef struct bf_select_candidate { char spec[160]; bf_fit_result *result; ...; } bf_select_candidate;
typedef struct bf_select { int n; bf_select_candidate *c; int best, chosen; ...; } bf_select;
typedef void (*bf_select_progress)(void *user, const bf_select *s, int i, int done);
int bf_select_default_candidates(int channels, const char ***specs);
bf_status bf_select_new(int n, const char *const *specs, int channels, const bf_options *o, bf_select **out,
                        bf_error *err);
void bf_select_free(bf_select *s);
bf_status bf_select_run(bf_select *s, bf_samples *data, const bf_options *o, bf_select_progress progress, void *user,
                        bf_error *err);
bf_status bf_select_json(const bf_select *s, const char *data, char **out, bf_error *err);

/* Cost against accuracy (tradeoff.h, render.h). */
typedef enum bf_plot_format { BF_PLOT_BY_NAME = 0, BF_PLOT_PNG = 1, BF_PLOT_SVG, BF_PLOT_PDF } bf_plot_format;
typedef struct bf_plot_axes { size_t size; ...; } bf_plot_axes;
typedef struct bf_tradeoff { int nrows; int best, recommended; int plot_width, plot_height; ...; } bf_tradeoff;
typedef void (*bf_tradeoff_progress)(void *user, const bf_tradeoff *t, int i);
bf_status bf_tradeoff_run(const bf_samples *data, const char *name, const char *model, const bf_options *o,
                          bf_tradeoff_progress progress, void *user, bf_tradeoff **out, bf_error *err);
void bf_tradeoff_free(bf_tradeoff *t);
bf_status bf_tradeoff_json(const bf_tradeoff *t, char **out, bf_error *err);
bf_status bf_tradeoff_fit_command(const bf_tradeoff *t, int i, char **out, bf_error *err);
bf_status bf_tradeoff_write_plot(const bf_tradeoff *t, const char *path, int format, int width, int height,
                                 bf_plot_axes *axes, bf_error *err);

/* Export (export.h). */
typedef struct bf_export_target { const char *name; const char *model; ...; } bf_export_target;
typedef struct bf_export_material { size_t size; int converted; ...; } bf_export_material;
void bf_export_material_init(bf_export_material *e);
int bf_export_target_count(void);
const bf_export_target *bf_export_target_get(int i);
const bf_export_target *bf_export_target_find(const char *name);
bf_status bf_export_check(const bf_export_target *t, const bf_model *src, int convert_any, bf_error *err);
bf_status bf_export_prepare(const bf_export_target *t, const bf_model *src, const double *xs, bf_export_material *e,
                            bf_fit_result *fit, bf_error *err);
bf_status bf_export_write(const bf_export_target *t, const bf_export_material *e, const char *path, bf_error *err);
bf_status bf_export_text(const bf_export_target *t, const bf_export_material *e, char **out, bf_error *err);

/* Front ends: brdfit info, render, fit-images and many files (_info.py, _render.py,
   _photo.py, _folders.py). */
bf_format bf_format_by_extension(const char *path);
typedef struct bf_range { double lo, hi; } bf_range;
typedef struct bf_samples_info {
    size_t size; size_t n; int channels; bf_range theta_i, theta_o, theta_h, theta_d;
    size_t below_horizon, nonfinite, negative, zero; bf_range *value; double *mean; int weighted; ...;
} bf_samples_info;
void bf_samples_info_init(bf_samples_info *info);
bf_status bf_samples_describe(bf_samples *s, bf_samples_info *info, bf_error *err);
void bf_samples_info_clear(bf_samples_info *info);
bf_status bf_samples_info_json(bf_samples *s, const bf_load_report *report, const bf_options *o,
                               const char *path, char **out, bf_error *err);
bf_status bf_samples_info_text(bf_samples *s, const bf_load_report *report, const bf_options *o,
                               const char *path, char **out, bf_error *err);
typedef struct bf_dir { double theta, phi; } bf_dir;
typedef struct bf_sphere_options { size_t size; int resolution; bf_dir view; const bf_dir *lights; int nlights; ...; }
    bf_sphere_options;
void bf_sphere_options_init(bf_sphere_options *o);
bf_status bf_sphere_options_check(const bf_sphere_options *o, bf_error *err);
bf_status bf_render_memory_check(int width, int height, bf_error *err);
typedef enum bf_tonemap_mode { BF_TONEMAP_CLAMP = 0, BF_TONEMAP_REINHARD, BF_TONEMAP_LOG } bf_tonemap_mode;
bf_status bf_tonemap_parse(const char *name, bf_tonemap_mode *out, bf_error *err);
typedef struct bf_tonemap_options { size_t size; bf_tonemap_mode mode; double exposure; double decades; ...; }
    bf_tonemap_options;
void bf_tonemap_options_init(bf_tonemap_options *o);
bf_status bf_tonemap_options_check(const bf_tonemap_options *o, bf_error *err);
bf_status bf_tonemap_apply(float *v, size_t n, const bf_tonemap_options *o, bf_error *err);
typedef struct bf_halfdiff_options { size_t size; int width, height; double phi_d; bf_tonemap_mode tonemap; ...; }
    bf_halfdiff_options;
void bf_halfdiff_options_init(bf_halfdiff_options *o);
bf_status bf_halfdiff_options_check(const bf_halfdiff_options *o, bf_error *err);
bf_status bf_render_sphere(const bf_model *m, const double *x, const bf_sphere_options *o, float *rgb, bf_error *err);
bf_status bf_render_sphere_merl(const bf_samples *merl, const bf_sphere_options *o, float *rgb, bf_error *err);
bf_status bf_render_halfdiff_model(const bf_model *m, const double *x, int width, int height, double phi_d,
                                   float *rgb, bf_error *err);
bf_status bf_render_halfdiff_merl(const bf_samples *merl, int width, int height, double phi_d, float *rgb,
                                  bf_error *err);
typedef struct bf_stack { int nimages; int width, height, channels; ...; } bf_stack;
bf_status bf_stack_read(const char *path, bf_stack **out, bf_error *err);
void bf_stack_free(bf_stack *s);
typedef enum bf_photo_normals { BF_NORMALS_FIT = 0, BF_NORMALS_FILE, BF_NORMALS_FLAT } bf_photo_normals;
typedef struct bf_photo_options {
    size_t size; const char *model; bf_photo_normals normals; const char *normals_file; const char *share;
    int clusters; int scale_given; double scale; int tile_index, tile_count; int threads; int relit_images;
    uint64_t seed; void (*progress)(void *user, double done); void *progress_user;
    const volatile sig_atomic_t *cancel; /* bf_cancel_flag (volatile: cffi checks the field) */
    bf_option_spelling spelling; ...;
} bf_photo_options;
void bf_photo_options_init(bf_photo_options *o);
bf_status bf_photo_options_check(const bf_photo_options *o, bf_error *err);
bf_status bf_photo_options_set_tile(bf_photo_options *o, const char *text, bf_error *err);
bf_status bf_photo_options_set_normals(bf_photo_options *o, const char *text, bf_error *err);
bf_status bf_photo_options_set_scale(bf_photo_options *o, const char *text, bf_error *err);
typedef struct bf_photo_counts {
    size_t pixels; size_t masked; size_t failed; size_t samples; size_t shadowed; size_t dark; size_t saturated;
    size_t invalid;
} bf_photo_counts;
typedef struct bf_photo_result {
    int width, height, channels; int y0, y1; bf_model *model; int nvalues; double scale; unsigned char *mask;
    float *normals; float *params; float *error; float *lambert_normals; float *lambert_albedo; int *cluster;
    int nclusters; int nshared; int shared_entry[...]; double *shared; bf_photo_counts counts; int nimages;
    double relit_rms, lambert_rms; double *image_rms, *image_lambert_rms; size_t *image_samples; int nrelit;
    int relit_index[...]; float *relit_measured[...], *relit_model[...]; size_t iterations; size_t restarted;
    int threads; double seconds; int cancelled; ...;
} bf_photo_result;
bf_status bf_photo_fit(const bf_stack *s, const bf_photo_options *o, bf_photo_result **out, bf_error *err);
void bf_photo_result_free(bf_photo_result *r);
bf_status bf_photo_result_json(const bf_photo_result *r, const bf_stack *s, const bf_photo_options *o,
                               const char *command_line, char **out, bf_error *err);
extern "Python" void _brdfit_photo_progress(void *user, double done);

/* The progress reports, into Python (_brdfit_report in brdfit/_run.py). */
extern "Python" int _brdfit_report(void *user, const bf_progress_report *report);
"""

SOURCE = r"""
#include "brdfit/compare.h"
#include "brdfit/export.h"
#include "brdfit/fit.h"
#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/load.h"
#include "brdfit/model.h"
#include "brdfit/objective.h"
#include "brdfit/options.h"
#include "brdfit/select.h"
#include "brdfit/tradeoff.h"
#include "brdfit/version.h"
/* Front ends (info, render, fit-images, many files). */
#include "brdfit/formats.h"
#include "brdfit/photo.h"
#include "brdfit/prep.h"
#include "brdfit/render.h"
"""


def _split(var: str) -> List[str]:
    return [p for p in os.environ.get(var, "").split(os.pathsep) if p]


def _where() -> Tuple[List[str], List[str]]:
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
