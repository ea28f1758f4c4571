/* Positions in JSON text (json_pos.h). */
#include "json_pos.h"

#include <stdlib.h>
#include <string.h>

const char *bf_json_skip_ws(const char *p)
{
    while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r')
        p++;
    return p;
}

/* Past the string whose opening quote is at p. */
static const char *skip_string(const char *p)
{
    for (p++; *p && *p != '"'; p++)
        if (*p == '\\' && p[1])
            p++;
    return *p ? p + 1 : p;
}

const char *bf_json_skip_value(const char *p)
{
    p = bf_json_skip_ws(p);
    if (*p == '"')
        return skip_string(p);
    if (*p != '{' && *p != '[') {
        while (*p && !strchr(",]} \t\r\n", *p))
            p++;
        return p;
    }
    int depth = 0;
    while (*p) {
        if (*p == '"') {
            p = skip_string(p);
            continue;
        }
        if (*p == '{' || *p == '[')
            depth++;
        else if ((*p == '}' || *p == ']') && --depth == 0)
            return p + 1;
        p++;
    }
    return p;
}

const char *bf_json_member(const char *p, const char *key, size_t klen, int want_key)
{
    if (!p || *(p = bf_json_skip_ws(p)) != '{')
        return NULL;
    for (p = bf_json_skip_ws(p + 1); *p == '"';) {
        const char *name = p + 1, *end = skip_string(p), *v = bf_json_skip_ws(end);
        if (*v != ':')
            return NULL;
        v = bf_json_skip_ws(v + 1);
        if ((size_t)(end - 1 - name) == klen && !memcmp(name, key, klen))
            return want_key ? p : v;
        p = bf_json_skip_ws(bf_json_skip_value(v));
        if (*p != ',')
            return NULL;
        p = bf_json_skip_ws(p + 1);
    }
    return NULL;
}

const char *bf_json_element(const char *p, long k)
{
    if (!p || *(p = bf_json_skip_ws(p)) != '[')
        return NULL;
    p = bf_json_skip_ws(p + 1);
    for (long i = 0; i < k; i++) {
        p = bf_json_skip_ws(bf_json_skip_value(p));
        if (*p != ',')
            return NULL;
        p = bf_json_skip_ws(p + 1);
    }
    return *p && *p != ']' ? p : NULL;
}

int bf_json_line(const char *text, const char *pos)
{
    int line = 1;
    for (const char *p = text; pos && p < pos && *p; p++)
        line += *p == '\n';
    return line;
}

int bf_json_line_of_path(const char *text, const char *path)
{
    if (!text)
        return 1;
    const char *at = bf_json_skip_ws(text), *seg = path;
    while (*seg) {
        size_t n = strcspn(seg, "/");
        const char *next = *at == '[' ? bf_json_element(at, strtol(seg, NULL, 10)) : bf_json_member(at, seg, n, 0);
        if (!next)
            break;
        at = next;
        seg += n;
        seg += *seg == '/';
    }
    return bf_json_line(text, at);
}

bf_status bf_json_parse_failure(const char *text, const char *end, const char *path, bf_error *err)
{
    /* Quote the line where cJSON stopped (it may stop just past the culprit). */
    char near[48] = "";
    const char *pos = end ? end : text, *b = pos;
    while (b > text && b[-1] != '\n' && pos - b < 40)
        b--;
    while (*b == ' ' || *b == '\t')
        b++;
    size_t k = 0;
    while (k < sizeof near - 1 && b[k] && b[k] != '\n' && b[k] != '\r')
        k++;
    memcpy(near, b, k);
    near[k] = '\0';
    size_t line = (size_t)bf_json_line(text, pos);
    if (!k && !*pos)
        return bf_fail(err, BF_ERR_PARSE, "%s:%zu: malformed JSON: unexpected end of file", path, line);
    return bf_fail(err, BF_ERR_PARSE, "%s:%zu: malformed JSON in or just before '%s'", path, line, k ? near : "?");
}
