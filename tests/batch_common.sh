# Sourced by the brdfit batch tests (cli_batch.sh, cli_batch_mpi.sh) after common_cli.sh:
# the manifest they share and the helpers that read a results database.
need sqlite3 sqlite3; need pgrep procps

cat > "$tmp/lam.json" <<'JSON'
{"model": "lambert", "channels": 3, "params": {"rho_d": [0.6, 0.4, 0.2]}}
JSON
cat > "$tmp/wal.json" <<'JSON'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 3,
 "params": {"rho_d": [0.3, 0.2, 0.1], "rho_s": [0.8, 0.8, 0.7], "alpha": 0.1, "f0": 0.05}}
JSON
# Materials lamK.csv and walK.csv (K = 1..3, $2 samples each, file names prefixed $1)
# and the manifest $1m.json of them x 4 models (24 items).
batch_manifest() {
  local mats="" k
  for k in 1 2 3; do
    "$SYNTH" --params "$tmp/lam.json" --pattern uniform --count "$2" --noise 0.01 --seed $k -o "$tmp/${1}lam$k.csv" &&
    "$SYNTH" --params "$tmp/wal.json" --pattern uniform --count "$2" --noise 0.01 --seed $((k + 10)) -o "$tmp/${1}wal$k.csv" ||
      bad "brdfit-synth failed"
    mats="$mats${mats:+, }\"${1}lam$k.csv\", \"${1}wal$k.csv\""
  done
  cat > "$tmp/${1}m.json" <<JSON
{"models": ["lambert", "walter", "cook_torrance", "blinn_phong"],
 "options": ["--threads", "1", "--seed", "3"], "materials": [$mats]}
JSON
}
# Every column but the wall times, in item order.
COLS="item,material,model,status,message,spec,samples,channels,n,k,rmse,rmse_log,rmse_cos,rmse_rel,max_err,weighted,crit_n,loglik,aic,aicc,bic,cv,work,params,stderr,warnings,warning_kinds,options,tool_version"
rows() { sqlite3 "$1" "SELECT $COLS FROM items ORDER BY item"; }
count() { sqlite3 "$1" "$2"; }
# Waits (up to 4 s) until database $1 of a running batch has $2 items finished.
wait_items() {
  for _ in $(seq 200); do
    n=$(count "$1" "SELECT count(*) FROM items WHERE status != 'pending'" 2>/dev/null || echo 0)
    [ "${n:-0}" -ge "$2" ] && return
    sleep 0.02
  done
}
# Runs brdfit batch on manifest $1 into database $2 in the background, sends it SIGINT
# once $3 items are finished, and sets rc to its exit status (stderr in $tmp/err).
interrupt_batch() {
  "$BRDFIT" batch "$1" -o "$2" 2>"$tmp/err" &
  local pid=$!
  wait_items "$2" "$3"
  kill -INT $pid
  wait $pid
  rc=$?
}
# A fit's process (cmd/batch_fitter.c) is named brdfit:ITEM while it fits ITEM alone and
# brdfit:ITEM+ while it fits ITEM and more of that material. kill_fit P COND finds one
# among the children and grandchildren of process P (a one-process batch, or mpirun and its
# ranks) whose first item i and flag more (1 for "+") meet COND (shell arithmetic), stops
# it with SIGSTOP, so that it cannot finish first, kills it with SIGKILL and prints i;
# it waits up to 10 s for one.
kill_fit() {
  local c name i more
  for _ in $(seq 2000); do
    for c in $(pgrep -P "$1") $(for k in $(pgrep -P "$1"); do pgrep -P "$k"; done); do
      name=$(cat /proc/$c/comm 2>/dev/null)
      [[ $name =~ ^brdfit:([0-9]+)(\+?)$ ]] || continue
      i=${BASH_REMATCH[1]} more=$([ -n "${BASH_REMATCH[2]}" ] && echo 1 || echo 0)
      if (( $2 )) && kill -STOP "$c" 2>/dev/null && [ "$(cat /proc/$c/comm 2>/dev/null)" = "$name" ]; then
        kill -KILL "$c"; echo "$i"; return 0
      fi
    done
    sleep 0.002
  done
  return 1
}
