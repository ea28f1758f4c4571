#!/usr/bin/env bash
# brdfit batch, report and merge from the shell: a manifest of synthetic materials x
# models into an SQLite database; report equal to compare for the same fits (tables,
# JSON, CSV); a run killed with SIGKILL part-way, then rerun, has every item exactly
# once and the rows of an uninterrupted run; SIGINT leaves a resumable database (exit
# 130); --redo failed; another manifest refused; a locked or damaged database refused
# with one line and left as it was; --shard runs merged equal the one-process run;
# merge refuses inconsistent inputs; a fit's process killed costs only its fits (run again,
# an error row the second time); a plain-list manifest is the JSON one it spells, and
# its errors name their line; each warning's kind is stored and decides the report's "?",
# and a schema 1 database (before kinds) is still reported, resumed and merged.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq; need script bsdutils
source "$(dirname "$0")/batch_common.sh"
batch_manifest "" 3000
cat > "$tmp/mm0.json" <<'JSON'
{"models": ["lambert", "walter"], "options": ["--threads", "1"], "materials": ["lam1.csv", "missing.csv"]}
JSON

# --- a run: 24 rows, all ok, the identity stored ----------------------------------------
if "$BRDFIT" batch "$tmp/m.json" -o "$tmp/one.db" 2>"$tmp/err"; then ok; else bad "batch: $(cat "$tmp/err")"; fi
[ ! -s "$tmp/err" ] && ok || bad "batch not quiet off a terminal: $(cat "$tmp/err")"
[ "$(count "$tmp/one.db" "SELECT count(*), sum(status = 'ok') FROM items")" = "24|24" ] && ok || bad "rows: $(count "$tmp/one.db" "SELECT status, count(*) FROM items GROUP BY 1")"
[ "$(count "$tmp/one.db" "SELECT value FROM meta WHERE key = 'shard'")" = all ] && ok || bad "meta shard"
[ "$(count "$tmp/one.db" "SELECT options FROM items WHERE item = 5")" = '["--threads","1","--seed","3","-m","walter"]' ] &&
  ok || bad "options column: $(count "$tmp/one.db" "SELECT options FROM items WHERE item = 5")"
[ "$(count "$tmp/one.db" "SELECT count(*) FROM items WHERE seconds > 0 AND finished_at LIKE '20%'")" = 24 ] && ok || bad "timings"
# Rerun: nothing to do, nothing changed.
rows "$tmp/one.db" > "$tmp/one.rows"
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/one.db" && ok || bad "rerun of a finished batch"
rows "$tmp/one.db" | cmp -s - "$tmp/one.rows" && ok || bad "rerun changed rows"

# --- progress on a terminal: items done, failures, ETA ---------------------------------------
# script(1) (bsdutils, on every Debian system) gives the run a pseudo-terminal.
script -qec "'$BRDFIT' batch '$tmp/mm0.json' -o '$tmp/tty.db'" /dev/null > "$tmp/tty" 2>&1
tr '\r' '\n' < "$tmp/tty" | grep -q "^brdfit batch: 4/4 items, 2 failed" && grep -q "ETA" "$tmp/tty" && ok ||
  bad "progress on a terminal: $(tr '\r' '\n' < "$tmp/tty" | tail -3)"

# --- report = compare for the same fits ---------------------------------------------------
(cd "$tmp" && "$BRDFIT" compare "$tmp"/lam1.csv "$tmp"/wal1.csv "$tmp"/lam2.csv "$tmp"/wal2.csv "$tmp"/lam3.csv "$tmp"/wal3.csv \
   -m lambert,walter,cook_torrance,blinn_phong --threads 1 --seed 3 --json c.json --csv c.csv >c.txt 2>/dev/null) ||
  bad "compare"
(cd "$tmp" && "$BRDFIT" report one.db --json r.json --csv r.csv --html rep >r.txt) && ok || bad "report"
cmp -s "$tmp/c.txt" "$tmp/r.txt" && ok || bad "report tables differ from compare's: $(diff "$tmp/c.txt" "$tmp/r.txt" | head -5)"
cmp -s "$tmp/c.json" "$tmp/r.json" && ok || bad "report JSON differs from compare's"
cmp -s "$tmp/c.csv" "$tmp/r.csv" && ok || bad "report CSV differs from compare's"
[ -s "$tmp/rep/index.html" ] && ok || bad "report --html"

# --- SIGKILL part-way, rerun: every item exactly once, the same rows -----------------------
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/k.db" 2>/dev/null &
pid=$!
wait_items "$tmp/k.db" 5
kill -KILL $pid 2>/dev/null
wait $pid 2>/dev/null
done_before=$(count "$tmp/k.db" "SELECT count(*) FROM items WHERE status != 'pending'")
[ "$done_before" -ge 5 ] && [ "$done_before" -lt 24 ] && ok || bad "killed run had $done_before items done (wanted 5..23)"
[ "$(count "$tmp/k.db" "PRAGMA integrity_check")" = ok ] && ok || bad "killed run left a damaged database"
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/k.db" && ok || bad "resume after SIGKILL"
[ "$(count "$tmp/k.db" "SELECT count(*), count(DISTINCT item), sum(status = 'ok') FROM items")" = "24|24|24" ] &&
  ok || bad "after resume: $(count "$tmp/k.db" "SELECT count(*), count(DISTINCT item) FROM items")"
rows "$tmp/k.db" | cmp -s - "$tmp/one.rows" && ok || bad "resumed rows differ from an uninterrupted run"

# --- SIGINT: finished fits kept, exit 130, resumable ----------------------------------------
interrupt_batch "$tmp/m.json" "$tmp/i.db" 3
if [ $rc = 130 ]; then
  ok
  grep -q "interrupted after .* items; the same command resumes" "$tmp/err" && ok || bad "SIGINT message: $(cat "$tmp/err")"
else
  # The run may have finished before the signal landed: then it must be complete.
  [ $rc = 0 ] && [ "$(count "$tmp/i.db" "SELECT count(*) FROM items WHERE status = 'pending'")" = 0 ] && ok ||
    bad "SIGINT: exit $rc"
fi
"$BRDFIT" report "$tmp/i.db" >/dev/null 2>&1 # a partial database reports (not_run) ...
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/i.db" && ok || bad "resume after SIGINT"
rows "$tmp/i.db" | cmp -s - "$tmp/one.rows" && ok || bad "rows after SIGINT + resume differ"

# --- --shard I/N + merge = one process -----------------------------------------------------
for s in 1 2 3; do # --jobs changes nothing in the rows
  "$BRDFIT" batch "$tmp/m.json" -o "$tmp/s$s.db" --shard $s/3 --jobs $s || bad "shard $s"
done
[ "$(count "$tmp/s2.db" "SELECT group_concat(item) FROM items")" = "1,4,7,10,13,16,19,22" ] && ok || bad "shard 2/3 items"
"$BRDFIT" merge "$tmp/s1.db" "$tmp/s2.db" "$tmp/s3.db" -o "$tmp/all.db" && ok || bad "merge"
rows "$tmp/all.db" | cmp -s - "$tmp/one.rows" && ok || bad "merged shards differ from the one-process run"
"$BRDFIT" merge "$tmp/s1.db" "$tmp/one.db" -o "$tmp/again.db" && ok || bad "merging equal results is allowed"
# The same item finished with another result: refused, no output.
cp "$tmp/s2.db" "$tmp/s2x.db"
sqlite3 "$tmp/s2x.db" "UPDATE items SET rmse = rmse * 2 WHERE item = 4"
if "$BRDFIT" merge "$tmp/s2.db" "$tmp/s2x.db" -o "$tmp/x.db" 2>"$tmp/err"; then bad "merge of clashing results accepted"; else ok; fi
grep -q "already merged with other results" "$tmp/err" && [ ! -e "$tmp/x.db" ] && ok || bad "merge clash: $(cat "$tmp/err")"
if "$BRDFIT" merge "$tmp/s1.db" -o "$tmp/all.db" 2>/dev/null; then bad "merge over an existing file"; else ok; fi
# A shard database is refused for another shard or for a whole run.
if "$BRDFIT" batch "$tmp/m.json" -o "$tmp/s1.db" --shard 2/3 2>"$tmp/err"; then bad "other shard accepted"; else ok; fi
grep -q "made by another --shard" "$tmp/err" && ok || bad "shard message: $(cat "$tmp/err")"

# --- warning kinds; a schema 1 database (before kinds): read, resumed, merged -------------
# cook_torrance from 2 starts on these 20 samples reaches its best from one: "?" in the
# report, decided on the stored kind. Schema 1 is made here as it was: no warning_kinds.
printf 'models: lambert cook_torrance\noptions: --rgb --starts 2 --screen 8 --threads 1\n%s\n' \
  "$DATA/cornell/cayman_head20.brdf" > "$tmp/k.txt"
"$BRDFIT" batch "$tmp/k.txt" -o "$tmp/k2.db" && ok || bad "batch for kinds"
[ "$(count "$tmp/k2.db" "SELECT count(*) FROM items WHERE json_array_length(warning_kinds) = json_array_length(warnings)
  AND json_array_length(warnings) > 0")" = 2 ] && ok || bad "a kind per warning: $(count "$tmp/k2.db" "SELECT warning_kinds FROM items")"
[ "$(count "$tmp/k2.db" "SELECT json_extract(warning_kinds, '\$[0]') FROM items WHERE item = 1")" = one_start ] && ok ||
  bad "one_start kind: $(count "$tmp/k2.db" "SELECT warnings, warning_kinds FROM items WHERE item = 1")"
"$BRDFIT" report "$tmp/k2.db" > "$tmp/k2.txt" && grep -q "^  ?: the best optimum was reached from one start" "$tmp/k2.txt" &&
  ok || bad "report of kinds: $(cat "$tmp/k2.txt")"
to_schema1() {
  cp "$1" "$2" && sqlite3 "$2" "ALTER TABLE items DROP COLUMN warning_kinds; UPDATE meta SET value = '1' WHERE key = 'schema'"
}
to_schema1 "$tmp/k2.db" "$tmp/k1.db"
"$BRDFIT" report "$tmp/k1.db" | cmp -s - "$tmp/k2.txt" && ok || bad "report of a schema 1 database differs"
# Resumed: upgraded to schema 2, the new row with kinds, the old one without.
sqlite3 "$tmp/k1.db" "UPDATE items SET status = 'pending', spec = NULL, warnings = NULL WHERE item = 1"
"$BRDFIT" batch "$tmp/k.txt" -o "$tmp/k1.db" && ok || bad "resume of a schema 1 database"
[ "$(count "$tmp/k1.db" "SELECT value FROM meta WHERE key = 'schema'")" = 2 ] &&
  [ "$(count "$tmp/k1.db" "SELECT group_concat(warning_kinds IS NULL) FROM items")" = "1,0" ] && ok ||
  bad "upgraded database: $(count "$tmp/k1.db" "SELECT item, warning_kinds FROM items")"
"$BRDFIT" report "$tmp/k1.db" | cmp -s - "$tmp/k2.txt" && ok || bad "report of an upgraded database differs"
# Merged: schema 1 shards into a schema 2 database; schema 1 with 2 refused.
for s in 1 2; do
  "$BRDFIT" batch "$tmp/k.txt" -o "$tmp/ks$s.db" --shard $s/2 && to_schema1 "$tmp/ks$s.db" "$tmp/ks${s}v1.db" || bad "shard $s for kinds"
done
"$BRDFIT" merge "$tmp/ks1v1.db" "$tmp/ks2v1.db" -o "$tmp/km1.db" && ok || bad "merge of schema 1 shards"
[ "$(count "$tmp/km1.db" "SELECT value FROM meta WHERE key = 'schema'")" = 2 ] && ok || bad "merged schema"
"$BRDFIT" report "$tmp/km1.db" | cmp -s - "$tmp/k2.txt" && ok || bad "report of merged schema 1 shards differs"
"$BRDFIT" merge "$tmp/ks1.db" "$tmp/ks2.db" -o "$tmp/km2.db" && rows "$tmp/km2.db" | cmp -s - <(rows "$tmp/k2.db") && ok ||
  bad "merged shards keep their kinds"
if "$BRDFIT" merge "$tmp/ks1v1.db" "$tmp/ks2.db" -o "$tmp/kx.db" 2>"$tmp/err"; then bad "schema 1 merged with 2"; else ok; fi
grep -q "another schema than the first input" "$tmp/err" && [ ! -e "$tmp/kx.db" ] && ok || bad "mixed schemas: $(cat "$tmp/err")"

# --- another manifest, another version: refused, untouched ------------------------------
sed 's/"--seed", "3"/"--seed", "4"/' "$tmp/m.json" > "$tmp/m4.json"
cp "$tmp/one.db" "$tmp/keep.db"
"$BRDFIT" batch "$tmp/m4.json" -o "$tmp/one.db" 2>"$tmp/err"
[ $? = 2 ] && grep -q "made by another manifest" "$tmp/err" && [ "$(wc -l < "$tmp/err")" = 1 ] && ok || bad "other manifest: $(cat "$tmp/err")"
cmp -s "$tmp/one.db" "$tmp/keep.db" && ok || bad "refused database changed"
sqlite3 "$tmp/keep.db" "UPDATE meta SET value = '0.0.0' WHERE key = 'tool_version'"
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/keep.db" 2>"$tmp/err"
[ $? = 2 ] && grep -q "made by another brdfit version" "$tmp/err" && ok || bad "other version: $(cat "$tmp/err")"
if "$BRDFIT" merge "$tmp/keep.db" "$tmp/one.db" -o "$tmp/v.db" 2>/dev/null; then bad "merge across versions"; else ok; fi

# --- a locked database: one line, nothing changed -----------------------------------------
cp "$tmp/one.db" "$tmp/l.db"
cp "$tmp/l.db" "$tmp/l.before"
mkfifo "$tmp/hold"
{ echo "BEGIN EXCLUSIVE;"; echo "UPDATE meta SET value = value WHERE key = 'schema';"; cat "$tmp/hold"; echo "ROLLBACK;"; } |
  sqlite3 "$tmp/l.db" &
lock=$!
exec 7>"$tmp/hold" # keeps the shell in its transaction until closed
for _ in $(seq 100); do [ -e "$tmp/l.db-journal" ] && break; sleep 0.02; done
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/l.db" --redo all 2>"$tmp/err"
rc=$?
"$BRDFIT" report "$tmp/l.db" >/dev/null 2>"$tmp/err2"
rc2=$?
exec 7>&-
wait $lock
[ $rc = 1 ] && grep -q "l.db: locked by another process" "$tmp/err" && [ "$(wc -l < "$tmp/err")" = 1 ] && ok ||
  bad "locked database (batch): exit $rc, $(cat "$tmp/err")"
[ $rc2 = 1 ] && grep -q "locked by another process" "$tmp/err2" && ok || bad "locked database (report): exit $rc2, $(cat "$tmp/err2")"
rows "$tmp/l.db" | cmp -s - "$tmp/one.rows" && ok || bad "locked database changed"
# Two batch runs on one database: the second refused at once.
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/two.db" 2>/dev/null &
pid=$!
for _ in $(seq 100); do [ -e "$tmp/two.db" ] && break; sleep 0.01; done
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/two.db" 2>"$tmp/err"
rc=$?
wait $pid
[ $rc = 1 ] && grep -q "in use by another brdfit batch" "$tmp/err" || [ $rc = 0 ] && ok || bad "two writers: exit $rc $(cat "$tmp/err")"

# --- a damaged database: one line, left as it was ------------------------------------------
cp "$tmp/one.db" "$tmp/d.db"
printf 'not an SQLite header' | dd of="$tmp/d.db" conv=notrunc 2>/dev/null
cp "$tmp/d.db" "$tmp/d.before"
for c in "batch $tmp/m.json -o" "report"; do
  "$BRDFIT" $c "$tmp/d.db" >/dev/null 2>"$tmp/err"
  [ $? = 1 ] && grep -q "d.db: damaged or not a database" "$tmp/err" && [ "$(wc -l < "$tmp/err")" = 1 ] && ok ||
    bad "damaged database ($c): $(cat "$tmp/err")"
done
cmp -s "$tmp/d.db" "$tmp/d.before" && ok || bad "damaged database was written"
printf 'SQLite format 3\0' > "$tmp/e.db"; head -c 4080 /dev/urandom >> "$tmp/e.db"
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/e.db" 2>"$tmp/err"
[ $? = 1 ] && grep -q "damaged or not a database" "$tmp/err" && ok || bad "random pages: $(cat "$tmp/err")"
sqlite3 "$tmp/other.db" "CREATE TABLE t(x)"
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/other.db" 2>"$tmp/err"
[ $? = 2 ] && grep -q "not brdfit batch results" "$tmp/err" && ok || bad "foreign database: $(cat "$tmp/err")"

# --- a missing data file: its items are errors; --redo failed runs them again --------------
cat > "$tmp/mm.json" <<'JSON'
{"models": ["lambert", "walter"], "options": ["--threads", "1"],
 "materials": ["lam1.csv", {"data": "later.csv", "options": ["--max-theta", "80"]}]}
JSON
"$BRDFIT" batch "$tmp/mm.json" -o "$tmp/f.db" 2>"$tmp/err"
[ $? = 1 ] && grep -q "2 of 4 items failed" "$tmp/err" && ok || bad "missing data: $(cat "$tmp/err")"
[ "$(count "$tmp/f.db" "SELECT group_concat(status) FROM items")" = "ok,ok,error,error" ] && ok || bad "error rows"
[ "$(count "$tmp/f.db" "SELECT options FROM items WHERE item = 3")" = '["--threads","1","--max-theta","80","-m","walter"]' ] &&
  ok || bad "material options in the options column"
"$BRDFIT" report "$tmp/f.db" --json "$tmp/f.json" >/dev/null 2>&1
jq -e '.materials[1].fits[0].status == "error" and (.materials[1].fits[0].message | test("later.csv: cannot open"))' "$tmp/f.json" >/dev/null &&
  ok || bad "report of error items"
cp "$tmp/lam2.csv" "$tmp/later.csv"
"$BRDFIT" batch "$tmp/mm.json" -o "$tmp/f.db" 2>/dev/null
[ "$(count "$tmp/f.db" "SELECT group_concat(status) FROM items")" = "ok,ok,error,error" ] && ok || bad "plain rerun redid errors"
"$BRDFIT" batch "$tmp/mm.json" -o "$tmp/f.db" --redo failed && ok || bad "--redo failed"
# --redo all: every row again, the same results.
cp "$tmp/one.db" "$tmp/redo.db"
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/redo.db" --redo all --jobs 2 && ok || bad "--redo all"
rows "$tmp/redo.db" | cmp -s - "$tmp/one.rows" && ok || bad "--redo all changed results"
[ "$(count "$tmp/redo.db" "ATTACH '$tmp/one.db' AS o;
       SELECT count(*) FROM items a JOIN o.items b USING(item) WHERE a.finished_at > b.finished_at")" = 24 ] &&
  ok || bad "--redo all did not run every item again"
[ "$(count "$tmp/f.db" "SELECT group_concat(status) FROM items")" = "ok,ok,ok,ok" ] && ok || bad "after --redo failed"

# --- bad usage and bad manifests: one line, exit 2, no database ---------------------------
for args in "" "$tmp/m.json" "$tmp/m.json -o $tmp/u.db --shard 4/3" "$tmp/m.json -o $tmp/u.db --redo some"; do
  "$BRDFIT" batch $args 2>"$tmp/err"
  [ $? = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && [ ! -e "$tmp/u.db" ] && ok || bad "usage '$args': $(cat "$tmp/err")"
done
for bad_manifest in '{"models": ["nosuchmodel"], "materials": ["lam1.csv"]}' \
                    '{"models": ["lambert"], "materials": ["lam1.csv"], "options": ["--residual", "nope"]}' \
                    '{"models": ["lambert"], "materials": [{"data": "lam1.csv", "options": ["--threads", "2"]}]}' \
                    '{"models": ["lambert"], "materials": []}' '[1, 2]' '{"models": ["lambert"], "materials": ["a"], "x": 1}'; do
  echo "$bad_manifest" > "$tmp/bad.json"
  "$BRDFIT" batch "$tmp/bad.json" -o "$tmp/u.db" 2>"$tmp/err"
  [ $? = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q "^brdfit batch: $tmp/bad.json: " "$tmp/err" &&
    [ ! -e "$tmp/u.db" ] && ok || bad "manifest $bad_manifest: $(cat "$tmp/err")"
done

# --- a fit's process killed: its material's unfinished fits run again, one at a time -------
# One material large enough that its fits last (the process is named brdfit:0+ while it
# fits the material's four items, brdfit:K while it runs item K again alone).
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 200000 --noise 0.01 --seed 21 -o "$tmp/kwal.csv" ||
  bad "brdfit-synth failed"
cat > "$tmp/km.json" <<'JSON'
{"models": ["cook_torrance", "walter", "lambert", "blinn_phong"], "options": ["--threads", "1", "--seed", "3"],
 "materials": ["kwal.csv"]}
JSON
"$BRDFIT" batch "$tmp/km.json" -o "$tmp/kone.db" || bad "batch (k)"
rows "$tmp/kone.db" > "$tmp/kone.rows"
"$BRDFIT" batch "$tmp/km.json" -o "$tmp/once.db" 2>"$tmp/err" &
pid=$!
kill_fit $pid "more" >/dev/null || bad "no fitting process under brdfit batch"
wait $pid && ok || bad "one lost fit: exit $?: $(head -c 600 "$tmp/err")"
grep -q "^brdfit batch: $tmp/kwal.csv: the process fitting it died (killed by signal 9 (Killed).*); its unfinished fits run again, one at a time$" "$tmp/err" &&
  [ "$(wc -l < "$tmp/err")" = 1 ] && ok || bad "one lost fit, stderr: $(head -c 600 "$tmp/err")"
rows "$tmp/once.db" | cmp -s - "$tmp/kone.rows" && ok || bad "rows after a lost fit differ from an uninterrupted run"
# Killed again while it runs an item alone: that item is an error row, the others finish.
"$BRDFIT" batch "$tmp/km.json" -o "$tmp/twice.db" 2>"$tmp/err" &
pid=$!
kill_fit $pid "more" >/dev/null && item=$(kill_fit $pid "!more") || bad "no second fitting process"
wait $pid
[ $? = 1 ] && ok || bad "an item lost twice: exit not 1"
[ "$(count "$tmp/twice.db" "SELECT item, status FROM items WHERE status != 'ok'")" = "$item|error" ] && ok ||
  bad "lost twice (item $item): $(count "$tmp/twice.db" "SELECT item, status FROM items")"
count "$tmp/twice.db" "SELECT message FROM items WHERE item = $item" |
  grep -qx "the process fitting it died each of the 2 times it ran; the last time: killed by signal 9 (Killed): a kill, or the kernel out of memory" &&
  ok || bad "lost twice, message: $(count "$tmp/twice.db" "SELECT message FROM items WHERE item = $item")"
grep -q "the process fitting it died again (killed by signal 9 .*); recorded as an error (--redo failed runs it again)$" "$tmp/err" &&
  ok || bad "lost twice, stderr: $(head -c 600 "$tmp/err")"
"$BRDFIT" batch "$tmp/km.json" -o "$tmp/twice.db" --redo failed && ok || bad "--redo failed after a lost item"
rows "$tmp/twice.db" | cmp -s - "$tmp/kone.rows" && ok || bad "rows after --redo failed differ"

# SIGINT reaches the fitting process through the batch process (which passes it on): the
# running fit finishes and is written, the next do not start, exit 130, resumable.
interrupt_batch "$tmp/km.json" "$tmp/int.db" 1
[ $rc = 130 ] && [ "$(count "$tmp/int.db" "SELECT count(*) FROM items WHERE status = 'pending'")" -ge 1 ] &&
  [ "$(count "$tmp/int.db" "SELECT count(*) FROM items WHERE status NOT IN ('ok', 'pending')")" = 0 ] && ok ||
  bad "SIGINT to a run of long fits: exit $rc, $(count "$tmp/int.db" "SELECT status, count(*) FROM items GROUP BY 1")"
"$BRDFIT" batch "$tmp/km.json" -o "$tmp/int.db" && rows "$tmp/int.db" | cmp -s - "$tmp/kone.rows" && ok ||
  bad "rows after SIGINT to long fits and resume differ"

# --- a plain-list manifest: the JSON manifest it spells, one identity, one database ---------
cat > "$tmp/m.txt" <<'LIST'
# m.json as a plain list
models: lambert walter cook_torrance blinn_phong
options: --threads 1 --seed 3   # shared by every fit
lam1.csv
wal1.csv

"lam2.csv"
  wal2.csv
lam3.csv
wal3.csv
LIST
"$BRDFIT" batch "$tmp/m.txt" -o "$tmp/one.db" 2>"$tmp/err" && [ ! -s "$tmp/err" ] && ok || bad "plain list on m.json's database: $(cat "$tmp/err")"
rows "$tmp/one.db" | cmp -s - "$tmp/one.rows" && ok || bad "the plain list changed m.json's rows"
# A material's own options and a scene, relative to the list's folder (one word, so a
# file named like an option stays a file).
mkdir -p "$tmp/sub"
cp "$(dirname "$0")/../examples/scenes/product_shot.json" "$tmp/sub/--studio.json"
cp "$tmp/lam1.csv" "$tmp/sub/lam 1.csv"
printf 'models: lambert\n"lam 1.csv" --scene --studio.json --subsample 500 --seed 2\n' > "$tmp/sub/s.txt"
"$BRDFIT" batch "$tmp/sub/s.txt" -o "$tmp/s.db" 2>"$tmp/err" && ok || bad "list with options: $(cat "$tmp/err")"
[ "$(count "$tmp/s.db" "SELECT data FROM materials")" = "$tmp/sub/lam 1.csv" ] && ok || bad "list material path"
[ "$(count "$tmp/s.db" "SELECT options FROM items")" = "[\"--subsample\",\"500\",\"--seed\",\"2\",\"--scene=$tmp/sub/--studio.json\",\"-m\",\"lambert\"]" ] &&
  ok || bad "list item options: $(count "$tmp/s.db" "SELECT options FROM items")"
"$BRDFIT" report "$tmp/s.db" > /dev/null && ok || bad "report of a plain-list run"
# Errors: one line naming the file and line, exit 2, no database.
i=0
while IFS='|' read -r text want; do
  i=$((i + 1))
  printf "$text" > "$tmp/bad.txt"
  "$BRDFIT" batch "$tmp/bad.txt" -o "$tmp/u.db" 2>"$tmp/err"
  [ $? = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -qF "brdfit batch: $tmp/bad.txt$want" "$tmp/err" &&
    [ ! -e "$tmp/u.db" ] && ok || bad "bad list $i ($text): $(cat "$tmp/err")"
done <<'CASES'
models: lambert\na.csv --scene\n|:2: --scene needs a file
models: lambert\n"a.csv\n|:2: a double quote is not closed on its line
options: --seed 1\na.csv\n|: no models: line
models:\na.csv\n|:1: models: lists no model
models: lambert\n# only a comment\n|: no material lines
models: lambert\nmodels: walter\na.csv\n|:2: a second models: line
models: lambert\noptions: --bogus 1\na.csv\n|: line 2: option '--bogus' is not taken here
models: lambert\n\na.csv --threads 2\n|: line 3: option '--threads' is not taken here (a material takes data options only)
models: lambert\na.csv --subsample\n|: line 2: --subsample needs a value
models: lambert\na.csv b.csv\n|: line 2: 'b.csv' is not an option
models: lambert\noptions: --help\na.csv\n|: line 2: unknown option '--help'
models: lambert\na.csv -q\n|: line 2: unknown option '-q'
models: nosuchmodel\na.csv\n|: unknown model 'nosuchmodel'
CASES

# --- docs/batch.md documents every column the database has ----------------------------------
doc=$(dirname "$0")/../docs/batch.md
for t in meta materials models items; do
  for col in $(sqlite3 "$tmp/one.db" "SELECT name FROM pragma_table_info('$t')"); do
    grep -Eq "(^| |\\(|,)$col (INTEGER|REAL|TEXT)" "$doc" && ok || bad "docs/batch.md: no column $t.$col"
  done
done
finish
