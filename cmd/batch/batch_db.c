/* The results database of brdfit batch, on SQLite (batch_db.h; schema: docs/batch.md).
 *
 * Decisions:
 *  - Every finished item is one transaction (BEGIN IMMEDIATE ... COMMIT) in SQLite's
 *    default rollback journal, so a process killed at any point leaves the database as
 *    of its last commit: at most the items in flight are lost, none is half written.
 *  - A busy timeout (BATCH_DB_BUSY_MS) turns a lock held elsewhere (the sqlite3 shell in
 *    a transaction, another writer) into a one-line error instead of a hang; nothing is
 *    written before the identity checks pass.
 *  - PRAGMA quick_check on open: a damaged file (or one that is not a database) is
 *    refused before any write, so it is never made worse.
 *  - Two batch processes on one database would run the same pending items twice: the
 *    writer holds an advisory flock on the file (SQLite's own locks are POSIX record
 *    locks, which flock does not touch) and a second writer is refused at once.
 *  - The identity (schema, manifest hash, tool version, shard) is checked on every
 *    open for writing: results of another manifest or version are never mixed in.
 *  - NaN is stored as NULL (SQLite makes it so anyway) and read back as NaN.
 *  - Schema 2 added items.warning_kinds (the warnings' kinds by name, batch_rows.c),
 *    beside warnings. A schema 1 database is still read (its rows without kinds:
 *    batch_rows.c, legacy_kind, says what is lost), upgraded in place when batch resumes
 *    it (ALTER TABLE puts the column last; its finished rows keep no kinds) and merged
 *    into a schema 2 one. Every statement names its columns, never relies on
 *    their order, so both layouts are read and merged alike. */
#include "batch_db.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <sqlite3.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "brdfit/version.h"

#define BATCH_DB_SCHEMA "2"
#define BATCH_DB_SCHEMA_NO_KINDS "1" /* before items.warning_kinds */
#define BATCH_DB_BUSY_MS 3000

struct batch_db {
    sqlite3 *db;
    char *path;
    int lock_fd; /* the flock of a writer, or -1 */
};

/* The columns that hold a result (all but item, material, model, the timings): what
 * merge compares; a schema 1 database has all but the last. */
#define RESULT_COLUMNS_1                                                                                               \
    "status, message, spec, samples, channels, n, k, rmse, rmse_log, rmse_cos, rmse_rel, max_err, weighted, "          \
    "crit_n, loglik, aic, aicc, bic, cv, work, params, stderr, warnings, options, tool_version"
#define RESULT_COLUMNS RESULT_COLUMNS_1 ", warning_kinds"

static const char schema_sql[] =
    "CREATE TABLE meta(key TEXT PRIMARY KEY, value TEXT NOT NULL);"
    "CREATE TABLE materials(material INTEGER PRIMARY KEY, data TEXT NOT NULL);"
    "CREATE TABLE models(model INTEGER PRIMARY KEY, spec TEXT NOT NULL);"
    "CREATE TABLE items("
    " item INTEGER PRIMARY KEY, material INTEGER NOT NULL, model INTEGER NOT NULL,"
    " status TEXT NOT NULL CHECK(status IN ('pending','ok','failed','error')),"
    " message TEXT, spec TEXT, samples INTEGER, channels INTEGER,"
    " n INTEGER, k INTEGER, rmse REAL, rmse_log REAL, rmse_cos REAL, rmse_rel REAL, max_err REAL,"
    " weighted INTEGER, crit_n INTEGER, loglik REAL, aic REAL, aicc REAL, bic REAL, cv REAL, work REAL,"
    " params TEXT, stderr TEXT, warnings TEXT, warning_kinds TEXT, options TEXT, tool_version TEXT,"
    " seconds REAL, finished_at TEXT);"
    "CREATE VIEW results AS SELECT i.item, m.data, o.spec AS model, i.status, i.k, i.rmse_log, i.bic, i.message"
    " FROM items i JOIN materials m USING(material) JOIN models o USING(model);";

static bf_status db_fail(batch_db *db, bf_error *err, const char *what)
{
    int code = sqlite3_extended_errcode(db->db);
    if ((code & 0xff) == SQLITE_BUSY || (code & 0xff) == SQLITE_LOCKED)
        return bf_fail(err, BF_ERR_IO, "%s: locked by another process (%s); nothing was changed", db->path, what);
    if ((code & 0xff) == SQLITE_NOTADB || (code & 0xff) == SQLITE_CORRUPT)
        return bf_fail(err, BF_ERR_PARSE, "%s: damaged or not a database (%s); left as it is", db->path,
                       sqlite3_errmsg(db->db));
    return bf_fail(err, BF_ERR_IO, "%s: %s: %s", db->path, what, sqlite3_errmsg(db->db));
}

static bf_status exec(batch_db *db, const char *sql, const char *what, bf_error *err)
{
    return sqlite3_exec(db->db, sql, NULL, NULL, NULL) == SQLITE_OK ? BF_OK : db_fail(db, err, what);
}

static bf_status prepare(batch_db *db, const char *sql, sqlite3_stmt **st, bf_error *err)
{
    return sqlite3_prepare_v2(db->db, sql, -1, st, NULL) == SQLITE_OK ? BF_OK : db_fail(db, err, "reading it");
}

void batch_db_close(batch_db *db)
{
    if (!db)
        return;
    sqlite3_close(db->db);
    if (db->lock_fd >= 0)
        close(db->lock_fd); /* releases the flock */
    free(db->path);
    free(db);
}

/* quick_check: "ok", or the file is refused. */
static bf_status check_file(batch_db *db, bf_error *err)
{
    sqlite3_stmt *st;
    bf_status rc = prepare(db, "PRAGMA quick_check", &st, err);
    if (rc != BF_OK)
        return rc;
    int step = sqlite3_step(st);
    const unsigned char *v = step == SQLITE_ROW ? sqlite3_column_text(st, 0) : NULL;
    if (step == SQLITE_ROW && (!v || strcmp((const char *)v, "ok")))
        rc = bf_fail(err, BF_ERR_PARSE, "%s: damaged database (quick_check: %s); left as it is", db->path,
                     v ? (const char *)v : "?");
    else if (step != SQLITE_ROW)
        rc = db_fail(db, err, "checking it");
    sqlite3_finalize(st);
    return rc;
}

/* The writer's advisory lock: refused at once when another writer holds it. */
static bf_status take_lock(batch_db *db, bf_error *err)
{
    if ((db->lock_fd = open(db->path, O_RDONLY | O_CLOEXEC)) < 0)
        return bf_fail(err, BF_ERR_IO, "%s: %s", db->path, strerror(errno));
    if (flock(db->lock_fd, LOCK_EX | LOCK_NB) != 0)
        return bf_fail(err, BF_ERR_IO, "%s: in use by another brdfit batch or merge; nothing was changed", db->path);
    return BF_OK;
}

bf_status batch_db_open(const char *path, batch_db_mode mode, batch_db **out, bf_error *err)
{
    *out = NULL;
    struct stat sb;
    const int exists = stat(path, &sb) == 0;
    if (mode == BATCH_DB_CREATE && exists)
        return bf_fail(err, BF_ERR_IO, "%s: exists; merge writes a new database", path);
    if (mode == BATCH_DB_READ && !exists)
        return bf_fail(err, BF_ERR_IO, "%s: no such database", path);
    batch_db *db = calloc(1, sizeof *db);
    if (!db || !(db->path = strdup(path))) {
        free(db);
        return bf_fail(err, BF_ERR_NOMEM, "out of memory");
    }
    db->lock_fd = -1;
    int flags = mode == BATCH_DB_READ ? SQLITE_OPEN_READONLY : SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE;
    bf_status rc = BF_OK;
    if (sqlite3_open_v2(path, &db->db, flags | SQLITE_OPEN_NOMUTEX, NULL) != SQLITE_OK)
        rc = db_fail(db, err, "opening it");
    if (rc == BF_OK)
        sqlite3_busy_timeout(db->db, BATCH_DB_BUSY_MS);
    if (rc == BF_OK && mode != BATCH_DB_READ)
        rc = take_lock(db, err);
    if (rc == BF_OK)
        rc = check_file(db, err);
    if (rc != BF_OK) {
        batch_db_close(db);
        return rc;
    }
    *out = db;
    return BF_OK;
}

bf_status batch_db_meta(batch_db *db, const char *key, char **value, bf_error *err)
{
    sqlite3_stmt *st;
    *value = NULL;
    bf_status rc = prepare(db, "SELECT value FROM meta WHERE key = ?", &st, err);
    if (rc != BF_OK)
        return rc;
    sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
    if (sqlite3_step(st) == SQLITE_ROW) {
        if (!(*value = strdup((const char *)sqlite3_column_text(st, 0))))
            rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    } else {
        rc = bf_fail(err, BF_ERR_PARSE, "%s: no %s in its meta table", db->path, key);
    }
    sqlite3_finalize(st);
    return rc;
}

/* 1 when the file has brdfit's tables, 0 when it is empty; else refused. */
static bf_status has_schema(batch_db *db, int *yes, bf_error *err)
{
    sqlite3_stmt *st;
    bf_status rc = prepare(db, "SELECT count(*), sum(name = 'meta') FROM sqlite_schema", &st, err);
    if (rc != BF_OK)
        return rc;
    *yes = 0;
    if (sqlite3_step(st) != SQLITE_ROW)
        rc = db_fail(db, err, "reading its schema");
    else if (sqlite3_column_int(st, 1) == 1)
        *yes = 1;
    else if (sqlite3_column_int(st, 0) > 0)
        rc = bf_fail(err, BF_ERR_ARG, "%s: a database, but not brdfit batch results; left as it is", db->path);
    sqlite3_finalize(st);
    return rc;
}

/* The stored value of key equals want, or BF_ERR_ARG naming the difference. */
static bf_status same(batch_db *db, const char *key, const char *want, const char *what, bf_error *err)
{
    char *v;
    bf_status rc = batch_db_meta(db, key, &v, err);
    if (rc == BF_OK && strcmp(v, want))
        rc = bf_fail(err, BF_ERR_ARG, "%s: made by %s (%s: %s, here %s); use another -o, or remove it to start over",
                     db->path, what, key, v, want);
    free(v);
    return rc;
}

static bf_status put_meta(batch_db *db, const char *key, const char *value, bf_error *err)
{
    sqlite3_stmt *st;
    bf_status rc = prepare(db, "INSERT INTO meta VALUES(?, ?)", &st, err);
    if (rc != BF_OK)
        return rc;
    sqlite3_bind_text(st, 1, key, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 2, value, -1, SQLITE_STATIC);
    if (sqlite3_step(st) != SQLITE_DONE)
        rc = db_fail(db, err, "writing its identity");
    sqlite3_finalize(st);
    return rc;
}

static bf_status put_names(batch_db *db, const batch_manifest *m, bf_error *err)
{
    sqlite3_stmt *mat, *mod;
    bf_status rc = prepare(db, "INSERT INTO materials VALUES(?, ?)", &mat, err);
    if (rc != BF_OK)
        return rc;
    if ((rc = prepare(db, "INSERT INTO models VALUES(?, ?)", &mod, err)) != BF_OK) {
        sqlite3_finalize(mat);
        return rc;
    }
    for (int i = 0; rc == BF_OK && i < m->nmaterials; i++) {
        sqlite3_bind_int(mat, 1, i);
        sqlite3_bind_text(mat, 2, m->materials[i].data, -1, SQLITE_STATIC);
        if (sqlite3_step(mat) != SQLITE_DONE)
            rc = db_fail(db, err, "writing the materials");
        sqlite3_reset(mat);
    }
    for (int j = 0; rc == BF_OK && j < m->nmodels; j++) {
        sqlite3_bind_int(mod, 1, j);
        sqlite3_bind_text(mod, 2, m->models[j], -1, SQLITE_STATIC);
        if (sqlite3_step(mod) != SQLITE_DONE)
            rc = db_fail(db, err, "writing the models");
        sqlite3_reset(mod);
    }
    sqlite3_finalize(mat);
    sqlite3_finalize(mod);
    return rc;
}

static bf_status create(batch_db *db, const batch_manifest *m, const char *shard, bf_error *err)
{
    bf_status rc = exec(db, schema_sql, "creating its tables", err);
    if (rc == BF_OK)
        rc = put_meta(db, "schema", BATCH_DB_SCHEMA, err);
    if (rc == BF_OK)
        rc = put_meta(db, "manifest_hash", m->hash, err);
    if (rc == BF_OK)
        rc = put_meta(db, "manifest", m->text, err);
    if (rc == BF_OK)
        rc = put_meta(db, "tool_version", bf_version(), err);
    if (rc == BF_OK)
        rc = put_meta(db, "shard", shard, err);
    if (rc == BF_OK)
        rc = put_names(db, m, err);
    return rc;
}

/* A pending row for every item of the shard that has none. */
static bf_status add_pending(batch_db *db, const batch_manifest *m, int shard, int nshards, bf_error *err)
{
    sqlite3_stmt *st;
    bf_status rc = prepare(db,
                           "INSERT OR IGNORE INTO items(item, material, model, status, options) "
                           "VALUES(?, ?, ?, 'pending', ?)",
                           &st, err);
    for (int i = 0; rc == BF_OK && i < m->nmaterials; i++)
        for (int j = 0; rc == BF_OK && j < m->nmodels; j++) {
            const int item = i * m->nmodels + j;
            if (!batch_item_in_shard(item, shard, nshards))
                continue;
            char *opts = batch_manifest_item_options(m, i, j);
            if (!opts) {
                rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
                break;
            }
            sqlite3_bind_int(st, 1, item);
            sqlite3_bind_int(st, 2, i);
            sqlite3_bind_int(st, 3, j);
            sqlite3_bind_text(st, 4, opts, -1, SQLITE_TRANSIENT);
            free(opts);
            if (sqlite3_step(st) != SQLITE_DONE)
                rc = db_fail(db, err, "adding the work items");
            sqlite3_reset(st);
        }
    sqlite3_finalize(st);
    return rc;
}

/* The warning_kinds column of schema 2 added to a schema 1 database, within the caller's
 * transaction (after every identity check, so a database of another run is untouched). */
static bf_status upgrade(batch_db *db, bf_error *err)
{
    return exec(db,
                "ALTER TABLE items ADD COLUMN warning_kinds TEXT;"
                "UPDATE meta SET value = '" BATCH_DB_SCHEMA "' WHERE key = 'schema';",
                "adding the warning_kinds column", err);
}

bf_status batch_db_setup(batch_db *db, const batch_manifest *m, int shard, int nshards, bf_error *err)
{
    char shard_name[48] = "all";
    if (nshards > 1)
        snprintf(shard_name, sizeof shard_name, "%d/%d", shard, nshards);
    bf_status rc = exec(db, "BEGIN IMMEDIATE", "starting a transaction", err);
    if (rc != BF_OK)
        return rc;
    int yes;
    rc = has_schema(db, &yes, err);
    if (rc == BF_OK && !yes)
        rc = create(db, m, shard_name, err);
    else if (rc == BF_OK) {
        char *schema = NULL;
        rc = batch_db_meta(db, "schema", &schema, err);
        const int old = rc == BF_OK && !strcmp(schema, BATCH_DB_SCHEMA_NO_KINDS);
        free(schema);
        if (rc == BF_OK && !old)
            rc = same(db, "schema", BATCH_DB_SCHEMA, "another schema", err);
        if (rc == BF_OK)
            rc = same(db, "manifest_hash", m->hash, "another manifest", err);
        if (rc == BF_OK)
            rc = same(db, "tool_version", bf_version(), "another brdfit version", err);
        if (rc == BF_OK)
            rc = same(db, "shard", shard_name, "another --shard", err);
        if (rc == BF_OK && old)
            rc = upgrade(db, err);
    }
    if (rc == BF_OK)
        rc = add_pending(db, m, shard, nshards, err);
    if (rc == BF_OK)
        rc = exec(db, "COMMIT", "committing", err);
    if (rc != BF_OK)
        sqlite3_exec(db->db, "ROLLBACK", NULL, NULL, NULL);
    return rc;
}

bf_status batch_db_redo(batch_db *db, int failed, int all, bf_error *err)
{
    if (!failed && !all)
        return BF_OK;
        /* Pending again, and emptied: a pending row never shows an old result. */
#define PENDING                                                                                                        \
    "UPDATE items SET status = 'pending', message = NULL, spec = NULL, samples = NULL, channels = NULL, "              \
    "n = NULL, k = NULL, rmse = NULL, rmse_log = NULL, rmse_cos = NULL, rmse_rel = NULL, max_err = NULL, "             \
    "weighted = NULL, crit_n = NULL, loglik = NULL, aic = NULL, aicc = NULL, bic = NULL, cv = NULL, work = NULL, "     \
    "params = NULL, stderr = NULL, warnings = NULL, tool_version = NULL, seconds = NULL, finished_at = NULL, "         \
    "warning_kinds = NULL "
    return exec(db, all ? PENDING "WHERE status != 'pending'" : PENDING "WHERE status IN ('failed', 'error')",
                "marking items to redo", err);
#undef PENDING
}

bf_status batch_db_pending(batch_db *db, int **items, int *n, bf_error *err)
{
    sqlite3_stmt *st;
    *items = NULL;
    *n = 0;
    bf_status rc = prepare(db, "SELECT item FROM items WHERE status = 'pending' ORDER BY item", &st, err);
    int cap = 0, step;
    while (rc == BF_OK && (step = sqlite3_step(st)) == SQLITE_ROW) {
        if (*n == cap) {
            int *p = realloc(*items, (size_t)(cap = cap ? 2 * cap : 256) * sizeof *p);
            if (!p) {
                rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
                break;
            }
            *items = p;
        }
        (*items)[(*n)++] = sqlite3_column_int(st, 0);
    }
    if (rc == BF_OK && step != SQLITE_DONE)
        rc = db_fail(db, err, "listing the pending items");
    sqlite3_finalize(st);
    return rc;
}

static void bind_real(sqlite3_stmt *st, int k, double v)
{
    if (isnan(v))
        sqlite3_bind_null(st, k);
    else
        sqlite3_bind_double(st, k, v);
}

static const char *status_name(const batch_row *r)
{
    return r->pending ? "pending" : bf_compare_state_name(r->state);
}

bf_status batch_db_put(batch_db *db, const batch_row *r, bf_error *err)
{
    sqlite3_stmt *st;
    bf_status rc = prepare(db,
                           "UPDATE items SET status = ?, message = ?, spec = ?, samples = ?, channels = ?, n = ?, "
                           "k = ?, rmse = ?, rmse_log = ?, rmse_cos = ?, rmse_rel = ?, max_err = ?, weighted = ?, "
                           "crit_n = ?, loglik = ?, aic = ?, aicc = ?, bic = ?, cv = ?, work = ?, params = ?, "
                           "stderr = ?, warnings = ?, tool_version = ?, seconds = ?, "
                           "finished_at = strftime('%Y-%m-%dT%H:%M:%fZ', 'now'), warning_kinds = ? WHERE item = ?",
                           &st, err);
    if (rc != BF_OK)
        return rc;
    const bf_metrics *m = &r->metrics;
    const int ran = r->state != BF_CMP_ERROR;
    sqlite3_bind_text(st, 1, status_name(r), -1, SQLITE_STATIC);
    if (r->message[0])
        sqlite3_bind_text(st, 2, r->message, -1, SQLITE_STATIC);
    if (r->spec)
        sqlite3_bind_text(st, 3, r->spec, -1, SQLITE_STATIC);
    sqlite3_bind_int64(st, 4, (sqlite3_int64)r->samples);
    sqlite3_bind_int(st, 5, r->channels);
    if (ran) {
        sqlite3_bind_int64(st, 6, (sqlite3_int64)m->n);
        sqlite3_bind_int(st, 7, m->k);
        const double v[] = {m->rmse, m->rmse_log, m->rmse_cos, m->rmse_rel, m->max_err};
        for (int k = 0; k < 5; k++)
            bind_real(st, 8 + k, v[k]);
        sqlite3_bind_int(st, 13, m->weighted);
        sqlite3_bind_int64(st, 14, (sqlite3_int64)m->crit_n);
        const double w[] = {m->loglik, m->aic, m->aicc, m->bic, r->cv, r->work};
        for (int k = 0; k < 6; k++)
            bind_real(st, 15 + k, w[k]);
    }
    if (r->params)
        sqlite3_bind_text(st, 21, r->params, -1, SQLITE_STATIC);
    if (r->stderr_)
        sqlite3_bind_text(st, 22, r->stderr_, -1, SQLITE_STATIC);
    if (r->warnings)
        sqlite3_bind_text(st, 23, r->warnings, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 24, bf_version(), -1, SQLITE_STATIC);
    bind_real(st, 25, r->seconds);
    if (r->warning_kinds)
        sqlite3_bind_text(st, 26, r->warning_kinds, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 27, r->item);
    /* One transaction per item: BEGIN IMMEDIATE so a lock taken meanwhile is waited for
     * (busy timeout) at the start, not found at the commit. */
    rc = exec(db, "BEGIN IMMEDIATE", "starting a transaction", err);
    if (rc == BF_OK && sqlite3_step(st) != SQLITE_DONE)
        rc = db_fail(db, err, "writing a result");
    if (rc == BF_OK)
        rc = exec(db, "COMMIT", "committing a result", err);
    if (rc != BF_OK)
        sqlite3_exec(db->db, "ROLLBACK", NULL, NULL, NULL);
    sqlite3_finalize(st);
    return rc;
}

static double real_of(sqlite3_stmt *st, int k)
{
    return sqlite3_column_type(st, k) == SQLITE_NULL ? NAN : sqlite3_column_double(st, k);
}

static char *text_of(sqlite3_stmt *st, int k)
{
    const unsigned char *t = sqlite3_column_text(st, k);
    return t ? strdup((const char *)t) : NULL;
}

/* The row st points at into r (texts malloc'd). */
static void row_of(sqlite3_stmt *st, batch_row *r)
{
    memset(r, 0, sizeof *r);
    r->item = sqlite3_column_int(st, 0);
    r->material = sqlite3_column_int(st, 1);
    r->model = sqlite3_column_int(st, 2);
    const char *status = (const char *)sqlite3_column_text(st, 3);
    r->pending = !strcmp(status, "pending");
    r->state = !strcmp(status, "ok") ? BF_CMP_OK : !strcmp(status, "failed") ? BF_CMP_FAILED : BF_CMP_ERROR;
    const unsigned char *msg = sqlite3_column_text(st, 4);
    snprintf(r->message, sizeof r->message, "%s", msg ? (const char *)msg : "");
    r->spec = text_of(st, 5);
    r->samples = (size_t)sqlite3_column_int64(st, 6);
    r->channels = sqlite3_column_int(st, 7);
    bf_metrics *m = &r->metrics;
    m->n = (size_t)sqlite3_column_int64(st, 8);
    m->k = sqlite3_column_int(st, 9);
    m->rmse = real_of(st, 10);
    m->rmse_log = real_of(st, 11);
    m->rmse_cos = real_of(st, 12);
    m->rmse_rel = real_of(st, 13);
    m->max_err = real_of(st, 14);
    m->weighted = sqlite3_column_int(st, 15);
    m->crit_n = (size_t)sqlite3_column_int64(st, 16);
    m->loglik = real_of(st, 17);
    m->aic = real_of(st, 18);
    m->aicc = real_of(st, 19);
    m->bic = real_of(st, 20);
    r->cv = real_of(st, 21);
    r->work = real_of(st, 22);
    r->params = text_of(st, 23);
    r->stderr_ = text_of(st, 24);
    r->warnings = text_of(st, 25);
    r->options = text_of(st, 26);
    r->version = (const char *)sqlite3_column_text(st, 27);
    r->seconds = real_of(st, 28);
    r->warning_kinds = text_of(st, 29);
}

bf_status batch_db_rows(batch_db *db, bf_status (*each)(void *ctx, const batch_row *r, bf_error *err), void *ctx,
                        bf_error *err)
{
#define ROW_COLUMNS                                                                                                    \
    "item, material, model, status, message, spec, samples, channels, n, k, rmse, rmse_log, rmse_cos, rmse_rel, "      \
    "max_err, weighted, crit_n, loglik, aic, aicc, bic, cv, work, params, stderr, warnings, options, "                 \
    "tool_version, seconds, "
    sqlite3_stmt *st = NULL;
    char *schema = NULL;
    bf_status rc = batch_db_meta(db, "schema", &schema, err);
    /* A schema 1 database has no kinds: NULL (batch_rows.c, legacy_kind). */
    const int old = rc == BF_OK && !strcmp(schema, BATCH_DB_SCHEMA_NO_KINDS);
    free(schema);
    if (rc == BF_OK)
        rc = prepare(db,
                     old ? "SELECT " ROW_COLUMNS "NULL FROM items ORDER BY item"
                         : "SELECT " ROW_COLUMNS "warning_kinds FROM items ORDER BY item",
                     &st, err);
#undef ROW_COLUMNS
    int step = SQLITE_DONE;
    while (rc == BF_OK && (step = sqlite3_step(st)) == SQLITE_ROW) {
        batch_row r;
        row_of(st, &r);
        rc = each(ctx, &r, err);
        batch_row_clear(&r);
    }
    if (rc == BF_OK && step != SQLITE_DONE)
        rc = db_fail(db, err, "reading the items");
    sqlite3_finalize(st);
    return rc;
}

bf_status batch_db_material(batch_db *db, int i, char **data, bf_error *err)
{
    sqlite3_stmt *st;
    *data = NULL;
    bf_status rc = prepare(db, "SELECT data FROM materials WHERE material = ?", &st, err);
    if (rc != BF_OK)
        return rc;
    sqlite3_bind_int(st, 1, i);
    if (sqlite3_step(st) != SQLITE_ROW)
        rc = bf_fail(err, BF_ERR_PARSE, "%s: no material %d", db->path, i);
    else if (!(*data = text_of(st, 0)))
        rc = bf_fail(err, BF_ERR_NOMEM, "out of memory");
    sqlite3_finalize(st);
    return rc;
}

/* One count query's answer (-1 after an error). */
static long long count_of(batch_db *db, const char *sql, bf_error *err)
{
    sqlite3_stmt *st;
    if (prepare(db, sql, &st, err) != BF_OK)
        return -1;
    long long n = sqlite3_step(st) == SQLITE_ROW ? sqlite3_column_int64(st, 0) : -1;
    if (n < 0)
        db_fail(db, err, "merging");
    sqlite3_finalize(st);
    return n;
}

/* An item's columns in the output, and as taken from an input of schema 2 or 1 (no
 * kinds: NULL). */
#define ITEM_COLUMNS "item, material, model, " RESULT_COLUMNS ", seconds, finished_at"
#define ITEM_COLUMNS_1 "item, material, model, " RESULT_COLUMNS_1 ", NULL, seconds, finished_at"

/* The attached input's schema: 1 for BATCH_DB_SCHEMA_NO_KINDS, 0 for BATCH_DB_SCHEMA;
 * any other is refused. */
static bf_status src_schema(batch_db *out, const char *input, int *old, bf_error *err)
{
    sqlite3_stmt *st;
    bf_status rc = prepare(out, "SELECT value FROM src.meta WHERE key = 'schema'", &st, err);
    if (rc != BF_OK)
        return rc;
    const unsigned char *v = sqlite3_step(st) == SQLITE_ROW ? sqlite3_column_text(st, 0) : NULL;
    const char *s = v ? (const char *)v : "none";
    *old = !strcmp(s, BATCH_DB_SCHEMA_NO_KINDS);
    if (!*old && strcmp(s, BATCH_DB_SCHEMA))
        rc = bf_fail(err, BF_ERR_ARG, "%s: schema %s, which this brdfit does not read; nothing merged", input, s);
    sqlite3_finalize(st);
    return rc;
}

/* Input k (attached as "src", of schema 1 when old): identity as the output's, then its
 * finished rows. */
static bf_status merge_one(batch_db *out, const char *input, int old, bf_error *err)
{
    /* The identity, as the output holds it (the first input's; the schema the caller
     * checks). */
    static const char *const keys[] = {"manifest_hash", "tool_version"};
    for (int k = 0; k < 2; k++) {
        char sql[200];
        snprintf(sql, sizeof sql,
                 "SELECT count(*) FROM main.meta a LEFT JOIN src.meta b ON b.key = a.key "
                 "WHERE a.key = '%s' AND (b.value IS NULL OR b.value != a.value)",
                 keys[k]);
        long long n = count_of(out, sql, err);
        if (n < 0)
            return err->code;
        if (n > 0)
            return bf_fail(err, BF_ERR_ARG, "%s: another %s than the first input; nothing merged", input,
                           k == 0 ? "manifest" : "brdfit version");
    }
#define CLASH(SRC)                                                                                                     \
    "SELECT count(*) FROM main.items a JOIN src.items b USING(item) WHERE "                                            \
    "a.status != 'pending' AND b.status != 'pending' AND "                                                             \
    "(SELECT " RESULT_COLUMNS " FROM main.items WHERE item = a.item) IS NOT "                                          \
    "(SELECT " SRC " FROM src.items WHERE item = a.item)"
    long long clash = count_of(out, old ? CLASH(RESULT_COLUMNS_1 ", NULL") : CLASH(RESULT_COLUMNS), err);
#undef CLASH
    if (clash < 0)
        return err->code;
    if (clash > 0)
        return bf_fail(err, BF_ERR_ARG, "%s: %lld item(s) already merged with other results; nothing merged", input,
                       clash);
        /* Rows the output lacks, then finished rows over its pending ones. */
#define COPY(SRC)                                                                                                      \
    "INSERT OR IGNORE INTO main.items(" ITEM_COLUMNS ") SELECT " SRC " FROM src.items;"                                \
    "REPLACE INTO main.items(" ITEM_COLUMNS ") SELECT " SRC " FROM src.items b WHERE b.status != 'pending' AND "       \
    "(SELECT status FROM main.items a WHERE a.item = b.item) = 'pending'"
    return exec(out, old ? COPY(ITEM_COLUMNS_1) : COPY(ITEM_COLUMNS), "merging the items", err);
#undef COPY
}

bf_status batch_db_merge(batch_db *out, const char *const *inputs, int n, bf_error *err)
{
    bf_status rc = BF_OK;
    int first_old = 0; /* the first input's schema: every other has it too */
    for (int k = 0; rc == BF_OK && k < n; k++) {
        /* Each input is checked as batch_db_open checks it before it is attached. */
        batch_db *in;
        if ((rc = batch_db_open(inputs[k], BATCH_DB_READ, &in, err)) != BF_OK)
            break;
        int yes;
        rc = has_schema(in, &yes, err);
        if (rc == BF_OK && !yes)
            rc = bf_fail(err, BF_ERR_ARG, "%s: empty, not brdfit batch results", inputs[k]);
        batch_db_close(in);
        sqlite3_stmt *st;
        /* SQLite attaches outside transactions: one transaction per input (the caller
         * writes the output under a temporary name, so a failure leaves nothing). */
        if (rc == BF_OK && (rc = prepare(out, "ATTACH ? AS src", &st, err)) == BF_OK) {
            sqlite3_bind_text(st, 1, inputs[k], -1, SQLITE_STATIC);
            if (sqlite3_step(st) != SQLITE_DONE)
                rc = db_fail(out, err, "attaching an input");
            sqlite3_finalize(st);
        }
        int old = 0;
        if (rc == BF_OK)
            rc = src_schema(out, inputs[k], &old, err);
        if (rc == BF_OK && k == 0)
            first_old = old;
        else if (rc == BF_OK && old != first_old)
            rc = bf_fail(err, BF_ERR_ARG, "%s: another schema than the first input; nothing merged", inputs[k]);
        if (rc != BF_OK) {
            sqlite3_exec(out->db, "DETACH src", NULL, NULL, NULL);
            break;
        }
        rc = exec(out, "BEGIN IMMEDIATE", "starting a transaction", err);
        if (rc == BF_OK && k == 0) /* the first input's identity and names make the output's */
            rc = exec(out, schema_sql, "creating its tables", err);
        /* The output is of this schema whatever the inputs' (theirs lack only kinds). */
        if (rc == BF_OK && k == 0)
            rc = exec(out,
                      "INSERT INTO main.meta SELECT key, CASE key WHEN 'shard' THEN 'all' "
                      "WHEN 'schema' THEN '" BATCH_DB_SCHEMA "' ELSE value END FROM src.meta;"
                      "INSERT INTO main.materials SELECT * FROM src.materials;"
                      "INSERT INTO main.models SELECT * FROM src.models;",
                      "copying the identity", err);
        if (rc == BF_OK)
            rc = merge_one(out, inputs[k], old, err);
        if (rc == BF_OK)
            rc = exec(out, "COMMIT", "committing", err);
        if (rc != BF_OK)
            sqlite3_exec(out->db, "ROLLBACK", NULL, NULL, NULL);
        sqlite3_exec(out->db, "DETACH src", NULL, NULL, NULL);
    }
    return rc;
}
