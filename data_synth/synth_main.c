/* brdfit-synth: a model's values at a direction pattern, with optional noise, written
 * as CSV or as a MERL .binary table. Exit status: 0 done, 1 bad input (parameter file,
 * output), 2 bad usage. Every error is one line on stderr; a failed run writes nothing. */
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/tool.h"
#include "brdfit/model.h"
#include "brdfit/samples.h"
#include "brdfit/version.h"
#include "synth.h"
#include "synth_cli.h"

#define PROG "brdfit-synth"
#define MAX_INCIDENCE 256

static int usage_error(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;
static int usage_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, PROG ": ");
    vfprintf(stderr, fmt, ap);
    fprintf(stderr, " (try " PROG " --help)\n");
    va_end(ap);
    return 2;
}

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno == ERANGE || !isfinite(v))
        return -1;
    *out = v;
    return 0;
}

static int parse_u64(const char *s, unsigned long long *out)
{
    if (*s < '0' || *s > '9') /* strtoull would accept a sign */
        return -1;
    char *end;
    errno = 0;
    unsigned long long v = strtoull(s, &end, 10);
    if (*end || errno == ERANGE)
        return -1;
    *out = v;
    return 0;
}

/* "0,30,60" -> values; returns the count or -1. */
static int parse_list(const char *s, double *v, int max)
{
    int n = 0;
    char buf[64];
    for (const char *p = s;;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (n == max || len == 0 || len >= sizeof buf)
            return -1;
        memcpy(buf, p, len);
        buf[len] = '\0';
        if (parse_double(buf, &v[n++]) != 0)
            return -1;
        if (!comma)
            return n;
        p = comma + 1;
    }
}

/* Where the samples go: --count for the patterns that take one, --incidence and --step
 * for gonio. Returns 0, or 2 after a usage message. */
static int build_directions(const synth_args *a, bf_synth_options *o, double *incidence)
{
    const char *pname = bf_synth_pattern_name(o->pattern);
    if (bf_synth_pattern_fixed_count(o->pattern)) {
        if (a->count)
            return usage_error("--count does not apply to pattern %s, whose settings fix the count", pname);
    } else {
        unsigned long long n;
        if (!a->count)
            return usage_error("--count N is required for pattern %s", pname);
        if (parse_u64(a->count, &n) != 0 || n < 1 || n > (unsigned long long)SIZE_MAX / 64)
            return usage_error("--count '%s' is not a positive integer in range", a->count);
        o->count = (size_t)n;
    }
    if (o->pattern != BF_SYNTH_GONIO && (a->incidence || a->step))
        return usage_error("--incidence and --step apply to pattern gonio only, not %s", pname);
    if (o->pattern != BF_SYNTH_GONIO)
        return 0;
    int ni = parse_list(a->incidence ? a->incidence : "0,30,60", incidence, MAX_INCIDENCE);
    if (ni < 0)
        return usage_error("--incidence '%s' is not a comma-separated list of angles in degrees", a->incidence);
    for (int k = 0; k < ni; k++)
        if (!(incidence[k] >= 0.0 && incidence[k] < 90.0))
            return usage_error("--incidence '%s': every angle must be in [0, 90) degrees", a->incidence);
    double step = 5.0;
    if (a->step && (parse_double(a->step, &step) != 0 || !(step >= 1e-3 && step <= 90.0)))
        return usage_error("--step '%s' must be a number of degrees in [0.001, 90]", a->step);
    o->gonio.incidence = incidence;
    o->gonio.n_incidence = ni;
    o->gonio.step = step;
    return 0;
}

/* --outliers FRACTION[,FACTOR]. Returns 0, or 2 after a usage message. */
static int build_outliers(const char *s, bf_synth_noise *nz)
{
    char buf[64];
    snprintf(buf, sizeof buf, "%s", s);
    char *comma = strchr(buf, ',');
    if (comma)
        *comma = '\0';
    if (strlen(s) >= sizeof buf || parse_double(buf, &nz->outlier_fraction) != 0 ||
        !(nz->outlier_fraction >= 0.0 && nz->outlier_fraction <= 1.0) ||
        (comma && (parse_double(comma + 1, &nz->outlier_factor) != 0 || !(nz->outlier_factor > 0.0))))
        return usage_error("--outliers '%s' must be FRACTION in [0, 1], optionally ,FACTOR > 0", s);
    return 0;
}

/* The noise: --noise alone means relative noise, --counts alone photon noise. Returns
 * 0, or 2 after a usage message. */
static int build_noise(const synth_args *a, bf_synth_noise *nz)
{
    int model = a->noise_model ? bf_synth_noise_model_from_name(a->noise_model)
                : a->noise     ? BF_NOISE_RELATIVE
                : a->counts    ? BF_NOISE_PHOTON
                               : BF_NOISE_NONE;
    if (model < 0)
        return usage_error("unknown noise model '%s' (relative, additive, photon, none)", a->noise_model);
    nz->model = (bf_synth_noise_model)model;
    double level = 0.0;
    if (a->noise && (parse_double(a->noise, &level) != 0 || level < 0.0))
        return usage_error("--noise '%s' must be a number >= 0", a->noise);
    if (a->counts && nz->model != BF_NOISE_PHOTON)
        return usage_error("--counts applies to --noise-model photon only");
    switch (nz->model) {
    case BF_NOISE_NONE:
        if (a->noise)
            return usage_error("--noise-model none takes no --noise");
        break;
    case BF_NOISE_RELATIVE:
    case BF_NOISE_ADDITIVE:
        if (!a->noise)
            return usage_error("--noise-model %s needs --noise S", a->noise_model);
        nz->level = level;
        break;
    case BF_NOISE_PHOTON:
        if (!!a->noise == !!a->counts)
            return usage_error("--noise-model photon needs either --noise S or --counts K");
        if (a->counts && (parse_double(a->counts, &nz->counts) != 0 || !(nz->counts > 0.0)))
            return usage_error("--counts '%s' must be a number > 0", a->counts);
        if (a->noise && (!(level > 0.0) || !isfinite(nz->counts = 1.0 / level / level)))
            return usage_error("--noise '%s' must be > 0 for the photon model", a->noise);
        break;
    }
    if (a->outliers && build_outliers(a->outliers, nz) != 0)
        return 2;
    nz->clamp = a->clamp;
    return 0;
}

/* Fills o from the parsed strings; returns 0, or 2 after a usage message. */
static int build_options(const synth_args *a, bf_synth_options *o, double *incidence)
{
    int p = bf_synth_pattern_from_name(a->pattern);
    if (p < 0)
        return usage_error("unknown pattern '%s' (uniform, cosine, stratified, random, gonio, merl)", a->pattern);
    o->pattern = (bf_synth_pattern)p;
    if (build_directions(a, o, incidence) != 0)
        return 2;
    if (a->seed) {
        unsigned long long seed;
        if (parse_u64(a->seed, &seed) != 0)
            return usage_error("--seed '%s' is not an unsigned 64-bit integer", a->seed);
        o->seed = (uint64_t)seed;
    }
    if (build_noise(a, &o->noise) != 0)
        return 2;
    /* The output's format must suit the pattern: only merl has a cell grid. */
    const char *pname = bf_synth_pattern_name(o->pattern);
    bf_format f = strcmp(a->out, "-") ? bf_format_for_writing(a->out) : BF_FORMAT_CSV;
    if (f == BF_FORMAT_AUTO)
        return usage_error("-o %s: the output must end in .csv or .binary", a->out);
    if (o->pattern == BF_SYNTH_MERL && f != BF_FORMAT_MERL)
        return usage_error("pattern merl writes a MERL table: -o must end in .binary, not '%s'", a->out);
    if (o->pattern != BF_SYNTH_MERL && f == BF_FORMAT_MERL)
        return usage_error("a MERL .binary output needs --pattern merl (%s has no cell grid)", pname);
    return 0;
}

/* brdfit-synth takes no operands: a stray word is bad usage, said as its other errors are. */
static int take_operand(void *ctx, const char *value, const char *cmd)
{
    (void)ctx, (void)cmd;
    usage_error("unexpected argument '%s'", value);
    return -1;
}

/* Takes the parsed command line into a (each valued option once: synth_cli.c) and checks
 * that the required ones are there. Returns 0, or 2 after a usage message. */
static int take_args(const cli_args *args, synth_args *a)
{
    void *const targets[] = {a, a};
    if (cli_take(&cli_synth, targets, CLI_COUNT(targets), args, take_operand, NULL, PROG) < 0)
        return 2;
    if (!a->params)
        return usage_error("--params P.json is required");
    if (!a->pattern)
        return usage_error("--pattern is required");
    if (!a->out)
        return usage_error("-o OUT.csv|OUT.binary is required");
    return 0;
}

/* Reads the parameter file, generates, writes: the exit status (0 or 1). */
static int generate(const synth_args *a, const bf_synth_options *o)
{
    bf_error err;
    bf_model *m = NULL;
    double *x = NULL;
    bf_samples *s = NULL;
    int status = 1;
    if (bf_params_read(a->params, &m, &x, &err) != BF_OK) {
        fprintf(stderr, PROG ": %s\n", err.msg);
        goto done;
    }
    if (o->pattern == BF_SYNTH_MERL && bf_model_channels(m) != 3) {
        fprintf(stderr, PROG ": %s: pattern merl needs a 3-channel (RGB) model, the file gives %d\n", a->params,
                bf_model_channels(m));
        goto done;
    }
    if (bf_synth_generate(m, x, o, &s, &err) != BF_OK ||
        bf_samples_write(s, a->out, strcmp(a->out, "-") ? BF_FORMAT_AUTO : BF_FORMAT_CSV, &err) != BF_OK) {
        fprintf(stderr, PROG ": %s\n", err.msg);
        goto done;
    }
    status = 0;
done:
    bf_samples_free(s);
    bf_model_free(m);
    free(x);
    return status;
}

int main(int argc, char **argv)
{
    synth_args a = {0};
    /* A run ended by a signal leaves no temporary. */
    bf_remove_temporaries_on_signals();
    if (argc == 2 && !strcmp(argv[1], "--version")) {
        printf(PROG " %s\n", bf_version());
        return 0;
    }
    cli_args args;
    int p = cli_parse(&cli_synth, argc, argv, &args);
    if (p != CLI_OK)
        return p == CLI_EXIT ? 0 : 2;
    int rc = take_args(&args, &a);
    cli_args_free(&args);
    if (rc != 0)
        return rc;

    bf_synth_options o = {0};
    double incidence[MAX_INCIDENCE];
    if ((rc = build_options(&a, &o, incidence)) != 0)
        return rc;
    bf_error err;
    /* Never over the parameter file, and a writable output before any work. */
    const bf_path_use in[] = {{"--params file", a.params}}, out[] = {{"-o", a.out}};
    if (bf_outputs_check(in, 1, out, 1, &err) != BF_OK) {
        fprintf(stderr, PROG ": %s\n", err.msg);
        return err.code == BF_ERR_ARG ? 2 : 1;
    }
    return generate(&a, &o);
}
