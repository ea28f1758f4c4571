/* Finds and loads the image module (see image_plugin.h) the first time an image is
 * written or read.
 *
 * Where the module (BRDFIT_PLUGIN_FILE, libbrdfit-oiio.so) is looked for, in order:
 *  1. $BRDFIT_PLUGIN_DIR, if set and not empty: there and nowhere else, so that a wrong
 *     setting fails loudly instead of quietly loading some other copy.
 *  2. Relative to the shared library libbrdfit.so, when this code runs in it (found with
 *     dladdr): <its directory>/BRDFIT_PLUGIN_LIB_REL_DIR (lib -> lib/brdfit), so any
 *     program linked to an installed (or relocated) library uses that install's module.
 *  3. Relative to the running executable, as installed: <directory of /proc/self/exe>/
 *     BRDFIT_PLUGIN_REL_DIR (the bin -> lib/brdfit step), so a relocated install (a
 *     staged DESTDIR, an unpacked package) uses its own module.
 *  4. The build tree (BRDFIT_PLUGIN_BUILD_DIR), so the commands and the tests run from
 *     the build directory without installing.
 *  5. The install directory (BRDFIT_PLUGIN_INSTALL_DIR, ${libdir}/brdfit).
 * The first of 2-5 where the file exists is loaded; if it is there but does not load
 * (a missing OpenImageIO library, a stale ABI) that is the error, rather than falling
 * through to an older copy. The outcome, success or failure, is kept for the process. */
/* dladdr is a GNU extension. */
#define _GNU_SOURCE
#include "io/image_plugin.h"

#include <dlfcn.h>
#include <limits.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef BRDFIT_PLUGIN_FILE
#define BRDFIT_PLUGIN_FILE "libbrdfit-oiio.so"
#endif

static pthread_once_t load_once = PTHREAD_ONCE_INIT;
static bf_image_plugin plugin;
static int plugin_ok;
static char load_error[sizeof((bf_error *)0)->msg];

/* load_error = the fixed prefix + the reason (cut to fit, like every bf_error). */
#if defined(__GNUC__)
__attribute__((format(printf, 1, 2)))
#endif
static void
set_error(const char *fmt, ...)
{
    int n = snprintf(load_error, sizeof load_error, "image support (%s) could not be loaded: ", BRDFIT_PLUGIN_FILE);
    if (n < 0 || (size_t)n >= sizeof load_error)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(load_error + n, sizeof load_error - (size_t)n, fmt, ap);
    va_end(ap);
}

/* dir + "/" + the module's file name into buf; 0 when it does not fit. */
static int module_path(char *buf, size_t size, const char *dir)
{
    int n = snprintf(buf, size, "%s/%s", dir, BRDFIT_PLUGIN_FILE);
    return n > 0 && (size_t)n < size;
}

/* Loads path and takes its entry points; on failure sets load_error and returns 0. */
static int load_from(const char *path)
{
    /* RTLD_LOCAL: OpenImageIO's symbols stay out of the global namespace. The handle is
     * never closed: the module lives as long as the process. */
    void *h = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (!h) {
        const char *e = dlerror();
        set_error("%s", e ? e : path);
        return 0;
    }
    /* The version first, so that a stale module (whose entry points differ) is named as
     * one rather than as missing some. */
    bf_oiio_abi_fn abi = (bf_oiio_abi_fn)dlsym(h, "bf_oiio_abi");
    if (!abi) {
        set_error("%s: missing entry points", path);
        dlclose(h);
        return 0;
    }
    int version = abi();
    if (version != BF_IMAGE_PLUGIN_ABI) {
        set_error("%s: interface version %d, want %d", path, version, BF_IMAGE_PLUGIN_ABI);
        dlclose(h);
        return 0;
    }
    plugin.encode = (bf_oiio_encode_fn)dlsym(h, "bf_oiio_encode");
    plugin.read = (bf_oiio_read_fn)dlsym(h, "bf_oiio_read");
    plugin.read_rows = (bf_oiio_read_rows_fn)dlsym(h, "bf_oiio_read_rows");
    plugin.info = (bf_oiio_info_fn)dlsym(h, "bf_oiio_info");
    if (!plugin.encode || !plugin.read || !plugin.read_rows || !plugin.info) {
        set_error("%s: missing entry points", path);
        dlclose(h);
        return 0;
    }
    return 1;
}

/* The directory of file joined with rel; 0 if the path does not fit. */
static int sibling_dir(char *buf, size_t size, const char *file, const char *rel)
{
    const char *slash = strrchr(file, '/');
    if (!slash)
        return 0;
    int m = snprintf(buf, size, "%.*s/%s", (int)(slash - file), file, rel);
    return m > 0 && (size_t)m < size;
}

/* The directory of the running executable joined with BRDFIT_PLUGIN_REL_DIR; 0 if
 * /proc is unavailable or the path does not fit. */
static int exe_relative_dir(char *buf, size_t size)
{
#ifdef BRDFIT_PLUGIN_REL_DIR
    char exe[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0)
        return 0;
    exe[n] = '\0';
    return sibling_dir(buf, size, exe, BRDFIT_PLUGIN_REL_DIR);
#else
    (void)buf;
    (void)size;
    return 0;
#endif
}

/* The directory of the shared library holding this code joined with
 * BRDFIT_PLUGIN_LIB_REL_DIR; 0 in a static link, where the object dladdr names is the
 * executable itself (step 3 covers that), or when the path is unknown. */
static int lib_relative_dir(char *buf, size_t size)
{
#ifdef BRDFIT_PLUGIN_LIB_REL_DIR
    Dl_info info;
    char exe[PATH_MAX], lib[PATH_MAX];
    if (!dladdr((void *)bf_image_plugin_get, &info) || !info.dli_fname || info.dli_fname[0] != '/')
        return 0;
    if (!realpath(info.dli_fname, lib) || !realpath("/proc/self/exe", exe) || !strcmp(lib, exe))
        return 0;
    return sibling_dir(buf, size, lib, BRDFIT_PLUGIN_LIB_REL_DIR);
#else
    (void)buf;
    (void)size;
    return 0;
#endif
}

static void load(void)
{
    char path[PATH_MAX];
    const char *env = getenv("BRDFIT_PLUGIN_DIR");
    if (env && *env) {
        if (!module_path(path, sizeof path, env))
            set_error("BRDFIT_PLUGIN_DIR is too long");
        else
            plugin_ok = load_from(path);
        return;
    }

    char dirs[4][PATH_MAX];
    int ndirs = 0;
    if (lib_relative_dir(dirs[ndirs], sizeof dirs[ndirs]))
        ndirs++;
    if (exe_relative_dir(dirs[ndirs], sizeof dirs[ndirs]))
        ndirs++;
#ifdef BRDFIT_PLUGIN_BUILD_DIR
    snprintf(dirs[ndirs++], PATH_MAX, "%s", BRDFIT_PLUGIN_BUILD_DIR);
#endif
#ifdef BRDFIT_PLUGIN_INSTALL_DIR
    snprintf(dirs[ndirs++], PATH_MAX, "%s", BRDFIT_PLUGIN_INSTALL_DIR);
#endif
    for (int i = 0; i < ndirs; i++) {
        if (module_path(path, sizeof path, dirs[i]) && access(path, F_OK) == 0) {
            plugin_ok = load_from(path);
            return;
        }
    }
    /* Nowhere: say where it was looked for. */
    char list[sizeof load_error] = "";
    for (int i = 0; i < ndirs; i++) {
        size_t used = strlen(list);
        snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "", dirs[i]);
    }
    set_error("not found in %s (set BRDFIT_PLUGIN_DIR)", list);
}

bf_status bf_image_plugin_get(const bf_image_plugin **out, bf_error *err)
{
    pthread_once(&load_once, load);
    *out = plugin_ok ? &plugin : NULL;
    return plugin_ok ? BF_OK : bf_fail(err, BF_ERR_IO, "%s", load_error);
}
