/* Repeated keys in JSON objects (json_keys.h). */
#include "json_keys.h"

#include <stdlib.h>
#include <string.h>

static int by_key(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

int bf_json_repeated_key(const cJSON *obj, const char **key)
{
    size_t n = 0;
    for (const cJSON *m = obj ? obj->child : NULL; m; m = m->next)
        n++;
    if (n < 2)
        return 0;
    const char **keys = malloc(n * sizeof *keys);
    if (!keys)
        return -1;
    n = 0;
    for (const cJSON *m = obj->child; m; m = m->next)
        keys[n++] = m->string ? m->string : "";
    qsort(keys, n, sizeof *keys, by_key);
    int found = 0;
    for (size_t i = 1; i < n && !found; i++)
        if (!strcmp(keys[i - 1], keys[i])) {
            *key = keys[i];
            found = 1;
        }
    free(keys);
    return found;
}
