/* Output files that appear only when complete, and exact decimal formatting. */
#include "brdfit/io.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

int bf_outfile_open(bf_outfile *o, const char *path, bf_error *err)
{
    memset(o, 0, sizeof *o);
    if (!path || strcmp(path, "-") == 0) {
        o->fp = stdout;
        return BF_OK;
    }
    size_t n = strlen(path);
    o->path = strdup(path);
    o->tmp = malloc(n + 16);
    if (!o->path || !o->tmp) {
        free(o->path);
        free(o->tmp);
        return bf_fail(err, BF_ERR_NOMEM, "%s: out of memory", path);
    }
    memcpy(o->tmp, path, n);
    memcpy(o->tmp + n, ".tmp.XXXXXX", 12);
    int fd = mkstemp(o->tmp);
    /* mkstemp makes the file 0600; the output gets the mode a plain create would. */
    mode_t mask = umask(0);
    umask(mask);
    if (fd >= 0)
        fchmod(fd, 0666 & ~mask);
    if (fd < 0 || !(o->fp = fdopen(fd, "w"))) {
        int e = errno;
        if (fd >= 0) {
            close(fd);
            unlink(o->tmp);
        }
        free(o->path);
        free(o->tmp);
        o->path = o->tmp = NULL;
        return bf_fail(err, BF_ERR_IO, "%s: cannot create: %s", path, strerror(e));
    }
    return BF_OK;
}

int bf_outfile_commit(bf_outfile *o, bf_error *err)
{
    int rc = BF_OK;
    if (!o->tmp) {
        if (fflush(o->fp) != 0)
            rc = bf_fail(err, BF_ERR_IO, "standard output: write error: %s", strerror(errno));
        return rc;
    }
    int bad = ferror(o->fp);
    if (fclose(o->fp) != 0 || bad)
        rc = bf_fail(err, BF_ERR_IO, "%s: write error: %s", o->path, strerror(errno));
    else if (rename(o->tmp, o->path) != 0)
        rc = bf_fail(err, BF_ERR_IO, "%s: cannot move into place: %s", o->path, strerror(errno));
    if (rc != BF_OK)
        unlink(o->tmp);
    free(o->path);
    free(o->tmp);
    memset(o, 0, sizeof *o);
    return rc;
}

void bf_outfile_abort(bf_outfile *o)
{
    if (o->tmp) {
        fclose(o->fp);
        unlink(o->tmp);
    }
    free(o->path);
    free(o->tmp);
    memset(o, 0, sizeof *o);
}

const char *bf_format_double(double v, char *buf, size_t size)
{
    for (int prec = 15; prec <= 17; prec++) {
        snprintf(buf, size, "%.*g", prec, v);
        if (strtod(buf, NULL) == v)
            break;
    }
    return buf;
}

void bf_csv_put_text(FILE *fp, const char *s)
{
    if (!strpbrk(s, ",\"\r\n")) {
        fputs(s, fp);
        return;
    }
    fputc('"', fp);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', fp);
        fputc(*s, fp);
    }
    fputc('"', fp);
}

void bf_csv_put_list(FILE *fp, const char *items, size_t stride, int n)
{
    /* Quoted as a whole when any item needs it, so the field reads back as one. */
    int quote = 0;
    for (int i = 0; i < n; i++)
        quote |= strpbrk(items + (size_t)i * stride, ",\"\r\n") != NULL;
    fputc(',', fp);
    if (quote)
        fputc('"', fp);
    for (int i = 0; i < n; i++) {
        if (i)
            fputs("; ", fp);
        for (const char *s = items + (size_t)i * stride; *s; s++) {
            if (*s == '"' && quote)
                fputc('"', fp);
            fputc(*s, fp);
        }
    }
    if (quote)
        fputc('"', fp);
}

void bf_csv_put_number(FILE *fp, double v)
{
    char buf[40];
    fputc(',', fp);
    if (isfinite(v))
        fputs(bf_format_double(v, buf, sizeof buf), fp);
}
