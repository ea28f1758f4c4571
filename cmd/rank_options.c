/* --rank, --folds and --timing from the library's table (rank_options.h). */
#include "rank_options.h"

const cli_group rank_options_bic = CLI_LIBRARY_GROUP("ranking", BF_TASK_COMPARE);
const cli_group rank_options_error = CLI_LIBRARY_GROUP("ranking", BF_TASK_SELECT);
