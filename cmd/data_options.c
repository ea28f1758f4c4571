/* The library's data options as command-line groups, and loading with errors printed
 * (data_options.h). */
#include "data_options.h"

#include <stdio.h>
#include <string.h>

const cli_group data_options_reading = CLI_LIBRARY_GROUP("reading", 0);
const cli_group data_options_preprocessing = CLI_LIBRARY_GROUP("preprocessing", 0);

bf_options *cmd_options_new(bf_task task, const char *cmd)
{
    bf_options *o = NULL;
    bf_error err;
    if (bf_options_new(task, &o, &err) != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err.msg);
        return NULL;
    }
    bf_options_set_spelling(o, BF_SPELL_COMMAND_LINE);
    return o;
}

int data_options_take_file(const char **data, const char *v, const char *cmd)
{
    if (*data) {
        fprintf(stderr, "%s: one data file only, got '%s' and '%s'\n", cmd, *data, v);
        return -1;
    }
    *data = v;
    return 0;
}

const char *data_options_scene(const bf_options *o, char *buf, size_t size)
{
    if (bf_options_get(o, "scene", buf, size, NULL) != BF_OK || !*buf)
        return NULL;
    return buf;
}

bf_samples *data_options_load(const bf_options *o, const char *path, bf_load_report *report, bf_error *err,
                              const char *cmd)
{
    bf_error e;
    bf_load_report r;
    bf_samples *s = NULL;
    bf_load_report_init(&r);
    if (!err)
        err = &e;
    bf_status rc = bf_samples_load(path, o, &s, &r, err);
    if (r.read > 0 || rc == BF_OK)
        cli_note(cmd, "read %s: %zu samples x %d channels", path, r.read, r.channels_read);
    if (rc != BF_OK) {
        fprintf(stderr, "%s: %s\n", cmd, err->msg);
        return NULL;
    }
    if (r.kept != r.read)
        cli_note(cmd, "%s: %zu samples after preprocessing%s", path, r.kept, r.scene ? " and the scene" : "");
    if (report)
        *report = r;
    return s;
}
