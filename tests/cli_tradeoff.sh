#!/usr/bin/env bash
# brdfit tradeoff from the shell: a small synthetic Walter set, --samples 500,2000,all
# x two methods; exit 0, the JSON table (rows in ascending sample count, one "all" row
# per setting, the recommendation within tolerance and the fastest such), CSV rows, the
# plot's size; bad usage: exit 2, one line on stderr, no output file.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq; need iinfo openimageio-tools

cat > "$tmp/wal.json" <<'JSON'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 3,
 "params": {"rho_d": [0.3, 0.2, 0.1], "rho_s": [0.8, 0.8, 0.7], "alpha": 0.1, "f0": 0.05}}
JSON
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 3000 --noise 0.01 --seed 2 -o "$tmp/w.csv" ||
  bad "brdfit-synth failed"
W="$tmp/w.csv"

if "$BRDFIT" tradeoff "$W" -m walter --samples 2000,500,all,9999 --methods ceres,LD_LBFGS --starts-list 1,2 \
     --threads 2 --seed 3 --json "$tmp/t.json" --csv "$tmp/t.csv" --plot "$tmp/t.png" --plot-size 320x200 \
     >"$tmp/out" 2>"$tmp/err"; then
  ok
  # 3000 samples, 20% held out: 2400 train / 600 test; 500, 2000, all(2400) x 2 x 2 = 12 rows.
  jq -e --arg w "$W" '. as $t | $t.rows[$t.recommended] as $r | $t.rows[$t.best] as $b
      | .version == 2 and .cost == "work" and .timing == false and .data == $w and .model == "walter" and .samples == 3000
      and .train_samples == 2400 and .test_samples == 600 and .channels == 3 and .seed == 3
      and .error == "rmse_log" and .tolerance == 0.05 and (.rows | length) == 12
      and [.rows[].samples] == [500,500,500,500,2000,2000,2000,2000,2400,2400,2400,2400]
      and [.rows[].all] == [false,false,false,false,false,false,false,false,true,true,true,true]
      and [.rows[].method] == ["ceres","ceres","LD_LBFGS","LD_LBFGS","ceres","ceres","LD_LBFGS","LD_LBFGS",
                               "ceres","ceres","LD_LBFGS","LD_LBFGS"]
      and [.rows[].starts] == [1,2,1,2,1,2,1,2,1,2,1,2]
      and all(.rows[]; .ok and .status == "ok" and .residual == "log" and .test.n == 1800
                       and .error == .test.rmse_log and .work > 0 and (has("seconds") | not))
      and [.rows[].train.n] == [1500,1500,1500,1500,6000,6000,6000,6000,7200,7200,7200,7200]
      and ([.rows[] | select(.recommended)] | length) == 1
      and ([.rows[] | select(.best)] | length) == 1
      and $r.recommended and $r.within_tolerance and $b.best
      and $r.error <= $b.error * 1.05
      and ([.rows[] | select(.within_tolerance and .work < $r.work)] | length) == 0
      and ([.rows[] | select(.error < $b.error)] | length) == 0
      and $b.on_front and $r.on_front
      and all(.rows[]; .test.rmse_log < 0.05)' "$tmp/t.json" >/dev/null \
    && ok || bad "JSON: $(jq -c '[.rows[] | {samples, method, starts, error, work}]' "$tmp/t.json")"
  # CSV: a header and 12 rows, sample counts never decreasing.
  [ "$(wc -l < "$tmp/t.csv")" = 13 ] && ok || bad "CSV lines: $(wc -l < "$tmp/t.csv")"
  awk -F, 'NR == 1 { ok = $1 == "samples" && $3 == "method"; next }
           { if ($1 + 0 < last) ok = 0; last = $1 + 0; if ($6 != "ok") ok = 0 }
           END { exit !ok }' "$tmp/t.csv" && ok || bad "CSV rows: $(cat "$tmp/t.csv")"
  # The plot: the size asked for (its text: cli_plots.sh).
  iinfo "$tmp/t.png" | grep -q '320 x  *200' && ok || bad "plot: $(iinfo "$tmp/t.png")"
  # Terminal table: 12 rows and the recommendation as brdfit fit options.
  [ "$(grep -c '^ *[0-9][0-9]* *\(500\|2000\|all\) ' "$tmp/out")" = 12 ] && ok || bad "table: $(cat "$tmp/out")"
  grep -q '^recommended: #[0-9]* .*brdfit fit .* -m walter .*--residual log --starts [12]$' "$tmp/out" && ok \
    || bad "recommendation line: $(tail -1 "$tmp/out")"
  grep -q "^plot $tmp/t.png: test rmse_log (y, log axis, .*) against fitting work (x, log axis, sample evaluations, .*); Pareto front labelled #N$" "$tmp/out" && ok \
    || bad "plot caption: $(cat "$tmp/out")"
  [ "$(grep -c '^brdfit tradeoff: [0-9]*/12 ' "$tmp/err")" = 12 ] && ok || bad "progress: $(cat "$tmp/err")"
else
  bad "tradeoff failed: $(cat "$tmp/err")"
fi

# Same seed, same bytes whatever the threads (no wall time is written); --quiet prints
# no progress; --timing adds the seconds and changes nothing else; --cost seconds.
if "$BRDFIT" tradeoff "$W" -m walter --samples 500,all --methods ceres,LD_LBFGS --threads 1 --seed 3 --quiet \
     --json "$tmp/a.json" --csv "$tmp/a.csv" 2>"$tmp/err" >"$tmp/a.out" &&
   "$BRDFIT" tradeoff "$W" -m walter --samples 500,all --methods ceres,LD_LBFGS --threads 2 --seed 3 --quiet \
     --json "$tmp/b.json" --csv "$tmp/b.csv" 2>>"$tmp/err" >"$tmp/b.out"; then
  # (the recommended command line repeats --threads as given)
  cmp -s "$tmp/a.json" "$tmp/b.json" && cmp -s "$tmp/a.csv" "$tmp/b.csv" &&
    [ "$(sed 's/--threads [12]//' "$tmp/a.out")" = "$(sed 's/--threads [12]//' "$tmp/b.out")" ] && ok \
    || bad "same seed, different outputs for 1 and 2 threads"
  [ -s "$tmp/err" ] && bad "--quiet printed: $(cat "$tmp/err")" || ok
else
  bad "seeded runs failed: $(cat "$tmp/err")"
fi
if "$BRDFIT" tradeoff "$W" -m walter --samples 500,all --methods ceres,LD_LBFGS --threads 1 --seed 3 --quiet \
     --timing --json "$tmp/c.json" --csv "$tmp/c.csv" >"$tmp/c.out" 2>&1; then
  jq -e '.timing and all(.rows[]; .seconds >= 0)' "$tmp/c.json" >/dev/null &&
    [ "$(jq -cS 'del(.timing, .rows[].seconds)' "$tmp/c.json")" = "$(jq -cS 'del(.timing)' "$tmp/a.json")" ] &&
    head -1 "$tmp/c.csv" | grep -q ',seconds$' && grep -q 'time s' "$tmp/c.out" && ok || bad "--timing"
else
  bad "--timing run failed: $(cat "$tmp/c.out")"
fi
"$BRDFIT" tradeoff "$W" -m walter --samples 500,all --methods ceres --seed 3 --quiet --cost seconds \
  --json "$tmp/d.json" >"$tmp/d.out" 2>&1 && jq -e '.cost == "seconds" and .timing and all(.rows[]; .seconds >= 0)' \
  "$tmp/d.json" >/dev/null && grep -q '^recommended: #[0-9]* (rmse_log .* for [0-9.]* s;' "$tmp/d.out" && ok ||
  bad "--cost seconds: $(cat "$tmp/d.out")"

# Bad usage: exit 2, one line naming the problem, no output file.
expect_error() {
  local name=$1 want=$2 pattern=$3
  shift 3
  rm -f "$tmp"/o.*
  "$BRDFIT" tradeoff "$@" --json "$tmp/o.json" --csv "$tmp/o.csv" --plot "$tmp/o.png" >"$tmp/out" 2>"$tmp/err"
  local got=$?
  [ "$got" = "$want" ] || bad "$name: exit status $got, expected $want"
  ls "$tmp" | grep -q '^o\.' && bad "$name: output file written"
  [ "$(wc -l < "$tmp/err")" = 1 ] || bad "$name: stderr is not one line: $(cat "$tmp/err")"
  grep -q -- "$pattern" "$tmp/err" && ok || bad "$name: message '$(cat "$tmp/err")' lacks '$pattern'"
}
expect_error "no model" 2 '-m MODEL is required' "$W"
expect_error "two models" 2 '-m takes one model' "$W" -m walter,lambert
expect_error "unknown model" 2 "unknown model 'nosuch'" "$W" -m nosuch
expect_error "bad cost" 2 "--cost needs work or seconds" "$W" -m walter --cost time
expect_error "bad samples" 2 "--samples: 'lots'" "$W" -m walter --samples 500,lots
expect_error "zero samples" 2 "--samples: '0'" "$W" -m walter --samples 0
expect_error "empty item" 2 '--samples: empty item' "$W" -m walter --samples 500,,all
expect_error "bad method" 2 '--methods: unknown method "LD_NOPE"' "$W" -m walter --methods ceres,LD_NOPE
expect_error "bad residual" 2 '--residuals' "$W" -m walter --residuals log,square
expect_error "bad starts" 2 "--starts-list: 'x'" "$W" -m walter --starts-list 1,x
expect_error "bad fraction" 2 '--test-fraction' "$W" -m walter --test-fraction 1
expect_error "bad repeats" 2 '--repeats' "$W" -m walter --repeats 0
expect_error "bad tolerance" 2 '--tolerance' "$W" -m walter --tolerance -1
expect_error "bad error" 2 '--error' "$W" -m walter --error mse
expect_error "bad plot size" 2 '--plot-size' "$W" -m walter --plot-size 10x10
expect_error "unknown option" 2 "unknown option '--frobnicate'" "$W" -m walter --frobnicate
expect_error "missing data" 1 'nothere.csv' "$tmp/nothere.csv" -m walter
# A plot name the image writer cannot take.
rm -f "$tmp"/o.*
"$BRDFIT" tradeoff "$W" -m walter --plot "$tmp/o.gif" >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q '.png, .svg or .pdf' "$tmp/err" && [ ! -e "$tmp/o.gif" ] && ok || bad "plot extension: $(cat "$tmp/err")"
"$BRDFIT" tradeoff --help | grep -q -- '--starts-list' && ok || bad "tradeoff --help"

finish
