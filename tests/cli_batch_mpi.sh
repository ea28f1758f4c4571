#!/usr/bin/env bash
# brdfit batch under mpirun (docs/batch.md, MPI): -np 3 (a coordinator, two workers) and
# -np 1 give the rows of the one-process run; the launcher killed with SIGKILL part-way
# takes its ranks with it, and reruns (under MPI and without) complete with every item
# exactly once and the same rows; a worker killed ends the run, which resumes; a bad
# manifest is one line. A fit's process killed costs only its item (handed out again, an
# error row the second time); a worker rank killed, or Ctrl-C, ends the run, which resumes.
# Fails without mpirun: scripts/setup.sh installs Open MPI.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need mpirun openmpi-bin; need pgrep procps; need script bsdutils; need timeout coreutils
source "$(dirname "$0")/batch_common.sh"
# As root (CI), on this machine only: the isolated launcher needs no ssh.
MPIRUN=(mpirun --allow-run-as-root --oversubscribe --mca plm isolated)
# In the sanitizer build, LeakSanitizer would report what Open MPI keeps until exit, much
# of it from MCA components it has unloaded by then (no module name to suppress): leak
# checking is off for the ranks (the batch code they run is leak-checked in cli_batch.sh;
# AddressSanitizer and UBSan stay on).
export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}detect_leaks=0"

batch_manifest "" 3000   # quick items: the equality checks
batch_manifest b 40000   # slower ones: a run to kill part-way
"$BRDFIT" batch "$tmp/m.json" -o "$tmp/one.db" || bad "one-process batch"
rows "$tmp/one.db" > "$tmp/one.rows"
"$BRDFIT" batch "$tmp/bm.json" -o "$tmp/bone.db" || bad "one-process batch (b)"
rows "$tmp/bone.db" > "$tmp/bone.rows"

# --- -np 3 and -np 1: the one-process rows --------------------------------------------------
if "${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/m.json" -o "$tmp/mpi.db" 2>"$tmp/err"; then ok; else bad "mpirun -np 3: $(head -c 600 "$tmp/err")"; fi
[ ! -s "$tmp/err" ] && ok || bad "mpirun -np 3 not quiet: $(head -c 600 "$tmp/err")"
[ "$(count "$tmp/mpi.db" "SELECT count(*), sum(status = 'ok') FROM items")" = "24|24" ] && ok || bad "-np 3 rows"
rows "$tmp/mpi.db" | cmp -s - "$tmp/one.rows" && ok || bad "-np 3 rows differ from one process: $(rows "$tmp/mpi.db" | diff - "$tmp/one.rows" | head -3)"
# The largest material first: wal* files are larger than lam* (longer numbers).
first=$(count "$tmp/mpi.db" "SELECT material FROM items ORDER BY finished_at LIMIT 1")
big=$(cd "$tmp" && ls -S lam?.csv wal?.csv | head -1)
[ "$(count "$tmp/mpi.db" "SELECT data FROM materials WHERE material = $first")" = "$tmp/$big" ] && ok ||
  bad "first item's material $first is not the largest ($big)"
"${MPIRUN[@]}" -np 1 "$BRDFIT" batch "$tmp/m.json" -o "$tmp/np1.db" && ok || bad "mpirun -np 1"
rows "$tmp/np1.db" | cmp -s - "$tmp/one.rows" && ok || bad "-np 1 rows differ from one process"
# Rerun under MPI: nothing to do, nothing changed.
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/m.json" -o "$tmp/mpi.db" && ok || bad "rerun of a finished MPI batch"
rows "$tmp/mpi.db" | cmp -s - "$tmp/one.rows" && ok || bad "MPI rerun changed rows"

# --- mpirun killed with SIGKILL part-way: its ranks go too; reruns complete -----------------
# Waits (up to 5 s) until no brdfit process has database $1 open.
wait_gone() { for _ in $(seq 250); do pgrep -f -- "-o $1" >/dev/null || return 0; sleep 0.02; done; return 1; }
for rerun in mpi plain; do
  db=$tmp/k$rerun.db
  "${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/bm.json" -o "$db" 2>/dev/null &
  pid=$!
  wait_items "$db" 3
  kill -KILL $pid 2>/dev/null
  wait $pid 2>/dev/null
  wait_gone "$db" && ok || bad "ranks outlived their killed mpirun"
  done_before=$(count "$db" "SELECT count(*) FROM items WHERE status != 'pending'")
  [ "$done_before" -ge 3 ] && [ "$done_before" -lt 24 ] && ok || bad "killed run had $done_before items done (wanted 3..23)"
  [ "$(count "$db" "PRAGMA integrity_check")" = ok ] && ok || bad "killed run left a damaged database"
  if [ $rerun = mpi ]; then
    "${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/bm.json" -o "$db" && ok || bad "resume under mpirun"
  else
    "$BRDFIT" batch "$tmp/bm.json" -o "$db" && ok || bad "resume without MPI"
  fi
  [ "$(count "$db" "SELECT count(*), count(DISTINCT item), sum(status = 'ok') FROM items")" = "24|24|24" ] &&
    ok || bad "after resume ($rerun): $(count "$db" "SELECT status, count(*) FROM items GROUP BY 1")"
  rows "$db" | cmp -s - "$tmp/bone.rows" && ok || bad "resumed rows ($rerun) differ from one process"
done

# --- a fit's process killed: only its item is lost, and handed out again --------------------
# A worker's fits run in a child process (kill_fit: batch_common.sh).
# A material large enough that its cook_torrance fit (item 0) lasts long enough to be seen.
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 200000 --noise 0.01 --seed 21 -o "$tmp/kwal.csv" ||
  bad "brdfit-synth failed"
cat > "$tmp/km.json" <<'JSON'
{"models": ["cook_torrance", "lambert"], "options": ["--threads", "1", "--seed", "3"], "materials": ["kwal.csv"]}
JSON
"$BRDFIT" batch "$tmp/km.json" -o "$tmp/kone.db" || bad "one-process batch (k)"
rows "$tmp/kone.db" > "$tmp/kone.rows"
db=$tmp/once.db
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/km.json" -o "$db" 2>"$tmp/err" &
pid=$!
item=$(kill_fit $pid "i == 0") || bad "no fitting process found under mpirun"
wait $pid && ok || bad "one lost fit: mpirun exit $?: $(head -c 600 "$tmp/err")"
[ "$(grep -c "the process fitting it on rank [12] died (killed by signal 9 (Killed).*); handed out again$" "$tmp/err")" = 1 ] &&
  [ "$(wc -l < "$tmp/err")" = 1 ] && ok || bad "one lost fit, stderr: $(head -c 600 "$tmp/err")"
[ "$(count "$db" "SELECT count(*), count(DISTINCT item), sum(status = 'ok') FROM items")" = "2|2|2" ] && ok ||
  bad "after one lost fit: $(count "$db" "SELECT status, count(*) FROM items GROUP BY 1")"
rows "$db" | cmp -s - "$tmp/kone.rows" && ok || bad "rows after one lost fit (item $item) differ from one process"

# The same item's process killed twice: that item is an error row with the reason, the
# others finish; --redo failed (under mpirun) completes it.
db=$tmp/twice.db
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/km.json" -o "$db" 2>"$tmp/err" &
pid=$!
item=$(kill_fit $pid "i == 0") && again=$(kill_fit $pid "i == $item") || bad "item $item: no second fitting process found"
wait $pid
rc=$?
[ $rc != 0 ] && ok || bad "an item lost twice: mpirun exit 0"
grep -q "recorded as an error (--redo failed runs it again)$" "$tmp/err" && ok || bad "lost twice, stderr: $(head -c 600 "$tmp/err")"
[ "$(count "$db" "SELECT item, status FROM items WHERE status != 'ok'")" = "$item|error" ] &&
  [ "$(count "$db" "SELECT count(*) FROM items")" = 2 ] && ok ||
  bad "lost twice (item $item): $(count "$db" "SELECT item, status FROM items WHERE status != 'ok'")"
count "$db" "SELECT message FROM items WHERE item = $item" |
  grep -qx "the process fitting it died each of the 2 times it ran; the last time: killed by signal 9 (Killed): a kill, or the kernel out of memory" &&
  ok || bad "lost twice, message: $(count "$db" "SELECT message FROM items WHERE item = $item")"
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/km.json" -o "$db" --redo failed && ok || bad "--redo failed under mpirun"
rows "$db" | cmp -s - "$tmp/kone.rows" && ok || bad "rows after --redo failed differ from one process"

# --- a worker rank killed: the run ends (Open MPI 4 ends the job), the database resumes -------
db=$tmp/w.db
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/bm.json" -o "$db" 2>/dev/null &
pid=$!
wait_items "$db" 2
worker=
for c in $(pgrep -P $pid); do
  tr '\0' '\n' < /proc/$c/environ 2>/dev/null | grep -qx 'OMPI_COMM_WORLD_RANK=2' && worker=$c
done
if [ -n "$worker" ]; then
  kill -KILL "$worker"
  wait $pid
  rc=$?
  [ $rc != 0 ] && ok || bad "a killed worker: mpirun exit 0"
  wait_gone "$db" && ok || bad "ranks (or their fits) outlived a killed worker"
  "$BRDFIT" batch "$tmp/bm.json" -o "$db" && ok || bad "resume after a killed worker"
  [ "$(count "$db" "SELECT count(*), count(DISTINCT item), sum(status = 'ok') FROM items")" = "24|24|24" ] && ok ||
    bad "after a killed worker: $(count "$db" "SELECT status, count(*) FROM items GROUP BY 1")"
  rows "$db" | cmp -s - "$tmp/bone.rows" && ok || bad "rows after a killed worker differ"
else
  wait $pid
  bad "no rank-2 process found under mpirun (pid $pid)"
fi

# --- Ctrl-C on the terminal: mpirun ends the job at once, the database resumes ---------------
# script(1) gives mpirun a pseudo-terminal; ^C written to it is the terminal's SIGINT to the
# foreground job (mpirun, its ranks and their fits). script runs the line with $SHELL (/bin/sh,
# which is dash, when unset, as in CI): dash would die of that SIGINT before printing the exit
# status, bash waits for mpirun and prints it.
# Items long enough to be in flight: three copies of the large material x 4 models.
cp "$tmp/kwal.csv" "$tmp/kwal2.csv" && cp "$tmp/kwal.csv" "$tmp/kwal3.csv"
cat > "$tmp/cm.json" <<'JSON'
{"models": ["lambert", "walter", "cook_torrance", "blinn_phong"], "options": ["--threads", "1", "--seed", "3"],
 "materials": ["kwal.csv", "kwal2.csv", "kwal3.csv"]}
JSON
"$BRDFIT" batch "$tmp/cm.json" -o "$tmp/cone.db" || bad "one-process batch (c)"
db=$tmp/c.db
line=$(printf '%q ' "${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/cm.json" -o "$db")
( wait_items "$db" 2; printf '\003'; sleep 10 ) |
  SHELL=/bin/bash timeout 60 script -qec "$line; echo \"exit \$?\"" /dev/null > "$tmp/tty" 2>&1
grep -aq "exit [1-9]" "$tmp/tty" && ok || bad "Ctrl-C under mpirun: $(head -c 600 "$tmp/tty")"
wait_gone "$db" && ok || bad "ranks outlived Ctrl-C"
[ "$(count "$db" "PRAGMA integrity_check")" = ok ] && ok || bad "Ctrl-C left a damaged database"
n=$(count "$db" "SELECT count(*) FROM items WHERE status = 'pending'")
[ "$n" -ge 1 ] && [ "$(count "$db" "SELECT count(*) FROM items WHERE status NOT IN ('ok', 'pending')")" = 0 ] && ok ||
  bad "after Ctrl-C: $(count "$db" "SELECT status, count(*) FROM items GROUP BY 1")"
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/cm.json" -o "$db" && ok || bad "resume after Ctrl-C"
[ "$(rows "$db")" = "$(rows "$tmp/cone.db")" ] && ok || bad "rows after Ctrl-C and resume differ from one process"

# --- errors: one line from rank 0, every rank stops ------------------------------------------
echo '{"models": ["nosuchmodel"], "materials": ["lam1.csv"]}' > "$tmp/bad.json"
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/bad.json" -o "$tmp/u.db" 2>"$tmp/err"
[ $? != 0 ] && [ "$(grep -c "^brdfit batch: $tmp/bad.json: " "$tmp/err")" = 1 ] && [ ! -e "$tmp/u.db" ] && ok ||
  bad "bad manifest under mpirun: $(head -c 600 "$tmp/err")"
# A database of another manifest: refused by the coordinator, the workers released.
timeout 60 "${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/bm.json" -o "$tmp/one.db" 2>"$tmp/err"
rc=$?
[ $rc != 0 ] && [ $rc != 124 ] && grep -q "made by another manifest" "$tmp/err" && ok || bad "other manifest under mpirun: exit $rc $(head -c 600 "$tmp/err")"
rows "$tmp/one.db" | cmp -s - "$tmp/one.rows" && ok || bad "refused database changed"
# A missing data file: that material's items are error rows sent by the workers.
echo '{"models": ["lambert", "walter"], "options": ["--threads", "1"], "materials": ["lam1.csv", "missing.csv"]}' > "$tmp/mm.json"
"$BRDFIT" batch "$tmp/mm.json" -o "$tmp/mm1.db" 2>/dev/null
"${MPIRUN[@]}" -np 3 "$BRDFIT" batch "$tmp/mm.json" -o "$tmp/mm3.db" 2>/dev/null
[ "$(count "$tmp/mm3.db" "SELECT group_concat(status) FROM items")" = "ok,ok,error,error" ] && ok || bad "error rows under mpirun"
[ "$(rows "$tmp/mm3.db")" = "$(rows "$tmp/mm1.db")" ] && ok || bad "error rows differ from one process"
finish
