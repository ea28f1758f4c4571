/* Direction sets for evaluable formats (direction_grid.h). */
#include "direction_grid.h"

#include "brdfit/io.h"
#include "brdfit/merl.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#define UNIFORM_MAX 128

/* Every MERL cell whose centre has both directions above the horizon. */
static bf_status merl_grid(int channels, bf_samples **out, bf_error *err)
{
    size_t n = 0;
    for (int32_t c = 0; c < BF_MERL_CELLS; c++) {
        double ti, pi, to, po;
        bf_merl_cell_directions(c, &ti, &pi, &to, &po);
        n += ti < 90.0 && to < 90.0;
    }
    bf_samples *s;
    bf_status rc = bf_samples_new_cells(n, channels, &s, err);
    if (rc != BF_OK)
        return rc;
    size_t i = 0;
    for (int32_t c = 0; c < BF_MERL_CELLS; c++) {
        double ti, pi, to, po;
        bf_merl_cell_directions(c, &ti, &pi, &to, &po);
        if (ti < 90.0 && to < 90.0)
            s->merl->cell[i++] = c;
    }
    *out = s;
    return BF_OK;
}

static bf_status uniform_grid(const char *spec, const char *count, int channels, bf_samples **out, bf_error *err)
{
    char *end;
    errno = 0;
    const long N = isdigit((unsigned char)*count) ? strtol(count, &end, 10) : 0;
    if (!isdigit((unsigned char)*count) || *end || errno || N < 1 || N > UNIFORM_MAX)
        return bf_fail(err, BF_ERR_ARG, "grid %s: uniform:N needs N from 1 to %d", spec, UNIFORM_MAX);
    const size_t n = (size_t)N * (size_t)N * (size_t)N;
    bf_samples *s;
    bf_status rc = bf_samples_new(n, channels, &s, err);
    if (rc != BF_OK)
        return rc;
    size_t i = 0;
    for (long a = 0; a < N; a++)
        for (long b = 0; b < N; b++)
            for (long c = 0; c < N; c++, i++) {
                s->theta_i[i] = (a + 0.5) * 90.0 / N;
                s->phi_i[i] = 0.0;
                s->theta_o[i] = (b + 0.5) * 90.0 / N;
                s->phi_o[i] = (c + 0.5) * 180.0 / N;
            }
    *out = s;
    return BF_OK;
}

static bf_status file_grid(const char *path, int channels, bf_samples **out, bf_error *err)
{
    bf_csv *t;
    bf_status rc = bf_csv_read(path, &t, err);
    if (rc != BF_OK)
        return rc;
    static const char *const names[4] = {"theta_i", "phi_i", "theta_o", "phi_o"};
    int col[4];
    for (int k = 0; k < 4; k++)
        if ((col[k] = bf_csv_column(t, names[k])) < 0) {
            bf_csv_free(t);
            return bf_fail(err, BF_ERR_PARSE, "%s: no column %s (a direction grid needs theta_i,phi_i,theta_o,phi_o)",
                           path, names[k]);
        }
    if (t->nrows == 0) {
        bf_csv_free(t);
        return bf_fail(err, BF_ERR_PARSE, "%s: no direction rows", path);
    }
    bf_samples *s;
    if ((rc = bf_samples_new(t->nrows, channels, &s, err)) != BF_OK) {
        bf_csv_free(t);
        return rc;
    }
    double *dst[4] = {s->theta_i, s->phi_i, s->theta_o, s->phi_o};
    for (size_t r = 0; r < t->nrows; r++)
        for (int k = 0; k < 4; k++)
            dst[k][r] = t->data[r * t->ncols + (size_t)col[k]];
    bf_csv_free(t);
    *out = s;
    return BF_OK;
}

bf_status bf_direction_grid(const char *spec, int channels, bf_samples **out, bf_error *err)
{
    *out = NULL;
    if (!strcmp(spec, "merl"))
        return merl_grid(channels, out, err);
    if (!strncmp(spec, "uniform:", 8))
        return uniform_grid(spec, spec + 8, channels, out, err);
    return file_grid(spec, channels, out, err);
}
