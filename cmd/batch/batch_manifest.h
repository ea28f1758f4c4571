/* The manifest of brdfit batch (docs/batch.md): the materials (a data file, its own data
 * options and scene), the models, and the options every fit shares, in JSON:
 *
 *   {"models": ["lambert", "walter"],
 *    "options": ["--residual", "log", "--seed", "3"],
 *    "materials": ["a.csv", {"data": "b.binary", "options": ["--subsample", "20000"],
 *                            "scene": "studio.json"}]}
 *
 * or as the plain list batch_list.h describes. Options are command-line words with the
 * names brdfit compare takes (parsed by the library's option table, brdfit/options.h,
 * as compare parses them); a material's options are data options only. Relative paths are
 * relative to the manifest's folder. The identity of a manifest is a hash of its
 * canonical JSON text (whitespace and key spacing do not count). */
#ifndef BRDFIT_BATCH_MANIFEST_H
#define BRDFIT_BATCH_MANIFEST_H

#include <cjson/cJSON.h>

#include "brdfit/compare.h"
#include "data_options.h"
#include "fit_options.h"
#include "rank_options.h"

#define BATCH_MAX_MODELS 128 /* models a manifest may list */

typedef struct batch_material {
    char *data;       /* the data file, resolved against the manifest's folder (owned) */
    char *scene;      /* its scene file, resolved (owned), or NULL */
    char *scene_word; /* "--scene=" and scene (owned), or NULL */
    char **words;     /* its data options as given (borrowed from the JSON tree), then
                        scene_word */
    int nwords;
} batch_material;

typedef struct batch_manifest {
    cJSON *root;
    char *text;    /* canonical JSON (owned) */
    char hash[17]; /* 64-bit FNV-1a of text, in hex */
    char **models; /* nmodels specs (owned), -m lists split as compare splits them */
    int nmodels;
    char **words; /* the shared options (borrowed from the JSON tree) */
    int nwords;
    batch_material *materials; /* nmaterials (owned) */
    int *lines;                /* a plain list's: the options: line, then each material's
                                   (owned; NULL for JSON), for the messages */
    int nmaterials;
    bf_options *o; /* the shared options, parsed (owned) */
} batch_manifest;

/* Reads and checks the manifest (like data_options.c, this prints its one-line errors,
 * prefix cmd, as the option parsers it calls do): the file at path, or text (path NULL:
 * a manifest stored in a results database; relative paths then stay as they are).
 * Every option is parsed and every model spec checked. 0, or -1 after the error. m is
 * zeroed first; clear it with batch_manifest_clear whatever the outcome. */
int batch_manifest_read(const char *path, const char *text, batch_manifest *m, const char *cmd);
void batch_manifest_clear(batch_manifest *m);

/* Material i's options: the shared ones, then its own data options, into *out (freed
 * with bf_options_free). 0, or -1 after the error. */
int batch_manifest_options(const batch_manifest *m, int i, bf_options **out, const char *cmd);

/* The options one work item ran with, exactly, as a JSON array of words (malloc'd;
 * NULL when out of memory): the shared options, the material's, then -m SPEC. */
char *batch_manifest_item_options(const batch_manifest *m, int material, int model);

#endif
