#!/usr/bin/env bash
# Whole-process figures of brdfit fit-images on a DiLiGenT-sized shiny sphere: a 160 x 160
# stack of 96 16-bit PNG images (16,292 masked pixels, the lights of DiLiGenT's layout,
# Cook-Torrance data with 0.5% noise and saturated highlights, made once by the test tool
# make_stack), fitted with walter (normals fitted) on every core and on one, and with
# lambert as the reference of the same run. Prints the best wall time of REPEATS runs and
# its peak memory, and the ratios to the reference (the machines are noisy: compare the
# rows of one run).
#
#   bench/bench_fit_images.sh [BUILD_DIR] [REPEATS]      (default: build, 3)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
repeats=${2:-3}
brdfit=$build/cmd/brdfit
make_stack=$build/tests/make_stack
for f in "$brdfit" "$make_stack" /usr/bin/time; do
  [ -x "$f" ] || { echo "$0: $f: not found (build first; /usr/bin/time is Debian's 'time')" >&2; exit 1; }
done
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$make_stack" --model cook_torrance --params 'rho_d=0.35:0.3:0.25,rho_s=0.9:0.9:0.9,m=0.08,f0=0.05' \
  --shape sphere --size 160 --lights diligent96 --intensities random --noise 0.005 --gain 1.6 -o "$tmp/ball" >/dev/null

best=()
measure() { # LABEL ARGS...
  local label=$1 b="" mem="" t m
  shift
  for _ in $(seq "$repeats"); do
    rm -rf "$tmp/out"
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$brdfit" fit-images "$tmp/ball" -o "$tmp/out" -q "$@" 2>"$tmp/err" ||
      { echo "$0: $label failed: $(tail -1 "$tmp/err")" >&2; exit 1; }
    read -r t m < "$tmp/time"
    if [ -z "$b" ] || awk -v a="$t" -v c="$b" 'BEGIN { exit !(a < c) }'; then b=$t mem=$m; fi
  done
  best+=("$b")
  printf '%-44s %7s s %8.1f MB\n' "$label" "$b" "$(awk -v k="$mem" 'BEGIN { print k / 1024 }')"
}
echo "machine: $(nproc) cores; stack: 160 x 160, 96 images, 16,292 pixels"
measure "lambert (reference), every core" -m lambert
measure "walter, normals fitted, every core" -m walter
measure "walter, normals fitted, 1 thread" -m walter --threads 1
awk -v r="${best[0]}" -v a="${best[1]}" -v b="${best[2]}" \
  'BEGIN { printf "ratios to lambert: walter %.2f, walter on 1 thread %.2f; 1 thread / every core %.2f\n", a / r, b / r, b / a }'
