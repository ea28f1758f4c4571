#!/usr/bin/env bash
# brdfit select from the shell: Lambert data selects lambert from the default
# candidates; white-highlight Walter data selects walter:mono=specular from a list; a
# scene that hides the highlight selects lambert and reports over fewer samples; JSON
# and the chosen fit's parameter file; bad usage and bad data (one line, exit 2 or 1,
# no output files).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

cat > "$tmp/lam.json" <<'JSON'
{"model": "lambert", "channels": 3, "params": {"rho_d": [0.6, 0.4, 0.2]}}
JSON
cat > "$tmp/wal.json" <<'JSON'
{"model": "walter", "channels": 3,
 "params": {"rho_d": [0.5, 0.4, 0.3], "rho_s": [0.8, 0.8, 0.8], "alpha": 0.05, "f0": 0.05}}
JSON
cat > "$tmp/scene.json" <<'JSON'
{"description": "lights near the normal, a camera beyond 50 degrees",
 "light": {"theta": [0, 20]}, "view": {"theta": [50, 85]}, "reciprocal": false}
JSON
"$SYNTH" --params "$tmp/lam.json" --pattern uniform --count 2000 --noise 0.01 --seed 1 -o "$tmp/lam.csv" &&
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 6000 --noise 0.01 --seed 2 -o "$tmp/wal.csv" ||
  bad "brdfit-synth failed"

# --- default candidates on Lambert data --------------------------------------------------
if "$BRDFIT" select "$tmp/lam.csv" --threads 2 --json "$tmp/lam_sel.json" -o "$tmp/lam_fit.json" \
     >"$tmp/out" 2>"$tmp/err"; then
  ok
  grep -q '^chosen: lambert (k 3,' "$tmp/out" && ok || bad "choice: $(cat "$tmp/out")"
  grep -q '^=>  lambert ' "$tmp/out" && ok || bad "table marks the choice: $(cat "$tmp/out")"
  [ "$(grep -c '^\[[0-9]*/[0-9]*\] ' "$tmp/err")" -gt 10 ] && ok || bad "progress: $(cat "$tmp/err")"
  jq -e '.chosen == "lambert" and .error == "rmse_log" and .tolerance == 0.05
         and (.candidates | length) > 10
         and ([.candidates[] | select(.chosen)] | length) == 1
         and any(.candidates[]; .model == "walter:mono=specular" and .k == 6 and (.coloured_specular | not))
         and all(.candidates[]; .status == "ok")' "$tmp/lam_sel.json" >/dev/null && ok || bad "select JSON"
  # --jobs: every candidate fitted again, 3 at once; the same table and JSON, the same fit
  # file but for what it records of the run (wall times, the solver threads it had).
  if "$BRDFIT" select "$tmp/lam.csv" --threads 2 --jobs 3 --json "$tmp/lam_sel3.json" -o "$tmp/lam_fit3.json" \
       >"$tmp/out3" 2>"$tmp/err3"; then
    run_free() { jq -S 'del(.seconds, .optimizer.seconds, .optimizer.screen.seconds, .optimizer.threads)' "$1"; }
    cmp -s "$tmp/out" "$tmp/out3" && cmp -s "$tmp/lam_sel.json" "$tmp/lam_sel3.json" &&
      [ "$(run_free "$tmp/lam_fit.json")" = "$(run_free "$tmp/lam_fit3.json")" ] && ok ||
      bad "--jobs 3 changed the outputs: $(diff "$tmp/out" "$tmp/out3" | head -4)"
    [ "$(grep -c '^\[[0-9]*/[0-9]*\] ' "$tmp/err3")" = "$(grep -c '^\[[0-9]*/[0-9]*\] ' "$tmp/err")" ] &&
      grep -q "^\[$(jq '.candidates | length' "$tmp/lam_sel.json")/" "$tmp/err3" && ok || bad "--jobs 3 progress: $(cat "$tmp/err3")"
  else
    bad "select --jobs 3: $(cat "$tmp/err3")"
  fi
  # The chosen fit is a parameter file.
  printf 'theta_i,phi_i,theta_o,phi_o\n0,0,0,0\n' > "$tmp/dirs.csv"
  "$BRDFIT" eval --params "$tmp/lam_fit.json" --dirs "$tmp/dirs.csv" -o "$tmp/ev.csv" &&
    awk -F, 'NR == 2 { exit !($5 > 0.18 && $5 < 0.2) }' "$tmp/ev.csv" && ok || bad "eval of the chosen fit"
else
  bad "select on Lambert data: $(cat "$tmp/err")"
fi

# --- a white highlight; then a scene that never sees it ------------------------------------
M=lambert,walter,walter:mono=specular,walter_aniso:mono=specular
if "$BRDFIT" select "$tmp/wal.csv" --models $M --threads 2 --quiet >"$tmp/out" 2>"$tmp/err"; then
  ok
  grep -q '^chosen: walter:mono=specular (k 6,' "$tmp/out" && ok || bad "white highlight: $(cat "$tmp/out")"
  [ ! -s "$tmp/err" ] && ok || bad "--quiet printed: $(cat "$tmp/err")"
else
  bad "select on Walter data: $(cat "$tmp/err")"
fi
if "$BRDFIT" select "$tmp/wal.csv" -m $M --threads 2 --scene "$tmp/scene.json" --json "$tmp/scene_sel.json" \
     >"$tmp/out" 2>"$tmp/err"; then
  ok
  grep -q '^chosen: lambert ' "$tmp/out" && ok || bad "scene choice: $(cat "$tmp/out")"
  n=$(jq '.candidates[0].metrics.n' "$tmp/scene_sel.json")
  [ "$n" -gt 30 ] && [ "$n" -lt 6000 ] && ok || bad "scene error over $n values"
else
  bad "select with a scene: $(cat "$tmp/err")"
fi

# --- --accuracy fast: the preset's subsample (16000) leaves 2000 samples whole; --subsample wins
"$BRDFIT" select "$tmp/lam.csv" -m lambert,walter --accuracy fast --threads 2 --quiet --json "$tmp/acc.json" \
    >/dev/null 2>"$tmp/err" && jq -e '.chosen == "lambert" and .candidates[0].metrics.n == 6000' "$tmp/acc.json" \
    >/dev/null && ok || bad "--accuracy fast: $(cat "$tmp/err")"
"$BRDFIT" select "$tmp/lam.csv" -m lambert --subsample 500 --accuracy fast --threads 2 --quiet --json "$tmp/acc.json" \
    >/dev/null 2>"$tmp/err" && jq -e '.candidates[0].metrics.n == 1500' "$tmp/acc.json" >/dev/null && ok ||
  bad "--subsample with --accuracy: $(cat "$tmp/err")"

# --- bad usage and bad data ------------------------------------------------------------------
expect() { # expect STATUS FRAGMENT ARGS...: exit status, one line naming the problem, no outputs
  local want=$1 frag=$2
  shift 2
  rm -f "$tmp/o.json" "$tmp/f.json"
  "$BRDFIT" select "$@" >/dev/null 2>"$tmp/err"
  local got=$?
  if [ "$got" = "$want" ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$frag" "$tmp/err" &&
     [ ! -e "$tmp/o.json" ] && [ ! -e "$tmp/f.json" ]; then ok
  else bad "select $* -> $got: $(cat "$tmp/err")"; fi
}
expect 2 "unknown option '--bogus'" "$tmp/lam.csv" --bogus --json "$tmp/o.json"
expect 2 "unknown model 'nonesuch'" "$tmp/lam.csv" -m lambert,nonesuch --json "$tmp/o.json"
expect 2 "--tolerance needs a number >= 0" "$tmp/lam.csv" --tolerance -1 --json "$tmp/o.json"
expect 2 "a data file is required" -m lambert --json "$tmp/o.json"
expect 2 "--error" "$tmp/lam.csv" --error nope --json "$tmp/o.json"
expect 2 "mono" "$tmp/lam.csv" -m lambert:mono=specular --json "$tmp/o.json"
expect 2 "accuracy" "$tmp/lam.csv" -m lambert --accuracy nope --json "$tmp/o.json"
expect 1 "$tmp/missing.csv" "$tmp/missing.csv" -m lambert --json "$tmp/o.json" -o "$tmp/f.json"
printf 'theta_i,phi_i,theta_o,phi_o,value\n10,0,20,180,nan\n' > "$tmp/nan.csv"
expect 1 "nan.csv:2" "$tmp/nan.csv" -m lambert --json "$tmp/o.json" -o "$tmp/f.json"

finish
