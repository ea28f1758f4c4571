/* Reference files: published fits, each an ordinary parameter file, alone or gathered in
 * a reference set, or a folder of such files (brdfit/reference.h).
 *
 * Decisions:
 *  - Each fit is read by the parameter-file reader (io/params_json.h), so a reference
 *    says its model, options, channels and values as any parameter file does; only the
 *    bounds are not enforced: the published values are kept and the entries outside
 *    named, so the comparison can say so.
 *  - A set's entries are read where they stand in the file (the reader looks for a key
 *    from the entry's start), so a message names the line of the entry at fault, and
 *    the entry's JSON path follows the line ("refs.json:12: materials/blue-acrylic:
 *    parameter alpha: expected a number").
 *  - A folder's "*.json" files are read in byte order of their names (strcmp, not the
 *    locale's collation), so the order of the outputs does not depend on the machine.
 *  - A file that fails leaves the set as it was: a caller refuses the whole run rather
 *    than compare against half a file. */
#include "brdfit/reference.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "io/json_keys.h"
#include "io/json_pos.h"
#include "io/params_json.h"
#include "io/read_text.h"
#include "run_options.h"

bf_status bf_reference_set_new(bf_reference_set **out, bf_error *err)
{
    if (!(*out = calloc(1, sizeof **out)))
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for a reference set");
    return BF_OK;
}

static void reference_clear(bf_reference *r)
{
    free(r->file);
    free(r->source);
    free(r->table);
    free(r->material);
    bf_model_free(r->model);
    free(r->x);
    memset(r, 0, sizeof *r);
}

/* Back to n references, the others freed. */
static void truncate_set(bf_reference_set *s, int n)
{
    while (s->n > n)
        reference_clear(&s->refs[--s->n]);
}

void bf_reference_set_free(bf_reference_set *s)
{
    if (!s)
        return;
    truncate_set(s, 0);
    free(s->refs);
    free(s);
}

const char *bf_reference_material(const char *data, char *buf, size_t size)
{
    const char *base = data ? strrchr(data, '/') : NULL;
    base = base ? base + 1 : data ? data : "";
    const char *dot = strrchr(base, '.');
    size_t n = dot && dot != base ? (size_t)(dot - base) : strlen(base);
    snprintf(buf, size, "%.*s", (int)n, base);
    return buf;
}

int bf_reference_matches(const bf_reference *r, const char *material, const char *spec)
{
    if (!r || !r->model || !material || !spec || !r->material || strcmp(r->material, material))
        return 0;
    bf_model *m = NULL;
    if (bf_model_new(spec, bf_model_channels(r->model), &m, NULL) != BF_OK)
        return 0;
    const int same = !strcmp(bf_model_spec(m), bf_model_spec(r->model));
    bf_model_free(m);
    return same;
}

/* r->outside: the entries of r->x outside the family's bounds. */
static void name_outside(bf_reference *r)
{
    const bf_model *m = r->model;
    const int C = bf_model_channels(m);
    size_t used = 0;
    r->outside[0] = '\0';
    for (int i = 0; i < bf_model_nparams(m); i++) {
        const bf_param_info *p = bf_model_param(m, i);
        for (int c = 0; c < (p->color ? C : 1); c++) {
            const int k = bf_model_param_offset(m, i) + c;
            const double v = r->x[k];
            if (!(v < p->lo || (p->lo_open && v == p->lo) || v > p->hi || (p->hi_open && v == p->hi)))
                continue;
            char name[64];
            bf_model_entry_name(m, k, name, sizeof name);
            const int n = snprintf(r->outside + used, sizeof r->outside - used, "%s%s", used ? ", " : "", name);
            if (n < 0 || (size_t)n >= sizeof r->outside - used) { /* cut, and said to be */
                snprintf(r->outside + sizeof r->outside - 5, 5, "...");
                return;
            }
            used += (size_t)n;
        }
    }
}

/* Room for one more reference. */
static bf_reference *grow(bf_reference_set *s, bf_error *err)
{
    bf_reference *more = realloc(s->refs, (size_t)(s->n + 1) * sizeof *more);
    if (!more) {
        bf_fail(err, BF_ERR_NOMEM, "out of memory for a reference");
        return NULL;
    }
    s->refs = more;
    memset(&s->refs[s->n], 0, sizeof s->refs[s->n]);
    return &s->refs[s->n++];
}

/* What one file's references share. */
typedef struct ref_file {
    const char *path, *text;
    const char *source, *table; /* NULL: none */
} ref_file;

/* One fit (the object root, starting at from in the text) of material into s. */
static bf_status add_fit(bf_reference_set *s, const ref_file *f, const cJSON *root, const char *from,
                         const char *material, bf_error *err)
{
    const bf_params_src src = {f->path, f->text, from};
    bf_model *m = NULL;
    double *x = NULL;
    bf_status rc = bf_params_from_json(&src, root, 0, &m, &x, err);
    if (rc != BF_OK)
        return rc;
    bf_reference *r = grow(s, err);
    if (!r) {
        bf_model_free(m);
        free(x);
        return BF_ERR_NOMEM;
    }
    r->model = m;
    r->x = x;
    r->line = bf_json_line(f->text, from);
    r->file = strdup(f->path);
    r->source = strdup(f->source ? f->source : f->path);
    r->table = f->table ? strdup(f->table) : NULL;
    r->material = strdup(material);
    if (!r->file || !r->source || (f->table && !r->table) || !r->material)
        return bf_fail(err, BF_ERR_NOMEM, "out of memory for a reference");
    name_outside(r);
    return BF_OK;
}

/* err's "PATH:LINE: problem" becomes "PATH:LINE: materials/NAME: problem". Through
 * bf_fail, so that NAME (any bytes a JSON key may hold) is escaped and the whole kept to
 * the message's length like every other message. */
static void name_entry(bf_error *err, const char *path, const char *material)
{
    const size_t n = strlen(path);
    if (strncmp(err->msg, path, n) || err->msg[n] != ':')
        return;
    const char *rest = strstr(err->msg + n + 1, ": ");
    if (!rest)
        return;
    bf_fail(err, err->code, "%.*s: materials/%s: %s", (int)(rest - err->msg), err->msg, material, rest + 2);
}

/* The optional text member key of a set: a string or absent. */
static bf_status set_text(const ref_file *f, const cJSON *root, const char *key, const char **out, bf_error *err)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(root, key);
    *out = NULL;
    if (!v)
        return BF_OK;
    if (!cJSON_IsString(v) || !*v->valuestring)
        return bf_fail(err, BF_ERR_PARSE, "%s:%d: \"%s\" must be a non-empty string", f->path,
                       bf_json_line(f->text, bf_json_member(f->text, key, strlen(key), 1)), key);
    *out = v->valuestring;
    return BF_OK;
}

/* {"source": ..., "table": ..., "materials": {NAME: PARAMETER FILE, ...}} into s. */
static bf_status read_set(bf_reference_set *s, ref_file *f, const cJSON *root, bf_error *err)
{
    bf_status rc;
    if ((rc = set_text(f, root, "source", &f->source, err)) != BF_OK ||
        (rc = set_text(f, root, "table", &f->table, err)) != BF_OK)
        return rc;
    if (!f->source)
        return bf_fail(err, BF_ERR_PARSE, "%s:1: a reference set needs \"source\": who published the fits", f->path);
    const cJSON *mats = cJSON_GetObjectItemCaseSensitive(root, "materials");
    const char *at = bf_json_member(f->text, "materials", 9, 0);
    const int line = bf_json_line(f->text, at);
    if (!cJSON_IsObject(mats) || !mats->child)
        return bf_fail(err, BF_ERR_PARSE, "%s:%d: \"materials\" must be an object of parameter files, one per material",
                       f->path, line);
    const char *key;
    int repeated = bf_json_repeated_key(mats, &key);
    if (repeated)
        return repeated < 0 ? bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", f->path)
                            : bf_fail(err, BF_ERR_PARSE, "%s:%d: material \"%s\" given twice", f->path, line, key);
    const cJSON *e;
    cJSON_ArrayForEach(e, mats)
    {
        const char *from = at ? bf_json_member(at, e->string, strlen(e->string), 0) : NULL;
        if (!*e->string)
            return bf_fail(err, BF_ERR_PARSE, "%s:%d: a material's name is empty", f->path, line);
        if ((rc = add_fit(s, f, e, from ? from : at, e->string, err)) != BF_OK) {
            name_entry(err, f->path, e->string);
            return rc;
        }
    }
    return BF_OK;
}

/* One file's text: a reference set when it has "materials", else a parameter file. */
static bf_status parse_into(bf_reference_set *s, const char *text, const char *path, bf_error *err)
{
    const char *end = NULL;
    cJSON *root = cJSON_ParseWithLengthOpts(text, strlen(text) + 1, &end, 1);
    if (!root)
        return bf_fail(err, BF_ERR_PARSE, "%s:%d: malformed JSON", path, bf_json_line(text, end ? end : text));
    bf_status rc;
    ref_file f = {path, text, NULL, NULL};
    const char *key;
    int repeated = cJSON_IsObject(root) ? bf_json_repeated_key(root, &key) : 0;
    if (!cJSON_IsObject(root))
        rc = bf_fail(err, BF_ERR_PARSE, "%s:1: expected a JSON object (a reference set or a parameter file)", path);
    else if (repeated)
        rc = repeated < 0 ? bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path)
                          : bf_fail(err, BF_ERR_PARSE, "%s:%d: \"%s\" given twice", path,
                                    bf_json_line(text, bf_json_member(text, key, strlen(key), 1)), key);
    else if (cJSON_GetObjectItemCaseSensitive(root, "materials"))
        rc = read_set(s, &f, root, err);
    else {
        char material[256];
        bf_reference_material(path, material, sizeof material);
        if ((rc = set_text(&f, root, "source", &f.source, err)) == BF_OK &&
            (rc = set_text(&f, root, "table", &f.table, err)) == BF_OK)
            rc = add_fit(s, &f, root, NULL, material, err);
    }
    cJSON_Delete(root);
    return rc;
}

bf_status bf_reference_parse(bf_reference_set *s, const char *text, const char *name, bf_error *err)
{
    bf_error local;
    if (!err)
        err = &local;
    const char *path = name ? name : "references";
    if (!s || !text)
        return bf_fail(err, BF_ERR_ARG, "%s: no reference set or no text", path);
    const int n0 = s->n;
    bf_status rc = parse_into(s, text, path, err);
    if (rc != BF_OK)
        truncate_set(s, n0);
    return rc;
}

static bf_status read_file(bf_reference_set *s, const char *path, bf_error *err)
{
    char *text = NULL;
    size_t len;
    bf_status rc = bf_read_text(path, &text, &len, err);
    if (rc == BF_OK)
        rc = bf_reference_parse(s, text, path, err);
    free(text);
    return rc;
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The "*.json" names in dir, sorted (*names: n strings, each and the array malloc'd). */
static bf_status json_names(const char *dir, char ***names, int *n, bf_error *err)
{
    DIR *d = opendir(dir);
    *names = NULL;
    *n = 0;
    if (!d)
        return bf_fail(err, BF_ERR_IO, "%s: cannot open: %s", dir, strerror(errno));
    bf_status rc = BF_OK;
    struct dirent *e;
    while (rc == BF_OK && (e = readdir(d)) != NULL) {
        const size_t len = strlen(e->d_name);
        if (len <= 5 || strcmp(e->d_name + len - 5, ".json") || e->d_name[0] == '.')
            continue;
        char **more = realloc(*names, (size_t)(*n + 1) * sizeof *more);
        if (!more || !(more[*n] = strdup(e->d_name))) {
            if (more)
                *names = more;
            rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
            break;
        }
        *names = more;
        (*n)++;
    }
    closedir(d);
    if (rc == BF_OK && *n == 0)
        rc = bf_fail(err, BF_ERR_ARG, "%s: a folder without a *.json reference file", dir);
    if (rc == BF_OK)
        qsort(*names, (size_t)*n, sizeof **names, by_name);
    return rc;
}

/* Every "*.json" of dir, in byte order of the names, files only. */
static bf_status read_dir(bf_reference_set *s, const char *dir, bf_error *err)
{
    char **names;
    int n;
    bf_status rc = json_names(dir, &names, &n, err);
    for (int k = 0; rc == BF_OK && k < n; k++) {
        const size_t dl = strlen(dir);
        char *path = malloc(dl + strlen(names[k]) + 2);
        struct stat st;
        if (!path) {
            rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", dir);
            break;
        }
        sprintf(path, "%s%s%s", dir, dl && dir[dl - 1] == '/' ? "" : "/", names[k]);
        if (stat(path, &st) == 0 && S_ISREG(st.st_mode))
            rc = read_file(s, path, err);
        free(path);
    }
    for (int k = 0; k < n; k++)
        free(names[k]);
    free(names);
    return rc;
}

bf_status bf_reference_read(bf_reference_set *s, const char *path, bf_error *err)
{
    bf_error local;
    if (!err)
        err = &local;
    if (!s || !path || !*path)
        return bf_fail(err, BF_ERR_ARG, "references: no set or no file");
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return read_file(s, path, err);
    const int n0 = s->n;
    bf_status rc = read_dir(s, path, err);
    if (rc != BF_OK)
        truncate_set(s, n0);
    return rc;
}

bf_status bf_reference_evaluate(const bf_reference *r, bf_samples *s, const bf_options *o, double *cost,
                                bf_metrics *metrics, bf_error *err)
{
    if (!r || !r->model || !r->x || !s || !o)
        return bf_fail(err, BF_ERR_ARG, "reference: no reference, samples or options");
    if (bf_options_task(o) == BF_TASK_READ)
        return bf_fail(err, BF_ERR_ARG, "reference: options for reading only (make them for a fitting task)");
    bf_fit_options fo;
    options_fit_get(o, &fo);
    return bf_fit_evaluate_with(s, r->model, r->x, &fo, cost, metrics, err);
}
