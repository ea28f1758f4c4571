/* Errors: every message is made safe to print where it is formatted (error.h), since
 * messages quote file content and go straight to terminals and logs. */
#include "brdfit/error.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Code points that act on a terminal or reorder what follows: C1 controls (U+009B is
 * a CSI), line and paragraph separators, bidirectional marks, embeddings and isolates;
 * and the two that are no characters at all (XML refuses them). */
static int is_control_point(unsigned cp)
{
    return cp <= 0x9f || cp == 0x061c || cp == 0x200e || cp == 0x200f || (cp >= 0x2028 && cp <= 0x202e) ||
           (cp >= 0x2066 && cp <= 0x2069) || cp == 0xfffe || cp == 0xffff;
}

/* One printed character of s: its text into out (at most 7 bytes and a NUL), *len its
 * bytes, *width its characters (an escape is several). Returns the bytes of s it covers. */
static size_t next_unit(const unsigned char *s, char out[8], size_t *len, size_t *width)
{
    unsigned c = s[0], cp = 0;
    size_t n = 0;
    if (c >= 0x20 && c < 0x7f) {
        out[0] = (char)c;
        *len = *width = 1;
        return 1;
    }
    if (c >= 0xc2 && c <= 0xdf)
        cp = c & 0x1f, n = 2;
    else if (c >= 0xe0 && c <= 0xef)
        cp = c & 0x0f, n = 3;
    else if (c >= 0xf0 && c <= 0xf4)
        cp = c & 0x07, n = 4;
    for (size_t k = 1; k < n; k++) {
        if ((s[k] & 0xc0) != 0x80) { /* also stops at the terminating NUL */
            n = 0;
            break;
        }
        cp = cp << 6 | (s[k] & 0x3fu);
    }
    /* Overlong forms, surrogates and values past U+10FFFF are not UTF-8. */
    if (n == 0 || (n == 3 && cp < 0x800) || (n == 4 && (cp < 0x10000 || cp > 0x10ffff)) ||
        (cp >= 0xd800 && cp <= 0xdfff)) {
        *len = *width = (size_t)snprintf(out, 8, "\\x%02x", c);
        return 1;
    }
    if (is_control_point(cp)) {
        *len = *width = (size_t)snprintf(out, 8, "\\u%04x", cp);
        return n;
    }
    memcpy(out, s, n);
    *len = n;
    *width = 1;
    return n;
}

/* The output under construction; cut is the last length at which "..." still fits. */
typedef struct sink {
    char *buf;
    size_t size, max_chars, used, chars, cut;
    int full;
} sink;

static void put(sink *k, const char *text, size_t len, size_t width)
{
    if (k->full)
        return;
    if (k->used + len > k->size - 1 || (k->max_chars && k->chars + width > k->max_chars)) {
        k->full = 1;
        return;
    }
    memcpy(k->buf + k->used, text, len);
    k->used += len;
    k->chars += width;
    if (k->used + 4 <= k->size && (!k->max_chars || k->chars + 3 <= k->max_chars))
        k->cut = k->used;
}

const char *bf_printable(const char *s, size_t max_token, size_t max_chars, char *buf, size_t size)
{
    sink k = {buf, size, max_chars, 0, 0, 0, 0};
    const unsigned char *p = (const unsigned char *)(s ? s : "");
    char u[8];
    size_t len, width;
    while (*p && !k.full) {
        if (*p == ' ') {
            put(&k, " ", 1, 1);
            p++;
            continue;
        }
        size_t n = 0; /* characters in this run without a blank */
        const unsigned char *end = p;
        while (*end && *end != ' ') {
            end += next_unit(end, u, &len, &width);
            n++;
        }
        size_t head = n, tail = n; /* characters [head, tail) become "..." */
        if (max_token >= 5 && n > max_token) {
            head = (max_token - 2) / 2;
            tail = n - (max_token - 3 - head);
        }
        for (size_t i = 0; p < end; i++) {
            p += next_unit(p, u, &len, &width);
            if (i < head || i >= tail)
                put(&k, u, len, width);
            else if (i == head)
                put(&k, "...", 3, 3);
        }
    }
    if (k.full) {
        memcpy(buf + k.cut, "...", 3);
        k.used = k.cut + 3;
    }
    buf[k.used] = '\0';
    return buf;
}

char *bf_printable_dup(const char *s)
{
    /* An escape is at most 4 characters per byte (\xHH; \uHHHH stands for 2 or 3). */
    size_t n = strlen(s);
    char *buf = n < (SIZE_MAX - 8) / 4 ? malloc(4 * n + 8) : NULL;
    return buf ? (char *)bf_printable(s, 0, 0, buf, 4 * n + 8) : NULL;
}

bf_status bf_failv(bf_error *err, bf_status code, const char *fmt, va_list ap)
{
    if (!err)
        return code;
    /* Formatted whole first (the problem is often named after a long quoted token),
     * into memory apart from err->msg, which may be one of the arguments. */
    char small[1024], *text = small;
    va_list again;
    va_copy(again, ap);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    if (n < 0)
        small[0] = '\0';
    else if ((size_t)n >= sizeof small && (text = malloc((size_t)n + 1)) != NULL)
        vsnprintf(text, (size_t)n + 1, fmt, again);
    else if (!text)
        text = small; /* out of memory: the message as far as it fitted */
    va_end(again);
    bf_printable(text, BF_ERROR_TOKEN_CHARS, BF_ERROR_MAX_CHARS, err->msg, sizeof err->msg);
    if (text != small)
        free(text);
    err->code = code;
    return code;
}

bf_status bf_fail(bf_error *err, bf_status code, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    bf_status rc = bf_failv(err, code, fmt, ap);
    va_end(ap);
    return rc;
}

const char *bf_status_name(bf_status code)
{
    switch (code) {
    case BF_OK: return "ok";
    case BF_ERR_ARG: return "arg";
    case BF_ERR_IO: return "io";
    case BF_ERR_PARSE: return "parse";
    case BF_ERR_RANGE: return "range";
    case BF_ERR_NOMEM: return "nomem";
    case BF_ERR_CANCELLED: return "cancelled";
    }
    return "unknown";
}

void bf_free(void *p)
{
    free(p);
}

void bf_error_clear(bf_error *err)
{
    if (err) {
        err->code = BF_OK;
        err->msg[0] = '\0';
    }
}
