/* Model lists as -m takes them (brdfit/model.h): one rule for every front end. */
#include "brdfit/model.h"

#include <stdlib.h>
#include <string.h>

/* A comma starts a new model where the next token names one: it has no '=', or a ':' of
 * its own ("G=smith_ggx" continues "microfacet:D=ggx"). */
static int starts_model(const char *tok, size_t len)
{
    const char *eq = memchr(tok, '=', len), *colon = memchr(tok, ':', len);
    return !eq || colon;
}

/* The entries of list as [start, length) pairs into spans (2 * max entries; NULL: only
 * counted), "all" expanded to the families; the count, or -1 after an error in err. */
static int entries(const char *list, size_t *spans, int max, size_t *bytes, bf_error *err)
{
    int n = 0, after_all = 0;
    *bytes = 0;
    for (const char *p = list; *p;) {
        const char *comma = strchr(p, ',');
        size_t len = comma ? (size_t)(comma - p) : strlen(p);
        if (len == 0) {
            bf_fail(err, BF_ERR_ARG, "empty model name in '%s'", list);
            return -1;
        }
        if (n > 0 && !starts_model(p, len)) { /* an option of the previous model */
            if (after_all) {
                bf_fail(err, BF_ERR_ARG, "'%.*s' follows all in '%s': options belong to one model", (int)len, p, list);
                return -1;
            }
            if (spans)
                spans[2 * (n - 1) + 1] = (size_t)(p + len - list) - spans[2 * (n - 1)];
            *bytes += len + 1;
        } else if (len == 3 && !strncmp(p, "all", 3)) {
            for (int f = 0; f < bf_family_count(); f++, n++) {
                if (spans && n < max) /* a family: marked by a start past the text */
                    spans[2 * n] = strlen(list) + 1 + (size_t)f, spans[2 * n + 1] = 0;
                *bytes += strlen(bf_family_get(f)->name) + 1;
            }
            after_all = 1;
        } else {
            after_all = 0;
            if (spans && n < max)
                spans[2 * n] = (size_t)(p - list), spans[2 * n + 1] = len;
            *bytes += len + 1;
            n++;
        }
        p = comma ? comma + 1 : p + len;
    }
    return n;
}

bf_status bf_model_list_split(const char *list, char ***specs, int *n, bf_error *err)
{
    *specs = NULL;
    *n = 0;
    if (!list || !*list)
        return bf_fail(err, BF_ERR_ARG, "empty model list");
    size_t bytes;
    int count = entries(list, NULL, 0, &bytes, err);
    if (count < 0)
        return BF_ERR_ARG;
    size_t *spans = malloc(2 * (size_t)count * sizeof *spans);
    /* One block: the pointers, then the texts (freed with one bf_free). */
    char **out = malloc((size_t)count * sizeof *out + bytes);
    if (!spans || !out) {
        free(spans);
        free(out);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    entries(list, spans, count, &bytes, err);
    char *text = (char *)(out + count);
    size_t end = strlen(list);
    for (int k = 0; k < count; k++) {
        const char *from =
            spans[2 * k] > end ? bf_family_get((int)(spans[2 * k] - end - 1))->name : list + spans[2 * k];
        size_t len = spans[2 * k] > end ? strlen(from) : spans[2 * k + 1];
        out[k] = text;
        memcpy(text, from, len);
        text[len] = '\0';
        text += len + 1;
    }
    free(spans);
    *specs = out;
    *n = count;
    return BF_OK;
}
