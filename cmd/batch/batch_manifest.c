/* Reading a batch manifest (batch_manifest.h).
 *
 * Decisions:
 *  - The options are parsed by the tables fit and compare use (cli_parse_words, then
 *    cli_take into the structs they bind), so a manifest takes exactly their names and
 *    values and refuses what they refuse.
 *  - --threads in a manifest is accepted but is not what a run uses when brdfit batch
 *    is given its own --threads (results do not depend on it, fit.h).
 *  - The identity hash is over the canonical text (cJSON's unformatted print), so
 *    reformatting a manifest keeps its results database; any change of content (a
 *    material, a model, an option, their order) makes another manifest.
 *  - A plain list (batch_list.h) is read into the JSON tree it stands for; the database
 *    stores the canonical JSON either way. */
#include "batch_manifest.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "batch_list.h"
#include "cli.h"

static const cli_option own[] = {CLI_LIB("--error"), CLI_LIB("--tolerance")};
static const cli_group own_group = CLI_GROUP_OPTIONS(NULL, own, BF_TASK_COMPARE, batch_manifest, o);
static const cli_group *const shared_groups[] = {&own_group,
                                                 &rank_options_bic,
                                                 &fit_options_fitting,
                                                 &fit_options_optimizer,
                                                 &data_options_reading,
                                                 &data_options_preprocessing};
static const cli_group *const material_groups[] = {&data_options_reading, &data_options_preprocessing};
/* Grammars for the manifest's word lists (never shown as commands; without --help,
 * --quiet, --verbose, which would act on the process). */
static const cli_command shared_cli = {
    "brdfit", "batch", "", "", NULL, NULL, shared_groups, sizeof shared_groups / sizeof shared_groups[0]};
static const cli_command material_cli = {
    "brdfit", "batch", "", "", NULL, NULL, material_groups, sizeof material_groups / sizeof material_groups[0]};

void batch_manifest_clear(batch_manifest *m)
{
    for (int j = 0; j < m->nmodels; j++)
        free(m->models[j]);
    free(m->models);
    for (int i = 0; i < m->nmaterials; i++) {
        free(m->materials[i].data);
        free(m->materials[i].scene);
        free(m->materials[i].scene_word);
        free(m->materials[i].words);
    }
    free(m->materials);
    free(m->words);
    free(m->text);
    free(m->lines);
    cJSON_Delete(m->root);
    bf_options_free(m->o);
    memset(m, 0, sizeof *m);
}

/* path relative to the manifest's folder (dir, with its '/'; "" for none); malloc'd. */
static char *resolve(const char *dir, const char *path)
{
    size_t nd = path[0] == '/' ? 0 : strlen(dir);
    char *r = malloc(nd + strlen(path) + 1);
    if (r) {
        memcpy(r, dir, nd);
        strcpy(r + nd, path);
    }
    return r;
}

/* The strings of a JSON array into a malloc'd list (borrowed strings) with room for
 * `extra` more; -1 after an error (not an array of strings). */
static int words_of(const cJSON *a, int extra, char ***out, const char *what, const char *where, const char *cmd)
{
    int n = a ? cJSON_GetArraySize(a) : 0;
    if (a && !cJSON_IsArray(a)) {
        fprintf(stderr, "%s: %s: %s must be an array of strings\n", cmd, where, what);
        return -1;
    }
    if (!(*out = calloc((size_t)n + (size_t)extra + 1, sizeof **out))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return -1;
    }
    int k = 0;
    for (const cJSON *e = a ? a->child : NULL; e; e = e->next) {
        if (!cJSON_IsString(e)) {
            fprintf(stderr, "%s: %s: %s must be an array of strings\n", cmd, where, what);
            return -1;
        }
        (*out)[k++] = e->valuestring;
    }
    return k;
}

/* A word that is not an option; ctx: the message's prefix. */
static int not_an_option(void *ctx, const char *value, const char *cmd)
{
    (void)cmd;
    fprintf(stderr, "%s: '%s' is not an option (one data file per material)\n", (const char *)ctx, value);
    return -1;
}

/* Words parsed by grammar c: every one an option, taken into targets[g] for c's group g.
 * 0, or -1 after an error, whose message starts "cmd: where" (the grammar's) or "cmd"
 * (a value's, as the option parsers say it). */
static int parse_words(const cli_command *c, void *const *targets, int ntargets, char **words, int n, const char *where,
                       const char *cmd)
{
    char prefix[700];
    snprintf(prefix, sizeof prefix, "%s: %s", cmd, where);
    /* An option these tables do not declare: said here, saying what the list takes. */
    for (int k = 0; k < n; k++) {
        const size_t len = strcspn(words[k], "=");
        if (!strncmp(words[k], "--", 2) && len > 2 && !cli_find(c, words[k], len)) {
            fprintf(stderr, "%s: option '%.*s' is not taken here (%s)\n", prefix, (int)(len > 64 ? 64 : len), words[k],
                    c == &material_cli ? "a material takes data options only" : "see docs/batch.md");
            return -1;
        }
    }
    cli_args args = {0};
    int rc = cli_parse_words(c, n, words, &args, prefix) == CLI_OK ? 0 : -1;
    if (rc == 0)
        rc = cli_take(c, targets, ntargets, &args, not_an_option, prefix, cmd);
    cli_args_free(&args);
    return rc;
}

/* The whole file, NUL-terminated (malloc'd); NULL after an error. A manifest beyond
 * 256 MiB is not one. */
static char *read_file(const char *path, const char *cmd)
{
    enum { MAX_BYTES = 256 << 20 };
    FILE *fp = fopen(path, "rb");
    char *buf = NULL;
    size_t n = 0, cap = 0;
    if (!fp) {
        fprintf(stderr, "%s: %s: cannot open the manifest\n", cmd, path);
        return NULL;
    }
    for (;;) {
        if (n + 4096 + 1 > cap) {
            char *b = cap >= MAX_BYTES ? NULL : realloc(buf, cap = cap ? 2 * cap : 65536);
            if (!b) {
                fprintf(stderr, "%s: %s: too large for a manifest\n", cmd, path);
                free(buf);
                fclose(fp);
                return NULL;
            }
            buf = b;
        }
        size_t got = fread(buf + n, 1, cap - n - 1, fp);
        n += got;
        if (got == 0)
            break;
    }
    int bad = ferror(fp);
    fclose(fp);
    if (bad) {
        fprintf(stderr, "%s: %s: read error\n", cmd, path);
        free(buf);
        return NULL;
    }
    buf[n] = '\0';
    return buf;
}

static uint64_t fnv1a(const char *s)
{
    uint64_t h = 14695981039346656037ull;
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 1099511628211ull;
    return h;
}

/* "materials": each a data file name, or {"data", "options", "scene"}. */
static int read_material(batch_manifest *m, const cJSON *e, const char *dir, batch_material *b, const char *where,
                         const char *cmd)
{
    const cJSON *data = cJSON_IsString(e) ? e : cJSON_GetObjectItemCaseSensitive(e, "data");
    const cJSON *scene = cJSON_IsObject(e) ? cJSON_GetObjectItemCaseSensitive(e, "scene") : NULL;
    if (!cJSON_IsString(data) || !data->valuestring[0] || (scene && !cJSON_IsString(scene))) {
        fprintf(stderr,
                "%s: %s: a material is a data file name or {\"data\": FILE, \"options\": [...], \"scene\": FILE}\n",
                cmd, where);
        return -1;
    }
    for (const cJSON *k = cJSON_IsObject(e) ? e->child : NULL; k; k = k->next)
        if (strcmp(k->string, "data") && strcmp(k->string, "options") && strcmp(k->string, "scene")) {
            fprintf(stderr, "%s: %s: unknown material key \"%s\"\n", cmd, where, k->string);
            return -1;
        }
    const cJSON *opts = cJSON_IsObject(e) ? cJSON_GetObjectItemCaseSensitive(e, "options") : NULL;
    if ((b->nwords = words_of(opts, 2, &b->words, "a material's \"options\"", where, cmd)) < 0 ||
        !(b->data = resolve(dir, data->valuestring)) || (scene && !(b->scene = resolve(dir, scene->valuestring)))) {
        if (b->nwords >= 0)
            fprintf(stderr, "%s: out of memory\n", cmd);
        return -1;
    }
    /* One word, "--scene=FILE": a file named like an option ("--x.json") is still the
     * value, here and when the stored manifest is read back without its folder. */
    if (b->scene) {
        if (!(b->scene_word = malloc(strlen(b->scene) + 9))) {
            fprintf(stderr, "%s: out of memory\n", cmd);
            return -1;
        }
        strcat(strcpy(b->scene_word, "--scene="), b->scene);
        b->words[b->nwords++] = b->scene_word;
    }
    bf_options *d = NULL;
    char prefix[600]; /* the parsers' messages name the manifest */
    snprintf(prefix, sizeof prefix, "%s: %s", cmd, where);
    int rc = batch_manifest_options(m, (int)(b - m->materials), &d, prefix);
    bf_options_free(d);
    return rc;
}

static int read_models(batch_manifest *m, const cJSON *models, const char *where, const char *cmd)
{
    if (!cJSON_IsArray(models) || cJSON_GetArraySize(models) == 0) {
        fprintf(stderr, "%s: %s: \"models\" must be a non-empty array of model specs\n", cmd, where);
        return -1;
    }
    if (!(m->models = calloc(BATCH_MAX_MODELS, sizeof *m->models))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return -1;
    }
    for (const cJSON *e = models->child; e; e = e->next) {
        if (!cJSON_IsString(e)) {
            fprintf(stderr, "%s: %s: \"models\" must be a non-empty array of model specs\n", cmd, where);
            return -1;
        }
        int k = fit_options_split_models(e->valuestring, m->models, m->nmodels, BATCH_MAX_MODELS, cmd);
        if (k < 0) { /* the specs it added before the error are not counted: freed here */
            for (int j = m->nmodels; j < BATCH_MAX_MODELS; j++) {
                free(m->models[j]);
                m->models[j] = NULL;
            }
            return -1;
        }
        m->nmodels = k;
    }
    char prefix[600];
    snprintf(prefix, sizeof prefix, "%s: %s", cmd, where);
    return fit_options_check(m->o, m->models, m->nmodels, prefix);
}

static int read_root(batch_manifest *m, const char *dir, const char *where, const char *cmd)
{
    if (!cJSON_IsObject(m->root)) {
        fprintf(stderr, "%s: %s: not a JSON object (see docs/batch.md)\n", cmd, where);
        return -1;
    }
    for (const cJSON *k = m->root->child; k; k = k->next)
        if (strcmp(k->string, "models") && strcmp(k->string, "options") && strcmp(k->string, "materials")) {
            fprintf(stderr, "%s: %s: unknown key \"%s\" (models, options, materials)\n", cmd, where, k->string);
            return -1;
        }
    char prefix[600]; /* the parsers' messages name the manifest: "brdfit batch: FILE" */
    snprintf(prefix, sizeof prefix, "%s: %s", cmd, where);
    void *const targets[] = {m, &m->o, &m->o, &m->o, &m->o, &m->o}; /* shared_groups' targets */
    char opts_where[32] = "\"options\"";
    if (m->lines)
        snprintf(opts_where, sizeof opts_where, "line %d", m->lines[0]);
    const cJSON *mats = cJSON_GetObjectItemCaseSensitive(m->root, "materials");
    if ((m->nwords = words_of(cJSON_GetObjectItemCaseSensitive(m->root, "options"), 0, &m->words, "\"options\"", where,
                              cmd)) < 0 ||
        parse_words(&shared_cli, targets, CLI_COUNT(targets), m->words, m->nwords, opts_where, prefix) < 0 ||
        read_models(m, cJSON_GetObjectItemCaseSensitive(m->root, "models"), where, cmd) < 0)
        return -1;
    if (!cJSON_IsArray(mats) || cJSON_GetArraySize(mats) == 0) {
        fprintf(stderr, "%s: %s: \"materials\" must be a non-empty array\n", cmd, where);
        return -1;
    }
    if (!(m->materials = calloc((size_t)cJSON_GetArraySize(mats), sizeof *m->materials))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return -1;
    }
    for (const cJSON *e = mats->child; e; e = e->next)
        if (read_material(m, e, dir, &m->materials[m->nmaterials++], where, cmd) < 0)
            return -1;
    return 0;
}

int batch_manifest_read(const char *path, const char *text, batch_manifest *m, const char *cmd)
{
    memset(m, 0, sizeof *m);
    if (!(m->o = cmd_options_new(BF_TASK_COMPARE, cmd)))
        return -1;
    char *own_text = NULL;
    if (path) {
        if (!(own_text = read_file(path, cmd)))
            return -1;
        text = own_text;
    }
    const char *where = path ? path : "the stored manifest";
    const int list = path && batch_list_is_list(text);
    m->root = list ? batch_list_parse(text, path, &m->lines, cmd) : cJSON_Parse(text);
    free(own_text);
    if (!m->root) {
        if (!list)
            fprintf(stderr, "%s: %s: not valid JSON\n", cmd, where);
        return -1;
    }
    if (!(m->text = cJSON_PrintUnformatted(m->root))) {
        fprintf(stderr, "%s: out of memory\n", cmd);
        return -1;
    }
    snprintf(m->hash, sizeof m->hash, "%016llx", (unsigned long long)fnv1a(m->text));
    /* The manifest's folder, with its '/', for the relative paths in it. */
    char dir[4096] = "";
    const char *slash = path ? strrchr(path, '/') : NULL;
    if (slash && (size_t)(slash - path) + 2 <= sizeof dir)
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path + 1), path);
    return read_root(m, dir, where, cmd);
}

int batch_manifest_options(const batch_manifest *m, int i, bf_options **out, const char *cmd)
{
    bf_error err;
    if (bf_options_copy(m->o, out, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return -1;
    }
    void *const targets[] = {out, out}; /* material_groups' targets */
    char where[64];
    if (m->lines)
        snprintf(where, sizeof where, "line %d", m->lines[i + 1]);
    else
        snprintf(where, sizeof where, "material %d", i + 1);
    return parse_words(&material_cli, targets, CLI_COUNT(targets), m->materials[i].words, m->materials[i].nwords, where,
                       cmd);
}

char *batch_manifest_item_options(const batch_manifest *m, int material, int model)
{
    cJSON *a = cJSON_CreateArray();
    const batch_material *b = &m->materials[material];
    for (int k = 0; a && k < m->nwords; k++)
        cJSON_AddItemToArray(a, cJSON_CreateString(m->words[k]));
    for (int k = 0; a && k < b->nwords; k++)
        cJSON_AddItemToArray(a, cJSON_CreateString(b->words[k]));
    cJSON_AddItemToArray(a, cJSON_CreateString("-m"));
    cJSON_AddItemToArray(a, cJSON_CreateString(m->models[model]));
    char *s = a ? cJSON_PrintUnformatted(a) : NULL;
    cJSON_Delete(a);
    return s;
}
