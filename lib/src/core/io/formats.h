/* Internal: the format a path's extension names (any readable format). */
#ifndef BF_IO_FORMATS_H
#define BF_IO_FORMATS_H

#include "brdfit/formats.h"
#include "brdfit/samples.h"

bf_format bf_format_by_extension(const char *path);

#endif
