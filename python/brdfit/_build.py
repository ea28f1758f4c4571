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
typedef struct bf_param_info { const char *name; int colour; double lo, hi, def; ...; } bf_param_info;
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

/* Geometry (geometry.h). */
bf_status bf_geometry_from_vectors(size_t n, const double *L, const double *V, bf_geometry **out, bf_error *err);
void bf_geometry_free(bf_geometry *g);

/* Samples (samples.h). */
typedef struct bf_samples {
    size_t n; int channels; char **channel_names; double *wavelength;
    double *theta_i, *phi_i, *theta_o, *phi_o; double *value; double *weight; double *scene_weight; ...;
} bf_samples;
bf_status bf_samples_new(size_t n, int channels, bf_samples **out, bf_error *err);
void bf_samples_free(bf_samples *s);
bf_status bf_samples_add_weights(bf_samples *s, bf_error *err);
void bf_samples_angle_block(const bf_samples *s, size_t i0, size_t cnt, double *buf, const double *dir[4]);
bf_status bf_samples_geometry(bf_samples *s, const bf_geometry **out, bf_error *err);
bf_status bf_samples_copy(const bf_samples *s, const unsigned char *keep, bf_samples **out, bf_error *err);

/* Run options (options.h): the table and a set of values. */
typedef enum bf_task { BF_TASK_READ = 1, BF_TASK_FIT = 2, BF_TASK_COMPARE = 4, BF_TASK_SELECT = 8 } bf_task;
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
typedef struct bf_load_report { size_t size; size_t read; size_t kept; ...; } bf_load_report;
void bf_load_report_init(bf_load_report *r);
bf_status bf_samples_load(const char *path, const bf_options *o, bf_samples **out, bf_load_report *report,
                          bf_error *err);
bf_status bf_samples_prepare(bf_samples *s, const bf_options *o, bf_load_report *report, bf_error *err);

/* Fitting (solve.h, fit.h). */
typedef enum bf_stop { BF_STOP_CONVERGED = 0, BF_STOP_ITERATIONS, BF_STOP_TIME, BF_STOP_CANCELLED, BF_STOP_FAILED } bf_stop;
typedef struct bf_solution { bf_stop stop; ...; } bf_solution;
typedef struct bf_fit_result { size_t size; bf_model *model; double *x; bf_solution solution; int ok; ...; } bf_fit_result;
void bf_fit_result_init(bf_fit_result *r);
bf_status bf_fit(bf_samples *s, const char *spec, const bf_options *o, bf_fit_result *r, bf_error *err);
void bf_fit_result_clear(bf_fit_result *r);
bf_status bf_fit_result_json(const bf_fit_result *r, const char *data_path, char **out, bf_error *err);
bf_status bf_params_read(const char *path, bf_model **model, double **x, bf_error *err);
bf_status bf_params_parse(const char *text, const char *name, bf_model **model, double **x, bf_error *err);

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

/* The progress reports, into Python (_brdfit_report in brdfit/_run.py). */
extern "Python" int _brdfit_report(void *user, const bf_progress_report *report);
"""

SOURCE = r"""
#include "brdfit/compare.h"
#include "brdfit/export.h"
#include "brdfit/fit.h"
#include "brdfit/io.h"
#include "brdfit/load.h"
#include "brdfit/model.h"
#include "brdfit/options.h"
#include "brdfit/select.h"
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
