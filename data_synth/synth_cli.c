/* brdfit-synth's options (cli.h): the command and the page generator (cmd/doc_main.c)
 * read the same table. */
#include "synth_cli.h"

/* A valued option: kept as given, once (what it means is checked after parsing, with the
 * others); a second one is bad usage. The field is the entry's .at. */
static int take_once(void *target, const cli_option *o, const char *v, const char *cmd)
{
    const char **dst = (const char **)((char *)target + o->at);
    if (*dst) {
        fprintf(stderr, "%s: %s given twice (try %s --help)\n", cmd, o->name, cmd);
        return -1;
    }
    *dst = v;
    return 0;
}
#define ONCE(FIELD) CLI_CALLS(take_once), .at = offsetof(synth_args, FIELD)

static const cli_option own[] = {
    {"--params", 0, "FILE",
     "the model and its parameters (a parameter file as for brdfit eval;\n"
     "a fit result works too; - for standard input)",
     "file", ONCE(params)},
    {"--output", 'o', "FILE", "OUT.csv or OUT.binary (- for standard output, CSV)", "file", ONCE(out)},
    {"--pattern", 0, "uniform|cosine|stratified|random|gonio|merl", "the direction pairs (below)", NULL, ONCE(pattern)},
    {"--count", 0, "N", "pairs for uniform, cosine, stratified and random", NULL, ONCE(count)},
    {"--incidence", 0, "LIST", "gonio: incidence angles, degrees, comma-separated (default 0,30,60)", NULL,
     ONCE(incidence)},
    {"--step", 0, "S", "gonio: degrees between detector positions (default 5)", NULL, ONCE(step)},
};
static const cli_option noise[] = {
    {"--noise", 0, "S", "noise level (relative model unless --noise-model says otherwise)", NULL, ONCE(noise)},
    {"--noise-model", 0, "relative|additive|photon",
     "relative: v (1 + S N(0,1)); additive: v + S N(0,1);\n"
     "photon: Poisson(k v) / k with k = 1/S^2 (relative noise S at v = 1)",
     NULL, ONCE(noise_model)},
    {"--counts", 0, "K", "photon model: k counts per unit value (instead of --noise)", NULL, ONCE(counts)},
    {"--outliers", 0, "F[,FACTOR]",
     "replace a fraction F of the samples by v * FACTOR, or by a\n"
     "random value in [0, channel maximum) without FACTOR",
     NULL, ONCE(outliers)},
    {"--clamp", 0, NULL, "set negative values to zero (always on for merl)", NULL, CLI_SETS(synth_args, clamp, 1)},
    {"--seed", 0, "K", "generator seed, an unsigned 64-bit integer (default 0);\nthe same seed gives the same file",
     NULL, ONCE(seed)},
};
static const cli_group own_group = CLI_GROUP(NULL, own);
static const cli_group noise_group = CLI_GROUP("noise (applied in this order: model, outliers, clamping)", noise);
static const cli_group *const groups[] = {&own_group, &noise_group};
const cli_command cli_synth = {
    "brdfit-synth",
    NULL,
    "--params P.json --pattern PATTERN [--count N] [options] -o OUT.csv|OUT.binary",
    "make synthetic reflectance data from a model",
    "Patterns: uniform (N pairs, each direction uniform in solid angle), cosine (each direction cosine-weighted), "
    "stratified (one pair per stratum of a jittered (cos theta, phi) grid per direction; N = m^4 gives m strata in "
    "each of the four dimensions), random (theta uniform in [0, 90) and phi in [0, 360) degrees, as a goniometer "
    "stepping at random), gonio (an in-plane sweep and an out-of-plane ring per incidence), merl (every MERL cell "
    "centre above the horizon; needs a 3-channel model and OUT.binary; other cells are written invalid).",
    NULL,
    groups,
    sizeof groups / sizeof groups[0],
};
