/* How much memory brdfit may still take (brdfit/limits.h). Linux hands out memory it
 * does not have (overcommit) and kills the process that touches too much of it, with no
 * message. So large allocations ask first: the least of what the machine has available,
 * what the process's control group (container, batch job) still allows, the process's
 * address-space limit, and BRDFIT_MEMORY. */
#include "big_alloc.h"

#include "brdfit/limits.h"

#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* 1 and *out set when s is a byte count, else 0. */
static int parse_bytes(const char *s, size_t *out)
{
    if (!s || !isdigit((unsigned char)*s))
        return 0;
    errno = 0;
    char *end;
    unsigned long long v = strtoull(s, &end, 10);
    if (errno)
        return 0;
    unsigned shift = 0;
    switch (toupper((unsigned char)*end)) {
    case 'K':
        shift = 10;
        end++;
        break;
    case 'M':
        shift = 20;
        end++;
        break;
    case 'G':
        shift = 30;
        end++;
        break;
    case 'T':
        shift = 40;
        end++;
        break;
    default: break;
    }
    if (*end || v > (SIZE_MAX >> shift))
        return 0;
    *out = (size_t)v << shift;
    return 1;
}

bf_status bf_bytes_parse(const char *s, size_t *out, bf_error *err)
{
    if (!parse_bytes(s, out))
        return bf_fail(err, BF_ERR_ARG, "'%s' is not a byte count (such as 4G, 512M or 1000000)", s ? s : "");
    return BF_OK;
}

/* The first number in a file, or 0 when it has none ("max" in cgroup v2). */
static int read_number(const char *path, unsigned long long *v)
{
    FILE *fp = fopen(path, "r");
    if (!fp)
        return 0;
    int ok = fscanf(fp, "%llu", v) == 1;
    fclose(fp);
    return ok;
}

/* A field of a key-value file such as /proc/meminfo or memory.stat. */
static int read_field(const char *path, const char *key, unsigned long long *v)
{
    FILE *fp = fopen(path, "r");
    if (!fp)
        return 0;
    char line[256];
    const size_t klen = strlen(key);
    int ok = 0;
    while (!ok && fgets(line, sizeof line, fp))
        if (!strncmp(line, key, klen) && (line[klen] == ' ' || line[klen] == ':'))
            ok = sscanf(line + klen + 1, " %llu", v) == 1;
    fclose(fp);
    return ok;
}

static void keep_least(size_t *least, unsigned long long v)
{
    if (v < *least)
        *least = (size_t)v;
}

/* A control group's limit less what it uses, page cache it can drop not counted. */
static void cgroup_room(const char *dir, const char *limit, const char *usage, const char *cache, size_t *least)
{
    char path[512];
    unsigned long long max, used, dropable = 0;
    snprintf(path, sizeof path, "%s/%s", dir, limit);
    if (!read_number(path, &max))
        return;
    snprintf(path, sizeof path, "%s/%s", dir, usage);
    if (!read_number(path, &used))
        return;
    snprintf(path, sizeof path, "%s/memory.stat", dir);
    (void)read_field(path, cache, &dropable);
    used = dropable < used ? used - dropable : 0;
    keep_least(least, max > used ? max - used : 0);
}

size_t bf_memory_available(void)
{
    size_t least = SIZE_MAX;
    unsigned long long kib;
    if (read_field("/proc/meminfo", "MemAvailable", &kib))
        keep_least(&least, kib * 1024ull);
    else {
        const long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        if (pages > 0 && page > 0)
            keep_least(&least, (unsigned long long)pages * (unsigned long long)page);
    }
    /* cgroup v2 as a container sees it, then v1. */
    cgroup_room("/sys/fs/cgroup", "memory.max", "memory.current", "inactive_file", &least);
    cgroup_room("/sys/fs/cgroup/memory", "memory.limit_in_bytes", "memory.usage_in_bytes", "total_inactive_file",
                &least);
    struct rlimit r;
    if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
        keep_least(&least, r.rlim_cur);
    size_t user;
    if (parse_bytes(getenv("BRDFIT_MEMORY"), &user))
        keep_least(&least, user);
    return least;
}

int bf_memory_allows(size_t bytes)
{
    return bytes < BF_MEMORY_UNCHECKED || bytes <= bf_memory_available();
}

/* Sizes in the unit that reads best, powers of 1024 as BRDFIT_MEMORY takes them:
 * 18.3 MiB, 4.56 GiB, 5 TiB. */
static void human(char *buf, size_t len, double bytes)
{
    static const char *unit[] = {"MiB", "GiB", "TiB"};
    int u = 0;
    bytes /= 1048576.0;
    while (u < 2 && bytes >= 1024.0) {
        bytes /= 1024.0;
        u++;
    }
    snprintf(buf, len, "%.3g %s", bytes, unit[u]);
}

bf_status bf_fail_memory(bf_error *err, const char *path, size_t line, size_t bytes)
{
    char where[32] = "";
    if (line)
        snprintf(where, sizeof where, ":%zu", line);
    char need[32], have[32];
    const size_t avail = bf_memory_available();
    human(need, sizeof need, (double)bytes);
    if (avail == SIZE_MAX || bytes == SIZE_MAX)
        return bf_fail(err, BF_ERR_NOMEM, "%s%s: out of memory", path, where);
    human(have, sizeof have, (double)avail);
    return bf_fail(err, BF_ERR_NOMEM, "%s%s: not enough memory: %s needed, %s available%s", path, where, need, have,
                   getenv("BRDFIT_MEMORY") ? " (BRDFIT_MEMORY)" : "");
}
