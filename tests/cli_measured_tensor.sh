#!/usr/bin/env bash
# RGL-EPFL .bsdf and NVIDIA .mbsdf files from the command line: info and a walter fit of
# each bundled real file converge with a finite error, the format comes from the
# extension, the content or --format, --grid picks the directions, --negative applies,
# and hostile files give one line naming the file, exit 1, no output and no signal.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
EX=$(dirname "$0")/../examples
RGL=("$EX/rgl/paper_white_rgb.bsdf" "$EX/rgl/cc_ibiza_sunset_rgb.bsdf")
MDL=$EX/mdl/carpaint_red.mbsdf

# --- info and fit on the real files ---------------------------------------------------------
for f in "${RGL[@]}" "$MDL"; do
  "$BRDFIT" info "$f" > "$tmp/info" 2>&1 && grep -q "channels: 3 (r, g, b)" "$tmp/info" && ok ||
    bad "info $f: $(head -3 "$tmp/info")"
  "$BRDFIT" fit "$f" -m walter -o "$tmp/fit.json" > "$tmp/fit" 2>&1 || bad "fit $f failed: $(tail -3 "$tmp/fit")"
  grep -q "CONVERGENCE" "$tmp/fit" && ok || bad "fit $f did not converge: $(cat "$tmp/fit")"
  awk '/rmse/ { for (i = 1; i <= NF; i++) if ($i == "rmse") { v = $(i + 1); exit } } END { exit !(v + 0 > 0 && v + 0 < 1e6) }' \
    "$tmp/fit" && ok || bad "fit $f: rmse not finite: $(grep rmse "$tmp/fit")"
done
"$BRDFIT" info "${RGL[0]}" | grep -q "7118 samples read" && ok || bad "paper: 7118 measured points"
"$BRDFIT" info "$MDL" | grep -q "182250 samples read" && ok || bad "car paint: 45 x 45 x 90 cells"

# --- format by content and by name ----------------------------------------------------------
cp "${RGL[0]}" "$tmp/paper.dat"
cp "$MDL" "$tmp/paint.dat"
"$BRDFIT" info "$tmp/paper.dat" | grep -q "7118 samples read" && ok || bad "RGL by content"
"$BRDFIT" info "$tmp/paint.dat" | grep -q "182250 samples read" && ok || bad "mbsdf by content"
"$BRDFIT" info "$tmp/paper.dat" --format rgl | grep -q "7118 samples read" && ok || bad "--format rgl"
"$BRDFIT" info "$tmp/paint.dat" --format mbsdf | grep -q "182250 samples read" && ok || bad "--format mbsdf"

# --- --grid and --negative ------------------------------------------------------------------
"$BRDFIT" info "${RGL[1]}" --grid uniform:4 | grep -q "64 samples read" && ok || bad "--grid uniform:4"
"$BRDFIT" info "$MDL" --grid uniform:3 | grep -q "27 samples read" && ok || bad "mbsdf --grid uniform:3"
printf 'theta_i,phi_i,theta_o,phi_o\n30,0,30,180\n30,0,30,90\n' > "$tmp/dirs.csv"
"$BRDFIT" convert "${RGL[1]}" "$tmp/g.csv" --grid "$tmp/dirs.csv" >/dev/null 2>&1 &&
  awk -F, 'NR == 2 { m = $5 } NR == 3 { s = $5 } END { exit !(m > 20 * s && s > 0) }' "$tmp/g.csv" && ok ||
  bad "--grid FILE: the film's highlight above its side"
"$BRDFIT" info "$MDL" --negative drop | grep -q "182250 samples read, 134012 used" && ok || bad "--negative drop"

# --- errors: one line, exit 1 (usage 2), no output --------------------------------------------
expect_fail() { # name want-rc pattern command...
  local name=$1 want=$2 pat=$3
  shift 3
  "$@" > /dev/null 2> "$tmp/err"
  local rc=$?
  if [ "$rc" = "$want" ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$pat" "$tmp/err" && [ ! -e "$tmp/out.csv" ]; then
    ok
  else
    bad "$name: exit $rc, $(cat -v "$tmp/err")"
  fi
}
expect_fail "grid on CSV" 1 "needs a format that can be evaluated anywhere" "$BRDFIT" convert "$tmp/dirs.csv" "$tmp/out.csv" --grid uniform:2
expect_fail "bad grid" 1 "uniform:N needs N from 1 to 128" "$BRDFIT" convert "${RGL[0]}" "$tmp/out.csv" --grid uniform:0
expect_fail "unknown format" 2 "unknown format 'tensor' (csv, merl, cornell, alta, rgl, mbsdf)" "$BRDFIT" info "${RGL[0]}" --format tensor
head -c 300 "${RGL[0]}" > "$tmp/cut.bsdf"
expect_fail "truncated RGL" 1 "cut.bsdf: byte offset" "$BRDFIT" fit "$tmp/cut.bsdf" -m walter -o "$tmp/out.csv"
head -c 100000 "$MDL" > "$tmp/cut.mbsdf"
expect_fail "truncated mbsdf" 1 "cut.mbsdf: truncated: the reflection table" "$BRDFIT" convert "$tmp/cut.mbsdf" "$tmp/out.csv"
{ printf 'tensor_file\0\1\0'; head -c 64 /dev/urandom; } > "$tmp/junk.bsdf"
expect_fail "junk RGL" 1 "junk.bsdf" "$BRDFIT" info "$tmp/junk.bsdf"
{ printf 'NVIDIA ARC MBSDF V1\nMBSDF_DATA_REFLECTION=\n\1\0\0\0\2\0\0\0\2\0\0\0'; head -c 96 /dev/zero | tr '\0' '\377'; } > "$tmp/nan.mbsdf"
expect_fail "NaN mbsdf" 1 "nan.mbsdf: byte offset 55: reflection value 0 is NaN" "$BRDFIT" info "$tmp/nan.mbsdf"
finish
