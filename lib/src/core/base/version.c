/* bf_version (brdfit/version.h). */
#include "brdfit/version.h"

#include "version_git.h"

const char *bf_version(void) { return bf_version_full; }
