/* --rank, --folds and --timing (rank_options.h). */
#include "rank_options.h"

#include "args.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

static int take_rank(void *target, const cli_option *o, const char *v, const char *cmd)
{
    bf_error err;
    (void)o;
    if (bf_compare_rank_parse(v, &((rank_options *)target)->rank_by, &err) != BF_OK) {
        fprintf(stderr, "%s: --rank: %s\n", cmd, err.msg);
        return -1;
    }
    return 0;
}

/* The default ranking differs (compare: bic, select: error), hence two tables. */
#define RANK_HELP(def)                                                                                                 \
    "what to rank by (default " def "): a criterion of each fit's\n"                                                  \
    "likelihood (docs/criteria.md), the cross-validated error of\n"                                                   \
    "the fitted objective, or the --error metric"
#define RANK_TABLE(def)                                                                                                \
    {                                                                                                                  \
        {"--rank", 0, "bic|aic|aicc|cv|error", RANK_HELP(def), NULL, CLI_CALLS(take_rank)},                           \
            {"--folds", 0, "K", "folds of --rank cv (default 5, 2 to 20; K more fits per model)", NULL,                \
             CLI_INT_AT(rank_options, folds, 2, BF_CV_MAX_FOLDS)},                                                     \
            {"--timing", 0, NULL, "wall times in the outputs too (then runs differ)", NULL,                            \
             CLI_SETS(rank_options, timing, 1)},                                                                       \
    }
static const cli_option rank_bic[] = RANK_TABLE("bic"), rank_error[] = RANK_TABLE("error");
const cli_group rank_options_bic = CLI_GROUP("ranking", rank_bic);
const cli_group rank_options_error = CLI_GROUP("ranking", rank_error);

void rank_options_init(rank_options *r, bf_compare_rank_by rank_by)
{
    r->rank_by = rank_by;
    r->folds = 5;
    r->timing = 0;
}

int rank_options_check(const rank_options *r, const bf_fit_options *fit, const char *cmd)
{
    if (fit->solver.loss.kind != BF_LOSS_NONE && r->rank_by != BF_RANK_CV && r->rank_by != BF_RANK_ERROR) {
        fprintf(stderr,
                "%s: --rank %s needs the likelihood of the residuals, and a robust loss (--loss) has none: "
                "rank by cv or error\n",
                cmd, bf_compare_rank_name(r->rank_by));
        return -1;
    }
    return 0;
}
