/* Test support shared by the model tests: every configuration of every registered
 * family, reproducible random parameters and directions, finite differences. */
#ifndef BF_TEST_SUPPORT_H
#define BF_TEST_SUPPORT_H

#include <stddef.h>
#include <stdint.h>

#include "brdfit/geometry.h"
#include "brdfit/model.h"
#include "brdfit/fit.h"
#include "fit_impl.h"
#include "io/read_options.h"
#include "samples/prep_options.h"
#include "brdfit/samples.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define DEG (M_PI / 180.0)

/* Every option combination of every family (lobes 1 and 2 where accepted), as spec
 * strings. When the environment variable BRDFIT_TEST_MODEL is set (a comma-separated
 * list of family names), only those families. Returns the count; free with
 * ts_free_specs. */
int ts_all_specs(char ***specs);
void ts_free_specs(char **specs, int n);

/* Deterministic generator (xorshift64*). */
typedef struct ts_rng {
    uint64_t s;
} ts_rng;
double ts_uniform(ts_rng *r); /* [0, 1) */

/* How a random parameter vector is drawn. */
enum {
    TS_PARAMS_ANY = 0,      /* anywhere in bounds, the bounds themselves often */
    TS_PARAMS_MODERATE = 1, /* lobes wide enough for quadrature, colour sums <= 1 */
};
void ts_random_params(const bf_model *m, ts_rng *r, int how, double *x);
/* Closest value to the bound that the bound's openness allows. */
double ts_param_lo(const bf_param_info *p);
double ts_param_hi(const bf_param_info *p);

/* n random direction pairs above the horizon (theta up to 89.5 degrees), about a third
 * of them near the mirror direction so sharp lobes are exercised. Radians. */
void ts_random_dirs(ts_rng *r, size_t n, double *ti, double *pi_, double *to, double *po);

/* One random pair in degrees for value tests: theta up to 85, and with near_mirror the
 * outgoing direction within 5 degrees of the mirror of the incident one. */
void ts_random_pair_deg(ts_rng *r, int near_mirror, double *ti, double *pi_, double *to, double *po);

/* L and V as docs/models.md defines them, from angles in degrees. */
void ts_dirs_deg(double ti, double pi_, double to, double po, double L[3], double V[3]);

/* Evaluates values only, over a geometry, into a malloc'd array (n*C). */
double *ts_eval(const bf_model *m, const double *x, const bf_geometry *g);

/* Geometry from degrees. */
bf_geometry *ts_geometry_deg(size_t n, const double *ti, const double *pi_, const double *to, const double *po);

/* A model that must exist (fails the current cmocka test otherwise). */
bf_model *ts_model(const char *spec, int C);
/* bf_samples_geometry, failing the test if it fails. */
const bf_geometry *ts_samples_geometry(bf_samples *s);
/* A whole file's bytes (malloc'd), failing the test if it cannot be read. */
unsigned char *ts_read_binary(const char *path, size_t *len);

/* Fails the current test unless |got - want| <= tol |want| (plus 1e-300); `what`
 * (may be NULL) names the quantity in the message. */
void ts_assert_rel(double got, double want, double tol, const char *what);

/* Like ts_assert_rel with an absolute floor `abs`, for values that may be ~0. */
void ts_assert_near(double got, double want, double rel, double abs, const char *what);

/* A per-process temporary directory, made on first use and removed at exit, and a
 * path inside it (one of 8 rotating buffers). */
const char *ts_tmpdir(void);
const char *ts_tmp_path(const char *name);
/* Writes len bytes of text to path (fails the test if it cannot). */
void ts_write_file(const char *path, const char *text, size_t len);
/* The file's first 64 kB as a string (a static buffer, overwritten by the next call). */
const char *ts_read_file(const char *path);

/* Writes text to ts_tmp_path(name), reads it with `reader`, and fails the test unless
 * the read fails with `code`, leaves *out NULL, and gives a one-line message that
 * names the file and contains `fragment`. */
typedef bf_status (*ts_reader)(const char *path, bf_samples **out, bf_error *err);
void ts_expect_read_error(ts_reader reader, const char *name, const char *text, size_t len, int code,
                          const char *fragment);

/* Fit options the fitting tests start from: the library's (bf_fit_options_init) with a
 * linear residual and one solver thread. */
void ts_fit_defaults(bf_fit_options *o);
/* A data file read with the default options (format by extension, then content). */
bf_samples *ts_read_data(const char *path);
/* Run options for task from command-line words ("--rank cv --folds 3 --rgb"), each one
 * asserted to be taken (free with bf_options_free). NULL or "": the defaults. */
bf_options *ts_options(bf_task task, const char *words);
/* A bundled Cornell measurement (examples/cornell/NAME) as linear sRGB, as --rgb reads it. */
bf_samples *ts_read_cornell_rgb(const char *name);
/* bf_fit that fails the test on an error or an unusable fit. */
void ts_fit_ok(bf_samples *s, const char *spec, const bf_fit_options *o, bf_fit_result *r);

/* Uniform in [0, 1] with its ends drawn often: 0 and 1 a tenth of the time each. */
double ts_uniform_ends(ts_rng *r);

/* The model `spec` against a reference formula the test writes out, for C = 1, 3 and 5:
 * `draw` fills the parameter vector x (and the test's own copy of the parameters in
 * ctx) at random; `ref` gives channel c at a direction pair in degrees from ctx. 400
 * draws per channel count, a third of the pairs near the mirror, each value to `tol`
 * relative. */
typedef void (*ts_draw_fn)(ts_rng *r, const bf_model *m, double *x, void *ctx);
typedef double (*ts_ref_fn)(const void *ctx, int C, double ti, double pi_, double to, double po, int c);
void ts_compare_reference(const char *spec, uint64_t seed, ts_draw_fn draw, ts_ref_fn ref, void *ctx, double tol);

/* Single value of channel c at one direction pair in degrees. */
double ts_eval1(const bf_model *m, const double *x, double ti, double pi_, double to, double po, int c);

#endif
