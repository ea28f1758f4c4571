/* Sample sets as CSV: angle columns (any names, degrees or radians), channel columns,
 * an optional weight column. */
#include "io/read_options.h"
#include "brdfit/formats.h"
#include "brdfit/io.h"
#include "brdfit/tool.h"
#include "brdfit/samples.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const default_angles[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};

/* The column named by the len bytes at name, or -1. */
static int column_of(const bf_csv *t, const char *name, size_t len)
{
    for (size_t c = 0; c < t->ncols; c++)
        if (strlen(t->names[c]) == len && !memcmp(t->names[c], name, len))
            return (int)c;
    return -1;
}

/* Column indices of the comma-separated names in list; returns the count or -1. */
/* idx[0..*n): the columns named in list (at most max). */
static bf_status find_columns(const bf_csv *t, const char *path, const char *list, int *idx, int max, int *n,
                              bf_error *err)
{
    *n = 0;
    for (const char *p = list; *p;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        int c = column_of(t, p, len);
        if (c < 0)
            return bf_fail(err, BF_ERR_PARSE, "%s: no column '%.*s' for a channel", path, (int)len, p);
        if (*n == max)
            return bf_fail(err, BF_ERR_PARSE, "%s: too many channel columns", path);
        idx[(*n)++] = c;
        if (!comma)
            break;
        p = comma + 1;
    }
    return BF_OK;
}

bf_status bf_samples_read_csv(const char *path, const bf_csv_map *map, bf_samples **out, bf_error *err)
{
    return bf_samples_read_csv_cancellable(path, map, NULL, out, err);
}

bf_status bf_samples_read_csv_cancellable(const char *path, const bf_csv_map *map, const bf_cancel_flag *cancel,
                                          bf_samples **out, bf_error *err)
{
    static const bf_csv_map defaults = {{NULL, NULL, NULL, NULL}, 0, NULL, NULL};
    if (!map)
        map = &defaults;
    *out = NULL;
    bf_csv *t;
    bf_status rc = bf_csv_read_cancellable(path, cancel, &t, err);
    if (rc != BF_OK)
        return rc;
    bf_samples *s = NULL;
    int *chan = malloc((t->ncols + 1) * sizeof *chan);
    int ang[4], wcol = -1, C = 0;
    if (!chan) {
        rc = bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
        goto done;
    }
    for (int k = 0; k < 4; k++) {
        const char *name = map->angle_cols[k] ? map->angle_cols[k] : default_angles[k];
        if ((ang[k] = bf_csv_column(t, name)) < 0) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s: missing angle column '%s' (columns are named with --angles)", path,
                         name);
            goto done;
        }
    }
    if (map->weight_col) {
        if ((wcol = bf_csv_column(t, map->weight_col)) < 0) {
            rc = bf_fail(err, BF_ERR_PARSE, "%s: no weight column '%s'", path, map->weight_col);
            goto done;
        }
    } else {
        wcol = bf_csv_column(t, "weight");
    }
    if (map->channels) {
        if ((rc = find_columns(t, path, map->channels, chan, (int)t->ncols, &C, err)) != BF_OK)
            goto done;
    } else {
        for (size_t c = 0; c < t->ncols; c++)
            if ((int)c != ang[0] && (int)c != ang[1] && (int)c != ang[2] && (int)c != ang[3] && (int)c != wcol)
                chan[C++] = (int)c;
    }
    if (C == 0) {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: no value columns besides the angles", path);
        goto done;
    }
    if (C > BF_MAX_CHANNELS) {
        rc = bf_fail(err, BF_ERR_RANGE, "%s: %d value columns; brdfit reads at most %d channels", path, C,
                     BF_MAX_CHANNELS);
        goto done;
    }
    if ((rc = bf_samples_new(t->nrows, C, &s, err)) != BF_OK) {
        goto done;
    }
    for (int c = 0; c < C; c++)
        if ((rc = bf_samples_set_channel_name(s, c, t->names[chan[c]], err)) != BF_OK)
            goto done;
    if (wcol >= 0 && (rc = bf_samples_add_weights(s, err)) != BF_OK)
        goto done;
    const double to_deg = map->radians ? 180.0 / M_PI : 1.0;
    double *angle[4] = {s->theta_i, s->phi_i, s->theta_o, s->phi_o};
    for (size_t r = 0; r < t->nrows; r++) {
        const double *row = t->data + r * t->ncols;
        for (int k = 0; k < 4; k++)
            angle[k][r] = row[ang[k]] * to_deg;
        /* theta beyond [0, 180] degrees names no direction this tool knows. */
        for (int k = 0; k < 4; k += 2)
            if (angle[k][r] < 0.0 || angle[k][r] > 180.0 + 1e-9) {
                rc = bf_fail(err, BF_ERR_RANGE, "%s:%zu: %s = %g is outside [0, %s]", path, t->line[r],
                             t->names[ang[k]], row[ang[k]], map->radians ? "pi" : "180");
                goto done;
            }
        for (int c = 0; c < C; c++)
            s->value[r * (size_t)C + (size_t)c] = row[chan[c]];
        if (wcol >= 0) {
            s->weight[r] = row[wcol];
            if (row[wcol] < 0.0) {
                rc = bf_fail(err, BF_ERR_RANGE, "%s:%zu: weight %g is negative", path, t->line[r], row[wcol]);
                goto done;
            }
        }
    }
done:
    free(chan);
    bf_csv_free(t);
    if (rc != BF_OK) {
        bf_samples_free(s);
        return rc;
    }
    *out = s;
    return BF_OK;
}

/* Whether channel c may be written under name: not an angle or weight column's name
 * (a CSV read with --angles or --weight may have a value column called so), nor a name
 * an earlier channel is written under or a later one has. */
static int name_free(const bf_samples *s, char *const *names, int c, const char *name)
{
    if (!*name)
        return 0;
    for (int k = 0; k < 4; k++)
        if (!strcmp(name, default_angles[k]))
            return 0;
    if (!strcmp(name, "weight"))
        return 0;
    for (int d = 0; d < s->channels; d++)
        if (d != c && !strcmp(name, d < c ? names[d] : s->channel_names[d]))
            return 0;
    return 1;
}

static void free_names(char **names, int n)
{
    for (int c = 0; c < n; c++)
        free(names[c]);
    free(names);
}

/* The header's channel names: each channel's own, or where that would make the file
 * unreadable or read back otherwise, the first free of NAME_2, NAME_3 ... (malloc'd
 * array of malloc'd names, NULL out of memory). */
static char **header_names(const bf_samples *s)
{
    char **names = calloc((size_t)s->channels, sizeof *names);
    for (int c = 0; names && c < s->channels; c++) {
        const char *own = s->channel_names[c];
        size_t size = strlen(own) + 24;
        if (!(names[c] = malloc(size))) {
            free_names(names, c);
            return NULL;
        }
        snprintf(names[c], size, "%s", own);
        for (unsigned long k = 2; !name_free(s, names, c, names[c]); k++)
            snprintf(names[c], size, "%s_%lu", own, k);
    }
    return names;
}

/* A header name as the reader reads it back: quoted when it holds a comma, a quote or
 * a line break (bf_csv_put_text), or starts or ends with a blank (which the reader
 * would trim). */
static void put_name(FILE *fp, const char *name)
{
    size_t len = strlen(name);
    fputc(',', fp);
    if (len && (isspace((unsigned char)name[0]) || isspace((unsigned char)name[len - 1])) && !strpbrk(name, ",\"\r\n"))
        fprintf(fp, "\"%s\"", name);
    else
        bf_csv_put_text(fp, name);
}

bf_status bf_samples_write_csv(const bf_samples *s, const char *path, bf_error *err)
{
    char **names = header_names(s);
    if (!names)
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    bf_outfile o;
    bf_status rc = bf_outfile_open(&o, path, err);
    if (rc != BF_OK) {
        free_names(names, s->channels);
        return rc;
    }
    const size_t C = (size_t)s->channels;
    char buf[40];
    fputs("theta_i,phi_i,theta_o,phi_o", o.fp);
    for (size_t c = 0; c < C; c++)
        put_name(o.fp, names[c]);
    free_names(names, s->channels);
    if (s->weight)
        fputs(",weight", o.fp);
    fputc('\n', o.fp);
    for (size_t i = 0; i < s->n; i++) {
        double dir[4];
        bf_samples_direction(s, i, dir);
        for (int k = 0; k < 4; k++)
            fprintf(o.fp, "%s%s", k ? "," : "", bf_format_double(dir[k], buf, sizeof buf));
        for (size_t c = 0; c < C; c++)
            fprintf(o.fp, ",%s", bf_format_double(s->value[i * C + c], buf, sizeof buf));
        if (s->weight)
            fprintf(o.fp, ",%s", bf_format_double(s->weight[i], buf, sizeof buf));
        fputc('\n', o.fp);
    }
    return bf_outfile_commit(&o, err); /* checks every write */
}
