/* A program built against an installed brdfit (tests/install/install_test.sh,
 * tests/package/package_test.sh): C only, the public headers only. Fits Lambert to
 * samples of rho_d = 0.3 made here, prints the fitted albedo and the library's version,
 * writes a small PNG when given a path (which loads the image module the way any program
 * linked to the library does) and, given a folder too, exports the fit to glTF, Blender
 * and Mitsuba there. */
#include <brdfit/error.h>
#include <brdfit/export.h>
#include <brdfit/fit.h>
#include <brdfit/image.h>
#include <brdfit/model.h>
#include <brdfit/options.h>
#include <brdfit/samples.h>
#include <brdfit/version.h>

#include <math.h>
#include <stdio.h>
#include <string.h>

#define RHO 0.3
#define PI 3.14159265358979323846

int main(int argc, char **argv)
{
    bf_error err;
    /* An 8 x 8 grid of incident and outgoing elevations in the plane, value rho/pi. */
    bf_samples *s = NULL;
    if (bf_samples_new(64, 1, &s, &err) != BF_OK) {
        fprintf(stderr, "consumer: %s\n", err.msg);
        return 1;
    }
    for (size_t i = 0; i < s->n; i++) {
        s->theta_i[i] = 5.0 + 10.0 * (double)(i / 8);
        s->theta_o[i] = 5.0 + 10.0 * (double)(i % 8);
        s->phi_o[i] = 180.0;
        s->value[i] = RHO / PI;
    }
    /* Options as text, as a command line gives them. */
    bf_options *o = NULL;
    if (bf_options_new(BF_TASK_FIT, &o, &err) != BF_OK || bf_options_set(o, "residual", "linear", &err) != BF_OK ||
        bf_options_set(o, "backend", "ceres", &err) != BF_OK || bf_options_set(o, "starts", "1", &err) != BF_OK) {
        fprintf(stderr, "consumer: %s\n", err.msg);
        return 1;
    }
    bf_fit_result r;
    bf_fit_result_init(&r);
    bf_status fitted = bf_fit(s, "lambert", o, &r, &err);
    bf_options_free(o);
    if (fitted != BF_OK || !r.ok) {
        fprintf(stderr, "consumer: the fit failed: %s\n", r.ok ? err.msg : r.solution.termination);
        return 1;
    }
    int k = bf_model_find_param(r.model, "rho_d");
    double rho = k < 0 ? NAN : r.x[bf_model_param_offset(r.model, k)];
    printf("rho_d %.6f\n", rho);
    printf("version %s (headers %s, %d.%d.%d)\n", bf_version(), BRDFIT_VERSION, BRDFIT_VERSION_MAJOR,
           BRDFIT_VERSION_MINOR, BRDFIT_VERSION_PATCH);
    /* With a folder: the fit exported to every renderer the library knows (converted:
     * Lambert is none of their native models), into FOLDER/brdfit.NAME. */
    for (int t = 0; argc > 2 && t < bf_export_target_count(); t++) {
        const bf_export_target *to = bf_export_target_get(t);
        bf_export_material e;
        bf_export_material_init(&e);
        bf_fit_result conversion;
        bf_fit_result_init(&conversion);
        char path[1024];
        snprintf(path, sizeof path, "%s/brdfit.%s", argv[2], to->name);
        if (bf_export_check(to, r.model, 0, &err) != BF_OK ||
            bf_export_prepare(to, r.model, r.x, &e, &conversion, &err) != BF_OK) {
            fprintf(stderr, "consumer: export to %s: %s\n", to->name, err.msg);
            return 1;
        }
        bf_status rc = bf_export_write(to, &e, path, &err);
        printf("exported %s (%s, rmse_log %.3g)\n", to->name, e.converted ? "converted" : "exact", e.metrics.rmse_log);
        bf_fit_result_clear(&conversion);
        if (rc != BF_OK) {
            fprintf(stderr, "consumer: export to %s: %s\n", to->name, err.msg);
            return 1;
        }
    }
    bf_fit_result_clear(&r);
    bf_samples_free(s);
    if (!(fabs(rho - RHO) < 1e-6) || strncmp(bf_version(), BRDFIT_VERSION, strlen(BRDFIT_VERSION)) != 0)
        return 1;

    if (argc > 1) {
        float rgb[4 * 4 * 3];
        for (size_t i = 0; i < sizeof rgb / sizeof rgb[0]; i++)
            rgb[i] = (float)RHO;
        if (bf_image_write_rgb(argv[1], 4, 4, rgb, &err) != BF_OK) {
            fprintf(stderr, "consumer: %s\n", err.msg);
            return 1;
        }
        printf("wrote %s\n", argv[1]);
    }
    return 0;
}
