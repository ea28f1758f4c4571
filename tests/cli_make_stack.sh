#!/usr/bin/env bash
# make_stack (tests/make_stack.c), the synthetic photometric-stereo stacks the fit-images
# tests read: a 32 x 32 Lambert sphere in both layouts of docs/images.md has every file,
# 16-bit PNGs (DiLiGenT) or float EXRs (JSON), pixels equal to E rho_d / pi n.l worked out
# here independently, the same output for the same arguments, and one-line errors with a
# non-zero status for bad arguments. The fifth argument is make_stack.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
MAKE_STACK=${5:?make_stack is the fifth argument}
need iinfo openimageio-tools; need oiiotool openimageio-tools; need idiff openimageio-tools; need jq jq
need awk mawk

RHO="0.8:0.5:0.2"
# The value of pixel (i, j) of a 32 x 32 sphere (radius 0.9) under light line k (1-based)
# of the 12 x 8 DiLiGenT grid, channel c (1-3), intensity E: E rho_c / pi max(0, n.l),
# every quantity from docs/images.md and the options' definitions, not from make_stack.
expect() { # i j k c E
  awk -v i="$1" -v j="$2" -v k="$3" -v c="$4" -v E="$5" -v rho="$RHO" 'BEGIN {
    N = 32; pi = atan2(0, -1); split(rho, r, ":")
    x = (i + 0.5 - N / 2) / (N / 2); y = -(j + 0.5 - N / 2) / (N / 2)
    nx = x / 0.9; ny = y / 0.9; nz = sqrt(1 - nx * nx - ny * ny)
    a = (k - 1) % 12; b = int((k - 1) / 12)
    lx = -0.75 + 1.5 * a / 11; ly = -0.5 + b / 7; lz = 1; n = sqrt(lx * lx + ly * ly + 1)
    d = (nx * lx + ny * ly + nz * lz) / n; if (d < 0) d = 0
    printf "%.9g\n", E * r[c] / pi * d }'
}
# Pixel (i, j) of an image as oiiotool prints it: "Pixel (i, j): v v v (...)" (each file
# dumped once: OpenImageIO's tools take most of a second to start).
pixel() {
  local dump=$tmp/dump_$(echo "$1" | tr '/' '_').txt
  [ -s "$dump" ] || oiiotool --dumpdata "$1" >"$dump"
  grep -F "Pixel ($2, $3):" "$dump" | sed 's/^[^:]*: //'
}
near() { awk -v a="$1" -v b="$2" -v tol="$3" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= tol) }'; }

# --- the DiLiGenT layout ------------------------------------------------------------------
D=$tmp/dil
"$MAKE_STACK" --model lambert --params "rho_d=$RHO" --shape sphere --size 32 --lights diligent96 \
  --layout diligent -o "$D" 2>"$tmp/err" && ok || bad "diligent run: $(cat "$tmp/err")"
for f in filenames.txt light_directions.txt light_intensities.txt mask.png normals_true.exr truth.json \
  001.png 096.png; do
  [ -s "$D/$f" ] && ok || bad "diligent: no $f"
done
[ -e "$D/097.png" ] && bad "diligent: a 97th image" || ok
[ "$(wc -l <"$D/filenames.txt")" = 96 ] && ok || bad "filenames.txt: $(wc -l <"$D/filenames.txt") lines"
[ "$(wc -l <"$D/light_directions.txt")" = 96 ] && ok || bad "light_directions.txt is not 96 lines"
[ "$(sort -u "$D/light_intensities.txt")" = "1 1 1" ] && ok || bad "equal intensities are not all 1 1 1"
[ "$(sed -n 50p "$D/filenames.txt")" = 050.png ] && ok || bad "filenames.txt line 50: $(sed -n 50p "$D/filenames.txt")"
# 16-bit PNGs, 3 channels, 32 x 32; the mask 8-bit, one channel.
iinfo "$D/050.png" "$D/001.png" "$D/mask.png" "$D/normals_true.exr" >"$tmp/info"
grep -q '050.png *: *32 x *32, 3 channel, uint16 png' "$tmp/info" && ok || bad "050.png: $(cat "$tmp/info")"
grep -q '001.png *: *32 x *32, 3 channel, uint16 png' "$tmp/info" && ok || bad "001.png: $(cat "$tmp/info")"
grep -q 'mask.png *: *32 x *32, 1 channel, uint8 png' "$tmp/info" && ok || bad "mask.png: $(cat "$tmp/info")"
grep -q 'normals_true.exr *: *32 x *32, 3 channel, float openexr' "$tmp/info" && ok ||
  bad "normals_true.exr: $(cat "$tmp/info")"
# Light 50's direction is the grid's, normalised, as %.9g.
want_l=$(awk 'BEGIN { lx = -0.75 + 1.5 * 1 / 11; ly = -0.5 + 4 / 7; n = sqrt(lx * lx + ly * ly + 1)
  printf "%.9g %.9g %.9g", lx / n, ly / n, 1 / n }')
[ "$(sed -n 50p "$D/light_directions.txt")" = "$want_l" ] && ok ||
  bad "light 50: $(sed -n 50p "$D/light_directions.txt"), want $want_l"
# One pixel: the 16-bit code is round(value * 65535).
read -r c1 c2 c3 _ <<<"$(pixel "$D/050.png" 16 10)"
codes=($c1 $c2 $c3)
for c in 1 2 3; do
  v=$(expect 16 10 50 $c 1)
  want=$(awk -v v="$v" 'BEGIN { printf "%d", v * 65535 + 0.5 }')
  near "${codes[$((c - 1))]}" "$want" 1 && ok || bad "050.png (16, 10) channel $c: code ${codes[$((c - 1))]}, want $want ($v)"
done
[ "$(pixel "$D/050.png" 0 0)" = "0 0 0 (0 0 0)" ] && ok || bad "outside the sphere: $(pixel "$D/050.png" 0 0)"
[ "$(pixel "$D/mask.png" 0 0)" = "0 (0)" ] && ok || bad "mask outside: $(pixel "$D/mask.png" 0 0)"
[ "$(pixel "$D/mask.png" 16 10)" = "255 (1)" ] && ok || bad "mask inside: $(pixel "$D/mask.png" 16 10)"
# The true normal there.
read -r n1 n2 n3 <<<"$(pixel "$D/normals_true.exr" 16 10)"
near "$n1" "$(awk 'BEGIN { print (16.5 - 16) / 16 / 0.9 }')" 1e-6 && near "$n2" "$(awk 'BEGIN { print (16 - 10.5) / 16 / 0.9 }')" 1e-6 &&
  ok || bad "normals_true.exr (16, 10): $n1 $n2 $n3"
# truth.json
jq -e '.model == "lambert" and .params.rho_d == [0.8, 0.5, 0.2] and .shape == "sphere" and .lights == 96' \
  "$D/truth.json" >/dev/null && ok || bad "truth.json: $(cat "$D/truth.json")"

# --- the JSON layout, random intensities -----------------------------------------------------
J=$tmp/json
"$MAKE_STACK" --model lambert --params "rho_d=$RHO" --size 32 --layout json --intensities random --seed 7 \
  -o "$J" 2>"$tmp/err" && ok || bad "json run: $(cat "$tmp/err")"
for f in stack.json mask.png normals_true.exr truth.json light_000.exr light_095.exr; do
  [ -s "$J/$f" ] && ok || bad "json: no $f"
done
jq -e '(.images | length) == 96 and .camera.type == "orthographic" and .camera.pixel_size == 0.0625 and
  .mask == "mask.png" and (.images[49].file == "light_049.exr")' "$J/stack.json" >/dev/null && ok ||
  bad "stack.json: $(head -c 300 "$J/stack.json")"
jq -e '[.images[].light.intensity[]] | all(. >= 0.8 and . <= 1.6) and (unique | length) > 200' \
  "$J/stack.json" >/dev/null && ok || bad "random intensities not in [0.8, 1.6]"
[ "$(jq -c '.images[49].light.direction' "$J/stack.json")" = "[$(echo "$want_l" | tr ' ' ',')]" ] && ok ||
  bad "stack.json light 50: $(jq -c '.images[49].light.direction' "$J/stack.json")"
iinfo "$J/light_049.exr" | grep -q '32 x *32, 3 channel, float openexr' && ok || bad "light_049.exr: $(iinfo "$J/light_049.exr")"
read -r v1 v2 v3 <<<"$(pixel "$J/light_049.exr" 16 10)"
vals=($v1 $v2 $v3)
for c in 1 2 3; do
  E=$(jq ".images[49].light.intensity[$((c - 1))]" "$J/stack.json")
  v=$(expect 16 10 50 $c "$E")
  near "${vals[$((c - 1))]}" "$v" "$(awk -v v="$v" 'BEGIN { print 1e-6 * v + 1e-9 }')" && ok ||
    bad "light_049.exr (16, 10) channel $c: ${vals[$((c - 1))]}, want $v"
done

# --- the same arguments, the same output ---------------------------------------------------
"$MAKE_STACK" --model lambert --params "rho_d=$RHO" --shape sphere --size 32 --lights diligent96 \
  --layout diligent -o "$tmp/dil2" 2>"$tmp/err" || bad "second diligent run: $(cat "$tmp/err")"
for f in filenames.txt light_directions.txt light_intensities.txt mask.png truth.json 001.png 050.png 096.png; do
  cmp -s "$D/$f" "$tmp/dil2/$f" && ok || bad "diligent $f differs between runs"
done
for run in n1 n2; do
  "$MAKE_STACK" --model lambert --params "rho_d=$RHO" --size 32 --layout json --intensities random \
    --lights grid25 --noise 0.02 --seed 3 --texture checker -o "$tmp/$run" 2>"$tmp/err" || bad "noisy run: $(cat "$tmp/err")"
done
cmp -s "$tmp/n1/stack.json" "$tmp/n2/stack.json" && ok || bad "stack.json differs between runs"
idiff -fail 0 -warn 0 "$tmp/n1/light_010.exr" "$tmp/n2/light_010.exr" >/dev/null && ok ||
  bad "noisy light_010.exr differs between runs"
# ... and another seed, other noise.
"$MAKE_STACK" --model lambert --params "rho_d=$RHO" --size 32 --layout json --intensities random \
  --lights grid25 --noise 0.02 --seed 4 --texture checker -o "$tmp/n3" 2>"$tmp/err" || bad "seed 4 run: $(cat "$tmp/err")"
idiff -fail 0 -warn 0 "$tmp/n1/light_010.exr" "$tmp/n3/light_010.exr" >/dev/null && bad "the seed changes nothing" || ok

# --- other shapes, lights, saturation --------------------------------------------------------
"$MAKE_STACK" --model walter --params 'rho_d=0.4:0.3:0.2,alpha=0.25' --shape bumps --size 16 --lights ring12 \
  --gain 40 -o "$tmp/b" 2>"$tmp/err" && ok || bad "bumps run: $(cat "$tmp/err")"
[ "$(wc -l <"$tmp/b/light_directions.txt")" = 12 ] && ok || bad "ring12: not 12 lights"
oiiotool --dumpdata "$tmp/b/mask.png" | grep -q ': 0 (0)' && bad "bumps: pixels outside the mask" || ok
oiiotool --dumpdata "$tmp/b/001.png" | grep -q ' 65535 ' && ok || bad "gain 40 saturates nothing"
"$MAKE_STACK" --model lambert --shape plane --size 8 --lights grid25 -o "$tmp/p" 2>"$tmp/err" && ok ||
  bad "plane run: $(cat "$tmp/err")"
[ "$(wc -l <"$tmp/p/filenames.txt")" = 25 ] && ok || bad "grid25: not 25 lights"

# --- bad arguments: one line, non-zero exit, nothing written --------------------------------
refuse() { # name, pattern, arguments
  local name=$1 pattern=$2
  shift 2
  "$MAKE_STACK" "$@" >/dev/null 2>"$tmp/err"
  local st=$?
  [ "$st" != 0 ] && ok || bad "$name: exit status 0"
  [ "$(grep -c . "$tmp/err")" = 1 ] && ok || bad "$name: not one line: $(cat "$tmp/err")"
  grep -qF -- "$pattern" "$tmp/err" && ok || bad "$name: message lacks '$pattern': $(cat "$tmp/err")"
}
refuse no-out "-o DIR" --model lambert
refuse shape "cube" --shape cube -o "$tmp/x"
refuse size "--size" --size 3 -o "$tmp/x"
refuse size-frac "--size" --size 32.5 -o "$tmp/x"
refuse lights "diligent96" --lights ring7 -o "$tmp/x"
refuse model "nosuchmodel" --model nosuchmodel -o "$tmp/x"
refuse param "nope" --params nope=1 -o "$tmp/x"
refuse param-value "rho_d" --params rho_d=0.5:0.5 -o "$tmp/x"
refuse param-range "rho_d" --params rho_d=7 -o "$tmp/x"
refuse gain "--gain" --gain -1 -o "$tmp/x"
refuse noise "--noise" --noise abc -o "$tmp/x"
refuse option "--bogus" --bogus -o "$tmp/x"
refuse extra "stray" -o "$tmp/x" stray
[ -e "$tmp/x" ] && bad "a refused run wrote $tmp/x" || ok

finish
