/* Internal: the full version string, in a source generated at configure time
 * (version_git.c.in) so that a new git revision recompiles that file alone. */
#ifndef BF_VERSION_GIT_H
#define BF_VERSION_GIT_H

extern const char bf_version_full[];

#endif
