/* The table of run options (brdfit/options.h): every option declared once, with how it
 * is taken and read. The command line's tables, --help, man pages and completion, and
 * the Python package's keywords and help are made from these rows. */
#include "run_options.h"
#include "tradeoff_options.h"

#include "brdfit/io.h"
#include "brdfit/tool.h"

#include <errno.h>
#include <float.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define STR_(x) #x
#define STR(x) STR_(x)
#define AT(field) offsetof(bf_options, field)

/* The option's name as the set's messages spell it ("--color" or "color"). */
#define SPELL(o, r, buf) option_spelled((o), (r)->d.name, (buf), sizeof(buf))

/* ---- Reading ------------------------------------------------------------------------ */

static bf_status set_format(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    (void)r;
    return bf_format_parse(v, &o->format, err);
}

static void get_format(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%s", o->format == BF_FORMAT_AUTO ? "" : bf_format_name(o->format));
}

/* Four comma-separated names, none empty. */
static bf_status set_angles(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    const char *p = v ? v : "";
    int commas = 0, ok = *p != '\0';
    for (const char *c = p; *c; c++)
        if (*c == ',') {
            commas++;
            ok &= c != p && c[1] != '\0' && c[-1] != ',';
        }
    if (!ok || commas != 3)
        return bf_fail(err, BF_ERR_ARG, "%s needs four comma-separated column names, got '%s'", SPELL(o, r, name), p);
    return option_keep_text(o, r, p, err);
}

/* ---- What spectral data becomes ------------------------------------------------------- */

/* --rgb, --color, --rgb-bands and --luminance each choose it, so two of them exclude each
 * other (--rgb with --color srgb repeats one choice). */
static bf_status choose_spectral(bf_options *o, const option_row *r, bf_color color, bf_error *err)
{
    int row = option_row_index(r);
    if (o->spectral_row >= 0 && o->spectral_row != row) {
        int same = color != BF_COLOR_NONE && o->color == color;
        if (!same) {
            char a[64], b[64];
            return bf_fail(err, BF_ERR_ARG, "%s and %s exclude each other",
                           option_spelled(o, option_rows[o->spectral_row].d.name, a, sizeof a), SPELL(o, r, b));
        }
    }
    o->spectral_row = row;
    if (color != BF_COLOR_NONE)
        o->color = color;
    else if (!strcmp(r->d.name, "rgb_bands"))
        o->to_bands = 1;
    else
        o->to_luminance = 1;
    return BF_OK;
}

/* A spectral flag turned off: its choice undone, if it was this one's. */
static void unchoose_spectral(bf_options *o, const option_row *r)
{
    if (o->spectral_row != option_row_index(r))
        return;
    o->spectral_row = -1;
    o->color = BF_COLOR_NONE;
    o->to_bands = o->to_luminance = 0;
}

static bf_status set_spectral_flag(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    if (v && (!strcmp(v, "false") || !strcmp(v, "0"))) {
        unchoose_spectral(o, r);
        return BF_OK;
    }
    if (v && strcmp(v, "true") && strcmp(v, "1"))
        return bf_fail(err, BF_ERR_ARG, "%s is on or off (true or false), got '%s'", SPELL(o, r, name), v);
    return choose_spectral(o, r, !strcmp(r->d.name, "rgb") ? BF_COLOR_SRGB : BF_COLOR_NONE, err);
}

static void get_spectral_flag(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    snprintf(buf, size, "%s", o->spectral_row == option_row_index(r) ? "true" : "false");
}

static bf_status set_color(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    bf_color c;
    if (bf_color_parse(v, &c, NULL) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s takes srgb, acescg or xyz, got '%s'", SPELL(o, r, name), v ? v : "");
    return choose_spectral(o, r, c, err);
}

static void get_color(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%s", o->color == BF_COLOR_NONE ? "" : bf_color_name(o->color));
}

static bf_status set_illuminant(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    if (bf_illuminant_parse(v, &o->illuminant, NULL) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s takes d65, e, a or d50, got '%s'", SPELL(o, r, name), v ? v : "");
    return BF_OK;
}

static void get_illuminant(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%s", bf_illuminant_name(o->illuminant));
}

/* ---- Preparing ----------------------------------------------------------------------- */

static const char *const negative_names[] = {"keep", "drop", "clamp"};

static bf_status set_negative(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    for (int k = 0; v && k < 3; k++)
        if (!strcmp(v, negative_names[k])) {
            o->negative = (bf_negative)k;
            return BF_OK;
        }
    return bf_fail(err, BF_ERR_ARG, "%s takes keep, drop or clamp, got '%s'", SPELL(o, r, name), v ? v : "");
}

static void get_negative(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%s", negative_names[o->negative]);
}

/* A count, or "all" (over a preset's); 0 is not a count. */
static bf_status set_subsample(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    long n = 0;
    if (!v || (strcmp(v, "all") && !bf_parse_long(v, 1, 1000000000000L, &n)))
        return bf_fail(err, BF_ERR_ARG, "%s needs a sample count of at least 1 or 'all', got '%s'", SPELL(o, r, name),
                       v ? v : "");
    o->subsample = (size_t)n; /* 0: every sample */
    return BF_OK;
}

static void get_subsample(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    bf_prep p;
    options_prep_get(o, &p);
    if (p.subsample)
        snprintf(buf, size, "%zu", p.subsample);
    else
        snprintf(buf, size, "all");
}

/* Any unsigned 64-bit integer, digits only. */
static bf_status set_seed(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64], *end = NULL;
    unsigned long long n = 0;
    int ok = v && *v >= '0' && *v <= '9';
    if (ok) {
        errno = 0;
        n = strtoull(v, &end, 10);
        ok = !*end && !errno;
    }
    if (!ok)
        return bf_fail(err, BF_ERR_ARG, "%s needs an integer from 0 to 18446744073709551615, got '%s'",
                       SPELL(o, r, name), v ? v : "");
    o->seed = (uint64_t)n;
    return BF_OK;
}

static void get_seed(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%llu", (unsigned long long)o->seed);
}

/* ---- Fitting -------------------------------------------------------------------------- */

static bf_status set_residual(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    bf_error e;
    if (bf_residual_parse(v, &o->residual, &e) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s: %s", SPELL(o, r, name), e.msg);
    return BF_OK;
}

static void get_residual(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    bf_fit_options f;
    options_fit_get(o, &f);
    snprintf(buf, size, "%s", bf_residual_name(f.objective.residual));
}

static bf_status set_loss(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    bf_error e;
    bf_loss l;
    if (bf_loss_parse(v, &l, &e) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s: %s", SPELL(o, r, name), e.msg);
    bf_status rc = option_keep_text(o, r, v, err);
    if (rc == BF_OK)
        o->loss = l;
    return rc;
}

static void get_loss(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    const char *t = o->text[option_row_index(r)];
    snprintf(buf, size, "%s", t ? t : "none");
}

/* reference FILE|DIR: one more, kept in the set's log (option_list_value) and read by the
 * comparison; a path may hold commas, so the option repeats rather than splits. */
static bf_status set_reference(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    if (!v || !*v)
        return bf_fail(err, BF_ERR_ARG, "%s needs a file or a folder", SPELL(o, r, name));
    return BF_OK;
}

static void get_references(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    size_t used = 0;
    buf[0] = '\0';
    const char *v;
    for (int k = 0; (v = option_list_value(o, r->d.name, k)) != NULL; k++) {
        int n = snprintf(buf + used, size - used, "%s%s", k ? "," : "", v);
        if (n < 0 || (size_t)n >= size - used)
            return;
        used += (size_t)n;
    }
}

/* fix NAME=VALUE or bound NAME=LO:HI: one more override. */
static bf_status set_override(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    bf_error e;
    bf_override ov;
    int fix = !strcmp(r->d.name, "fix");
    if ((fix ? bf_override_parse_fix(v, &ov, &e) : bf_override_parse_bound(v, &ov, &e)) != BF_OK)
        return bf_fail(err, e.code, "%s: %s", SPELL(o, r, name), e.msg);
    bf_override *grown = realloc(o->overrides, (size_t)(o->noverrides + 1) * sizeof *grown);
    if (!grown)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    o->overrides = grown;
    o->overrides[o->noverrides++] = ov;
    return BF_OK;
}

static void get_overrides(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    int fix = !strcmp(r->d.name, "fix");
    size_t used = 0;
    buf[0] = '\0';
    for (int k = 0; k < o->noverrides; k++) {
        const bf_override *ov = &o->overrides[k];
        if (ov->fix != fix)
            continue;
        char entry[128], lo[32], hi[32];
        if (ov->channel >= 0)
            snprintf(entry, sizeof entry, "%s[%d]", ov->name, ov->channel);
        else
            snprintf(entry, sizeof entry, "%s", ov->name);
        int n = fix ? snprintf(buf + used, size - used, "%s%s=%s", used ? "," : "", entry,
                               bf_format_double(ov->value, lo, sizeof lo))
                    : snprintf(buf + used, size - used, "%s%s=%s:%s", used ? "," : "", entry,
                               bf_format_double(ov->lo, lo, sizeof lo), bf_format_double(ov->hi, hi, sizeof hi));
        if (n < 0 || (size_t)n >= size - used)
            return;
        used += (size_t)n;
    }
}

static bf_status set_backend(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    if (bf_backend_parse(v, &o->backend, NULL) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s takes ceres or nlopt, got '%s'", SPELL(o, r, name), v ? v : "");
    return BF_OK;
}

static void get_backend(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    bf_fit_options f;
    options_fit_get(o, &f);
    snprintf(buf, size, "%s", bf_backend_name(f.solver.backend));
}

static void get_algorithm(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    bf_fit_options f;
    options_fit_get(o, &f);
    snprintf(buf, size, "%s", f.solver.algorithm ? f.solver.algorithm : "");
}

/* The effective values of the search's counts (a preset's where the user gave none). */
static void get_fit_int(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    bf_fit_options f;
    options_fit_get(o, &f);
    int v = !strcmp(r->d.name, "starts") ? f.starts : !strcmp(r->d.name, "screen") ? f.screen : f.solver.max_iterations;
    snprintf(buf, size, "%d", v);
}

/* N (at least 64) or off. */
static bf_status set_presolve(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    long n = -1; /* off */
    if (!v || (strcmp(v, "off") && !bf_parse_long(v, 64, 1000000000, &n)))
        return bf_fail(err, BF_ERR_ARG, "%s needs a sample count of at least 64 or 'off', got '%s'", SPELL(o, r, name),
                       v ? v : "");
    o->presolve = n;
    return BF_OK;
}

static void get_presolve(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    if (o->presolve < 0)
        snprintf(buf, size, "off");
    else if (o->presolve == 0)
        snprintf(buf, size, "auto");
    else
        snprintf(buf, size, "%ld", o->presolve);
}

static bf_status set_accuracy(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    if (bf_fit_accuracy_parse(v, &o->accuracy, NULL) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s takes fast, balanced or best, got '%s'", SPELL(o, r, name), v ? v : "");
    return BF_OK;
}

static void get_accuracy(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%s", bf_fit_accuracy_name(o->accuracy));
}

/* ---- Ranking, comparing, selecting ----------------------------------------------------- */

static bf_status set_rank(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    bf_error e;
    if (bf_compare_rank_parse(v, &o->rank_by, &e) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s: %s", SPELL(o, r, name), e.msg);
    return BF_OK;
}

static void get_rank(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%s", bf_compare_rank_name(o->rank_by));
}

static void get_folds(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%d", o->folds);
}

static bf_status set_metric(bf_options *o, const option_row *r, const char *v, bf_error *err)
{
    char name[64];
    bf_error e;
    if (bf_compare_metric_parse(v, &o->metric, &e) != BF_OK)
        return bf_fail(err, BF_ERR_ARG, "%s: %s", SPELL(o, r, name), e.msg);
    return BF_OK;
}

static void get_metric(const bf_options *o, const option_row *r, char *buf, size_t size)
{
    (void)r;
    snprintf(buf, size, "%s", bf_compare_metric_name(o->metric));
}

/* ---- The rows ------------------------------------------------------------------------- */

#define DATA_TASKS (BF_TASK_READ | BF_TASK_FIT | BF_TASK_COMPARE | BF_TASK_SELECT | BF_TASK_TRADEOFF)
#define FIT_TASKS (BF_TASK_FIT | BF_TASK_COMPARE | BF_TASK_SELECT | BF_TASK_TRADEOFF)
#define RANK_TASKS (BF_TASK_COMPARE | BF_TASK_SELECT)

/* Each row: name, group, tasks, type, arg, help, complete, choices, default, lo, hi,
 * range in words; then its set and get (NULL: by type), field, flag value, given bit. */
#define ROW(NAME, GROUP, TASKS, TYPE, ARG, HELP, COMPLETE, CHOICES, DEF, LO, HI, RANGE)                                \
    .d = {NAME, GROUP, TASKS, TYPE, ARG, HELP, COMPLETE, CHOICES, DEF, LO, HI, RANGE}

/* The default ranking differs (compare: bic, select: error), hence two rows. */
#define RANK_HELP(def)                                                                                                 \
    "what to rank by (default " def "): a criterion of each fit's\n"                                                   \
    "likelihood (docs/criteria.md), the cross-validated error of\n"                                                    \
    "the fitted objective, or the --error metric"

/* The counts' limits: beyond these a run would take days or a thread per core many
 * times over, which is never what was meant. Options an --accuracy preset gives way to
 * carry their BF_FIT_GIVEN_* bit (bf_fit_options_apply_accuracy). The names (--values,
 * --weight, --grid, --channels, --scene) are kept as given and checked when the data is
 * read. */
const option_row option_rows[] = {
    /* Reading. */
    {ROW("format", "reading", DATA_TASKS, BF_OPTION_CHOICE, "csv|merl|cornell|alta|rgl|mbsdf",
         "file format (default: by extension, then content)", NULL, "csv|merl|cornell|alta|rgl|mbsdf", NULL, 0, 0,
         NULL),
     .set = set_format, .get = get_format},
    {ROW("grid", "reading", DATA_TASKS, BF_OPTION_TEXT, "merl|uniform:N|FILE",
         "evaluate an RGL .bsdf or .mbsdf file at these directions\ninstead of its measured points "
         "(docs/formats.md)",
         NULL, NULL, NULL, 0, 0, NULL)},
    {ROW("angles", "reading", DATA_TASKS, BF_OPTION_TEXT, "TI,PI,TO,PO",
         "CSV angle column names (default theta_i,phi_i,theta_o,phi_o)", NULL, NULL, "theta_i,phi_i,theta_o,phi_o", 0,
         0, NULL),
     .set = set_angles},
    {ROW("radians", "reading", DATA_TASKS, BF_OPTION_FLAG, NULL, "CSV angles are in radians (default degrees)", NULL,
         NULL, NULL, 0, 0, NULL),
     .at = AT(radians), .flag_on = 1},
    {ROW("values", "reading", DATA_TASKS, BF_OPTION_TEXT, "COL,...",
         "CSV value columns (default: all but angles and weight)", NULL, NULL, NULL, 0, 0, NULL)},
    {ROW("weight", "reading", DATA_TASKS, BF_OPTION_TEXT, "COL", "CSV weight column (default: 'weight' if present)",
         NULL, NULL, NULL, 0, 0, NULL)},
    /* Preprocessing. */
    {ROW("channels", "preprocessing", DATA_TASKS, BF_OPTION_TEXT, "NAME|INDEX,...",
         "keep these channels, in this order", NULL, NULL, NULL, 0, 0, NULL)},
    {ROW("rgb", "preprocessing", DATA_TASKS, BF_OPTION_FLAG, NULL,
         "spectral data to linear sRGB (CIE 1931 2 deg, D65; --color srgb)", NULL, NULL, NULL, 0, 0, NULL),
     .set = set_spectral_flag, .get = get_spectral_flag},
    {ROW("color", "preprocessing", DATA_TASKS, BF_OPTION_CHOICE, "srgb|acescg|xyz",
         "spectral data to this colour space (docs/color.md)", NULL, "srgb|acescg|xyz", NULL, 0, 0, NULL),
     .set = set_color, .get = get_color},
    {ROW("illuminant", "preprocessing", DATA_TASKS, BF_OPTION_CHOICE, "d65|e|a|d50",
         "illuminant of --color/--rgb, or of --luminance on spectra (default d65)", NULL, "d65|e|a|d50", "d65", 0, 0,
         NULL),
     .set = set_illuminant, .get = get_illuminant},
    {ROW("rgb_bands", "preprocessing", DATA_TASKS, BF_OPTION_FLAG, NULL,
         "spectral data to three band means (600-700, 500-600,\n400-500 nm; not colorimetric: the old --rgb)", NULL,
         NULL, NULL, 0, 0, NULL),
     .set = set_spectral_flag, .get = get_spectral_flag},
    {ROW("luminance", "preprocessing", DATA_TASKS, BF_OPTION_FLAG, NULL,
         "spectral (CIE Y) or RGB (Rec. 709) data to one channel", NULL, NULL, NULL, 0, 0, NULL),
     .set = set_spectral_flag, .get = get_spectral_flag},
    {ROW("max_theta", "preprocessing", DATA_TASKS, BF_OPTION_NUMBER, "DEG",
         "drop samples with theta_i or theta_o above DEG", NULL, NULL, NULL, DBL_TRUE_MIN, 90.0, "degrees in (0, 90]"),
     .at = AT(max_theta)},
    {ROW("negative", "preprocessing", DATA_TASKS, BF_OPTION_CHOICE, "keep|drop|clamp",
         "negative values (default keep: they are data)", NULL, "keep|drop|clamp", "keep", 0, 0, NULL),
     .set = set_negative, .get = get_negative},
    {ROW("subsample", "preprocessing", DATA_TASKS, BF_OPTION_CHOICE, "N|all",
         "seeded stratified subsample to N samples (all: every one)", NULL, "all", "all", 1, 1e12,
         "a sample count of at least 1 or 'all'"),
     .set = set_subsample, .get = get_subsample, .fit_given = BF_FIT_GIVEN_SUBSAMPLE},
    {ROW("seed", "preprocessing", DATA_TASKS, BF_OPTION_INT, "K",
         "seeds the subsample, the multistart and anything else random (default 0)", NULL, NULL, "0", 0,
         18446744073709551615.0, "an integer from 0 to 18446744073709551615"),
     .set = set_seed, .get = get_seed},
    {ROW("scene", "preprocessing", DATA_TASKS, BF_OPTION_TEXT, "FILE",
         "keep and weight the samples a scene's lights and views use\n(JSON; docs/scenes.md); error is reported "
         "over "
         "them",
         "file", NULL, NULL, 0, 0, NULL)},
    /* Accuracy. The numbers are the library's (brdfit/fit.h), which says why they were
     * chosen. */
    {ROW("accuracy", "accuracy", BF_TASK_FIT | BF_TASK_SELECT, BF_OPTION_CHOICE, "fast|balanced|best",
         "option bundles (explicit options win, in any order):\n"
         "fast: --subsample " STR(
             BF_ACCURACY_FAST_SUBSAMPLE) " --backend ceres --starts 1\n"
                                         "balanced: the defaults (all samples, --backend ceres, automatic "
                                         "starts,\n"
                                         "--screen " STR(
                                             BF_FIT_SCREEN) ")\n"
                                                            "best: all samples, --backend ceres "
                                                            "--starts " STR(BF_ACCURACY_BEST_STARTS) " --screen " STR(
                                                                BF_ACCURACY_BEST_SCREEN) "\n--max-"
                                                                                         "iterations"
                                                                                         " " STR(
                                                                                             BF_ACCURACY_BEST_ITERATIONS),
         NULL, "fast|balanced|best", NULL, 0, 0, NULL),
     .set = set_accuracy, .get = get_accuracy},
    /* Fitting. */
    {ROW("residual", "fitting", FIT_TASKS, BF_OPTION_CHOICE, "linear|cosine|log|cbrt|relative",
         "residual form (default log)", NULL, "linear|cosine|log|cbrt|relative", "log", 0, 0, NULL),
     .set = set_residual, .get = get_residual, .fit_given = BF_FIT_GIVEN_RESIDUAL},
    {ROW("loss", "fitting", FIT_TASKS, BF_OPTION_CHOICE, "none|huber|cauchy|soft_l1|arctan[:SCALE]",
         "robust loss (default none)", "none|huber|cauchy|soft_l1|arctan", "none|huber|cauchy|soft_l1|arctan", "none",
         0, 0, NULL),
     .set = set_loss, .get = get_loss},
    {ROW("fix", "fitting", FIT_TASKS, BF_OPTION_LIST, "NAME=VALUE",
         "hold a parameter (NAME or NAME[c]) at VALUE (repeatable)", NULL, NULL, NULL, 0, 0, NULL),
     .set = set_override, .get = get_overrides},
    {ROW("bound", "fitting", FIT_TASKS, BF_OPTION_LIST, "NAME=LO:HI", "narrow a parameter's bounds (repeatable)", NULL,
         NULL, NULL, 0, 0, NULL),
     .set = set_override, .get = get_overrides},
    {ROW("solid_angle", "fitting", FIT_TASKS, BF_OPTION_FLAG, NULL, "weight MERL cells by their solid angle", NULL,
         NULL, NULL, 0, 0, NULL),
     .at = AT(solid_angle), .flag_on = 1},
    {ROW("no_weights", "fitting", FIT_TASKS, BF_OPTION_FLAG, NULL, "ignore the samples' own weights", NULL, NULL, NULL,
         0, 0, NULL),
     .at = AT(no_weights), .flag_on = 1},
    {ROW("constrain_energy", "fitting", FIT_TASKS, BF_OPTION_FLAG, NULL,
         "energy conservation as a constraint (the methods that take one:\nbrdfit methods)", NULL, NULL, NULL, 0, 0,
         NULL),
     .at = AT(use_constraint), .flag_on = 1},
    /* Optimizer. */
    {ROW("backend", "optimizer", FIT_TASKS, BF_OPTION_CHOICE, "ceres|nlopt", "(default ceres)", NULL, "ceres|nlopt",
         "ceres", 0, 0, NULL),
     .set = set_backend, .get = get_backend, .fit_given = BF_FIT_GIVEN_BACKEND},
    {ROW("algorithm", "optimizer", FIT_TASKS, BF_OPTION_TEXT, "NAME",
         "a method of the back end (default: the back end's own);\nbrdfit methods lists them with what each can do",
         "method", NULL, NULL, 0, 0, NULL),
     .get = get_algorithm, .fit_given = BF_FIT_GIVEN_ALGORITHM},
    {ROW("local", "optimizer", FIT_TASKS, BF_OPTION_TEXT, "NAME", "local method of G_MLSL_LDS (default LD_LBFGS)",
         "local_method", NULL, NULL, 0, 0, NULL)},
    {ROW("max_iterations", "optimizer", FIT_TASKS, BF_OPTION_INT, "N",
         "(default: ceres 100 iterations, nlopt 2000 evaluations)", NULL, NULL, NULL, 1, 10000000, NULL),
     .get = get_fit_int, .at = AT(max_iterations), .fit_given = BF_FIT_GIVEN_MAX_ITERATIONS},
    {ROW("starts", "optimizer", FIT_TASKS, BF_OPTION_INT, "N",
         "starts solved to convergence, the data-driven one first (default:\nautomatic, " STR(BF_FIT_STARTS) " to " STR(
             BF_FIT_STARTS_MAX) " by the data's size; 1: it alone)",
         NULL, NULL, NULL, 1, 10000, NULL),
     .get = get_fit_int, .at = AT(starts), .fit_given = BF_FIT_GIVEN_STARTS},
    {ROW("screen", "optimizer", FIT_TASKS, BF_OPTION_INT, "M",
         "random candidates whose cost on a small subsample chooses the\nother starts, solved there first "
         "(default " STR(BF_FIT_SCREEN) "; 0: the other starts\nare drawn at random and solved on all samples)",
         NULL, NULL, STR(BF_FIT_SCREEN), 0, 10000, NULL),
     .get = get_fit_int, .at = AT(screen), .fit_given = BF_FIT_GIVEN_SCREEN},
    {ROW("presolve", "optimizer", FIT_TASKS, BF_OPTION_CHOICE, "N|off",
         "solve the starts on a seeded stratified subsample of N samples\nfirst (default: " STR(
             BF_FIT_PRESOLVE_SAMPLES) " for data of " STR(BF_FIT_PRESOLVE_MIN) " samples and more)",
         "off", "off", NULL, 64, 1000000000, "a sample count of at least 64 or 'off'"),
     .set = set_presolve, .get = get_presolve},
    {ROW("threads", "optimizer", FIT_TASKS, BF_OPTION_INT, "N", "(default: every core; results do not depend on it)",
         NULL, NULL, NULL, 1, 1024, "an integer from 1 to 1024"),
     .at = AT(threads)},
    /* Ranking. */
    {ROW("rank", "ranking", BF_TASK_COMPARE, BF_OPTION_CHOICE, "bic|aic|aicc|cv|error", RANK_HELP("bic"), NULL,
         "bic|aic|aicc|cv|error", "bic", 0, 0, NULL),
     .set = set_rank, .get = get_rank},
    {ROW("rank", "ranking", BF_TASK_SELECT, BF_OPTION_CHOICE, "bic|aic|aicc|cv|error", RANK_HELP("error"), NULL,
         "bic|aic|aicc|cv|error", "error", 0, 0, NULL),
     .set = set_rank, .get = get_rank},
    {ROW("folds", "ranking", RANK_TASKS, BF_OPTION_INT, "K",
         "folds of --rank cv (default 5, 2 to 20; K more fits per model)", NULL, NULL, "5", 2, BF_CV_MAX_FOLDS, NULL),
     .get = get_folds, .at = AT(folds)},
    {ROW("timing", "ranking", RANK_TASKS, BF_OPTION_FLAG, NULL, "wall times in the outputs too (then runs differ)",
         NULL, NULL, NULL, 0, 0, NULL),
     .at = AT(timing), .flag_on = 1},
    /* Comparing. */
    {ROW("error", "comparing", BF_TASK_COMPARE, BF_OPTION_CHOICE, "rmse|rmse_log|rmse_cos|rmse_rel",
         "error for the Pareto fronts and the tolerance\n(default rmse_log; with --rank cv the cross-validated "
         "error)",
         NULL, "rmse|rmse_log|rmse_cos|rmse_rel", "rmse_log", 0, 0, NULL),
     .set = set_metric, .get = get_metric},
    {ROW("tolerance", "comparing", BF_TASK_COMPARE, BF_OPTION_NUMBER, "T",
         "relative: the simplest model with error <= best * (1 + T)\nis chosen (default 0.05)", NULL, NULL, "0.05", 0.0,
         HUGE_VAL, "a number >= 0 (relative, 0.05 = 5%)"),
     .at = AT(tolerance)},
    {ROW("jobs", "comparing", BF_TASK_COMPARE, BF_OPTION_INT, "N",
         "fits run at once (default 1); each gets --threads / N threads", NULL, NULL, "1", 1, 1024, NULL),
     .at = AT(jobs)},
    {ROW("reference", "comparing", BF_TASK_COMPARE, BF_OPTION_LIST, "FILE|DIR",
         "published fits to show beside brdfit's where the material and\nmodel match: a reference set, a parameter "
         "file, or a folder\nof them (*.json); repeatable",
         "file", NULL, NULL, 0, 0, NULL),
     .set = set_reference, .get = get_references},
    /* Selecting. */
    {ROW("tolerance", "selecting", BF_TASK_SELECT, BF_OPTION_NUMBER, "T",
         "relative: candidates with error <= best * (1 + T) + A qualify\n(default 0.05); the one with the fewest "
         "free "
         "parameters is chosen,\nthen isotropic, one lobe, monochrome highlight, lower error",
         NULL, NULL, "0.05", 0.0, HUGE_VAL, "a number >= 0"),
     .at = AT(tolerance)},
    {ROW("abs_tolerance", "selecting", BF_TASK_SELECT, BF_OPTION_NUMBER, "A",
         "absolute part of the tolerance (default 1e-6)", NULL, NULL, "1e-6", 0.0, HUGE_VAL, "a number >= 0"),
     .at = AT(abs_tolerance)},
    {ROW("jobs", "selecting", BF_TASK_SELECT, BF_OPTION_INT, "N",
         "candidates fitted at once (default 1); each gets --threads / N threads", NULL, NULL, "1", 1, 1024, NULL),
     .at = AT(jobs)},
    {ROW("error", "selecting", BF_TASK_SELECT, BF_OPTION_CHOICE, "rmse|rmse_log|rmse_cos|rmse_rel",
         "the error compared (default rmse_log)", NULL, "rmse|rmse_log|rmse_cos|rmse_rel", "rmse_log", 0, 0, NULL),
     .set = set_metric, .get = get_metric},
    /* Measuring cost against accuracy (tradeoff_options.c). The lists are checked once
     * every option is in (bf_options_check), their defaults following the base setting. */
    {ROW("samples", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_TEXT, "N,...|all",
         "training sample counts (default 1000,4000,16000,64000,all;\n"
         "'k' suffix: thousands); counts >= the training set are 'all'",
         NULL, NULL, "1000,4000,16000,64000,all", 0, 0, NULL),
     .get = options_tradeoff_get_list},
    {ROW("methods", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_TEXT, "M,...",
         "ceres (Levenberg-Marquardt), ceres:dogleg, or NLopt names\n"
         "(LD_LBFGS, LD_SLSQP, LN_BOBYQA ...); default: the --backend /\n"
         "--algorithm setting if given, else ceres,LD_LBFGS",
         NULL, NULL, NULL, 0, 0, NULL),
     .get = options_tradeoff_get_list},
    {ROW("residuals", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_TEXT, "R,...",
         "residual forms (default: --residual, log)", NULL, NULL, NULL, 0, 0, NULL),
     .get = options_tradeoff_get_list},
    {ROW("starts_list", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_TEXT, "N|auto,...",
         "start counts (brdfit fit --starts; auto: its automatic\ncount; default: --starts, or auto)", NULL, NULL, NULL,
         0, 0, NULL),
     .get = options_tradeoff_get_list},
    {ROW("test_fraction", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_NUMBER, "F",
         "held-out share of the samples, seeded random (default 0.2)", NULL, NULL, "0.2", DBL_TRUE_MIN,
         1.0 - DBL_EPSILON / 2, "a number between 0 and 1 (exclusive)"),
     .set = options_tradeoff_set_number, .get = options_tradeoff_get_kept},
    {ROW("cost", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_CHOICE, "work|seconds",
         "what a setting costs: sample evaluations (default; the same on\n"
         "every machine) or wall time (varies from run to run)",
         NULL, "work|seconds", "work", 0, 0, NULL),
     .set = options_tradeoff_set_cost, .get = options_tradeoff_get_kept},
    {ROW("timing", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_FLAG, NULL, "wall times in the table and the files too",
         NULL, NULL, NULL, 0, 0, NULL),
     .at = AT(timing), .flag_on = 1},
    {ROW("repeats", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_INT, "N",
         "fit each setting N times, keep the least time (default 1)", NULL, NULL, "1", 1, 1000,
         "an integer from 1 to 1000"),
     .set = options_tradeoff_set_number, .get = options_tradeoff_get_kept},
    {ROW("error", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_CHOICE, "rmse|rmse_log|rmse_cos|rmse_rel",
         "test error to judge by (default rmse_log)", NULL, "rmse|rmse_log|rmse_cos|rmse_rel", "rmse_log", 0, 0, NULL),
     .set = set_metric, .get = get_metric},
    {ROW("tolerance", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_NUMBER, "T",
         "recommend the cheapest setting with test error <= best * (1 + T)\n(default 0.05)", NULL, NULL, "0.05", 0.0,
         HUGE_VAL, "a number >= 0 (relative, 0.05 = 5%)"),
     .at = AT(tolerance)},
    {ROW("plot_size", "tradeoff", BF_TASK_TRADEOFF, BF_OPTION_TEXT, "WxH",
         "pixels (PNG) or points (SVG, PDF); default 640x400", NULL, NULL, "640x400", 40, 8192, "WxH, each 40 to 8192"),
     .set = options_tradeoff_set_plot_size, .get = options_tradeoff_get_kept},
};
const int option_nrows = (int)(sizeof option_rows / sizeof option_rows[0]);
_Static_assert(sizeof option_rows / sizeof option_rows[0] <= OPTION_ROWS_MAX, "raise OPTION_ROWS_MAX");
