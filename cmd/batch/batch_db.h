/* The results database of brdfit batch (SQLite; the schema is in docs/batch.md): one row
 * per work item (a material x a model), each finished item written in its own
 * transaction, and the identity of the run (manifest hash, tool version, shard) it
 * belongs to. No SQLite type leaves batch_db.c. */
#ifndef BRDFIT_BATCH_DB_H
#define BRDFIT_BATCH_DB_H

#include "batch_manifest.h"
#include "batch_rows.h"
#include "brdfit/error.h"

typedef struct batch_db batch_db;

typedef enum batch_db_mode {
    BATCH_DB_READ,   /* an existing database, read only */
    BATCH_DB_WRITE,  /* an existing one or a new one, held by this process alone */
    BATCH_DB_CREATE, /* a new file only (one that exists is refused) */
} batch_db_mode;

/* Opens path: with a busy timeout (a lock held by another process becomes a clear
 * error, not a hang), then PRAGMA quick_check before anything is written, so a damaged
 * or foreign file is refused untouched. WRITE also takes an advisory lock (flock) on
 * the file so that two batch runs never share one database. */
bf_status batch_db_open(const char *path, batch_db_mode mode, batch_db **out, bf_error *err);
void batch_db_close(batch_db *db);

/* The work items, shard `shard` (1-based) of `nshards`: item = material * nmodels +
 * model, in shard s when item % nshards == s - 1. */
static inline int batch_item_in_shard(int item, int shard, int nshards)
{
    return item % nshards == shard - 1;
}

/* Makes a new database the manifest's (tables, identity, the materials and models, a
 * pending row per item of the shard), or checks that an existing one is: same schema,
 * manifest hash, tool version and shard, else BF_ERR_ARG saying which differs (never
 * mixed); one of schema 1 (before warning kinds) that passes the other checks is
 * upgraded to this schema. Then the items of the shard without a row get a pending one. */
bf_status batch_db_setup(batch_db *db, const batch_manifest *m, int shard, int nshards, bf_error *err);

/* --redo: makes the items in these states pending again (one transaction). */
bf_status batch_db_redo(batch_db *db, int failed, int all, bf_error *err);

/* The pending items, ascending (malloc'd list in *items, count in *n). */
bf_status batch_db_pending(batch_db *db, int **items, int *n, bf_error *err);

/* Writes one finished item in its own transaction. */
bf_status batch_db_put(batch_db *db, const batch_row *r, bf_error *err);

/* A value of the meta table (malloc'd in *value). */
bf_status batch_db_meta(batch_db *db, const char *key, char **value, bf_error *err);

/* Every row in item order, one call of each per row (r's strings valid during the
 * call only); each returns BF_OK to go on, else a status (with err) that stops the reading. */
bf_status batch_db_rows(batch_db *db, bf_status (*each)(void *ctx, const batch_row *r, bf_error *err), void *ctx,
                        bf_error *err);

/* Material i's data file, as the run read it (malloc'd in *data). */
bf_status batch_db_material(batch_db *db, int i, char **data, bf_error *err);

/* Merges the databases inputs[0..n-1] into the new database out (created here):
 * refused (BF_ERR_ARG) unless every input has the same schema, manifest and tool
 * version, and unless an item finished in two inputs has the same result in both
 * (every column but the timings). The merged database is shard "all", of this schema
 * (schema 1 inputs give rows without kinds); items no input finished stay pending. */
bf_status batch_db_merge(batch_db *out, const char *const *inputs, int n, bf_error *err);

#endif
