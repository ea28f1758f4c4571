/* A plain-list batch manifest turned into its JSON manifest (batch_list.h).
 *
 * Decisions:
 *  - The list is only another spelling: it is converted to the JSON tree and everything
 *    after (option parsing, identity hash, storage in the database) is the JSON path's.
 *  - "--scene FILE" on a material line becomes the material's "scene" key, so that its
 *    path is resolved against the manifest's folder as the JSON key is.
 *  - Errors name the line; options and models are checked after the conversion by the
 *    JSON path, with its messages. */
#include "batch_list.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int batch_list_is_list(const char *text)
{
    text += strspn(text, " \t\r\n");
    return *text != '{' && *text != '[';
}

/* The next word of the line at *p (advanced past it) into a malloc'd *word; 1 a word,
 * 0 none left on the line, -1 an unterminated quote. */
static int next_word(const char **p, char **word)
{
    const char *s = *p + strspn(*p, " \t\r");
    if (!*s || *s == '\n' || *s == '#') {
        *p = s;
        return 0;
    }
    char *w = malloc(strcspn(s, "\n") + 1), *o = w;
    if (!w)
        return -1;
    if (*s == '"') {
        for (s++; *s != '"'; s++) {
            if (!*s || *s == '\n') {
                free(w);
                return -1;
            }
            if (*s == '\\' && (s[1] == '"' || s[1] == '\\'))
                s++;
            *o++ = *s;
        }
        s++;
    } else {
        while (*s && !strchr(" \t\r\n", *s))
            *o++ = *s++;
    }
    *o = '\0';
    *p = s, *word = w;
    return 1;
}

/* The words of one line (from *p, advanced to the next line) into array a (made when
 * NULL). The number of words, or -1 (a bad quote, or no memory: *why). */
static int line_words(const char **p, cJSON **a, const char **why)
{
    int n = 0, r;
    char *w;
    if (!*a && !(*a = cJSON_CreateArray())) {
        *why = "out of memory";
        return -1;
    }
    while ((r = next_word(p, &w)) > 0) {
        cJSON *s = cJSON_CreateString(w);
        free(w);
        if (!s || !cJSON_AddItemToArray(*a, s)) {
            cJSON_Delete(s);
            *why = "out of memory";
            return -1;
        }
        n++;
    }
    *p += strcspn(*p, "\n");
    if (**p)
        (*p)++;
    if (r < 0)
        *why = "a double quote is not closed on its line";
    return r < 0 ? -1 : n;
}

/* A material line's words (data file first) as the JSON material: the name alone, or
 * {"data", "options", "scene"}. NULL after *why (or no memory, why left NULL). */
static cJSON *material_of(const cJSON *words, const char **why)
{
    const int n = cJSON_GetArraySize(words);
    cJSON *o = cJSON_CreateObject(), *opts = cJSON_CreateArray();
    const char *scene = NULL;
    int ok = o && opts;
    for (int k = 1; ok && k < n; k++) {
        const char *w = cJSON_GetArrayItem(words, k)->valuestring;
        if (strcmp(w, "--scene") && strncmp(w, "--scene=", 8)) {
            ok = cJSON_AddItemToArray(opts, cJSON_CreateString(w));
        } else if (scene || (w[7] != '=' && k + 1 == n)) {
            *why = scene ? "--scene given twice" : "--scene needs a file";
            ok = 0;
        } else {
            scene = w[7] == '=' ? w + 8 : cJSON_GetArrayItem(words, ++k)->valuestring;
        }
    }
    const char *data = words->child->valuestring;
    if (ok && !scene && !cJSON_GetArraySize(opts)) {
        cJSON_Delete(o);
        cJSON_Delete(opts);
        return cJSON_CreateString(data);
    }
    /* Keys in the order docs/batch.md writes them: the canonical text, hence the
     * identity, is that of the same manifest written in JSON that way. */
    ok = ok && cJSON_AddStringToObject(o, "data", data);
    if (ok && cJSON_GetArraySize(opts) && (ok = cJSON_AddItemToObject(o, "options", opts)))
        opts = NULL;
    ok = ok && (!scene || cJSON_AddStringToObject(o, "scene", scene));
    if (!ok) {
        cJSON_Delete(o);
        o = NULL;
    }
    cJSON_Delete(opts);
    return o;
}

cJSON *batch_list_parse(const char *text, const char *path, int **lines, const char *cmd)
{
    cJSON *root = cJSON_CreateObject(), *models = NULL, *options = NULL, *mats = cJSON_CreateArray();
    const char *p = text, *why = NULL;
    int line = 0, nmats = 0;
    /* At most one material per line, and a line per '\n'. */
    size_t nlines = 2;
    for (const char *c = text; *c; c++)
        nlines += *c == '\n';
    if ((*lines = calloc(nlines + 1, sizeof **lines)) == NULL)
        cJSON_Delete(root), root = NULL;
    while (root && mats && *p && !why) {
        line++;
        const char *s = p + strspn(p, " \t\r");
        cJSON *words = NULL;
        if (!strncmp(s, "models:", 7) || !strncmp(s, "options:", 8)) {
            const int is_models = s[0] == 'm';
            if (is_models ? models != NULL : options != NULL) {
                why = is_models ? "a second models: line" : "a second options: line";
                break;
            }
            p = s + (is_models ? 7 : 8);
            if (!is_models)
                (*lines)[0] = line;
            if (line_words(&p, is_models ? &models : &options, &why) == 0 && is_models)
                why = "models: lists no model";
            continue;
        }
        const int n = line_words(&p, &words, &why);
        if (n > 0) {
            cJSON *m = material_of(words, &why);
            if (m && cJSON_AddItemToArray(mats, m))
                (*lines)[++nmats] = line;
            else if (!why)
                why = "out of memory";
        }
        cJSON_Delete(words);
    }
    if (!why && root && mats && !models)
        line = 0, why = "no models: line (models: lambert walter ...)";
    if (!why && root && mats && !cJSON_GetArraySize(mats))
        line = 0, why = "no material lines (one data file per line)";
    if (why || !root || !mats) {
        if (line > 0)
            fprintf(stderr, "%s: %s:%d: %s\n", cmd, path, line, why ? why : "out of memory");
        else
            fprintf(stderr, "%s: %s: %s\n", cmd, path, why ? why : "out of memory");
        cJSON_Delete(root);
        cJSON_Delete(models);
        cJSON_Delete(options);
        cJSON_Delete(mats);
        free(*lines);
        *lines = NULL;
        return NULL;
    }
    cJSON_AddItemToObject(root, "models", models);
    if (options && cJSON_GetArraySize(options))
        cJSON_AddItemToObject(root, "options", options);
    else
        cJSON_Delete(options);
    cJSON_AddItemToObject(root, "materials", mats);
    return root;
}
