/* A batch manifest written as a plain list (docs/batch.md) instead of JSON:
 *
 *   # comments and blank lines are skipped
 *   models: lambert walter microfacet:D=ggx,lobes=2
 *   options: --residual log --seed 3
 *   merl/alum-bronze.binary
 *   scans/cloth.csv --values r,g,b --scene studio.json
 *
 * One material per line: its data file, then its own data options. Words are separated
 * by blanks; a word with blanks goes in double quotes (\" and \\ inside); a word that
 * starts with # starts a comment. The list becomes the JSON manifest it stands for, so
 * both spellings of one manifest are the same manifest (one identity, one database). */
#ifndef BRDFIT_BATCH_LIST_H
#define BRDFIT_BATCH_LIST_H

#include <cjson/cJSON.h>

/* 1 when text is a plain list (its first non-blank character is neither '{' nor '[',
 * which start JSON), else 0. */
int batch_list_is_list(const char *text);

/* The JSON manifest that the plain list text (read from path, for the messages) stands
 * for; NULL after a one-line error on stderr ("cmd: path:LINE: problem"). *lines: a
 * malloc'd array, the line of the options: line (0 for none) then that of each material,
 * for the messages of later checks. */
cJSON *batch_list_parse(const char *text, const char *path, int **lines, const char *cmd);

#endif
