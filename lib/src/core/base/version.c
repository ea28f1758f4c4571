/* bf_version and the version numbers (brdfit/version.h): those the library was built
 * with, which may differ from the headers a program was compiled with. */
#include "brdfit/version.h"

#include "version_git.h"

const char *bf_version(void)
{
    return bf_version_full;
}

void bf_version_numbers(int *major, int *minor, int *patch)
{
    if (major)
        *major = BRDFIT_VERSION_MAJOR;
    if (minor)
        *minor = BRDFIT_VERSION_MINOR;
    if (patch)
        *patch = BRDFIT_VERSION_PATCH;
}

int bf_version_number(void)
{
    return BRDFIT_VERSION_NUMBER;
}
