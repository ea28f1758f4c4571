// A C++ program built against an installed brdfit (tests/install/install_test.sh,
// tests/package/package_test.sh): every public header included by name, and a function
// declared in each called, so that a header that does not compile as C++ or a function
// without C linkage or export fails to build or link. One line per header,
// "header NAME: ok (VALUE)", or a message and exit 1 when a value is wrong.
// install_test.sh checks that every installed header is included here and reported.
// The calls need no files beyond small temporary CSVs, no image module and no network.
// Each header's calls sit in one small function: a signature change is a local fix.
#include <brdfit/api.h> // macros only (BF_API, BF_DEPRECATED): no function to call
#include <brdfit/clock.h>
#include <brdfit/color.h>
#include <brdfit/compare.h>
#include <brdfit/error.h>
#include <brdfit/export.h>
#include <brdfit/fit.h>
#include <brdfit/formats.h>
#include <brdfit/geometry.h>
#include <brdfit/image.h>
#include <brdfit/io.h>
#include <brdfit/limits.h>
#include <brdfit/load.h>
#include <brdfit/merl.h>
#include <brdfit/metrics.h>
#include <brdfit/model.h>
#include <brdfit/objective.h>
#include <brdfit/options.h>
#include <brdfit/photo.h>
#include <brdfit/prep.h>
#include <brdfit/reference.h>
#include <brdfit/regress.h>
#include <brdfit/render.h>
#include <brdfit/samples.h>
#include <brdfit/scene.h>
#include <brdfit/select.h>
#include <brdfit/solve.h>
#include <brdfit/tool.h>
#include <brdfit/tradeoff.h>
#include <brdfit/version.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>

#include <unistd.h>

#ifndef BF_API
#error "brdfit/api.h defines no BF_API"
#endif

namespace
{

// The library's objects owned the C++ way: their bf_x_free as the deleter.
using model_ptr = std::unique_ptr<bf_model, decltype(&bf_model_free)>;
using samples_ptr = std::unique_ptr<bf_samples, decltype(&bf_samples_free)>;
using geometry_ptr = std::unique_ptr<bf_geometry, decltype(&bf_geometry_free)>;

const double pi = 3.14159265358979323846;

bool near(double a, double b, double tol)
{
    return std::fabs(a - b) <= tol;
}
bool same(const char *a, const char *b)
{
    return a && b && std::strcmp(a, b) == 0;
}

std::string format(const char *fmt, double v)
{
    char buf[64];
    std::snprintf(buf, sizeof buf, fmt, v);
    return buf;
}

// A temporary file holding text, removed when the object goes.
struct temp_file {
    std::string path;
    explicit temp_file(const char *text)
    {
        const char *dir = std::getenv("TMPDIR");
        std::string name = std::string(dir && *dir ? dir : "/tmp") + "/brdfit-consumer-XXXXXX.csv";
        int fd = mkstemps(&name[0], 4);
        if (fd < 0)
            return;
        size_t n = std::strlen(text);
        bool written = write(fd, text, n) == (ssize_t)n;
        if (close(fd) == 0 && written)
            path = name;
        else
            unlink(name.c_str());
    }
    ~temp_file()
    {
        if (!path.empty())
            unlink(path.c_str());
    }
};

// Each check calls its header's functions, puts what they gave into value (shown on the
// header's line) and returns whether it is right.

bool check_api(std::string &value)
{
    value = "macros only";
    return true;
}

bool check_clock(std::string &value)
{
    double t0 = bf_now_seconds(), t1 = bf_now_seconds();
    value = format("%.3g s between two calls", t1 - t0);
    return std::isfinite(t0) && t1 >= t0;
}

bool check_color(std::string &value)
{
    // A flat spectrum of 1 is white: (1, 1, 1) in linear sRGB.
    bf_color c;
    bf_error err;
    const double wl[2] = {400.0, 700.0};
    double w[3 * 2];
    if (bf_color_parse("sRGB", &c, &err) != BF_OK || bf_color_weights(wl, 2, c, BF_ILLUMINANT_D65, w, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = std::string(bf_color_name(c)) + " white " + format("%.6f", w[0] + w[1]) + " " +
            format("%.6f", w[2] + w[3]) + " " + format("%.6f", w[4] + w[5]);
    return c == BF_COLOR_SRGB && same(bf_color_name(c), "srgb") && near(w[0] + w[1], 1.0, 1e-6) &&
           near(w[2] + w[3], 1.0, 1e-6) && near(w[4] + w[5], 1.0, 1e-6);
}

bool check_compare(std::string &value)
{
    bf_compare_metric m;
    bf_error err;
    if (bf_compare_metric_parse("rmse_log", &m, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    // (3, 3) is dominated by (2, 2); the other two are on the front.
    const double x[3] = {1, 2, 3}, y[3] = {3, 2, 3};
    int on[3];
    bf_compare_pareto(3, x, y, on);
    value = std::string(bf_compare_metric_name(m)) + ", " + bf_compare_rank_name(BF_RANK_BIC) + ", front " +
            std::to_string(on[0] + on[1] + on[2]) + " of 3";
    return m == BF_CMP_RMSE_LOG && same(bf_compare_rank_name(BF_RANK_BIC), "bic") && on[0] && on[1] && !on[2];
}

bool check_error(std::string &value)
{
    bf_error err;
    bf_status rc = bf_fail(&err, BF_ERR_RANGE, "value %d of %s", 3, "x");
    bf_free(nullptr);
    value = std::string(bf_status_name(rc)) + ": " + err.msg;
    return rc == BF_ERR_RANGE && err.code == BF_ERR_RANGE && same(err.msg, "value 3 of x") &&
           same(bf_status_name(BF_ERR_PARSE), "parse");
}

bool check_export(std::string &value)
{
    const bf_export_target *t = bf_export_target_find("gltf");
    int n = bf_export_target_count();
    value = std::to_string(n) + " targets, gltf's model " + (t && t->model ? t->model : "(none)");
    return n >= 1 && t && same(t->name, "gltf") && bf_export_target_find("no such target") == nullptr;
}

bool check_fit(std::string &value)
{
    // Lambert's directional albedo is rho_d at every incidence.
    bf_model *m = nullptr;
    bf_error err;
    if (bf_model_new("lambert", 1, &m, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    model_ptr owned(m, bf_model_free);
    const double x[1] = {0.3};
    double albedo = 0, theta = 0;
    int channel = -1;
    if (bf_fit_max_albedo(m, x, &albedo, &theta, &channel, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = format("lambert 0.3's largest albedo %.6f", albedo);
    return near(albedo, 0.3, 1e-3) && channel == 0;
}

bool check_formats(std::string &value)
{
    bf_format f = bf_format_by_extension("table.BINARY"), g;
    bf_error err;
    if (bf_format_parse("cornell", &g, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = std::string(bf_format_name(f)) + ", " + bf_format_name(g);
    return f == BF_FORMAT_MERL && g == BF_FORMAT_CORNELL && bf_format_parse("no such format", &g, nullptr) != BF_OK;
}

bool check_geometry(std::string &value)
{
    // L along the normal, V at 45 degrees (not normalised: the library does it).
    const double L[3] = {0, 0, 1}, V[3] = {1, 0, 1};
    bf_geometry *g = nullptr;
    bf_error err;
    if (bf_geometry_from_vectors(1, L, V, &g, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    geometry_ptr owned(g, bf_geometry_free);
    value = format("N.V %.6f", g->vz[0]) + format(", N.H %.6f", g->hz[0]);
    return g->n == 1 && bf_geometry_stored(g) && bf_geometry_valid_at(g, 0) && near(g->vz[0], std::sqrt(0.5), 1e-12) &&
           near(g->hz[0], std::cos(pi / 8), 1e-12);
}

bool check_image(std::string &value)
{
    // Neither call needs the image module.
    float half = bf_srgb_decode(bf_srgb_encode(0.5f));
    bf_image img;
    bf_image_init(&img);
    bf_image_clear(&img);
    value = format("sRGB round trip of 0.5: %.6f", half);
    return bf_image_format_of("x.EXR") == BF_IMAGE_EXR && bf_image_format_of("x.png") == BF_IMAGE_PNG &&
           near(half, 0.5, 1e-5);
}

bool check_io(std::string &value)
{
    temp_file csv("a,b\n1,2\n3,4\n");
    bf_csv *t = nullptr;
    bf_error err;
    if (csv.path.empty() || bf_csv_read(csv.path.c_str(), &t, &err) != BF_OK) {
        value = csv.path.empty() ? "cannot write a temporary CSV" : err.msg;
        return false;
    }
    char buf[32];
    bool ok = t->nrows == 2 && t->ncols == 2 && bf_csv_column(t, "b") == 1 && t->data[3] == 4.0;
    value = std::to_string(t->nrows) + "x" + std::to_string(t->ncols) + " CSV, 0.1 as " +
            bf_format_double(0.1, buf, sizeof buf);
    bf_csv_free(t);
    return ok && same(buf, "0.1");
}

bool check_load(std::string &value)
{
    // Two samples, one below the horizon: loading drops it.
    temp_file csv("theta_i,phi_i,theta_o,phi_o,value\n10,0,20,180,0.1\n30,0,95,180,0.1\n");
    bf_options *o = nullptr;
    bf_samples *s = nullptr;
    bf_load_report rep;
    bf_load_report_init(&rep);
    bf_error err;
    bf_status rc = csv.path.empty() ? BF_ERR_IO : bf_options_new(BF_TASK_READ, &o, &err);
    if (rc == BF_OK)
        rc = bf_samples_load(csv.path.c_str(), o, &s, &rep, &err);
    bf_options_free(o);
    if (rc != BF_OK) {
        value = csv.path.empty() ? "cannot write a temporary CSV" : err.msg;
        return false;
    }
    samples_ptr owned(s, bf_samples_free);
    value = std::to_string(rep.read) + " read, " + std::to_string(rep.kept) + " kept";
    return rep.read == 2 && rep.below_horizon == 1 && rep.kept == 1 && s->n == 1;
}

bool check_limits(std::string &value)
{
    size_t n = 0;
    bf_error err;
    if (bf_bytes_parse("4K", &n, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = "4K is " + std::to_string(n) + " bytes";
    return n == 4096 && bf_memory_available() > 0 && bf_bytes_parse("-1", &n, nullptr) == BF_ERR_ARG;
}

bool check_merl(std::string &value)
{
    const int32_t cell = 105 + 68 * BF_MERL_PD + 40 * BF_MERL_PD * BF_MERL_TD;
    double ti, pi_, to, po;
    bf_merl_cell_directions(cell, &ti, &pi_, &to, &po);
    int32_t back = bf_merl_cell_of(ti, pi_, to, po);
    value = "cell " + std::to_string(cell) + " -> " + std::to_string(back);
    return back == cell;
}

bool check_metrics(std::string &value)
{
    bf_metrics m = {};
    bf_metrics_criteria(&m, 100, 2, 1.0, 0.0);
    value = format("aic %.6f", m.aic) + format(", bic %.6f", m.bic);
    // k + 1 parameters, sigma included.
    return near(m.aic, -2 * m.loglik + 2 * 3, 1e-9) && near(m.bic, -2 * m.loglik + 3 * std::log(100.0), 1e-9);
}

bool check_model(std::string &value)
{
    bf_model *m = nullptr;
    bf_error err;
    if (bf_family_count() < 1 || bf_model_new("lambert", 1, &m, &err) != BF_OK) {
        value = bf_family_count() < 1 ? "no model families" : err.msg;
        return false;
    }
    model_ptr owned(m, bf_model_free);
    int k = bf_model_find_param(m, "rho_d");
    if (k < 0 || bf_model_nvalues(m) != 1) {
        value = "lambert has no single rho_d";
        return false;
    }
    double x[1] = {0.3}, f = 0;
    const double L[3] = {0, 0, 1}, V[3] = {0.5, 0, 1};
    bf_geometry *g = nullptr;
    if (bf_geometry_from_vectors(1, L, V, &g, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    bf_model_eval(m, x, g, &f, nullptr);
    bf_geometry_free(g);
    value = std::string(bf_model_name(m)) + " " + bf_model_param(m, k)->name + format(" 0.3: f = %.6f", f);
    return same(bf_model_name(m), "lambert") && bf_model_param_offset(m, k) == 0 && near(f, 0.3 / pi, 1e-12);
}

bool check_objective(std::string &value)
{
    bf_residual r;
    bf_error err;
    if (bf_residual_parse("cbrt", &r, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = bf_residual_name(r);
    return r == BF_RESIDUAL_CBRT && bf_residual_parse("no such residual", &r, nullptr) != BF_OK;
}

bool check_options(std::string &value)
{
    // The table by either spelling, and a value set as text and read back.
    const bf_option *opt = bf_option_find("max_theta", BF_TASK_FIT);
    bf_options *o = nullptr;
    bf_error err;
    if (!opt || bf_options_new(BF_TASK_FIT, &o, &err) != BF_OK) {
        value = opt ? err.msg : "no option max_theta";
        return false;
    }
    char buf[64] = "";
    bool ok = bf_options_set(o, "max_theta", "80", &err) == BF_OK &&
              bf_options_get(o, "max_theta", buf, sizeof buf, &err) == BF_OK;
    value = ok ? std::to_string(bf_option_count()) + " options, max_theta " + buf : err.msg;
    ok = ok && bf_options_given(o, "max_theta") && near(std::atof(buf), 80.0, 0.0) &&
         bf_option_find("--max-theta", 0) != nullptr && bf_options_set(o, "no_such_option", "1", nullptr) == BF_ERR_ARG;
    bf_options_free(o);
    return ok;
}

bool check_photo(std::string &value)
{
    bf_photo_options o;
    bf_photo_options_init(&o);
    value = std::string("default model ") + (o.model ? o.model : "(none)");
    return o.model && *o.model && o.normals == BF_NORMALS_FIT;
}

bool check_prep(std::string &value)
{
    // Four samples, one below the horizon: bf_samples_describe counts it.
    bf_samples *s = nullptr;
    bf_error err;
    if (bf_samples_new(4, 1, &s, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    samples_ptr owned(s, bf_samples_free);
    for (size_t i = 0; i < s->n; i++) {
        s->theta_i[i] = 10.0 + 10.0 * (double)i;
        s->theta_o[i] = 20.0;
        s->phi_o[i] = 180.0;
        s->value[i] = 0.1;
    }
    s->theta_o[3] = 95.0;
    bf_samples_info info;
    bf_samples_info_init(&info);
    if (bf_samples_describe(s, &info, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = std::to_string(info.n) + " samples, " + std::to_string(info.below_horizon) + " below the horizon, mean " +
            std::to_string(info.mean[0]);
    const bool ok = info.n == 4 && info.below_horizon == 1 && std::fabs(info.mean[0] - 0.1) < 1e-12;
    bf_samples_info_clear(&info);
    return ok;
}

bool check_reference(std::string &value)
{
    bf_reference_set *s = nullptr;
    bf_error err;
    char material[64];
    if (bf_reference_set_new(&s, &err) != BF_OK ||
        bf_reference_parse(s, "{\"model\": \"lambert\", \"params\": {\"rho_d\": 1.2}}", "refs/red.json", &err) !=
            BF_OK) {
        value = err.msg;
        bf_reference_set_free(s);
        return false;
    }
    const bf_reference *r = &s->refs[0];
    value = std::string(r->material) + "'s lambert, outside: " + r->outside;
    const bool ok =
        same(r->material, "red") && same(r->outside, "rho_d") &&
        bf_reference_matches(r, bf_reference_material("data/red.binary", material, sizeof material), "lambert");
    bf_reference_set_free(s);
    return ok;
}

bool check_regress(std::string &value)
{
    int found = -1;
    for (int i = 0; i < bf_regress_nmetric_names; i++)
        if (same(bf_regress_metric_names[i], "rmse_log"))
            found = i;
    value = std::to_string(bf_regress_nmetric_names) + " metric names";
    return found >= 0;
}

bool check_render(std::string &value)
{
    // theta_h = theta_d = 0: light and view both along the normal.
    double L[3], V[3];
    bf_halfdiff_dirs(0.0, 0.0, 0.0, L, V);
    bf_plot_format f;
    bf_error err;
    if (bf_plot_format_parse("svg", &f, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = "svg is format " + std::to_string(f) + format(", L.z %.6f", L[2]);
    return f == BF_PLOT_SVG && bf_plot_format_of("a.PDF") == BF_PLOT_PDF && near(L[2], 1.0, 1e-12) &&
           near(V[2], 1.0, 1e-12);
}

bool check_samples(std::string &value)
{
    bf_samples *s = nullptr;
    bf_error err;
    if (bf_samples_new(5, 3, &s, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    samples_ptr owned(s, bf_samples_free);
    value =
        std::to_string(s->n) + " samples, channels " + s->channel_names[0] + s->channel_names[1] + s->channel_names[2];
    return s->n == 5 && s->channels == 3 && same(s->channel_names[0], "r") && same(s->channel_names[2], "b");
}

bool check_scene(std::string &value)
{
    bf_scene *sc = nullptr;
    bf_error err;
    if (bf_scene_parse("{\"view\": {\"theta\": [0, 60]}}", "consumer scene", &sc, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    value = format("view theta up to %.0f", sc->view_theta.hi) + ", " + std::to_string(sc->nlights) + " lights";
    bool ok = near(sc->view_theta.hi, 60.0, 0.0) && sc->nlights == 0;
    bf_scene_free(sc);
    return ok;
}

bool check_select(std::string &value)
{
    const char **specs = nullptr;
    int n = bf_select_default_candidates(1, &specs);
    bool ok = n > 0 && specs && specs[0];
    if (ok) {
        // The first default candidate is a model the library makes.
        bf_model *m = nullptr;
        ok = bf_model_new(specs[0], 1, &m, nullptr) == BF_OK;
        value = std::to_string(n) + " default candidates, first " + specs[0];
        bf_model_free(m);
    } else {
        value = "no default candidates";
    }
    bf_free(specs); // the array only: its strings are the library's
    return ok;
}

bool check_solve(std::string &value)
{
    bf_backend b;
    bf_loss loss;
    bf_error err;
    if (bf_backend_parse("nlopt", &b, &err) != BF_OK || bf_loss_parse("huber:0.5", &loss, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    // The header's inline function: beyond the scale, huber's g = sqrt(2 a |r| - a^2).
    double dg, g = bf_loss_residual(&loss, 2.0, &dg);
    const bf_method_info *def = bf_method_default(BF_BACKEND_CERES);
    value =
        std::string(bf_backend_name(b)) + ", ceres' default " + (def ? def->name : "(none)") + format(", g %.6f", g);
    return b == BF_BACKEND_NLOPT && bf_method_count() > 0 && def && loss.kind == BF_LOSS_HUBER &&
           near(g, std::sqrt(1.75), 1e-12) && same(bf_stop_name(BF_STOP_CONVERGED), "converged");
}

bool check_tool(std::string &value)
{
    // Strict numbers: the whole text, in range; "+5" and "5x" are not.
    long l = 0;
    double d = 0;
    bool ok = bf_parse_long("42", 0, 100, &l) && bf_parse_number("0.25", 0.0, 1.0, &d);
    value = std::to_string(l) + format(", %g", d);
    return ok && l == 42 && d == 0.25 && !bf_parse_long("+5", 0, 100, &l) && !bf_parse_number("5x", 0.0, 10.0, &d) &&
           !bf_parse_long("500", 0, 100, &l);
}

bool check_tradeoff(std::string &value)
{
    // 10 samples split 30 % for testing: 3 and 7, together all of them.
    bf_samples *s = nullptr, *train = nullptr, *test = nullptr;
    bf_error err;
    if (bf_samples_new(10, 1, &s, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    samples_ptr owned(s, bf_samples_free);
    if (bf_tradeoff_split(s, 0.3, 1, &train, &test, &err) != BF_OK) {
        value = err.msg;
        return false;
    }
    samples_ptr owned_train(train, bf_samples_free), owned_test(test, bf_samples_free);
    value = std::to_string(train->n) + " training, " + std::to_string(test->n) + " test samples, cost " +
            bf_tradeoff_cost_name(BF_TRADEOFF_COST_WORK);
    return train->n == 7 && test->n == 3 && same(bf_tradeoff_cost_name(BF_TRADEOFF_COST_WORK), "work");
}

bool check_version(std::string &value)
{
    int major = -1, minor = -1, patch = -1;
    bf_version_numbers(&major, &minor, &patch);
    value = std::string(bf_version()) + ", number " + std::to_string(bf_version_number());
    return bf_version_number() == BRDFIT_VERSION_NUMBER && major == BRDFIT_VERSION_MAJOR &&
           minor == BRDFIT_VERSION_MINOR && patch == BRDFIT_VERSION_PATCH &&
           std::strncmp(bf_version(), BRDFIT_VERSION, std::strlen(BRDFIT_VERSION)) == 0;
}

struct check {
    const char *header;
    bool (*run)(std::string &value);
};

const check checks[] = {
    {"api.h", check_api},
    {"clock.h", check_clock},
    {"color.h", check_color},
    {"compare.h", check_compare},
    {"error.h", check_error},
    {"export.h", check_export},
    {"fit.h", check_fit},
    {"formats.h", check_formats},
    {"geometry.h", check_geometry},
    {"image.h", check_image},
    {"io.h", check_io},
    {"limits.h", check_limits},
    {"load.h", check_load},
    {"merl.h", check_merl},
    {"metrics.h", check_metrics},
    {"model.h", check_model},
    {"objective.h", check_objective},
    {"options.h", check_options},
    {"photo.h", check_photo},
    {"prep.h", check_prep},
    {"reference.h", check_reference},
    {"regress.h", check_regress},
    {"render.h", check_render},
    {"samples.h", check_samples},
    {"scene.h", check_scene},
    {"select.h", check_select},
    {"solve.h", check_solve},
    {"tool.h", check_tool},
    {"tradeoff.h", check_tradeoff},
    {"version.h", check_version},
};

} // namespace

int main()
{
    int failed = 0;
    for (const check &c : checks) {
        std::string value;
        if (c.run(value)) {
            std::printf("header %s: ok (%s)\n", c.header, value.c_str());
        } else {
            std::fprintf(stderr, "consumer_cxx: header %s: wrong value: %s\n", c.header, value.c_str());
            failed++;
        }
    }
    return failed ? 1 : 0;
}
