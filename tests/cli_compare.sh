#!/usr/bin/env bash
# brdfit compare from the shell: two synthetic materials (Lambert and Walter) x three
# models; the simplest model chosen for each; JSON and CSV contents; results independent
# of --jobs; SIGINT keeps finished fits; bad usage and bad data (one line on stderr,
# exit 2 or 1, no output files).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

cat > "$tmp/lam.json" <<'EOF'
{"model": "lambert", "channels": 3, "params": {"rho_d": [0.6, 0.4, 0.2]}}
EOF
cat > "$tmp/wal.json" <<'EOF'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 3,
 "params": {"rho_d": [0.3, 0.2, 0.1], "rho_s": [0.8, 0.8, 0.7], "alpha": 0.1, "f0": 0.05}}
EOF
"$SYNTH" --params "$tmp/lam.json" --pattern uniform --count 2000 --noise 0.01 --seed 1 -o "$tmp/lam.csv" &&
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 2000 --noise 0.01 --seed 2 -o "$tmp/wal.csv" ||
  bad "brdfit-synth failed"
MODELS=lambert,walter,cook_torrance

# --- a comparison: summary, JSON, CSV ---------------------------------------------------
if "$BRDFIT" compare "$tmp/lam.csv" "$tmp/wal.csv" -m $MODELS --threads 2 --json "$tmp/r.json" \
     --csv "$tmp/r.csv" >"$tmp/out" 2>"$tmp/err"; then
  ok
  grep -q "simplest within 5% of the best rmse_log (.*): lambert" "$tmp/out" && ok || bad "summary: $(cat "$tmp/out")"
  grep -q '^summary over 2 materials' "$tmp/out" && ok || bad "no cross-material summary"
  [ "$(grep -c ' ok, rmse_log ' "$tmp/err")" = 6 ] && ok || bad "progress lines (not a terminal): $(cat "$tmp/err")"
  jq -e --arg l "$tmp/lam.csv" --arg w "$tmp/wal.csv" '
      .version == 2 and .rank_by == "bic" and .error == "rmse_log" and .tolerance == 0.05 and .residual == "log"
      and .timing == false and .folds == null
      and .interrupted == false and .models == ["lambert", "walter", "cook_torrance"]
      and [.materials[].data] == [$l, $w] and all(.materials[]; .samples == 2000 and .channels == 3)
      and .materials[0].simplest == "lambert" and .materials[1].simplest != "lambert"
      and .materials[1].simplest == "walter"
      and [.materials[1].fits[].model] == ["lambert", "walter", "cook_torrance"]
      and all(.materials[].fits[]; .ok and .status == "ok" and .n == 6000 and (.rank_bic | type) == "number"
              and .rank == .rank_bic and .rank_cv == null and .cv == null and .work > 6000
              and (.bic | type) == "number" and (.aicc | type) == "number" and (.loglik | type) == "number"
              and (has("seconds") | not) and (.stderr | type) == "object" and (.warnings | type) == "array")
      and [.materials[].fits[].k] == [3, 8, 8, 3, 8, 8]
      and .materials[1].fits[1].rank_bic == 1 and .materials[1].fits[0].rank_bic == 3
      and .materials[1].fits[1].pareto_k and (.materials[1].fits[2].pareto_k | not)
      and .materials[0].fits[0].pareto_k
      and (.materials[0].fits[0].params.rho_d[0] - 0.6 | fabs) < 0.01
      and (.materials[1].fits[1].params.alpha - 0.1 | fabs) < 0.01
      and .materials[1].fits[1].spec == "walter:fresnel=schlick,lobes=1"
      and ([.summary[].model] == ["lambert", "walter", "cook_torrance"])
      and .summary[0].chosen_simplest == 1 and .summary[1].chosen_simplest == 1
      and .summary[2].chosen_simplest == 0 and all(.summary[]; .materials == 2)
      and .summary[1].mean_rank_bic <= 1.5' "$tmp/r.json" >/dev/null \
    && ok || bad "JSON: $(jq -c '[.materials[] | {simplest, fits: [.fits[] | {model, k, rank_bic, error}]}]' "$tmp/r.json")"
  # CSV: a header and 2 x 3 rows; per material exactly one simplest; lambert's row on
  # lambert data is the simplest, and its error equals rmse_log.
  awk -F, -v l="$tmp/lam.csv" '
    NR == 1 { for (i = 1; i <= NF; i++) col[$i] = i; next }
    { rows++; simp[$1] += $(col["simplest"])
      if ($(col["status"]) != "ok" || $(col["error"]) != $(col["rmse_log"])) bad = 1
      if ($1 == l && $2 == "lambert" && $(col["simplest"]) != 1) bad = 1 }
    END { if (rows != 6 || length(simp) != 2) bad = 1; for (m in simp) if (simp[m] != 1) bad = 1; exit bad }' \
    "$tmp/r.csv" && ok || bad "CSV: $(cat "$tmp/r.csv")"
  ls "$tmp" | grep -q '\.tmp\.' && bad "temporary file left behind" || ok
else
  bad "compare failed: $(cat "$tmp/err")"
fi

# --- --jobs and --threads: the same bytes (no wall time is written, none decides);
# --quiet: silent stderr
if "$BRDFIT" compare "$tmp/lam.csv" "$tmp/wal.csv" -m $MODELS --jobs 3 --threads 6 --quiet --json "$tmp/j.json" \
     --csv "$tmp/j.csv" >"$tmp/jout" 2>"$tmp/err"; then
  "$BRDFIT" compare "$tmp/lam.csv" "$tmp/wal.csv" -m $MODELS --threads 2 >"$tmp/rout" 2>/dev/null
  cmp -s "$tmp/jout" "$tmp/rout" && ok || bad "--jobs 3 --threads 6 changed the printed table"
  [ -s "$tmp/err" ] && bad "--quiet wrote to stderr: $(cat "$tmp/err")" || ok
  cmp -s "$tmp/j.json" "$tmp/r.json" && ok || bad "--jobs 3 --threads 6 changed the JSON bytes"
  cmp -s "$tmp/j.csv" "$tmp/r.csv" && ok || bad "--jobs 3 --threads 6 changed the CSV bytes"
else
  bad "compare --jobs 3 failed: $(cat "$tmp/err")"
fi
"$BRDFIT" compare "$tmp/lam.csv" "$tmp/wal.csv" -m $MODELS --jobs 1 --threads 1 --quiet --json "$tmp/j1.json" \
  >/dev/null 2>&1 && cmp -s "$tmp/j1.json" "$tmp/r.json" && ok || bad "--jobs 1 --threads 1 changed the JSON bytes"

# --- --timing: wall times in their own fields, nothing else changes -------------------------
"$BRDFIT" compare "$tmp/lam.csv" "$tmp/wal.csv" -m $MODELS --timing --quiet --json "$tmp/tm.json" \
  --csv "$tmp/tm.csv" >/dev/null 2>&1 &&
  jq -e 'all(.materials[].fits[]; (.seconds | type) == "number" and .seconds >= 0) and .timing' "$tmp/tm.json" \
    >/dev/null && head -1 "$tmp/tm.csv" | grep -q ',seconds,' &&
  [ "$(jq -cS 'del(.materials[].fits[].seconds, .timing)' "$tmp/tm.json")" = "$(jq -cS 'del(.timing)' "$tmp/r.json")" ] \
  && ok || bad "--timing"

# --- --rank: AIC, AICc, the error, cross-validation ----------------------------------------
for by in aic aicc error; do
  "$BRDFIT" compare "$tmp/wal.csv" -m $MODELS --rank $by --quiet --json "$tmp/rk.json" >/dev/null 2>&1 &&
    jq -e --arg by "$by" '.rank_by == $by and .materials[0].fits[1].rank == 1
      and all(.materials[0].fits[]; .rank == (if $by == "error" then .rank else .["rank_" + $by] end))' \
      "$tmp/rk.json" >/dev/null && ok || bad "--rank $by: $(jq -c '[.materials[0].fits[] | [.rank, .rank_aic]]' "$tmp/rk.json")"
done
if "$BRDFIT" compare "$tmp/wal.csv" -m lambert,walter --rank cv --folds 4 --quiet --json "$tmp/cv.json" \
     >"$tmp/out" 2>"$tmp/err"; then
  jq -e '.rank_by == "cv" and .folds == 4 and .error == "cv"
    and all(.materials[0].fits[]; (.cv | type) == "number" and .cv > 0 and .rank == .rank_cv and .error == .cv)
    and .materials[0].fits[1].rank == 1 and .materials[0].fits[0].cv > 10 * .materials[0].fits[1].cv
    and .materials[0].simplest == "walter"' "$tmp/cv.json" >/dev/null && ok || bad "--rank cv: $(cat "$tmp/cv.json")"
else
  bad "--rank cv failed: $(cat "$tmp/err")"
fi

# --- other error metric and tolerance; -m all ----------------------------------------------
"$BRDFIT" compare "$tmp/wal.csv" -m lambert,walter --error rmse --tolerance 1000 --quiet --json "$tmp/t.json" \
  >/dev/null 2>&1 && jq -e '.error == "rmse" and .tolerance == 1000 and .materials[0].simplest == "lambert"
    and .materials[0].fits[0].error == .materials[0].fits[0].rmse' "$tmp/t.json" >/dev/null \
  && ok || bad "--error rmse --tolerance 1000"
"$BRDFIT" compare "$tmp/lam.csv" -m all --help >"$tmp/out" 2>&1 && grep -q -- '--tolerance' "$tmp/out" && ok ||
  bad "--help"

# --- SIGINT: finished fits kept, interrupted marked, exit 130 ---------------------------
for k in 1 2 3 4 5 6 7 8; do cp "$tmp/wal.csv" "$tmp/m$k.csv"; done
"$BRDFIT" compare "$tmp"/m?.csv -m walter,cook_torrance,ward --starts 40 --threads 1 --json "$tmp/i.json" \
  --csv "$tmp/i.csv" >/dev/null 2>"$tmp/ierr" &
pid=$!
# Interrupt once the first fit has finished (progress: one line per fit on a non-terminal),
# so some results exist and most fits are still to come.
for _ in $(seq 300); do
  [ -s "$tmp/ierr" ] && break
  sleep 0.1
done
kill -INT $pid 2>/dev/null
wait $pid
st=$?
if [ $st = 130 ]; then
  jq -e '.interrupted == true and ([.materials[].fits[] | select(.status == "not_run")] | length) > 0
         and all(.materials[].fits[]; .status == "ok" or .status == "not_run")' "$tmp/i.json" >/dev/null \
    && ok || bad "interrupted JSON: $(jq -c '[.interrupted, [.materials[].fits[].status]]' "$tmp/i.json")"
  [ "$(wc -l < "$tmp/i.csv")" = 25 ] && ok || bad "interrupted CSV rows: $(wc -l < "$tmp/i.csv")"
  grep -q 'interrupted after' "$tmp/ierr" && ok || bad "interrupted stderr: $(tail -2 "$tmp/ierr")"
else
  bad "SIGINT: exit status $st, expected 130 (did the run end before the interrupt?)"
fi

# --- bad usage (2) and bad data (1): one line, no output files ----------------------------
expect_fail() { # status, what, args...
  local want=$1 what=$2
  shift 2
  rm -f "$tmp/x.json" "$tmp/x.csv"
  "$BRDFIT" compare "$@" --json "$tmp/x.json" --csv "$tmp/x.csv" >/dev/null 2>"$tmp/err"
  local st=$?
  [ $st = "$want" ] && ok || bad "$what: exit status $st, expected $want"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q '^brdfit compare: ' "$tmp/err" && ok || bad "$what: stderr: $(cat "$tmp/err")"
  [ -e "$tmp/x.json" ] || [ -e "$tmp/x.csv" ] && bad "$what: output file written" || ok
}
expect_fail 2 "no models" "$tmp/lam.csv"
expect_fail 2 "no data" -m lambert
expect_fail 2 "unknown model" "$tmp/lam.csv" -m lambert,nosuchmodel
expect_fail 2 "unknown option" "$tmp/lam.csv" -m lambert --frobnicate
expect_fail 2 "bad --error" "$tmp/lam.csv" -m lambert --error mse
expect_fail 2 "bad --tolerance" "$tmp/lam.csv" -m lambert --tolerance -1
expect_fail 2 "bad --jobs" "$tmp/lam.csv" -m lambert --jobs 0
expect_fail 2 "bad --residual" "$tmp/lam.csv" -m lambert --residual square
expect_fail 2 "bad --rank" "$tmp/lam.csv" -m lambert --rank mdl
expect_fail 2 "bad --folds" "$tmp/lam.csv" -m lambert --rank cv --folds 1
expect_fail 2 "criteria with a robust loss" "$tmp/lam.csv" -m lambert --loss huber
grep -q 'robust' "$tmp/err" && ok || bad "robust loss refusal not explained: $(cat "$tmp/err")"
expect_fail 1 "missing data file" "$tmp/lam.csv" "$tmp/missing.csv" -m lambert
grep -q 'missing.csv' "$tmp/err" && ok || bad "missing data file not named: $(cat "$tmp/err")"
printf 'theta_i,phi_i,theta_o,phi_o,value\n10,0,oops,180,0.1\n' > "$tmp/broken.csv"
expect_fail 1 "malformed data" "$tmp/broken.csv" -m lambert
grep -q 'broken.csv' "$tmp/err" && ok || bad "malformed data file not named: $(cat "$tmp/err")"

# Two bundled real materials (the Cornell car paint, the MERL felt slice in ALTA form)
# and three models: both fitted and ranked, the glossy paint not called Lambertian.
EX="$DATA/../../examples/cornell/cayman.brdf"
if "$BRDFIT" compare "$EX" "$DATA/alta/pink-felt-1d.alta" -m lambert,walter,cook_torrance --quiet \
     --json "$tmp/bundled.json" >/dev/null 2>&1; then
  jq -e '(.materials | length) == 2 and ([.materials[].fits[] | select(.ok)] | length) == 6
         and .materials[0].simplest != "lambert"' "$tmp/bundled.json" >/dev/null && ok || bad "bundled compare contents"
else
  bad "bundled compare run"
fi

finish
