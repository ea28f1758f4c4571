/* Temporary files and folders that must not outlive the process: every one the library
 * creates is registered here until it is renamed into place or removed, so that the
 * handler installed by bf_remove_temporaries_on_signals (io.h) can remove them when a
 * fatal signal ends the process. */
#ifndef BRDFIT_TEMP_REGISTRY_H
#define BRDFIT_TEMP_REGISTRY_H

#include <sys/types.h>

/* Creates a new file (is_dir 0: opened O_WRONLY, its descriptor returned) or folder
 * (is_dir 1: 0 returned) named "<base>.tmp.XXXXXX" (random), registered before it
 * exists. mode as for open/mkdir (the umask applies). On success *path (malloc'd) and
 * *handle belong to the caller, who ends with bf_temp_forget after renaming or removing
 * it. Returns -1 with errno set on failure (nothing created, nothing registered). */
int bf_temp_create(const char *base, int is_dir, mode_t mode, char **path, int *handle);

/* Drops a registration (the file has been renamed into place or removed). */
void bf_temp_forget(int handle);

#endif
