/* brdfit batch manifests, JSON and plain list (cmd/batch/batch_manifest.c, cmd/batch/batch_list.c):
 * read; when one is accepted, its canonical JSON, which the results database stores and
 * brdfit report and merge read back, must read back as the same manifest: the same
 * identity, models, options and materials (paths as resolved against the folder). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "batch/batch_manifest.h"
#include "fuzz_common.h"

/* a, a path resolved against folder dir (with its '/'), is b as stored: b itself when
 * absolute, else dir + b. */
static int same_path(const char *a, const char *b, const char *dir)
{
    if (b[0] == '/')
        return !strcmp(a, b);
    const size_t n = strlen(dir);
    return !strncmp(a, dir, n) && !strcmp(a + n, b);
}

static void same_manifest(const batch_manifest *a, const batch_manifest *b, const char *dir)
{
    if (a->nmodels != b->nmodels || a->nmaterials != b->nmaterials || a->nwords != b->nwords)
        fuzz_fail("%d x %d items, %d options read back as %d x %d, %d", a->nmaterials, a->nmodels, a->nwords,
                  b->nmaterials, b->nmodels, b->nwords);
    for (int j = 0; j < a->nmodels; j++)
        if (strcmp(a->models[j], b->models[j]))
            fuzz_fail("model %d '%s' read back as '%s'", j, a->models[j], b->models[j]);
    for (int k = 0; k < a->nwords; k++)
        if (strcmp(a->words[k], b->words[k]))
            fuzz_fail("option %d '%s' read back as '%s'", k, a->words[k], b->words[k]);
    for (int i = 0; i < a->nmaterials; i++) {
        const batch_material *x = &a->materials[i], *y = &b->materials[i];
        if (!same_path(x->data, y->data, dir) || !x->scene != !y->scene ||
            (x->scene && !same_path(x->scene, y->scene, dir)) || x->nwords != y->nwords)
            fuzz_fail("material %d (%s) read back as %s", i, x->data, y->data);
        /* Its own words, then "--scene" and the resolved scene. */
        for (int k = 0; k < x->nwords - (x->scene ? 1 : 0); k++)
            if (strcmp(x->words[k], y->words[k]))
                fuzz_fail("material %d: option '%s' read back as '%s'", i, x->words[k], y->words[k]);
        bf_options *o = NULL;
        if (batch_manifest_options(b, i, &o, "fuzz") < 0)
            fuzz_fail("material %d's options do not parse when read back", i);
        bf_options_free(o);
    }
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write("manifest", data, size);
    char dir[512];
    snprintf(dir, sizeof dir, "%s", path);
    strrchr(dir, '/')[1] = '\0';
    batch_manifest m, back;
    if (batch_manifest_read(path, NULL, &m, "fuzz") == 0) {
        if (m.nmodels < 1 || m.nmaterials < 1 || !m.text || strlen(m.hash) != 16)
            fuzz_fail("accepted a manifest with %d models, %d materials", m.nmodels, m.nmaterials);
        /* As brdfit report and merge read it from a database: no folder. */
        if (batch_manifest_read(NULL, m.text, &back, "fuzz") < 0)
            fuzz_fail("the canonical text of an accepted manifest is refused: %s", m.text);
        if (strcmp(m.hash, back.hash))
            fuzz_fail("identity %s read back as %s", m.hash, back.hash);
        same_manifest(&m, &back, dir);
        batch_manifest_clear(&back);
    }
    batch_manifest_clear(&m);
    return 0;
}
