/* bf_outputs_check (io.h): a command's outputs against its inputs and each other,
 * before any work. Files are compared by device and inode, not by name, so "./x",
 * "dir/../x", a hard link and a symbolic link to x are all x. */
#include "brdfit/io.h"
#include "brdfit/tool.h"

#include "io/out_target.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* What a path is, for comparison: an existing regular file (dev, ino), or a file not
 * there yet (its folder's dev, ino and its name). Anything else is never "the same". */
typedef struct file_id {
    enum { ID_NONE, ID_FILE, ID_NEW } kind;
    dev_t dev;
    ino_t ino;
    const char *name; /* ID_NEW: the last component */
} file_id;

static int same(const file_id *a, const file_id *b)
{
    return a->kind != ID_NONE && a->kind == b->kind && a->dev == b->dev && a->ino == b->ino &&
           (a->kind == ID_FILE || !strcmp(a->name, b->name));
}

static file_id input_id(const char *path)
{
    file_id id = {ID_NONE, 0, 0, NULL};
    struct stat st;
    /* A missing input is its reader's error, reported later. */
    if (path && strcmp(path, "-") && stat(path, &st) == 0 && S_ISREG(st.st_mode))
        id = (file_id){ID_FILE, st.st_dev, st.st_ino, NULL};
    return id;
}

static file_id output_id(const out_target *t)
{
    file_id id = {ID_NONE, 0, 0, NULL};
    struct stat st;
    if (t->kind != OUT_NEW) {
        if (S_ISREG(t->st.st_mode))
            id = (file_id){ID_FILE, t->st.st_dev, t->st.st_ino, NULL};
        return id;
    }
    char *dir = out_dirname(t->file);
    if (dir && stat(dir, &st) == 0) {
        const char *slash = strrchr(t->file, '/');
        id = (file_id){ID_NEW, st.st_dev, st.st_ino, slash ? slash + 1 : t->file};
    }
    free(dir);
    return id;
}

bf_status bf_outputs_check(const bf_path_use *inputs, int ninputs, const bf_path_use *outputs, int noutputs,
                           bf_error *err)
{
    /* Usage first: standard input read twice, names that can never be written. */
    for (int i = 0, from_stdin = -1; i < ninputs; i++)
        if (inputs[i].path && !strcmp(inputs[i].path, "-")) {
            if (from_stdin >= 0)
                return bf_fail(err, BF_ERR_ARG, "%s - and %s - both read standard input", inputs[from_stdin].what,
                               inputs[i].what);
            from_stdin = i;
        }
    int to_stdout = -1;
    for (int o = 0; o < noutputs; o++) {
        const char *p = outputs[o].path;
        if (!p)
            continue;
        if (!*p)
            return bf_fail(err, BF_ERR_ARG, "%s: the file name is empty", outputs[o].what);
        if (!strcmp(p, "-")) {
            if (to_stdout >= 0)
                return bf_fail(err, BF_ERR_ARG, "%s - and %s - both write to standard output", outputs[to_stdout].what,
                               outputs[o].what);
            to_stdout = o;
        }
    }
    out_target *t = calloc((size_t)noutputs + 1, sizeof *t);
    file_id *ids = calloc((size_t)noutputs + 1, sizeof *ids);
    bf_status rc = t && ids ? BF_OK : bf_fail(err, BF_ERR_NOMEM, "out of memory");
    for (int a = 0; rc == BF_OK && a < noutputs; a++) {
        const char *p = outputs[a].path;
        if (p && strcmp(p, "-") && (rc = out_resolve(p, &t[a], err)) == BF_OK)
            ids[a] = output_id(&t[a]);
    }
    for (int a = 0; rc == BF_OK && a < noutputs; a++) {
        for (int i = 0; rc == BF_OK && i < ninputs; i++) {
            file_id in = input_id(inputs[i].path);
            if (same(&ids[a], &in))
                rc = bf_fail(err, BF_ERR_ARG, "%s %s is the same file as the %s %s: not overwriting an input",
                             outputs[a].what, outputs[a].path, inputs[i].what, inputs[i].path);
        }
        for (int b = 0; rc == BF_OK && b < a; b++)
            if (same(&ids[a], &ids[b]))
                rc = bf_fail(err, BF_ERR_ARG, "%s %s and %s %s are the same file", outputs[b].what, outputs[b].path,
                             outputs[a].what, outputs[a].path);
    }
    for (int a = 0; rc == BF_OK && a < noutputs; a++)
        if (t[a].file)
            rc = out_writable(&t[a], outputs[a].path, err);
    for (int a = 0; t && a < noutputs; a++)
        out_target_clear(&t[a]);
    free(t);
    free(ids);
    return rc;
}
