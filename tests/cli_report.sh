#!/usr/bin/env bash
# brdfit compare --html: two synthetic materials x three models make one report folder
# (index.html + PNGs, relative links, the images' sizes as the page says); the model
# table per material (fitted parameters, the error once) and the summary across
# materials; how the report was made; shared sphere exposure and the reasons for what is
# not drawn; scattered samples' half/difference figures as points (thinned when many);
# MERL tables' half/difference figures (whole table with --subsample);
# --plot-format; the same bytes whatever --jobs; a failing run leaves nothing; an
# existing folder that is not a report is refused before any fit, a previous report is
# replaced.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need iinfo openimageio-tools; need oiiotool openimageio-tools; need pdftotext poppler-utils; need xmllint libxml2-utils

cat > "$tmp/lam.json" <<'JSON'
{"model": "lambert", "channels": 3, "params": {"rho_d": [0.6, 0.4, 0.2]}}
JSON
cat > "$tmp/wal.json" <<'JSON'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 3,
 "params": {"rho_d": [0.3, 0.2, 0.1], "rho_s": [0.8, 0.8, 0.7], "alpha": 0.1, "f0": 0.05}}
JSON
"$SYNTH" --params "$tmp/lam.json" --pattern uniform --count 800 --noise 0.01 --seed 1 -o "$tmp/lam<1>.csv" &&
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 800 --noise 0.01 --seed 2 -o "$tmp/wal.csv" ||
  bad "brdfit-synth failed"
MODELS=lambert,walter,cook_torrance
R=$tmp/out/report

# --- a report ---------------------------------------------------------------------------
mkdir -p "$tmp/out"
if "$BRDFIT" compare "$tmp/lam<1>.csv" "$tmp/wal.csv" -m $MODELS --threads 2 --quiet --plot-format pdf --html "$R" \
     >"$tmp/stdout" 2>"$tmp/err"; then
  ok
else
  bad "compare --html failed: $(cat "$tmp/err")"
fi
[ -f "$R/index.html" ] && ok || bad "no index.html"
[ -f "$R/.brdfit-report" ] && ok || bad "no marker file"
[ -z "$(ls -a "$tmp/out" | grep -v -x -e . -e .. -e report)" ] && ok || bad "leftovers beside the report: $(ls -a "$tmp/out")"
html=$R/index.html
# Every <img>: a relative name that exists in the folder, with the size the page states.
nimg=0
while read -r src w h; do
  nimg=$((nimg + 1))
  case $src in /* | *:* | */*) bad "image link not relative to the folder: $src"; continue ;; esac
  [ -f "$R/$src" ] || { bad "missing image $src"; continue; }
  size=$(iinfo "$R/$src" | grep -o '[0-9]* x *[0-9]*' | head -1 | tr -d ' ')
  [ "$size" = "${w}x${h}" ] && ok || bad "$src is $size, the page says ${w}x${h}"
done < <(grep -o '<img src="[^"]*" width="[0-9]*" height="[0-9]*"' "$html" |
         sed 's/<img src="\([^"]*\)" width="\([0-9]*\)" height="\([0-9]*\)"/\1 \2 \3/')
# Per material: 2 scatter plots + 3 slices + 3 spheres + the samples as points and 3
# models' differences at them (each plot also as a linked PDF: cli_plots.sh reads them).
[ "$nimg" = 24 ] && ok || bad "expected 24 images, found $nimg"
[ "$(grep -c '<img' "$html")" = "$nimg" ] && ok || bad "an <img> the size check did not parse"
[ "$(ls "$R"/*.png | wc -l)" = 24 ] && ok || bad "PNG count: $(ls "$R")"
# Spheres are 160x160, scatter plots 520x360 and slices 440x330, as asked for a quick report.
grep -q 'src="m1-sphere-1.png" width="160" height="160"' "$html" && ok || bad "sphere size"
grep -q 'src="m2-k.png" width="520" height="360"' "$html" && ok || bad "scatter plot size"
grep -q 'src="m2-slice-1.png" width="440" height="330"' "$html" && ok || bad "slice plot size"
[ "$(ls "$R"/*.pdf | wc -l)" = 18 ] && ok || bad "PDF count (2 x (2 scatter + 3 slices + 4 half/difference)): $(ls "$R")"
# The model table lists the three models per material, in a row each, the name linking
# to the model's view in the material's viewer; the summary table.
for m in lambert walter cook_torrance; do
  [ "$(grep -c "<td class=\"spec\"><a href=\"#m[12]-view-[123]\">$m</a></td><td>" "$html")" = 2 ] &&
    [ "$(grep -c "<td class=\"spec\">$m</td><td>" "$html")" = 1 ] && ok ||
    bad "$m: expected 2 material rows (linked) + 1 summary row"
done
grep -q '<h2 id="summary">Summary over 2 materials</h2>' "$html" && ok || bad "no summary table"
# How it was made: the tool, the command line, the data options and the scene.
grep -q '<th>command</th><td><code>brdfit compare .*--html ' "$html" && ok || bad "no command line in the report"
grep -q '<th>data options</th><td><code>(none: every sample as read)</code>' "$html" && ok || bad "no data options row"
grep -q '<th>scene</th><td>none' "$html" && ok || bad "no scene row"
# The error (rmse_log by default) is one column, not also "log RMSE".
grep -q '<th>log RMSE</th>' "$html" && bad "rmse_log shown twice" || ok
grep -q '<th>rmse_log</th><th>RMSE</th><th>AIC</th>' "$html" && ok || bad "error column header"
# Fitted parameters, one line per entry.
grep -q '<td class="params">rho_d\[0\]&nbsp;' "$html" && ok || bad "no fitted parameters"
# Spheres: one exposure for all, from the data, stated; CSV data cannot be drawn as a
# sphere or a half/difference image, and the report says why; its samples are drawn as
# points on the half/difference axes instead, with each model's log2 ratio at them.
[ "$(grep -o 'One exposure for all, &times;[0-9.e+-]*' "$html" | wc -l)" = 2 ] && ok || bad "exposure captions"
grep -q 'The measurement is not drawn: the data is not a MERL table' "$html" && ok || bad "no reason for no measured sphere"
grep -q '<p>Not drawn:' "$html" && bad "half/difference section not drawn for CSV samples" || ok
[ "$(grep -c '<p>The measurement is not drawn as an image: the data is not a MERL table.*Its samples are drawn as points instead, each at its &theta;<sub>h</sub>.*every &phi;<sub>d</sub> together.*All 800 samples drawn\.</p>' "$html")" = 2 ] &&
  ok || bad "half/difference paragraph for samples: $(grep -o '<p>The measurement is not drawn as an image[^/]*' "$html" | head -1)"
for m in 1 2; do
  grep -q "src=\"m$m-hd-measured.png\" width=\"340\" height=\"280\" alt=\"measured samples\"" "$html" && [ -s "$R/m$m-hd-measured.pdf" ] &&
    ok || bad "material $m: no measured samples figure"
  for j in 1 2 3; do
    grep -q "src=\"m$m-hd-diff-$j.png\" width=\"340\" height=\"280\"" "$html" && [ -s "$R/m$m-hd-diff-$j.pdf" ] &&
      ok || bad "material $m: no difference figure for model $j"
  done
  [ ! -e "$R/m$m-hd-model-1.png" ] && ok || bad "material $m: a model image where only points were asked for"
done
[ "$(grep -c '<figcaption>measured<br>800 samples as points, every &phi;<sub>d</sub> together</figcaption>' "$html")" = 2 ] &&
  ok || bad "measured samples caption: $(grep -o '<figcaption>measured<br>[^/]*' "$html" | head -1)"
grep -q '<figcaption>log2(walter / measured)<br>at the same samples</figcaption>' "$html" && ok || bad "difference caption"
# The points figures have the table figures' axes and colour bars.
pdftotext "$R/m2-hd-measured.pdf" - > "$tmp/pts.txt"
for want in "wal.csv: measured samples" "half angle θh (√ scale)" "difference angle θd (°)" "45°"; do
  grep -qxF -- "$want" "$tmp/pts.txt" && ok || bad "points figure lacks '$want': $(tr '\n' '|' < "$tmp/pts.txt")"
done
pdftotext "$R/m2-hd-diff-2.pdf" - | grep -qxF "log2(model / measured)" && ok || bad "difference points figure: no colour bar title"
# Slices at the incidences the data has (uniform data: none exactly at 0).
grep -q 'at incidence [0-9.]*&deg;, [0-9.]*&deg; and [0-9.]*&deg; (colours; the measured incidences nearest' "$html" &&
  ok || bad "slice incidences not from the data: $(grep -o 'at incidence [^(]*' "$html" | head -1)"
# lambert is the simplest on the Lambert data (and its row is marked), walter on Walter's.
awk '/<h2 id="m1">/{m=1} /<h2 id="m2">/{m=2} /class="chosen"/{print m, $0}' "$html" > "$tmp/chosen"
grep -q '^1 .*spec"><a href="#m1-view-1">lambert<' "$tmp/chosen" && grep -q '^2 .*spec"><a href="#m2-view-2">walter<' "$tmp/chosen" &&
  [ "$(wc -l < "$tmp/chosen")" = 2 ] && ok || bad "chosen rows: $(cat "$tmp/chosen")"
# File names are escaped: the data file is called lam<1>.csv.
grep -q 'lam&lt;1&gt;.csv</h2>' "$html" && ok || bad "file name not escaped"
grep -q 'lam<1>' "$html" && bad "raw '<' from a file name in the page" || ok
# The sphere of a fitted model is lit (not blank); the scatter plot shows red front points.
oiiotool "$R/m1-sphere-1.png" --printstats 2>/dev/null | grep -q 'Stats Max: *[1-9]' && ok ||
  bad "sphere is black: $(oiiotool "$R/m1-sphere-1.png" --printstats 2>&1 | grep Max)"

# --- a previous report is replaced ----------------------------------------------------------
touch "$R/stale.png"
"$BRDFIT" compare "$tmp/wal.csv" -m lambert --quiet --html "$R" >/dev/null 2>"$tmp/err" && ok ||
  bad "replacing a report failed: $(cat "$tmp/err")"
[ -f "$R/index.html" ] && [ ! -e "$R/stale.png" ] && ok || bad "previous report not replaced"
grep -q Summary "$html" && bad "one material: no summary expected" || ok
[ -z "$(ls -a "$tmp/out" | grep -v -x -e . -e .. -e report)" ] && ok || bad "leftovers: $(ls -a "$tmp/out")"

# --- an existing folder that is not a report is refused, before fitting -----------------
mkdir -p "$tmp/mine" && echo keep > "$tmp/mine/notes.txt"
"$BRDFIT" compare "$tmp/wal.csv" -m lambert --quiet --html "$tmp/mine" >"$tmp/stdout" 2>"$tmp/err"
rc=$?
[ $rc = 1 ] && ok || bad "non-report folder: exit $rc"
[ "$(wc -l < "$tmp/err")" = 1 ] && grep -q "mine: exists and is not a brdfit report" "$tmp/err" && ok ||
  bad "message: $(cat "$tmp/err")"
[ ! -s "$tmp/stdout" ] && ok || bad "fits ran before the refusal"
[ "$(ls -a "$tmp/mine" | wc -l)" = 3 ] && [ "$(cat "$tmp/mine/notes.txt")" = keep ] && ok || bad "folder touched"
echo x > "$tmp/afile"
"$BRDFIT" compare "$tmp/wal.csv" -m lambert --quiet --html "$tmp/afile" >/dev/null 2>&1
[ $? = 1 ] && [ "$(cat "$tmp/afile")" = x ] && ok || bad "a file as DIR"

# --- a failing run leaves nothing --------------------------------------------------------
# The parent is a file: the folder cannot be made.
"$BRDFIT" compare "$tmp/wal.csv" -m lambert --quiet --html "$tmp/afile/report" >/dev/null 2>"$tmp/err"
rc=$?
[ $rc = 1 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q "afile/report" "$tmp/err" && ok ||
  bad "unwritable DIR: exit $rc, $(cat "$tmp/err")"
# Bad data fails before anything is written.
echo "theta_i,phi_i" > "$tmp/broken.csv"
"$BRDFIT" compare "$tmp/broken.csv" -m lambert --quiet --html "$tmp/out2/r" >/dev/null 2>&1
[ $? = 1 ] && [ ! -e "$tmp/out2" ] && ok || bad "bad data left $(ls -R "$tmp/out2" 2>&1)"
# --html needs a value.
"$BRDFIT" compare "$tmp/wal.csv" -m lambert --html >/dev/null 2>&1
[ $? = 2 ] && ok || bad "--html without a value"

# A MERL table: the measured sphere leads the spheres, and the half-diff images of the
# measurement, each model and their difference are there.
printf '{"model":"walter","channels":3,"params":{"rho_d":[0.5,0.3,0.1],"rho_s":[0.6,0.6,0.6],"alpha":0.2,"f0":0.04}}' > "$tmp/wm.json"
if "$SYNTH" --params "$tmp/wm.json" --pattern merl --seed 1 -o "$tmp/wm.binary" >/dev/null 2>&1 &&
   "$BRDFIT" compare "$tmp/wm.binary" -m lambert,walter --plot-format pdf --html "$tmp/merl_report" --quiet \
     >/dev/null 2>&1; then
  for f in m1-sphere-measured.png m1-hd-measured.png m1-hd-model-2.png m1-hd-diff-2.png; do
    [ -s "$tmp/merl_report/$f" ] && grep -q "src=\"$f\"" "$tmp/merl_report/index.html" && ok || bad "MERL report: $f"
  done
  for f in m1-hd-measured m1-hd-model-2 m1-hd-diff-2; do
    [ -s "$tmp/merl_report/$f.pdf" ] && ok || bad "MERL report: no $f.pdf"
  done
  # The half/difference figures: a sqrt theta_h axis ticked in degrees, colour bars.
  pdftotext "$tmp/merl_report/m1-hd-diff-2.pdf" - > "$tmp/hd.txt"
  for want in "half angle θh (√ scale)" "difference angle θd (°)" "log2(model / measured)" "45°" "90°"; do
    grep -qxF -- "$want" "$tmp/hd.txt" && ok || bad "difference figure lacks '$want': $(tr '\n' '|' < "$tmp/hd.txt")"
  done
  # Measurement and model share one colour scale: the same colour bar labels.
  pdftotext "$tmp/merl_report/m1-hd-measured.pdf" - | grep '^10' > "$tmp/bar1"
  pdftotext "$tmp/merl_report/m1-hd-model-2.pdf" - | grep '^10' > "$tmp/bar2"
  [ -s "$tmp/bar1" ] && cmp -s "$tmp/bar1" "$tmp/bar2" && ok || bad "colour bars differ: $(cat "$tmp/bar1" "$tmp/bar2" | tr '\n' ' ')"
  # A whole table is drawn as images, not as points.
  grep -q 'Its samples are drawn as points' "$tmp/merl_report/index.html" && bad "MERL report: points where the table can be drawn" || ok
else
  bad "MERL report run"
fi
# Many scattered samples: every k-th is drawn as a point (a set number at most, so a large
# file stays quick), and the page and the caption say so.
if "$SYNTH" --params "$tmp/lam.json" --pattern uniform --count 5000 --noise 0.01 --seed 3 -o "$tmp/many.csv" >/dev/null 2>&1 &&
   "$BRDFIT" compare "$tmp/many.csv" -m lambert --quiet --html "$tmp/many_report" >/dev/null 2>"$tmp/err"; then
  h=$tmp/many_report/index.html
  grep -q 'Every 2<sup>nd</sup> sample is drawn: 2500 of 5000\.</p>' "$h" && ok ||
    bad "thinned samples: $(grep -o 'Every [^.]*' "$h" | head -1)"
  grep -q '<figcaption>measured<br>2500 samples as points (every 2<sup>nd</sup> of 5000), every &phi;<sub>d</sub> together</figcaption>' "$h" &&
    ok || bad "thinned samples caption: $(grep -o '<figcaption>measured<br>[^/]*' "$h")"
  [ -s "$tmp/many_report/m1-hd-measured.png" ] && [ -s "$tmp/many_report/m1-hd-diff-1.png" ] && ok ||
    bad "thinned samples: figures missing"
else
  bad "report of 5000 samples: $(cat "$tmp/err")"
fi
# With --subsample the fits use a subsample, and the pictures of the measurement the
# whole table (read again); the plots can be embedded as SVG.
if "$BRDFIT" compare "$tmp/wm.binary" -m lambert --subsample 3000 --plot-format svg --html "$tmp/sub_report" \
     --quiet >/dev/null 2>"$tmp/err"; then
  h=$tmp/sub_report/index.html
  grep -q 'src="m1-sphere-measured.png"' "$h" && ok || bad "subsampled MERL report: no measured sphere"
  grep -q 'src="m1-hd-measured.svg"' "$h" && ok || bad "subsampled MERL report: no measured half/difference image"
  # SVG figures only: PDFs are written with --plot-format pdf.
  grep -q 'src="m1-slice-1.svg"' "$h" && ! grep -q 'href="m1-slice-1.pdf"' "$h" && [ ! -e "$tmp/sub_report/m1-slice-1.pdf" ] &&
    ok || bad "--plot-format svg"
  xmllint --noout "$tmp/sub_report/m1-hd-measured.svg" && ok || bad "half/difference SVG is not well formed"
  grep -q '<th>data options</th><td><code>--subsample 3000</code>' "$h" && ok || bad "data options: $(grep -o '<th>data options</th>[^/]*' "$h")"
  grep -q '<th>log RMSE</th>' "$h" && bad "rmse_log shown twice" || ok
else
  bad "subsampled MERL report: $(cat "$tmp/err")"
fi
# --jobs and --threads change no byte of the report: the command line shown leaves them out
# (both spellings); the other words stay, a file named like an option after -- too.
cp "$tmp/lam<1>.csv" "$tmp/--jobs=2"
if (cd "$tmp" && "$BRDFIT" compare "lam<1>.csv" -m lambert,walter --quiet --jobs 2 --threads=2 --html j2 -- --jobs=2 &&
     "$BRDFIT" compare "lam<1>.csv" -m lambert,walter --quiet --threads 1 --html j1 -- --jobs=2) >/dev/null 2>&1; then
  for f in "$tmp/j1"/*; do
    b=$(basename "$f")
    [ "$b" = index.html ] || { cmp -s "$f" "$tmp/j2/$b" && ok || bad "--jobs changed $b"; }
  done
  cmd=$(grep '<th>command</th>' "$tmp/j1/index.html")
  diff <(sed 's#--html j1#--html DIR#' "$tmp/j1/index.html") <(sed 's#--html j2#--html DIR#' "$tmp/j2/index.html") >/dev/null &&
    ok || bad "--jobs changed index.html: $(diff "$tmp/j1/index.html" "$tmp/j2/index.html" | head -4)"
  [[ "$cmd" != *"--jobs 2"* && "$cmd" != *--threads* && "$cmd" == *"--quiet --html j1 -- --jobs=2<"* ]] &&
    ok || bad "command shown: $cmd"
else
  bad "reports for the --jobs check"
fi
"$BRDFIT" compare "$tmp/wm.binary" -m lambert --plot-format gif --html "$tmp/gif_report" >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q -- '--plot-format' "$tmp/err" && [ ! -e "$tmp/gif_report" ] && ok || bad "--plot-format gif: $(cat "$tmp/err")"

finish
