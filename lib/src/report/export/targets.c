/* Export (brdfit/export.h): the targets and the atomic write. The writers are gltf.c,
 * blender.c and mitsuba.c; the check and the conversion fit are
 * lib/src/study/export/convert.c. */
#include "brdfit/export.h"

#include "base/sized.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brdfit/io.h"

#include "export_impl.h"

static const bf_export_target targets[] = {
    {"gltf", "gltf", "glTF 2.0 (.gltf with a sphere)", bf_export_write_gltf},
    {"blender", "blender_principled", "Blender 3.4 (a Python script)", bf_export_write_blender},
    {"mitsuba", "mitsuba_principled", "Mitsuba 3 (scene XML)", bf_export_write_mitsuba},
};
enum { NTARGETS = sizeof targets / sizeof targets[0] };

int bf_export_target_count(void)
{
    return NTARGETS;
}

const bf_export_target *bf_export_target_get(int i)
{
    return i >= 0 && i < NTARGETS ? &targets[i] : NULL;
}

const bf_export_target *bf_export_target_find(const char *name)
{
    for (int i = 0; name && i < NTARGETS; i++)
        if (!strcmp(name, targets[i].name))
            return &targets[i];
    return NULL;
}

bf_status bf_export_text(const bf_export_target *t, const bf_export_material *e, char **out, bf_error *err)
{
    *out = NULL;
    if (e && bf_sized_check(e, sizeof *e, "bf_export_material", err) != BF_OK)
        return BF_ERR_ARG;
    if (!t || !e || !e->model || !e->x)
        return bf_fail(err, BF_ERR_ARG, "export: no target or no material");
    char *text = NULL;
    size_t len = 0;
    FILE *fp = open_memstream(&text, &len);
    if (!fp)
        return bf_fail(err, BF_ERR_NOMEM, "export: out of memory");
    bf_status rc = t->write(e, fp, err);
    if (fclose(fp) != 0 && rc == BF_OK)
        rc = bf_fail(err, BF_ERR_NOMEM, "export: out of memory");
    if (rc != BF_OK) {
        free(text);
        return rc;
    }
    *out = text;
    return BF_OK;
}

bf_status bf_export_write(const bf_export_target *t, const bf_export_material *e, const char *path, bf_error *err)
{
    if (e && bf_sized_check(e, sizeof *e, "bf_export_material", err) != BF_OK)
        return BF_ERR_ARG;
    if (!t || !e || !e->model || !e->x)
        return bf_fail(err, BF_ERR_ARG, "export: no target or no material");
    bf_outfile out;
    bf_status rc = bf_outfile_open(&out, path, err);
    if (rc != BF_OK)
        return rc;
    if ((rc = t->write(e, out.fp, err)) != BF_OK) {
        bf_outfile_abort(&out);
        return rc;
    }
    return bf_outfile_commit(&out, err);
}
