#!/usr/bin/env bash
# brdfit's default fit against the literature's published fit of the same family, on
# MERL-size tables (docs/published.md).
#
#   bench/published_check.sh [-n N] [--truth TABLE] [--noise S] [BUILD_DIR] [TABLE...]
#
# For each table of data/published/brdfit (default: all) and N of its materials spread
# over the alphabet (default 5), a MERL table is made with brdfit-synth from a published
# fit (the same table's, or --truth TABLE's fit of the same material, a different model),
# with noise S (default 0.02, seed 0), and `brdfit compare --reference` fits the table's
# model by default and evaluates the published fit in the same metric. With the table's
# own fit as the truth the published parameters are the noise-free optimum, so brdfit's
# objective must not be above theirs; with another model as the truth the published fit
# is just a good point of the family. Prints one line per case and the count where
# brdfit's fit is worse (the search missed) with the worst ratio; exits 1 if any is.
set -euo pipefail
cd "$(dirname "$0")/.."
n=5 truth="" noise=0.02
while [ $# -gt 0 ]; do
  case $1 in
  -n) n=$2; shift 2 ;;
  --truth) truth=$2; shift 2 ;;
  --noise) noise=$2; shift 2 ;;
  *) break ;;
  esac
done
build=${1:-build}
[ $# -gt 0 ] && shift
brdfit=$build/cmd/brdfit
synth=$build/data_synth/brdfit-synth
for f in "$brdfit" "$synth"; do
  [ -x "$f" ] || { echo "$0: $f: not found (build first)" >&2; exit 1; }
done
command -v jq >/dev/null || { echo "$0: jq is missing: install the Debian package jq" >&2; exit 1; }
tables=("$@")
[ ${#tables[@]} -gt 0 ] || mapfile -t tables < <(ls data/published/brdfit | sed 's/\.json$//')
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

worse=0 cases=0 worst=0
printf '%-28s %-26s %14s %14s %8s %6s\n' table material brdfit published ratio wall
for t in "${tables[@]}"; do
  ref=data/published/brdfit/$t.json
  src=data/published/brdfit/${truth:-$t}.json
  mapfile -t mats < <(jq -r --slurpfile s "$src" '.materials | keys[] as $k | select($s[0].materials[$k]) | $k' "$ref")
  step=$(( (${#mats[@]} + n - 1) / n ))
  for ((i = 0; i < ${#mats[@]}; i += step)); do
    mat=${mats[$i]}
    jq --arg m "$mat" '.materials[$m]' "$src" >"$tmp/truth.json"
    spec=$(jq -r --arg m "$mat" '.materials[$m].model' "$ref")
    mkdir -p "$tmp/$t"
    if ! "$synth" --params "$tmp/truth.json" --pattern merl --noise "$noise" --seed 0 -q -o "$tmp/$t/$mat.binary" 2>"$tmp/err"; then
      printf '%-28s %-26s %s\n' "$t" "$mat" "(not made: $(tail -n 1 "$tmp/err"))"
      continue
    fi
    t0=$(date +%s.%N)
    "$brdfit" compare "$tmp/$t/$mat.binary" -m "$spec" --reference "$ref" -q --json "$tmp/r.json" >/dev/null 2>"$tmp/err" ||
      { echo "$0: $t $mat: $(tail -n 1 "$tmp/err")" >&2; exit 1; }
    wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
    read -r own pub < <(jq -r '.materials[0].fits[0] | "\(.references[0].brdfit_cost) \(.references[0].cost)"' "$tmp/r.json")
    ratio=$(awk -v a="$own" -v b="$pub" 'BEGIN { printf "%.4f", a / b }')
    cases=$((cases + 1))
    if awk -v a="$own" -v b="$pub" 'BEGIN { exit !(a > b * (1 + 1e-9)) }'; then
      worse=$((worse + 1))
      flag=" WORSE"
    else
      flag=""
    fi
    awk -v r="$ratio" -v w="$worst" 'BEGIN { exit !(r > w) }' && worst=$ratio
    printf '%-28s %-26s %14.6g %14.6g %8s %6s%s\n' "$t" "$mat" "$own" "$pub" "$ratio" "$wall" "$flag"
    rm -f "$tmp/$t/$mat.binary"
  done
done
echo "$cases cases, brdfit worse than the published fit in $worse (largest ratio brdfit/published $worst)"
[ "$worse" -eq 0 ]
