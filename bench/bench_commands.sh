#!/usr/bin/env bash
# Whole-process figures of the brdfit command on a full synthetic MERL table: wall time
# and peak memory (/usr/bin/time) of start-up, reading, fitting, comparing and
# selecting, as a user sees them. Prints one row per command, the best wall time of
# REPEATS runs (the machines are noisy: compare rows of one run, not runs of two days).
#
#   bench/bench_commands.sh [BUILD_DIR] [REPEATS]      (default: build, 3)
#
# The table is generated once into a temporary folder by brdfit-synth (walter with
# examples/walter_rgb.json, 2% relative noise, seed 0): 1,096,216 cells x RGB, 35 MB.
# Slow rows (compare, select) run once whatever REPEATS says.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
repeats=${2:-3}
brdfit=$build/cmd/brdfit
synth=$build/data_synth/brdfit-synth
for f in "$brdfit" "$synth" /usr/bin/time; do
  [ -x "$f" ] || { echo "$0: $f: not found (build first; /usr/bin/time is Debian's 'time')" >&2; exit 1; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
table=$tmp/walter.binary
"$synth" --params examples/walter_rgb.json --pattern merl --noise 0.02 -o "$table"

# Best wall time and the peak memory of that run, over N runs of a command.
measure() { # N LABEL COMMAND...
  local n=$1 label=$2 best="" mem="" t m
  shift 2
  for _ in $(seq "$n"); do
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$@" >/dev/null 2>"$tmp/err" ||
      { echo "$0: $label failed: $(tail -1 "$tmp/err")" >&2; exit 1; }
    read -r t m < "$tmp/time"
    if [ -z "$best" ] || awk -v a="$t" -v b="$best" 'BEGIN { exit !(a < b) }'; then best=$t mem=$m; fi
  done
  printf '%-58s %8s s %8.1f MB\n' "$label" "$best" "$(awk -v k="$mem" 'BEGIN { print k / 1024 }')"
}

ten=lambert,oren_nayar,blinn_phong,ward_iso,cook_torrance,walter,ashikhmin_shirley_iso,lafortune,walter:lobes=2,disney
echo "machine: $(nproc) cores, $(awk '/MemTotal/ { printf "%.0f GiB", $2 / 1048576 }' /proc/meminfo); table: $table"
printf '%-58s %10s %11s\n' "command" "wall" "peak"
measure "$repeats" "brdfit models" "$brdfit" models
measure "$repeats" "brdfit fit --help" "$brdfit" fit --help
measure "$repeats" "brdfit info walter.binary" "$brdfit" info "$table"
measure "$repeats" "brdfit fit walter.binary -m walter" "$brdfit" fit "$table" -m walter
measure "$repeats" "brdfit fit walter.binary -m walter --threads 1" "$brdfit" fit "$table" -m walter --threads 1
measure "$repeats" "brdfit fit walter.binary -m walter --presolve off" "$brdfit" fit "$table" -m walter --presolve off
measure "$repeats" "brdfit fit walter.binary -m lambert" "$brdfit" fit "$table" -m lambert
for m in oren_nayar blinn_phong ward_iso cook_torrance ashikhmin_shirley_iso lafortune ward walter_aniso \
         ashikhmin_shirley cook_torrance:lobes=2 walter:lobes=2 disney; do
  measure 1 "brdfit fit walter.binary -m $m" "$brdfit" fit "$table" -m "$m"
done
measure 1 "brdfit compare walter.binary -m (10 models)" "$brdfit" compare "$table" -m "$ten" --quiet
measure 1 "brdfit select walter.binary (24 candidates)" "$brdfit" select "$table" --quiet
