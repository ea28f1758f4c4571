#!/usr/bin/env bash
# Strict option values and consistent exit codes: absurd counts, signs and spaces in
# integers, --subsample 0, conflicting --fix/--bound of one parameter and bounds outside
# a model's range are usage errors (exit 2, one line naming the option, nothing written,
# no data read); a render size the machine could not hold is refused.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"

"$SYNTH" --params "$DATA/lambert_rgb.json" --pattern uniform --count 200 --seed 1 -o "$tmp/d.csv" 2>/dev/null ||
  bad "brdfit-synth failed"

usage() { # what, fragment, command args...
  local what=$1 fragment=$2
  shift 2
  rm -f "$tmp/o.json"
  "$BRDFIT" "$@" >/dev/null 2>"$tmp/err"
  local st=$?
  [ $st = 2 ] && ok || bad "$what: exit status $st, expected 2 ($(cat "$tmp/err"))"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -qF -- "$fragment" "$tmp/err" && ok ||
    bad "$what: stderr: $(cat "$tmp/err")"
  [ -e "$tmp/o.json" ] && bad "$what: output written" || ok
}
F=(fit "$tmp/d.csv" -m walter -o "$tmp/o.json")
usage "--threads huge" "--threads needs an integer from 1 to 1024" "${F[@]}" --threads 100000000
usage "--starts huge" "--starts needs an integer from 1 to 10000" "${F[@]}" --starts 100000000
usage "--starts with a space" "got ' 5'" "${F[@]}" --starts ' 5'
usage "--starts with a sign" "got '+5'" "${F[@]}" --starts +5
usage "--max-iterations 0" "--max-iterations needs an integer" "${F[@]}" --max-iterations 0
usage "--subsample 0" "--subsample needs a sample count of at least 1" "${F[@]}" --subsample 0
usage "--subsample -3" "--subsample needs a sample count" "${F[@]}" --subsample -3
usage "--seed with a sign" "--seed needs an integer" "${F[@]}" --seed +1
usage "--presolve 10" "--presolve needs a sample count of at least 64" "${F[@]}" --presolve 10
usage "fix and bound" "fix alpha and bound alpha both set alpha" "${F[@]}" --fix alpha=0.1 --bound alpha=0.2:0.3
usage "two fixes" "both set alpha" "${F[@]}" --fix alpha=0.1 --fix alpha=0.2
usage "fix all and one channel" "both set rho_d[1]" "${F[@]}" --fix rho_d=0.1 --bound 'rho_d[1]=0.2:0.3'
usage "bound outside the model" "outside the model's bounds" "${F[@]}" --bound alpha=0.2:3
usage "fix outside the model" "outside the model's bounds" "${F[@]}" --fix f0=2
usage "unknown parameter" "has no parameter 'beta'" "${F[@]}" --fix beta=1
usage "lo > hi" "is not below upper bound" "${F[@]}" --bound alpha=0.3:0.2
usage "max-theta 0" "--max-theta" "${F[@]}" --max-theta 0
usage "compare --jobs space" "--jobs needs an integer" compare "$tmp/d.csv" -m lambert --jobs ' 2' --json "$tmp/o.json"
usage "compare --tolerance junk" "--tolerance needs a number" compare "$tmp/d.csv" -m lambert --tolerance 0.1x --json "$tmp/o.json"
usage "compare --folds sign" "--folds needs an integer" compare "$tmp/d.csv" -m lambert --rank cv --folds +3 --json "$tmp/o.json"
usage "select --tolerance space" "--tolerance needs a number" select "$tmp/d.csv" -m lambert --tolerance ' 1' --json "$tmp/o.json"
usage "tradeoff --plot-size sign" "--plot-size needs WxH" tradeoff "$tmp/d.csv" -m lambert --plot-size +40x40 --json "$tmp/o.json"
usage "tradeoff --samples sign" "--samples" tradeoff "$tmp/d.csv" -m lambert --samples +100 --json "$tmp/o.json"
usage "render --size too big" "bad value '16385' for --size" render --params "$DATA/lambert_rgb.json" --size 16385 -o "$tmp/o.png"
usage "render --size sign" "bad value '+64' for --size" render --params "$DATA/lambert_rgb.json" --size +64 -o "$tmp/o.png"

# The limits themselves are accepted.
"$BRDFIT" fit "$tmp/d.csv" -m lambert --threads 1024 --starts 3 --subsample 1 --seed 18446744073709551615 \
  -o "$tmp/o.json" >/dev/null 2>&1 && ok || bad "limits refused"

finish
