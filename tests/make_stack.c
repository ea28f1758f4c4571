/* make_stack: a synthetic photometric-stereo stack (test support, not installed).
 *
 * Renders one shape under many directional lights with brdfit's own models, in the
 * formats `brdfit fit-images` reads (docs/images.md): a DiLiGenT folder (16-bit PNG
 * images, filenames.txt, light_directions.txt, light_intensities.txt, mask.png) or a JSON
 * stack (float EXR images, stack.json, mask.png). Beside them, the truth: normals_true.exr
 * (RGB = the normal's xyz in the camera frame, 0 outside the mask) and truth.json (the
 * model's canonical spec, every parameter, the shape, the number of lights).
 *
 * Image formation as docs/images.md gives it with scale 1: channel c of a pixel under
 * light k is E_kc * f_c(L_local, V_local) * max(0, n . l_k), times --gain, plus --noise.
 * The view is v = (0, 0, 1) (orthographic, looking along -z). Each pixel's tangent frame is
 * t = normalize(x - (x . n) n), b = n x t, and L_local = (t . l, b . l, n . l), the same
 * for V. Pixel (i, j) (column i, row j from the top) lies at x = (i + 0.5 - N/2) / (N/2),
 * y = -(j + 0.5 - N/2) / (N/2): the image spans [-1, 1]^2.
 *
 * Shapes: sphere (radius 0.9, masked outside the disc, where values are 0), bumps (the
 * height 0.08 sin(3 pi x) sin(2 pi y), its analytic normal, every pixel in the mask),
 * plane (normal +z). Texture checker: the image is a 4 x 4 board whose odd cells scale the
 * diffuse colour (the parameters whose role is BF_ROLE_DIFFUSE) by 0.4.
 *
 * The output depends only on the arguments (the random intensities and the noise come
 * from --seed); note that OpenEXR files carry the time they were written. Errors are one
 * line on standard error: exit 2 for bad arguments, 1 for failures. */
#define _GNU_SOURCE
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>

#include "brdfit/geometry.h"
#include "brdfit/image.h"
#include "brdfit/model.h"

#define C 3              /* channels: RGB */
#define CHECKER_CELLS 4  /* the board is CHECKER_CELLS x CHECKER_CELLS cells */
#define CHECKER_DARK 0.4 /* the odd cells' diffuse colour, relative */
#define MAX_LIGHTS 96

enum { SHAPE_SPHERE, SHAPE_BUMPS, SHAPE_PLANE };
enum { LIGHTS_DILIGENT96, LIGHTS_RING12, LIGHTS_GRID25 };
enum { LAYOUT_DILIGENT, LAYOUT_JSON };

static const char *const shape_names[] = {"sphere", "bumps", "plane", NULL};
static const char *const light_names[] = {"diligent96", "ring12", "grid25", NULL};
static const char *const layout_names[] = {"diligent", "json", NULL};
static const char *const intensity_names[] = {"equal", "random", NULL};
static const char *const texture_names[] = {"none", "checker", NULL};

typedef struct options {
    const char *model, *params, *out;
    int shape, lights, layout, random_intensities, checker;
    int size;
    double gain, noise;
    uint64_t seed;
} options;

#if defined(__GNUC__)
__attribute__((format(printf, 2, 3)))
#endif
static _Noreturn void
die(int status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("make_stack: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    exit(status);
}

static void usage(void)
{
    fputs("usage: make_stack --model SPEC [--params 'name=v,name=r:g:b'] [--shape sphere|bumps|plane]\n"
          "       [--size N] [--lights diligent96|ring12|grid25] [--intensities equal|random] [--gain G]\n"
          "       [--noise S] [--seed N] [--layout diligent|json] [--texture none|checker] -o DIR\n",
          stdout);
}

/* --- numbers and names ---------------------------------------------------------------- */

static int choice(const char *opt, const char *arg, const char *const *names)
{
    for (int i = 0; names[i]; i++)
        if (strcmp(arg, names[i]) == 0)
            return i;
    char list[256] = "";
    for (int i = 0; names[i]; i++) {
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", names[i]);
    }
    die(2, "--%s: unknown value '%s' (one of %s)", opt, arg, list);
}

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

static double number_arg(const char *opt, const char *arg, double lo, double hi)
{
    double v;
    if (!parse_double(arg, &v) || v < lo || v > hi)
        die(2, "--%s: '%s' is not a number in [%g, %g]", opt, arg, lo, hi);
    return v;
}

static double whole_arg(const char *opt, const char *arg, double lo, double hi)
{
    double v;
    if (!parse_double(arg, &v) || v < lo || v > hi || v != floor(v))
        die(2, "--%s: '%s' is not a whole number in [%.17g, %.17g]", opt, arg, lo, hi);
    return v;
}

/* --- randomness: splitmix64, uniform doubles, Gaussians (Box-Muller) -------------------- */

typedef struct rng {
    uint64_t s;
} rng;

static uint64_t next_u64(rng *r)
{
    uint64_t z = (r->s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
}

static double uniform01(rng *r) /* (0, 1) */
{
    return ((double)(next_u64(r) >> 11) + 0.5) / 9007199254740992.0;
}

static double gaussian(rng *r)
{
    double u = uniform01(r), v = uniform01(r);
    return sqrt(-2.0 * log(u)) * cos(2.0 * M_PI * v);
}

/* --- model parameters ------------------------------------------------------------------- */

/* Every parameter of m at its default, then the --params list "name=v,name=v1:v2:v3"
 * (a colour parameter takes one value for every channel or one per channel). */
static void parse_params(const bf_model *m, const char *text, double *x)
{
    bf_model_defaults(m, x);
    if (!text || !*text)
        return;
    char *copy = strdup(text);
    if (!copy)
        die(1, "out of memory");
    char *save = NULL;
    for (char *item = strtok_r(copy, ",", &save); item; item = strtok_r(NULL, ",", &save)) {
        char *eq = strchr(item, '=');
        if (!eq)
            die(2, "--params: '%s' is not name=value", item);
        *eq = '\0';
        int p = bf_model_find_param(m, item);
        if (p < 0)
            die(2, "--params: %s has no parameter '%s'", bf_model_name(m), item);
        const bf_param_info *info = bf_model_param(m, p);
        int off = bf_model_param_offset(m, p), width = info->color ? bf_model_channels(m) : 1;
        double v[C];
        int n = 0;
        char *save2 = NULL;
        for (char *tok = strtok_r(eq + 1, ":", &save2); tok; tok = strtok_r(NULL, ":", &save2)) {
            if (n == C || !parse_double(tok, &v[n]))
                die(2, "--params: bad value for %s (a number%s)", item, info->color ? ", or r:g:b" : "");
            n++;
        }
        if (n != 1 && n != width)
            die(2, "--params: %s takes %d value%s, not %d", item, width, width > 1 ? "s (or one)" : "", n);
        for (int c = 0; c < width; c++)
            x[off + c] = v[n == 1 ? 0 : c];
    }
    free(copy);
    bf_error err;
    if (bf_model_check(m, x, &err) != BF_OK)
        die(2, "--params: %s", err.msg);
}

/* x with its diffuse colour scaled by f (the checker's dark cells). */
static int scale_diffuse(const bf_model *m, double *x, double f)
{
    int found = 0;
    for (int p = 0; p < bf_model_nparams(m); p++) {
        const bf_param_info *info = bf_model_param(m, p);
        if (info->role != BF_ROLE_DIFFUSE)
            continue;
        int off = bf_model_param_offset(m, p), width = info->color ? bf_model_channels(m) : 1;
        for (int c = 0; c < width; c++)
            x[off + c] *= f;
        found = 1;
    }
    return found;
}

/* --- lights and shapes ------------------------------------------------------------------ */

static void normalize3(double v[3])
{
    double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= n;
    v[1] /= n;
    v[2] /= n;
}

static int make_lights(int which, double dirs[][3])
{
    int k = 0;
    if (which == LIGHTS_DILIGENT96) { /* 12 x 8 points on z = 1, row by row */
        for (int j = 0; j < 8; j++)
            for (int i = 0; i < 12; i++, k++) {
                dirs[k][0] = -0.75 + 1.5 * i / 11.0;
                dirs[k][1] = -0.5 + 1.0 * j / 7.0;
                dirs[k][2] = 1.0;
                normalize3(dirs[k]);
            }
    } else if (which == LIGHTS_RING12) { /* 35 degrees from +z, every 30 degrees of azimuth */
        const double th = 35.0 * M_PI / 180.0;
        for (; k < 12; k++) {
            double ph = 2.0 * M_PI * k / 12.0;
            dirs[k][0] = sin(th) * cos(ph);
            dirs[k][1] = sin(th) * sin(ph);
            dirs[k][2] = cos(th);
        }
    } else { /* 5 x 5 points on z = 1 in [-0.6, 0.6]^2 */
        for (int j = 0; j < 5; j++)
            for (int i = 0; i < 5; i++, k++) {
                dirs[k][0] = -0.6 + 1.2 * i / 4.0;
                dirs[k][1] = -0.6 + 1.2 * j / 4.0;
                dirs[k][2] = 1.0;
                normalize3(dirs[k]);
            }
    }
    return k;
}

/* The normal at image point (x, y); 0 outside the shape. */
static int shape_normal(int shape, double x, double y, double n[3])
{
    if (shape == SHAPE_SPHERE) {
        const double R = 0.9;
        double r2 = (x * x + y * y) / (R * R);
        if (r2 >= 1.0)
            return 0;
        n[0] = x / R;
        n[1] = y / R;
        n[2] = sqrt(1.0 - r2);
        normalize3(n);
        return 1;
    }
    if (shape == SHAPE_BUMPS) { /* h = 0.08 sin(3 pi x) sin(2 pi y) */
        double hx = 0.08 * 3.0 * M_PI * cos(3.0 * M_PI * x) * sin(2.0 * M_PI * y);
        double hy = 0.08 * 2.0 * M_PI * sin(3.0 * M_PI * x) * cos(2.0 * M_PI * y);
        n[0] = -hx;
        n[1] = -hy;
        n[2] = 1.0;
        normalize3(n);
        return 1;
    }
    n[0] = n[1] = 0.0;
    n[2] = 1.0;
    return 1;
}

/* (t . d, b . d, n . d) for the pixel's tangent frame t = normalize(x - (x . n) n), b = n x t. */
static void to_local(const double n[3], const double d[3], double out[3])
{
    double t[3] = {1.0 - n[0] * n[0], -n[0] * n[1], -n[0] * n[2]};
    normalize3(t);
    double b[3] = {n[1] * t[2] - n[2] * t[1], n[2] * t[0] - n[0] * t[2], n[0] * t[1] - n[1] * t[0]};
    out[0] = t[0] * d[0] + t[1] * d[1] + t[2] * d[2];
    out[1] = b[0] * d[0] + b[1] * d[1] + b[2] * d[2];
    out[2] = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
}

/* --- output ----------------------------------------------------------------------------- */

static char *join(const char *dir, const char *name)
{
    size_t n = strlen(dir) + strlen(name) + 2;
    char *p = malloc(n);
    if (!p)
        die(1, "out of memory");
    snprintf(p, n, "%s/%s", dir, name);
    return p;
}

static void make_dirs(const char *dir)
{
    char *p = strdup(dir);
    if (!p)
        die(1, "out of memory");
    for (char *s = p + 1;; s++) {
        if (*s == '/' || *s == '\0') {
            char keep = *s;
            *s = '\0';
            if (mkdir(p, 0777) != 0 && errno != EEXIST)
                die(1, "%s: cannot create: %s", p, strerror(errno));
            *s = keep;
            if (!keep)
                break;
        }
    }
    struct stat st;
    if (stat(dir, &st) != 0 || !S_ISDIR(st.st_mode))
        die(1, "%s: not a directory", dir);
    free(p);
}

static FILE *open_text(const char *dir, const char *name, char **path)
{
    *path = join(dir, name);
    FILE *f = fopen(*path, "w");
    if (!f)
        die(1, "%s: cannot write: %s", *path, strerror(errno));
    return f;
}

static void close_text(FILE *f, char *path)
{
    if (ferror(f) | fclose(f))
        die(1, "%s: write failed", path);
    free(path);
}

static void write_image(const char *dir, const char *name, int n, int channels, const float *px, unsigned flags)
{
    char *path = join(dir, name);
    bf_error err;
    if (bf_image_write(path, BF_IMAGE_BY_NAME, n, n, channels, px, flags, &err) != BF_OK)
        die(1, "%s", err.msg);
    free(path);
}

/* A JSON string (the model spec has no control characters; quotes and backslashes are
 * escaped all the same). */
static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fputc('\\', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

/* v in the fewest digits that read back as v. */
static void json_number(FILE *f, double v)
{
    char buf[32];
    for (int digits = 6; digits <= 17; digits++) {
        snprintf(buf, sizeof buf, "%.*g", digits, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    fputs(buf, f);
}

static void write_truth(const options *o, const bf_model *m, const double *x, int nlights)
{
    char *path;
    FILE *f = open_text(o->out, "truth.json", &path);
    fputs("{\"model\": ", f);
    json_string(f, bf_model_spec(m));
    fputs(", \"params\": {", f);
    for (int p = 0; p < bf_model_nparams(m); p++) {
        const bf_param_info *info = bf_model_param(m, p);
        int off = bf_model_param_offset(m, p);
        fprintf(f, "%s", p ? ", " : "");
        json_string(f, info->name);
        fputs(info->color ? ": [" : ": ", f);
        for (int c = 0; c < (info->color ? C : 1); c++) {
            fputs(c ? ", " : "", f);
            json_number(f, x[off + c]);
        }
        fputs(info->color ? "]" : "", f);
    }
    fprintf(f, "}, \"shape\": \"%s\", \"lights\": %d, \"size\": %d, \"layout\": \"%s\", \"texture\": \"%s\"",
            shape_names[o->shape], nlights, o->size, layout_names[o->layout], texture_names[o->checker]);
    if (o->checker)
        fprintf(f, ", \"checker_cells\": %d, \"checker_dark\": %g", CHECKER_CELLS, CHECKER_DARK);
    fprintf(f, ", \"intensities\": \"%s\", \"gain\": ", intensity_names[o->random_intensities]);
    json_number(f, o->gain);
    fputs(", \"noise\": ", f);
    json_number(f, o->noise);
    fprintf(f, ", \"seed\": %llu}\n", (unsigned long long)o->seed);
    close_text(f, path);
}

/* --- the stack -------------------------------------------------------------------------- */

static void make_stack(const options *o)
{
    bf_error err;
    bf_model *m;
    if (bf_model_new(o->model, C, &m, &err) != BF_OK)
        die(2, "--model: %s", err.msg);
    int P = bf_model_nvalues(m);
    double *x = malloc((size_t)P * sizeof *x), *x_dark = malloc((size_t)P * sizeof *x_dark);
    if (!x || !x_dark)
        die(1, "out of memory");
    parse_params(m, o->params, x);
    memcpy(x_dark, x, (size_t)P * sizeof *x);
    if (o->checker && !scale_diffuse(m, x_dark, CHECKER_DARK))
        die(2, "--texture checker: %s has no diffuse colour", bf_model_name(m));

    double lights[MAX_LIGHTS][3], E[MAX_LIGHTS][C];
    int K = make_lights(o->lights, lights);
    rng r = {o->seed};
    for (int k = 0; k < K; k++)
        for (int c = 0; c < C; c++)
            E[k][c] = o->random_intensities ? 0.8 + 0.8 * uniform01(&r) : 1.0;

    /* The pixels in the mask: their normals, local view directions and checker cells. */
    const int N = o->size;
    const size_t npix = (size_t)N * (size_t)N;
    size_t *where = malloc(npix * sizeof *where);
    double *normal = malloc(3 * npix * sizeof *normal), *V = malloc(3 * npix * sizeof *V),
           *L = malloc(3 * npix * sizeof *L);
    unsigned char *dark = calloc(npix, 1);
    float *mask = calloc(npix, sizeof *mask), *nimg = calloc(3 * npix, sizeof *nimg),
          *img = malloc(3 * npix * sizeof *img);
    double *val = malloc(3 * npix * sizeof *val), *val_dark = malloc(3 * npix * sizeof *val_dark);
    if (!where || !normal || !V || !L || !dark || !mask || !nimg || !img || !val || !val_dark)
        die(1, "out of memory");
    size_t np = 0;
    const double view[3] = {0.0, 0.0, 1.0}, half = 0.5 * N;
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            double px = (i + 0.5 - half) / half, py = -(j + 0.5 - half) / half, n[3];
            if (!shape_normal(o->shape, px, py, n))
                continue;
            size_t q = (size_t)j * N + i;
            where[np] = q;
            memcpy(normal + 3 * np, n, sizeof n);
            to_local(n, view, V + 3 * np);
            dark[np] = o->checker && ((i * CHECKER_CELLS / N + j * CHECKER_CELLS / N) & 1);
            mask[q] = 1.0f;
            for (int c = 0; c < 3; c++)
                nimg[3 * q + c] = (float)n[c];
            np++;
        }

    make_dirs(o->out);
    write_image(o->out, "mask.png", N, 1, mask, BF_IMAGE_CODES);
    write_image(o->out, "normals_true.exr", N, 3, nimg, 0);

    const int diligent = o->layout == LAYOUT_DILIGENT;
    char *list_path, *dir_path, *int_path;
    FILE *list = open_text(o->out, diligent ? "filenames.txt" : "stack.json", &list_path);
    FILE *fdir = diligent ? open_text(o->out, "light_directions.txt", &dir_path) : NULL;
    FILE *fint = diligent ? open_text(o->out, "light_intensities.txt", &int_path) : NULL;
    if (!diligent)
        fputs("{\n  \"images\": [\n", list);
    for (int k = 0; k < K; k++) {
        const double *l = lights[k];
        for (size_t p = 0; p < np; p++)
            to_local(normal + 3 * p, l, L + 3 * p);
        bf_geometry *g;
        if (np && bf_geometry_from_vectors(np, L, V, &g, &err) != BF_OK)
            die(1, "%s", err.msg);
        if (np) {
            bf_model_eval(m, x, g, val, NULL);
            if (o->checker)
                bf_model_eval(m, x_dark, g, val_dark, NULL);
            bf_geometry_free(g);
        }
        memset(img, 0, 3 * npix * sizeof *img);
        for (size_t p = 0; p < np; p++) {
            double cosl = L[3 * p + 2] > 0.0 ? L[3 * p + 2] : 0.0;
            const double *f = dark[p] ? val_dark : val;
            for (int c = 0; c < C; c++) {
                double v = E[k][c] * f[C * p + c] * cosl * o->gain;
                if (o->noise > 0.0)
                    v += gaussian(&r) * (o->noise * v + o->noise * 1e-3);
                if (diligent) /* clipped to [0, 1]: a clipped value becomes code 65535, saturated */
                    v = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
                img[3 * where[p] + c] = (float)v;
            }
        }
        char name[32];
        snprintf(name, sizeof name, diligent ? "%03d.png" : "light_%03d.exr", diligent ? k + 1 : k);
        write_image(o->out, name, N, 3, img, diligent ? BF_IMAGE_CODES | BF_IMAGE_16BIT : 0);
        if (diligent) {
            fprintf(list, "%s\n", name);
            fprintf(fdir, "%.9g %.9g %.9g\n", l[0], l[1], l[2]);
            fprintf(fint, "%.9g %.9g %.9g\n", E[k][0], E[k][1], E[k][2]);
        } else {
            fprintf(list,
                    "    {\"file\": \"%s\", \"light\": {\"direction\": [%.9g, %.9g, %.9g], "
                    "\"intensity\": [%.9g, %.9g, %.9g]}, \"exposure\": 1}%s\n",
                    name, l[0], l[1], l[2], E[k][0], E[k][1], E[k][2], k + 1 < K ? "," : "");
        }
    }
    if (!diligent)
        fprintf(list,
                "  ],\n  \"camera\": {\"type\": \"orthographic\", \"pixel_size\": %.17g},\n"
                "  \"mask\": \"mask.png\",\n  \"transfer\": \"linear\",\n  \"scale\": 1\n}\n",
                2.0 / N);
    close_text(list, list_path);
    if (diligent) {
        close_text(fdir, dir_path);
        close_text(fint, int_path);
    }
    write_truth(o, m, x, K);

    free(where);
    free(normal);
    free(V);
    free(L);
    free(dark);
    free(mask);
    free(nimg);
    free(img);
    free(val);
    free(val_dark);
    free(x);
    free(x_dark);
    bf_model_free(m);
}

int main(int argc, char **argv)
{
    options o = {"lambert", NULL, NULL, SHAPE_SPHERE, LIGHTS_DILIGENT96, LAYOUT_DILIGENT, 0, 0, 64, 1.0, 0.0, 1};
    static const struct option longs[] = {
        {"model", required_argument, NULL, 'm'},   {"params", required_argument, NULL, 'p'},
        {"shape", required_argument, NULL, 's'},   {"size", required_argument, NULL, 'n'},
        {"lights", required_argument, NULL, 'l'},  {"intensities", required_argument, NULL, 'i'},
        {"gain", required_argument, NULL, 'g'},    {"noise", required_argument, NULL, 'e'},
        {"seed", required_argument, NULL, 'r'},    {"layout", required_argument, NULL, 'y'},
        {"texture", required_argument, NULL, 't'}, {"out", required_argument, NULL, 'o'},
        {"help", no_argument, NULL, 'h'},          {NULL, 0, NULL, 0}};
    opterr = 0;
    int ch;
    while ((ch = getopt_long(argc, argv, ":o:h", longs, NULL)) != -1) {
        switch (ch) {
        case 'm': o.model = optarg; break;
        case 'p': o.params = optarg; break;
        case 's': o.shape = choice("shape", optarg, shape_names); break;
        case 'n': o.size = (int)whole_arg("size", optarg, 4, 8192); break;
        case 'l': o.lights = choice("lights", optarg, light_names); break;
        case 'i': o.random_intensities = choice("intensities", optarg, intensity_names); break;
        case 'g': o.gain = number_arg("gain", optarg, 1e-300, 1e300); break;
        case 'e': o.noise = number_arg("noise", optarg, 0.0, 1e3); break;
        case 'r': o.seed = (uint64_t)whole_arg("seed", optarg, 0, 9007199254740992.0); break;
        case 'y': o.layout = choice("layout", optarg, layout_names); break;
        case 't': o.checker = choice("texture", optarg, texture_names); break;
        case 'o': o.out = optarg; break;
        case 'h': usage(); return 0;
        case ':': die(2, "%s needs a value", argv[optind - 1]); break;
        default: die(2, "unknown option %s (see --help)", argv[optind - 1]); break;
        }
    }
    if (optind < argc)
        die(2, "unexpected argument '%s' (see --help)", argv[optind]);
    if (!o.out || !*o.out)
        die(2, "-o DIR is required");
    make_stack(&o);
    return 0;
}
