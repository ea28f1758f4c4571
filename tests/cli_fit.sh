#!/usr/bin/env bash
# brdfit fit from the shell: synthetic data -> fit -> result JSON -> brdfit eval gives the
# generating model's values; several models; a failed fit; bad usage and bad data (one
# line on stderr, exit 2 or 1, no output file).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

cat > "$tmp/truth.json" <<'EOF'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 3,
 "params": {"rho_d": [0.6, 0.4, 0.2], "rho_s": [0.8, 0.8, 0.7], "alpha": 0.12, "f0": 0.05}}
EOF
"$SYNTH" --params "$tmp/truth.json" --pattern uniform --count 3000 --seed 5 -o "$tmp/w.csv" || bad "brdfit-synth failed"

# --- one model: result file, summary, eval through the result ------------------------
if "$BRDFIT" fit "$tmp/w.csv" -m walter --threads 2 -o "$tmp/r.json" >"$tmp/out" 2>"$tmp/err"; then
  ok
  [ -s "$tmp/err" ] && bad "stderr not empty on success: $(cat "$tmp/err")"
  grep -q '^walter:fresnel=schlick,lobes=1  ok' "$tmp/out" && ok || bad "summary: $(cat "$tmp/out")"
  grep -q 'rmse' "$tmp/out" && grep -q 'alpha' "$tmp/out" && ok || bad "summary lacks rmse or parameters"
  jq -e '.model == "walter" and .options.fresnel == "schlick" and .options.lobes == 1 and .channels == 3
         and (.brdfit_version | startswith("0."))
         and .ok == true and .samples == 3000 and .residual == "log" and .metrics.n == 9000 and .metrics.k == 8
         and (.params.alpha - 0.12 | fabs) < 1e-8 and (.params.rho_d[0] - 0.6 | fabs) < 1e-8
         and .optimizer.backend == "ceres" and .optimizer.threads == 2 and .optimizer.starts >= 8
         and .optimizer.starts_at_best >= 2 and .optimizer.candidates >= 64 and .optimizer.screen.samples == 1024
         and .optimizer.seed == 0 and (.fixed | length) == 0 and (.stderr.alpha | type) == "number"
         and .data == $d and (.metrics | has("rmse_cos") and has("rmse_rel") and has("max_err") and has("aic") and has("bic"))' \
    --arg d "$tmp/w.csv" "$tmp/r.json" >/dev/null && ok || bad "result JSON: $(cat "$tmp/r.json")"
  ls "$tmp" | grep -q '\.tmp\.' && bad "temporary file left behind" || ok
  # The result is a parameter file: eval gives the generating model's values.
  if "$BRDFIT" eval --params "$tmp/r.json" --dirs "$DATA/dirs_small.csv" -o "$tmp/fit.csv" 2>"$tmp/err" &&
     "$BRDFIT" eval --params "$tmp/truth.json" --dirs "$DATA/dirs_small.csv" -o "$tmp/truth.csv" 2>>"$tmp/err"; then
    paste -d, "$tmp/fit.csv" "$tmp/truth.csv" | tail -n +2 | awk -F, '
      { for (c = 5; c <= 7; c++) { d = $c - $(c + 7); if (d < 0) d = -d; a = $(c + 7); if (a < 0) a = -a
          if (d > 1e-7 * (a + 1e-3)) { print "row " NR " column " c ": " $c " vs " $(c + 7); bad = 1 } } }
      END { exit bad }' && ok || bad "eval of the fitted parameters differs from the truth"
  else
    bad "eval with the result file failed: $(cat "$tmp/err")"
  fi
else
  bad "fit failed: $(cat "$tmp/err")"
fi

# Options: NLopt, --fix, --bound, linear residual, multistart with a seed.
if "$BRDFIT" fit "$tmp/w.csv" -m walter --backend nlopt --algorithm LD_LBFGS --fix f0=0.05 --bound alpha=0.05:0.3 \
     --residual linear --starts 3 --seed 9 --threads 1 -o "$tmp/r2.json" >/dev/null 2>"$tmp/err"; then
  jq -e '.params.f0 == 0.05 and .fixed == ["f0"] and .stderr.f0 == 0 and .metrics.k == 7 and .residual == "linear"
         and .optimizer.backend == "nlopt" and .optimizer.algorithm == "LD_LBFGS" and .optimizer.starts == 3
         and .optimizer.seed == 9 and .params.alpha >= 0.05 and .params.alpha <= 0.3' "$tmp/r2.json" >/dev/null \
    && ok || bad "nlopt/fix/bound result: $(cat "$tmp/r2.json")"
else
  bad "fit with options failed: $(cat "$tmp/err")"
fi

# Several models, options with commas: {"fits": [...]} in -m order.
if "$BRDFIT" fit "$tmp/w.csv" -m lambert,microfacet:D=beckmann,G=smith_beckmann -m phong -o "$tmp/many.json" \
     >"$tmp/out" 2>"$tmp/err"; then
  jq -e '[.fits[].model] == ["lambert", "microfacet", "phong"] and .fits[1].options.D == "beckmann"
         and .fits[1].options.G == "smith_beckmann" and all(.fits[]; .ok)
         and (.brdfit_version | startswith("0.")) and all(.fits[]; has("brdfit_version") | not)' "$tmp/many.json" >/dev/null \
    && ok || bad "several models: $(jq -c '[.fits[] | {model, options}]' "$tmp/many.json")"
  [ "$(grep -c '  ok$' "$tmp/out")" = 3 ] && ok || bad "three summaries expected: $(cat "$tmp/out")"
else
  bad "several models failed: $(cat "$tmp/err")"
fi

# A fit that cannot succeed (values whose squares overflow, linear residual): exit 1,
# one line, the result written with ok false and finite parameters.
printf 'theta_i,phi_i,theta_o,phi_o,value\n' > "$tmp/huge.csv"
for t in 10 20 30 40 50 60; do printf '%s,0,%s,180,1e300\n%s,90,20,10,1e300\n' $t $t $t >> "$tmp/huge.csv"; done
if "$BRDFIT" fit "$tmp/huge.csv" -m walter --residual linear -o "$tmp/failed.json" >/dev/null 2>"$tmp/err"; then
  bad "impossible fit: exit status 0"
else
  [ $? = 1 ] && ok || bad "impossible fit: exit status not 1"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q 'fit failed' "$tmp/err" && ok || bad "impossible fit stderr: $(cat "$tmp/err")"
  jq -e '.ok == false and .channels == 1 and ([.params[] | .. | numbers] | length) == 4' "$tmp/failed.json" >/dev/null \
    && ok || bad "impossible fit result: $(cat "$tmp/failed.json" 2>/dev/null)"
fi

# --- bad usage (exit 2) and bad data (exit 1): one line, no output file ----------------
expect_error() { # name, status, pattern, args...
  local name=$1 want=$2 pattern=$3
  shift 3
  rm -f "$tmp/o.json"
  "$BRDFIT" fit -o "$tmp/o.json" "$@" >/dev/null 2>"$tmp/err"
  local got=$?
  [ "$got" = "$want" ] || bad "$name: exit status $got, expected $want"
  [ -e "$tmp/o.json" ] && bad "$name: output file written"
  ls "$tmp" | grep -q 'o.json.tmp' && bad "$name: temporary file left"
  [ "$(wc -l < "$tmp/err")" = 1 ] || bad "$name: stderr is not one line: $(cat "$tmp/err")"
  grep -q -- "$pattern" "$tmp/err" && ok || bad "$name: message '$(cat "$tmp/err")' lacks '$pattern'"
}
W="$tmp/w.csv"
expect_error "no model" 2 '-m MODEL is required' "$W"
expect_error "no data" 2 'a data file is required' -m walter
expect_error "unknown model" 2 "unknown model 'nosuch'" "$W" -m walter,nosuch
expect_error "bad model option" 2 'option' "$W" -m walter:fresnel=glass
expect_error "unknown option" 2 "unknown option '--frobnicate'" "$W" -m walter --frobnicate
expect_error "bad residual" 2 '--residual' "$W" -m walter --residual square
expect_error "bad loss" 2 '--loss' "$W" -m walter --loss nosuch:1
expect_error "bad backend" 2 "--backend takes ceres or nlopt" "$W" -m walter --backend gsl
expect_error "bad starts" 2 '--starts needs an integer from 1 to' "$W" -m walter --starts 0
expect_error "bad threads" 2 '--threads needs an integer from 1 to' "$W" -m walter --threads two
expect_error "missing value" 2 '--fix needs a value' "$W" -m walter --fix
expect_error "bad fix" 2 'fix' "$W" -m walter --fix f0=abc
expect_error "unknown parameter" 2 'nosuch' "$W" -m walter --fix nosuch=1
expect_error "unknown algorithm" 2 'nosuch' "$W" -m walter --backend nlopt --algorithm nosuch
expect_error "two data files" 2 'one data file only' "$W" "$W" -m walter
expect_error "missing data file" 1 'nothere.csv: cannot open' "$tmp/nothere.csv" -m walter
printf 'theta_i,phi_i,theta_o,phi_o,value\n10,0,10,180,0.5\n20,0,abc,180,0.5\n' > "$tmp/badrow.csv"
expect_error "malformed data" 1 'badrow.csv:3' "$tmp/badrow.csv" -m walter
printf 'theta_i,phi_i,theta_o,phi_o,value\n95,0,10,180,0.5\n' > "$tmp/below.csv"
expect_error "no usable sample" 1 'below.csv' "$tmp/below.csv" -m walter
if "$BRDFIT" fit --help | grep -q -- '--residual'; then ok; else bad "fit --help"; fi

# --accuracy: presets fill only what was not given, whatever the order on the line.
"$SYNTH" --params "$tmp/truth.json" --pattern uniform --count 20000 --seed 6 -o "$tmp/big.csv" || bad "brdfit-synth (big)"
acc() { # ARGS... -> "samples starts backend" of the result
  "$BRDFIT" fit "$tmp/big.csv" -m walter --threads 2 -o "$tmp/acc.json" "$@" >/dev/null 2>"$tmp/err" &&
    jq -r '"\(.samples) \(.optimizer.starts) \(.optimizer.backend)"' "$tmp/acc.json"
}
[ "$(acc --accuracy fast)" = "16000 1 ceres" ] && ok || bad "fast: $(acc --accuracy fast) $(cat "$tmp/err")"
# Automatic starts: 8 on a screening set of 1024 samples (docs/fitting.md).
[ "$(acc --accuracy balanced)" = "20000 8 ceres" ] && ok || bad "balanced: $(acc --accuracy balanced)"
[ "$(acc --accuracy best)" = "20000 64 ceres" ] && ok || bad "best: $(acc --accuracy best)"
[ "$(acc)" = "20000 8 ceres" ] && ok || bad "no preset: $(acc)"
[ "$(acc --starts 3 --screen 0)" = "20000 3 ceres" ] && ok || bad "plain multistart: $(acc --starts 3 --screen 0)"
jq -e '.optimizer | has("screen") or has("candidates") | not' "$tmp/acc.json" >/dev/null && ok || bad "--screen 0 still screened"
[ "$(acc --subsample 5000 --accuracy fast --starts 2)" = "5000 2 ceres" ] && ok || bad "explicit before: $(acc --subsample 5000 --accuracy fast --starts 2)"
[ "$(acc --accuracy best --starts 3 --backend nlopt)" = "20000 3 nlopt" ] && ok || bad "explicit after: $(acc --accuracy best --starts 3 --backend nlopt)"
[ "$(acc --accuracy fast --subsample all)" = "20000 1 ceres" ] && ok || bad "--subsample all keeps all: $(acc --accuracy fast --subsample all)"
expect_error "bad accuracy" 2 "--accuracy takes fast, balanced or best, got 'quick'" "$W" -m walter --accuracy quick
expect_error "accuracy without value" 2 '--accuracy needs a value' "$W" -m walter --accuracy
"$BRDFIT" fit --help | grep -q -- '--accuracy fast|balanced|best' && ok || bad "fit --help lacks --accuracy"
"$BRDFIT" fit --help | grep -q -- 'fast: --subsample [0-9]* --backend ceres --starts 1' && ok || bad "fit --help lacks the fast preset"

# --presolve: the starts on a subsample, then all samples; the same optimum as without.
"$SYNTH" --params "$tmp/truth.json" --pattern uniform --count 20000 --noise 0.05 --seed 7 -o "$tmp/noisy.csv" ||
  bad "brdfit-synth (noisy)"
"$BRDFIT" fit "$tmp/noisy.csv" -m walter --presolve 3000 -o "$tmp/pre.json" >"$tmp/out" 2>"$tmp/err" &&
  jq -e '.optimizer.presolve.samples == 3000 and .optimizer.presolve.iterations > 0 and .samples == 20000' \
    "$tmp/pre.json" >/dev/null && grep -q 'presolved on 3000 samples' "$tmp/out" && ok ||
  bad "--presolve 3000: $(cat "$tmp/err") $(cat "$tmp/out")"
"$BRDFIT" fit "$tmp/noisy.csv" -m walter --presolve off -o "$tmp/nopre.json" >/dev/null 2>"$tmp/err" &&
  jq -e '(.optimizer | has("presolve") | not)' "$tmp/nopre.json" >/dev/null && ok || bad "--presolve off: $(cat "$tmp/err")"
jq -n --slurpfile a "$tmp/pre.json" --slurpfile b "$tmp/nopre.json" \
  '(($a[0].metrics.rmse_log - $b[0].metrics.rmse_log) | fabs) <= 1e-7 * $b[0].metrics.rmse_log and
   (($a[0].params.alpha - $b[0].params.alpha) | fabs) <= 1e-4 * $b[0].params.alpha' -e >/dev/null && ok ||
  bad "presolved and direct fits differ: $(jq -c '[.params.alpha, .metrics.rmse_log]' "$tmp/pre.json" "$tmp/nopre.json")"
"$BRDFIT" fit "$tmp/big.csv" -m walter -o "$tmp/auto.json" >/dev/null 2>&1 &&
  jq -e '(.optimizer | has("presolve") | not)' "$tmp/auto.json" >/dev/null && ok || bad "20000 samples should not presolve by default"
expect_error "bad presolve" 2 "--presolve needs a sample count of at least 64 or 'off', got '10'" "$W" -m walter --presolve 10
expect_error "presolve word" 2 "--presolve needs a sample count of at least 64 or 'off', got 'on'" "$W" -m walter --presolve on

finish
