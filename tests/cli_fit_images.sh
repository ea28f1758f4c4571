#!/usr/bin/env bash
# brdfit fit-images on synthetic stacks from make_stack (tests/make_stack.c), whose truth is
# known: normals and parameters recovered (DiLiGenT and JSON layouts, fitted, flat and given
# normals, shared parameters per material cluster), the two readers agreeing on one stack,
# counts that add up, tiles that are bands of the whole run, results independent of the
# threads, a glTF material the Khronos validator accepts, one-line refusals of bad stacks and
# usage that leave no output behind, Ctrl-C, and which existing folders are replaced. The
# fifth argument is make_stack, the sixth normal_error (tests/normal_error.c).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
MAKE_STACK=${5:?make_stack is the fifth argument}
NORMAL_ERROR=${6:?normal_error is the sixth argument}
need oiiotool openimageio-tools; need idiff openimageio-tools; need iinfo openimageio-tools; need jq jq
need awk mawk; need node nodejs
here=$(cd "$(dirname "$0")" && pwd)
validator="$here/../tools/node_modules/gltf-validator"

# The material of every stack but a few: a Walter sphere whose highlight the DiLiGenT
# lights see over the centre of the sphere.
WALTER='rho_d=0.5:0.35:0.2,rho_s=0.3,alpha=0.15,f0=0.04'
ALPHA=0.15

# fit NAME STACK ARGS...: brdfit fit-images STACK -o $tmp/NAME ARGS..., quiet; its stderr in
# $tmp/NAME.err; a failure is counted and named.
fit() {
  local name=$1 stack=$2
  shift 2
  "$BRDFIT" fit-images "$stack" -o "$tmp/$name" -q "$@" 2>"$tmp/$name.err" && ok ||
    { bad "fit-images $name ($*): exit $?: $(cat "$tmp/$name.err")"; return 1; }
}
stack() { # DIR ARGS...: make_stack ... -o $tmp/DIR
  local dir=$1
  shift
  "$MAKE_STACK" "$@" -o "$tmp/$dir" 2>"$tmp/make.err" && ok || bad "make_stack $dir: $(cat "$tmp/make.err")"
}
# One field of normal_error's line "mean M median D max X pixels N" for A against B.
nerr() { # FIELD A B
  "$NORMAL_ERROR" "$2" "$3" 2>&1 | awk -v f="$1" '{ for (i = 1; i < NF; i++) if ($i == f) { print $(i + 1); exit } }
    END { if (NR == 0) print "none" }'
}
# awk comparisons that fail on anything but numbers: lt A B, within V WANT REL.
lt() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a ~ /^[-+0-9.eE]+$/ && a + 0 < b + 0) }'; }
within() { awk -v v="$1" -v w="$2" -v r="$3" 'BEGIN { d = v - w; if (d < 0) d = -d; exit !(v ~ /^[-+0-9.eE]+$/ && d <= r * w) }'; }
# The values of IMAGE at the pixels where MASK is non-zero, one pixel a line (one oiiotool
# --dumpdata for both: a header line per file, then "Pixel (x, y): v v v").
masked_values() { # IMAGE MASK
  oiiotool --dumpdata "$2" "$1" | awk '/^[^ ]/ { f++; next } /Pixel \(/ { key = $2 $3; sub(/^[^:]*: /, "")
      if (f == 1) { if ($1 + 0 > 0) m[key] = 1 } else if (key in m) print }'
}
median() { # [COLUMN]: the median of a column (default 1) of standard input
  awk -v c="${1:-1}" '{ print $c }' | sort -g |
    awk '{ a[NR] = $1 } END { if (NR) print (NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2); else print "none" }'
}
# Nothing at OUT, and no OUT.tmp.* beside it.
no_output() { # NAME OUT
  [ -e "$2" ] && bad "$1: $2 was left behind" || ok
  compgen -G "$2.tmp.*" >/dev/null && bad "$1: $(compgen -G "$2.tmp.*") was left behind" || ok
}

# --- 1. known answers: a Walter sphere, DiLiGenT layout, noise ------------------------------
stack dil --model walter --params "$WALTER" --shape sphere --size 48 --lights diligent96 --noise 0.005
if fit d "$tmp/dil" -m walter; then
  D=$tmp/d
  m=$(nerr mean "$D/normals.exr" "$tmp/dil/normals_true.exr")
  ml=$(nerr mean "$D/lambert_normals.exr" "$tmp/dil/normals_true.exr")
  lt "$m" 0.5 && ok || bad "walter sphere: mean normal error $m degrees (want < 0.5)"
  # The Lambertian baseline, misled by the highlight, is several times worse.
  lt "$m" "$(awk -v l="$ml" 'BEGIN { print l / 5 }')" && ok ||
    bad "walter sphere: mean normal error $m degrees, not well below the Lambertian baseline's $ml"
  # Over the sphere's rim the lights show no highlight and alpha is free: the median.
  a=$(masked_values "$D/alpha.exr" "$D/mask.png" | median)
  within "$a" "$ALPHA" 0.1 && ok || bad "walter sphere: median alpha $a, truth $ALPHA"
  jq -e '.relit_error.ratio < 0.5 and .relit_error.model > 0' "$D/fit.json" >/dev/null && ok ||
    bad "walter sphere: relit error $(jq -c '.relit_error | del(.per_image)' "$D/fit.json")"
  jq -e '.counts as $c | $c.samples_used + $c.shadowed + $c.dark_outliers + $c.saturated + $c.invalid
      == $c.pixels * .stack.images and $c.pixels > 0 and $c.failed_pixels == 0
      and $c.pixels + $c.masked_pixels == 48 * 48' "$D/fit.json" >/dev/null && ok ||
    bad "walter sphere: counts do not add up: $(jq -c .counts "$D/fit.json")"
  [ "$(nerr pixels "$D/normals.exr" "$tmp/dil/normals_true.exr")" = "$(jq .counts.pixels "$D/fit.json")" ] && ok ||
    bad "walter sphere: normals.exr's pixels are not the counted pixels"
  for f in normals.exr rho_d.exr rho_s.exr alpha.exr f0.exr error.exr lambert_normals.exr lambert_albedo.exr \
    normals.png albedo.png mask.png relit_000.png relit_095.exr fit.json; do
    [ -s "$D/$f" ] && ok || bad "walter sphere: no $f"
  done
fi

# Saturation: every sample with a 65535 code is counted saturated, not used (12 lights).
stack s_sat --model walter --params 'rho_d=0.4:0.3:0.2,alpha=0.25' --size 24 --lights ring12 --gain 12
if fit sat "$tmp/s_sat" -m walter; then
  n65535=$(oiiotool --dumpdata "$tmp"/s_sat/0??.png | grep -c 'Pixel.* 65535')
  jq -e --argjson n "$n65535" '.counts as $c | $n > 0 and $c.saturated == $n and
      $c.samples_used + $c.shadowed + $c.dark_outliers + $c.saturated + $c.invalid == $c.pixels * 12' \
    "$tmp/sat/fit.json" >/dev/null && ok ||
    bad "saturated samples: $(jq -c .counts "$tmp/sat/fit.json"), the images have $n65535 saturated"
fi

# --- 2. the DiLiGenT and JSON readers on the same files ----------------------------------------
# A JSON stack file in another folder, naming the DiLiGenT stack's PNGs, lights and intensities.
mkdir "$tmp/s_dj"
paste -d' ' "$tmp/dil/filenames.txt" "$tmp/dil/light_directions.txt" "$tmp/dil/light_intensities.txt" |
  jq -R -s '{images: [split("\n")[] | select(length > 0) | split(" ")
     | {file: ("../dil/" + .[0]), light: {direction: (.[1:4] | map(tonumber)), intensity: (.[4:7] | map(tonumber))}}],
   mask: "../dil/mask.png", transfer: "linear", scale: "auto"}' >"$tmp/s_dj/stack.json"
if [ -s "$tmp/d/fit.json" ] && fit dj "$tmp/s_dj/stack.json" -m walter; then
  x=$(nerr max "$tmp/d/normals.exr" "$tmp/dj/normals.exr")
  lt "$x" 0.0001 && ok || bad "DiLiGenT and JSON readers: normals differ by up to $x degrees"
  jq -e '.stack.layout == "json"' "$tmp/dj/fit.json" >/dev/null && ok || bad "the JSON stack is not read as JSON"
  # The same counts and scale.
  [ "$(jq -c '[.counts, .options.scale]' "$tmp/d/fit.json")" = "$(jq -c '[.counts, .options.scale]' "$tmp/dj/fit.json")" ] &&
    ok || bad "DiLiGenT and JSON readers: counts or scale differ"
fi

# --- 3. JSON layout, float EXRs, random intensities: calibrated, so rho_d too ----------------
stack s_jl --model walter --params "$WALTER" --size 40 --lights diligent96 --noise 0.005 --layout json \
  --intensities random --seed 5
if fit jl "$tmp/s_jl/stack.json" -m walter; then
  m=$(nerr mean "$tmp/jl/normals.exr" "$tmp/s_jl/normals_true.exr")
  lt "$m" 0.5 && ok || bad "JSON layout: mean normal error $m degrees (want < 0.5)"
  masked_values "$tmp/jl/rho_d.exr" "$tmp/jl/mask.png" >"$tmp/jl_rho_d.txt"
  c=1
  for want in 0.5 0.35 0.2; do
    v=$(median $c <"$tmp/jl_rho_d.txt")
    within "$v" "$want" 0.02 && ok || bad "JSON layout: median rho_d channel $c $v, truth $want"
    c=$((c + 1))
  done
  jq -e '.options.scale == 1 and .stack.layout == "json"' "$tmp/jl/fit.json" >/dev/null && ok ||
    bad "JSON layout: scale $(jq .options.scale "$tmp/jl/fit.json"), want the stack's 1"
fi

# --- 4. given normals: flat on a plane, a file ------------------------------------------------
stack s_pl --model walter --params "$WALTER" --shape plane --size 32 --lights diligent96 --layout json
if fit pl "$tmp/s_pl/stack.json" -m walter --normals flat; then
  oiiotool --pattern constant:color=0,0,1 32x32 3 -o "$tmp/flat.exr"
  idiff -fail 0 -warn 0 "$tmp/pl/normals.exr" "$tmp/flat.exr" >/dev/null && ok ||
    bad "--normals flat: normals.exr is not (0, 0, 1) everywhere: $(oiiotool --stats "$tmp/pl/normals.exr")"
  jq -e '.counts.pixels == 1024 and .options.normals == "flat"' "$tmp/pl/fit.json" >/dev/null && ok ||
    bad "--normals flat: $(jq -c '[.counts.pixels, .options.normals]' "$tmp/pl/fit.json")"
  a=$(masked_values "$tmp/pl/alpha.exr" "$tmp/pl/mask.png" | median)
  within "$a" "$ALPHA" 0.01 && ok || bad "--normals flat, noiseless plane: median alpha $a, truth $ALPHA"
fi
if fit nf "$tmp/dil" -m walter --normals "$tmp/dil/normals_true.exr"; then
  idiff -fail 0 -warn 0 "$tmp/nf/normals.exr" "$tmp/dil/normals_true.exr" >/dev/null && ok ||
    bad "--normals FILE: normals.exr differs from the file: $(idiff "$tmp/nf/normals.exr" "$tmp/dil/normals_true.exr" | tail -4)"
  jq -e --arg f "$tmp/dil/normals_true.exr" '.options.normals == "file" and .options.normals_file == $f' \
    "$tmp/nf/fit.json" >/dev/null && ok || bad "--normals FILE: fit.json options $(jq -c .options "$tmp/nf/fit.json")"
  a=$(masked_values "$tmp/nf/alpha.exr" "$tmp/nf/mask.png" | median)
  within "$a" "$ALPHA" 0.1 && ok || bad "--normals FILE: median alpha $a, truth $ALPHA"
fi

# --- 5. shared parameters per material cluster ---------------------------------------------------
stack s_ck --model walter --params "$WALTER" --size 40 --lights diligent96 --noise 0.005 --texture checker
if fit ck "$tmp/s_ck" -m walter --share alpha,f0 --clusters 2; then
  jq -e '.shared | length == 2 and (map(.cluster) | sort) == [0, 1]
      and all(.[]; (.values | keys) == ["alpha", "f0"])' "$tmp/ck/fit.json" >/dev/null && ok ||
    bad "--share alpha,f0 --clusters 2: shared is $(jq -c .shared "$tmp/ck/fit.json")"
  for cl in 0 1; do
    a=$(jq ".shared[] | select(.cluster == $cl) | .values.alpha" "$tmp/ck/fit.json")
    within "$a" "$ALPHA" 0.1 && ok || bad "--share alpha,f0 --clusters 2: cluster $cl alpha $a, truth $ALPHA"
  done
  # clusters.exr: 0 and 1 in the mask, -1 outside; the clusters are the checker's cells
  # (make_stack: the cell of pixel (i, j) is dark when (4 i / N + 4 j / N) is odd).
  if [ -s "$tmp/ck/clusters.exr" ]; then
    oiiotool --dumpdata "$tmp/ck/clusters.exr" | awk -F'[(), :]+' -v N=40 '/Pixel/ {
        i = $3; j = $4; c = $5 + 0; if (c == -1) next; n++; seen[c] = 1
        dark = (int(4 * i / N) + int(4 * j / N)) % 2; same += (c == dark) }
      END { k = 0; for (c in seen) k++; a = same > n - same ? same : n - same
            printf "%d %s %.4f\n", k, ((0 in seen) && (1 in seen)) ? "01" : "no", n ? a / n : 0 }' >"$tmp/ck.cl"
    read -r k which agree <"$tmp/ck.cl"
    [ "$k" = 2 ] && [ "$which" = 01 ] && ok || bad "clusters.exr: $k distinct values in the mask ($which)"
    lt 0.98 "$agree" && ok || bad "clusters.exr: only a fraction $agree of the pixels follows the checker"
  else
    bad "--clusters 2: no clusters.exr"
  fi
fi

# --- 6. tiles: bands of rows of the whole run -----------------------------------------------------
stack t32 --model walter --params "$WALTER" --size 32 --lights diligent96 --noise 0.005
fit whole "$tmp/t32" -m walter --threads 2
fit tile1 "$tmp/t32" -m walter --tile 1/2
fit tile2 "$tmp/t32" -m walter --tile 2/2
if [ -s "$tmp/whole/fit.json" ] && [ -s "$tmp/tile1/fit.json" ] && [ -s "$tmp/tile2/fit.json" ]; then
  jq -e -s '.[1].options.tile as $a | .[2].options.tile as $b
      | $a.rows_from == 0 and $a.rows_to == $b.rows_from and $b.rows_to == 32 and $a.rows_to > 0 and $b.rows_from < 32
      and .[1].counts.pixels + .[2].counts.pixels == .[0].counts.pixels
      and .[1].counts.pixels > 0 and .[2].counts.pixels > 0' \
    "$tmp/whole/fit.json" "$tmp/tile1/fit.json" "$tmp/tile2/fit.json" >/dev/null && ok ||
    bad "tiles: $(jq -c '[.options.tile, .counts.pixels]' "$tmp/whole/fit.json" "$tmp/tile1/fit.json" "$tmp/tile2/fit.json")"
  for t in 1 2; do
    T=$tmp/tile$t
    # Its fitted pixels lie in its rows only.
    read -r from to <<<"$(jq -r '.options.tile | "\(.rows_from) \(.rows_to)"' "$T/fit.json")"
    oiiotool --dumpdata "$T/mask.png" | awk -F'[(), :]+' -v a="$from" -v b="$to" \
      '/Pixel/ && $5 > 0 { n++; if ($4 < a || $4 >= b) out++ } END { exit !(n > 0 && out == 0) }' && ok ||
      bad "tile $t: fitted pixels outside rows $from to $to"
    [ "$(nerr pixels "$T/normals.exr" "$tmp/whole/normals.exr")" = "$(jq .counts.pixels "$T/fit.json")" ] && ok ||
      bad "tile $t: normals where it fitted no pixel, or none where it did"
    x=$(nerr max "$T/normals.exr" "$tmp/whole/normals.exr")
    [ "$x" = 0.0000 ] && ok || bad "tile $t: normals differ from the whole run's by up to $x degrees"
    # Exactly: the whole run's maps cut to the tile's mask.
    oiiotool "$tmp/whole/normals.exr" "$T/mask.png" --ch 0,0,0 --mul -o "$tmp/cut_n$t.exr" &&
      idiff -fail 0 -warn 0 "$tmp/cut_n$t.exr" "$T/normals.exr" >/dev/null && ok ||
      bad "tile $t: normals.exr is not the whole run's in its band"
    oiiotool "$tmp/whole/alpha.exr" "$T/mask.png" --mul -o "$tmp/cut_a$t.exr" &&
      idiff -fail 0 -warn 0 "$tmp/cut_a$t.exr" "$T/alpha.exr" >/dev/null && ok ||
      bad "tile $t: alpha.exr is not the whole run's in its band"
  done
fi

# --- 7. the threads change nothing but the time ----------------------------------------------------
if fit one "$tmp/t32" -m walter --threads 1 && [ -s "$tmp/whole/fit.json" ]; then
  for f in normals.exr alpha.exr rho_d.exr error.exr lambert_normals.exr; do
    idiff -fail 0 -warn 0 "$tmp/one/$f" "$tmp/whole/$f" >/dev/null && ok || bad "--threads 1 and 2: $f differs"
  done
  diff <(jq -S 'del(.timing, .command)' "$tmp/one/fit.json") <(jq -S 'del(.timing, .command)' "$tmp/whole/fit.json") \
    >"$tmp/threads.diff" && ok || bad "--threads 1 and 2: fit.json differs: $(head -c 600 "$tmp/threads.diff")"
  jq -e '.timing.threads == 1' "$tmp/one/fit.json" >/dev/null && ok || bad "--threads 1: timing.threads is not 1"
  jq -e '.command | test("--threads") | not' "$tmp/whole/fit.json" >/dev/null && ok ||
    bad "fit.json's command records --threads: $(jq .command "$tmp/whole/fit.json")"
fi

# --- 8. -m gltf: a textured glTF material the Khronos validator accepts ----------------------------
if fit g "$tmp/t32" -m gltf; then
  for f in material.gltf base_color.png metallic_roughness.png normal.png; do
    [ -s "$tmp/g/$f" ] && ok || bad "-m gltf: no $f"
  done
  jq -e '([.images[].uri] | sort) == ["base_color.png", "metallic_roughness.png", "normal.png"]
      and .asset.version == "2.0" and (.materials | length) == 1' "$tmp/g/material.gltf" >/dev/null && ok ||
    bad "-m gltf: material.gltf's images: $(jq -c '[.images[]?.uri]' "$tmp/g/material.gltf")"
  iinfo "$tmp/g/base_color.png" | grep -q ': *32 x *32, 3 channel' && ok ||
    bad "-m gltf: base_color.png is $(iinfo "$tmp/g/base_color.png")"
  if [ -d "$validator" ]; then
    node "$here/gltf_validate.js" "$validator" "$tmp/g/material.gltf" >"$tmp/issues" 2>&1 && ok ||
      bad "glTF validator reports errors on material.gltf: $(cat "$tmp/issues")"
    jq -e '.numErrors == 0 and .numWarnings == 0' "$tmp/issues" >/dev/null && ok ||
      bad "glTF validator issues on material.gltf: $(cat "$tmp/issues")"
    # The images are loaded and checked: one missing is an error.
    cp -r "$tmp/g" "$tmp/g_nopng"
    rm "$tmp/g_nopng/normal.png"
    node "$here/gltf_validate.js" "$validator" "$tmp/g_nopng/material.gltf" >"$tmp/issues" 2>&1 &&
      bad "glTF validator does not see a missing normal.png: $(cat "$tmp/issues")" || ok
    jq -e '.numErrors > 0 and any(.messages[]; .code == "IO_ERROR" and .pointer == "/images/2/uri")' \
      "$tmp/issues" >/dev/null && ok || bad "glTF validator on a missing normal.png: $(cat "$tmp/issues")"
  else
    bad "the glTF validator is not installed ($validator): run scripts/setup.sh"
  fi
fi

# --- 9. bad stacks and bad usage: one line, the status, no output --------------------------------------
# refuse NAME STATUS PATTERN... -- ARGS...: brdfit fit-images ARGS... -o $tmp/o_NAME exits
# STATUS with one line on stderr holding every PATTERN, and leaves no $tmp/o_NAME.
refuse() {
  local name=$1 want=$2 pats=()
  shift 2
  while [ "$1" != -- ]; do
    pats+=("$1")
    shift
  done
  shift
  local out=$tmp/o_$name
  "$BRDFIT" fit-images "$@" -o "$out" >/dev/null 2>"$tmp/err"
  local st=$?
  [ "$st" = "$want" ] && ok || bad "$name: exit status $st, want $want: $(cat "$tmp/err")"
  # libpng itself prints "libpng error: ..." on stderr for a damaged PNG (OpenImageIO 2.4
  # installs no handler of its own): brdfit's own message is the one other line.
  [ "$(grep -vc '^libpng error: ' "$tmp/err")" = 1 ] && ok || bad "$name: not one line on stderr: $(cat "$tmp/err")"
  for p in "${pats[@]}"; do
    grep -qF -- "$p" "$tmp/err" && ok || bad "$name: message lacks '$p': $(cat "$tmp/err")"
  done
  no_output "$name" "$out"
}
# broken NAME 'COMMAND': a copy of the small DiLiGenT stack, COMMAND run in it.
stack small --model lambert --size 16 --lights ring12
broken() {
  cp -r "$tmp/small" "$tmp/$1"
  (cd "$tmp/$1" && eval "$2") || bad "could not break $1"
}
fit small_ok "$tmp/small" -m lambert # the stack itself is good
broken b_missing 'rm 005.png'
refuse missing-image 1 "b_missing/005.png" -- "$tmp/b_missing" -m lambert
broken b_size 'oiiotool 005.png --resize 8x8 -d uint16 -o 005.png'
refuse image-size 1 "b_size/005.png" "8x8" "16x16" -- "$tmp/b_size" -m lambert
broken b_unit 'sed -i "3s/.*/0.5 0.5 0.5/" light_directions.txt'
refuse not-unit 1 "light_directions.txt:3:" "unit vector" -- "$tmp/b_unit" -m lambert
broken b_nan 'sed -i "4s/.*/nan 0 1/" light_directions.txt'
refuse nan-direction 1 "light_directions.txt:4:" "finite" -- "$tmp/b_nan" -m lambert
broken b_ints 'sed -i "\$d" light_intensities.txt'
refuse few-intensities 1 "light_intensities.txt" "11 light intensities for 12 images" -- "$tmp/b_ints" -m lambert
broken b_garbage 'echo "not a PNG" >005.png'
refuse corrupt-png 1 "b_garbage/005.png" -- "$tmp/b_garbage" -m lambert
# A PNG cut short: its header reads, its pixels do not (the fit fails, not the reading).
broken b_cut 'head -c 300 005.png >cut && mv cut 005.png'
refuse truncated-png 1 "b_cut/005.png" -- "$tmp/b_cut" -m lambert

# JSON stack files naming the small stack's PNGs, one image a line (image k on line k + 3).
mkdir "$tmp/js"
{
  echo '{'
  echo '  "images": ['
  paste -d' ' "$tmp/small/filenames.txt" "$tmp/small/light_directions.txt" | awk '{ printf \
    "    {\"file\": \"../small/%s\", \"light\": {\"direction\": [%s, %s, %s], \"intensity\": 1}}%s\n",
    $1, $2, $3, $4, NR < 12 ? "," : "" }'
  echo '  ],'
  echo '  "mask": "../small/mask.png"'
  echo '}'
} >"$tmp/js/good.json"
fit js_ok "$tmp/js/good.json" -m lambert
jbroken() { # NAME SED-SCRIPT
  sed "$2" "$tmp/js/good.json" >"$tmp/js/$1.json"
  cmp -s "$tmp/js/good.json" "$tmp/js/$1.json" && bad "$1: the sed script changed nothing"
}
jbroken malformed '7s/"intensity": 1/"intensity" 1/'
refuse malformed-json 1 "malformed.json:7:" -- "$tmp/js/malformed.json" -m lambert
jbroken nanstring '8s/"direction": \[[^,]*,/"direction": ["NaN",/'
refuse nan-string 1 "nanstring.json:8:" "images/5/light/direction" "finite" -- "$tmp/js/nanstring.json" -m lambert
jbroken bare_nan '9s/"direction": \[[^,]*,/"direction": [NaN,/'
refuse bare-nan 1 "bare_nan.json:9:" -- "$tmp/js/bare_nan.json" -m lambert
jbroken huge '10s/"direction": \[[^,]*,/"direction": [1e999,/'
refuse huge-number 1 "huge.json:10:" "images/7/light/direction" "finite" -- "$tmp/js/huge.json" -m lambert
jbroken two '11s/"direction": \[[^,]*,/"direction": [/'
refuse two-numbers 1 "two.json:11:" "images/8/light/direction" "3 numbers" -- "$tmp/js/two.json" -m lambert
jbroken unitj '12s/"direction": \[[^,]*,/"direction": [0.9,/'
refuse json-not-unit 1 "unitj.json:12:" "images/9/light/direction" "unit vector" -- "$tmp/js/unitj.json" -m lambert

# Usage: exit 2.
refuse unknown-model 2 "nosuchmodel" -- "$tmp/small" -m nosuchmodel
refuse bad-model-option 2 "lobes" -- "$tmp/small" -m 'walter:lobes=9'
refuse tile-3-of-2 2 "--tile" "3/2" -- "$tmp/small" -m lambert --tile 3/2
refuse tile-0 2 "--tile" -- "$tmp/small" -m lambert --tile 0/2
refuse two-stacks 2 "one stack" -- "$tmp/small" "$tmp/small" -m lambert
refuse unknown-option 2 "--bogus" -- "$tmp/small" -m lambert --bogus
refuse bad-scale 2 "--scale" -- "$tmp/small" -m lambert --scale -1
"$BRDFIT" fit-images "$tmp/small" -m lambert >/dev/null 2>"$tmp/err"
st=$?
[ "$st" = 2 ] && [ "$(grep -c '' "$tmp/err")" = 1 ] && grep -qF -- "-o" "$tmp/err" && ok ||
  bad "no -o: exit $st: $(cat "$tmp/err")"

# --- 10. Ctrl-C: exit 130, "interrupted", nothing written ----------------------------------------------
# 160 x 160 x 96: several seconds of fitting. The fit's worker threads show it is past reading
# the stack (where SIGINT, ignored by a background job, is not yet caught).
stack big --model walter --params "$WALTER" --size 160 --lights diligent96
"$BRDFIT" fit-images "$tmp/big" -m walter -o "$tmp/o_int" --threads 2 2>"$tmp/int.err" &
pid=$!
for _ in $(seq 200); do
  [ "$(ls "/proc/$pid/task" 2>/dev/null | wc -l)" -gt 1 ] && break
  sleep 0.05
done
sleep 0.5
kill -INT $pid 2>/dev/null
wait $pid
st=$?
[ "$st" = 130 ] && ok || bad "SIGINT: exit status $st, want 130 (did the fit end before it?): $(cat "$tmp/int.err")"
grep -q 'interrupted' "$tmp/int.err" && ok || bad "SIGINT: no 'interrupted' message: $(cat "$tmp/int.err")"
no_output SIGINT "$tmp/o_int"

# --- 11. existing folders: a user's is refused, a previous output replaced ---------------------------
mkdir "$tmp/user"
echo keep >"$tmp/user/keep.txt"
"$BRDFIT" fit-images "$tmp/small" -m lambert -o "$tmp/user" 2>"$tmp/err"
st=$?
[ "$st" = 1 ] && ok || bad "a user's folder: exit status $st, want 1"
grep -qF "$tmp/user" "$tmp/err" && [ "$(grep -c '' "$tmp/err")" = 1 ] && ok || bad "a user's folder: $(cat "$tmp/err")"
[ "$(ls -A "$tmp/user")" = keep.txt ] && [ "$(cat "$tmp/user/keep.txt")" = keep ] && ok ||
  bad "a user's folder was changed: $(ls -A "$tmp/user")"
compgen -G "$tmp/user.tmp.*" >/dev/null && bad "a user's folder: a temporary was left behind" || ok
echo keep >"$tmp/userfile"
"$BRDFIT" fit-images "$tmp/small" -m lambert -o "$tmp/userfile" 2>/dev/null
st=$?
[ "$st" = 1 ] && [ "$(cat "$tmp/userfile")" = keep ] && ok || bad "a file as -o: exit $st, or it was changed"
# A previous output (small_ok, above: lambert) is replaced whole; an empty folder is taken.
echo stray >"$tmp/small_ok/stray.txt"
if fit small_ok "$tmp/small" -m walter; then
  [ -e "$tmp/small_ok/stray.txt" ] && bad "a previous output: stray.txt survived its replacement" || ok
  jq -e '.model == "walter"' "$tmp/small_ok/fit.json" >/dev/null && ok || bad "a previous output was not replaced"
  [ -s "$tmp/small_ok/alpha.exr" ] && ok || bad "a previous output: the new run's alpha.exr is missing"
fi
mkdir "$tmp/empty"
fit empty "$tmp/small" -m lambert && { [ -s "$tmp/empty/fit.json" ] && ok || bad "an empty folder: no fit.json"; }

finish
