#!/usr/bin/env bash
# The best-known optimum of every bundled real measurement (and the synthetic MERL table)
# for the ten models of the speed benchmarks, found by exhaustive search, and the gap and
# cost of brdfit's default fit against it (docs/fitting.md).
#
#   bench/best_known.sh [--models LIST] [BUILD_DIR] [OUT.json]
#                                        (default: build, bench/best_known.json)
#
# With --models only those models are searched, and their cases replace theirs in OUT.json
# (the others are kept, and new models join its list): for a new family, or a family whose
# bounds changed, without the whole search again.
#
# For each material the ten models are fitted (brdfit compare, log residual, seed 0) by:
#   starts256  --starts 256 --screen 0: the data-driven start and 255 random ones, each
#              solved on the data (or its presolve subsample);
#   best       --accuracy best's search: --starts 64 --screen 512 --max-iterations 500;
#   mlsl       NLopt's G_MLSL_LDS with LD_LBFGS, 20,000 evaluations (data sets below the
#              presolve size only: on a full MERL table each evaluation is a pass over
#              3.3 M residuals);
#   default    brdfit's defaults.
# The best rmse_log of all goes into OUT.json with what found it; tests/cli_optimum.sh
# holds the default to it. Then a table: per material and model, the best-known
# rmse_log, the default's, its gap in percent, and the default's fitting work (millions
# of sample evaluations, deterministic) against the one-start fit's (--accuracy fast
# without its subsample: --starts 1 --screen 0). Takes about 40 minutes on two cores.
set -euo pipefail
cd "$(dirname "$0")/.."
only=""
if [ "${1:-}" = --models ]; then
  only=$2
  shift 2
fi
build=${1:-build}
out=${2:-bench/best_known.json}
brdfit=$build/cmd/brdfit
synth=$build/data_synth/brdfit-synth
for f in "$brdfit" "$synth"; do
  [ -x "$f" ] || { echo "$0: $f: not found (build first)" >&2; exit 1; }
done
command -v jq >/dev/null || { echo "$0: jq is missing: install the Debian package jq" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
models=lambert,oren_nayar,blinn_phong,ward_iso,cook_torrance,walter,ashikhmin_shirley_iso,lafortune,walter:lobes=2,disney
models=$models,student_t,low_smooth,he
all=$models
[ -z "$only" ] || models=$only
"$synth" --params examples/walter_rgb.json --pattern merl --noise 0.02 -o "$tmp/merl.binary"

# name|data|options (the options split on spaces)
materials=(
  "cayman|examples/cornell/cayman.brdf|--rgb"
  "garnet_red|examples/cornell/garnet_red.brdf|--rgb"
  "paper_white|examples/rgl/paper_white_rgb.bsdf|"
  "cc_ibiza_sunset|examples/rgl/cc_ibiza_sunset_rgb.bsdf|"
  "carpaint_red|examples/mdl/carpaint_red.mbsdf|"
  "pink_felt|tests/data/alta/pink-felt-1d.alta|"
  "ptfe|tests/data/nist_ptfe/PTFE.data.random.csv|--angles thetai,phi,thetar,phir --values f_r11"
  "merl_walter|MERL|"
)

# compare NAME DATA TAG OPTIONS...: the fits' rmse_log and work as "model rmse_log work"
# lines in $tmp/NAME.TAG.
compare() {
  local name=$1 data=$2 tag=$3
  shift 3
  "$brdfit" compare "$data" -m "$models" --quiet --json "$tmp/$name.$tag.json" "$@" >/dev/null 2>"$tmp/err" ||
    { echo "$0: $name $tag: $(tail -n 1 "$tmp/err")" >&2; exit 1; }
  jq -r '.materials[0].fits[] | "\(.model) \(.rmse_log) \(.work)"' "$tmp/$name.$tag.json" >"$tmp/$name.$tag"
}

entries=()
printf '%-16s %-24s %12s %12s %8s %9s %9s\n' material model best-known default gap% work-M one-start-M
for m in "${materials[@]}"; do
  IFS='|' read -r name data opts <<<"$m"
  [ "$data" = MERL ] && data=$tmp/merl.binary
  read -r -a o <<<"$opts"
  t0=$(date +%s)
  compare "$name" "$data" default "${o[@]}"
  compare "$name" "$data" one "${o[@]}" --starts 1 --screen 0
  compare "$name" "$data" starts256 "${o[@]}" --starts 256 --screen 0
  compare "$name" "$data" best "${o[@]}" --starts 64 --screen 512 --max-iterations 500
  tags="default one starts256 best"
  if [ "$(jq '.materials[0].samples' "$tmp/$name.default.json")" -lt 131072 ]; then
    compare "$name" "$data" mlsl "${o[@]}" --backend nlopt --algorithm G_MLSL_LDS --local LD_LBFGS
    tags="$tags mlsl"
  fi
  echo "($name: $(($(date +%s) - t0)) s)" >&2
  while read -r model def work; do
    best="" by=""
    for tag in $tags; do
      v=$(awk -v m="$model" '$1 == m { print $2 }' "$tmp/$name.$tag")
      if [ -n "$v" ] && [ "$v" != null ] && { [ -z "$best" ] || awk -v a="$v" -v b="$best" 'BEGIN { exit !(a < b) }'; }; then
        best=$v by=$tag
      fi
    done
    one=$(awk -v m="$model" '$1 == m { print $3 }' "$tmp/$name.one")
    printf '%-16s %-24s %12.6g %12.6g %8.2f %9.3f %9.3f\n' "$name" "$model" "$best" "$def" \
      "$(awk -v a="$def" -v b="$best" 'BEGIN { print 100 * (a - b) / b }')" \
      "$(awk -v w="$work" 'BEGIN { print w / 1e6 }')" "$(awk -v w="$one" 'BEGIN { print w / 1e6 }')"
    entries+=("$(jq -cn --arg mat "$name" --arg model "$model" --argjson v "$best" --arg by "$by" \
      '{material: $mat, model: $model, rmse_log: $v, found_by: $by}')")
  done <"$tmp/$name.default"
done

{
  jq -n --arg models "$all" --arg version "$("$brdfit" --version)" \
    '{comment: "Best-known rmse_log of each bundled measurement and model (the lowest of exhaustive searches). Regenerate: bench/best_known.sh [--models LIST] [BUILD_DIR] [OUT.json]; tests/cli_optimum.sh holds brdfit'"'"'s default within 0.5% of it.",
      brdfit_version: $version, models: ($models | split(",")), cases: []}'
} >"$tmp/head.json"
printf '%s\n' "${entries[@]}" >"$tmp/new.jsonl"
if [ -n "$only" ]; then
  # Keep the other models' cases; this run's replace theirs; cases in the list's order.
  [ -f "$out" ] || { echo "$0: --models needs an existing $out" >&2; exit 1; }
  jq -s --slurpfile old "$out" --arg only "$only" '($only | split(",")) as $o
      | [$old[0].cases[] | select(.model as $m | $o | index($m) | not)] + . ' "$tmp/new.jsonl" >"$tmp/cases.json"
else
  jq -s . "$tmp/new.jsonl" >"$tmp/cases.json"
fi
mats=$(printf '%s\n' "${materials[@]}" | cut -d'|' -f1 | paste -sd,)
jq --slurpfile h "$tmp/head.json" --arg mats "$mats" '($mats | split(",")) as $mo | $h[0].models as $ms
    | $h[0] + {cases: sort_by([(.material as $x | $mo | index($x)), (.model as $x | $ms | index($x))])}' \
  "$tmp/cases.json" >"$tmp/out.json"
mv "$tmp/out.json" "$out"
echo "wrote $out"
