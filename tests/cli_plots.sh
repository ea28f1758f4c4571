#!/usr/bin/env bash
# Plots as a reader gets them (Cairo: lib/src/report/plot): render --slice, tradeoff --plot and
# the compare report's figures as PNG (the size asked for), SVG (well-formed, the size in
# points) and PDF (pdftoppm renders it; pdftotext finds the title, the axis titles, tick
# labels that match the data and the legend's names); the slices of one material share
# one y range; formats a plot cannot take are refused with no file left.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need iinfo openimageio-tools; need pdftotext poppler-utils; need pdftoppm poppler-utils; need pdfinfo poppler-utils; need xmllint libxml2-utils
MINUS=$'\xe2\x88\x92'

# A grey Lambert surface: f = 0.5/pi = 0.159 everywhere, so the y axis is a narrow
# padded range around it and its ticks are values near 0.16.
cat > "$tmp/lam.json" <<'JSON'
{"model": "lambert", "channels": 1, "params": {"rho_d": 0.5}}
JSON
cat > "$tmp/wal.json" <<'JSON'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 3,
 "params": {"rho_d": [0.3, 0.2, 0.1], "rho_s": [0.8, 0.8, 0.7], "alpha": 0.1, "f0": 0.05}}
JSON
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 2000 --noise 0.01 --seed 4 -o "$tmp/w.csv" ||
  bad "brdfit-synth failed"

# --- render --slice: PDF text -----------------------------------------------------------
if "$BRDFIT" render --params "$tmp/lam.json" --slice --incidence 10,50 -o "$tmp/lam.pdf" 2>"$tmp/err"; then
  ok
  pdftotext "$tmp/lam.pdf" "$tmp/lam.txt" && ok || bad "pdftotext cannot read the slice PDF"
  for want in "In-plane slices of lambert" "viewing angle θo in the plane of incidence (°; + mirror side)" \
              "BRDF f (sr${MINUS}1)" "θi = 10°, 50°" "θi = 10°, 50°: the same curve, drawn once" "${MINUS}90" "${MINUS}30" "60" "90"; do
    grep -qxF -- "$want" "$tmp/lam.txt" && ok || bad "slice PDF lacks '$want': $(tr '\n' '|' < "$tmp/lam.txt")"
  done
  # y ticks: numbers near 0.159 only (the padded range), at least two of them.
  awk '/^0\.[0-9]+$/ { n++; if ($1 < 0.14 || $1 > 0.18) bad = 1 } END { exit !(n >= 2 && !bad) }' "$tmp/lam.txt" &&
    ok || bad "y tick labels do not match f = 0.159: $(grep '^0\.' "$tmp/lam.txt" | tr '\n' ' ')"
  pdfinfo "$tmp/lam.pdf" | grep -q 'Page size: *640 x 480 pts' && ok || bad "PDF page: $(pdfinfo "$tmp/lam.pdf")"
  pdftoppm -png -r 36 "$tmp/lam.pdf" "$tmp/lamppm" && [ -s "$tmp/lamppm-1.png" ] && ok || bad "pdftoppm failed"
else
  bad "render --slice to PDF failed: $(cat "$tmp/err")"
fi
# With measured samples: the legend counts them; RGB models name the channels.
if "$BRDFIT" render --params "$tmp/wal.json" --slice --data "$tmp/w.csv" --plane-tol 5 -o "$tmp/wal.pdf" 2>"$tmp/err"; then
  pdftotext "$tmp/wal.pdf" "$tmp/wal.txt"
  for want in "channel R" "channel G" "channel B" "θi = 30°" "θi = 60°"; do
    grep -qxF -- "$want" "$tmp/wal.txt" && ok || bad "RGB slice PDF lacks '$want'"
  done
  # Without --incidence: the measured incidence nearest 0 (uniform data has none at 0).
  inc0=$(sed -n 's/^θi = \([0-9.]*\)°$/\1/p' "$tmp/wal.txt" | head -1)
  awk -v a="$inc0" 'BEGIN { exit !(a > 0 && a < 10) }' && ok || bad "first slice incidence '$inc0' is not measured"
  grep -q '^measured ([0-9][0-9]*)$' "$tmp/wal.txt" && ok || bad "no measured count: $(tr '\n' '|' < "$tmp/wal.txt")"
  # Under three decades: labelled 1-2-5 values, one of them a whole decade.
  grep -qx '0\.1\|1\|10' "$tmp/wal.txt" && grep -qx '0\.2\|2\|20' "$tmp/wal.txt" && ok ||
    bad "glossy slice: no 1-2-5 tick labels"
else
  bad "render --slice with data failed: $(cat "$tmp/err")"
fi

# --- render --slice: PNG and SVG, by extension and by --to ----------------------------
"$BRDFIT" render --params "$tmp/lam.json" --slice --size 500x300 -o "$tmp/s.png" 2>"$tmp/err" &&
  iinfo "$tmp/s.png" | grep -Eq ': +500 x +300, 3 channel' && ok || bad "slice PNG: $(cat "$tmp/err") $(iinfo "$tmp/s.png" 2>&1)"
"$BRDFIT" render --params "$tmp/lam.json" --slice --size 500x300 -o "$tmp/s.svg" 2>"$tmp/err" &&
  xmllint --noout "$tmp/s.svg" && grep -q 'width="500pt" height="300pt"' "$tmp/s.svg" && ok ||
  bad "slice SVG: $(cat "$tmp/err")"
"$BRDFIT" render --params "$tmp/lam.json" --slice --to svg -o - 2>"$tmp/err" >"$tmp/stdout.svg" &&
  xmllint --noout "$tmp/stdout.svg" && ok || bad "slice SVG to standard output: $(cat "$tmp/err")"
"$BRDFIT" render --params "$tmp/lam.json" --slice --to pdf -o - 2>/dev/null | head -c 5 | grep -q '%PDF-' && ok ||
  bad "slice PDF to standard output"
# Twice the same plot: the same bytes (no date in the PDF).
"$BRDFIT" render --params "$tmp/lam.json" --slice --incidence 10,50 -o "$tmp/lam2.pdf" 2>/dev/null &&
  cmp -s "$tmp/lam.pdf" "$tmp/lam2.pdf" && ok || bad "the same slice PDF differs between runs"

# --- formats a picture cannot take: exit 2, one line, no file ------------------------------
refused() { # name, pattern, out, args...
  local name=$1 pattern=$2 out=$3
  shift 3
  "$BRDFIT" "$@" >/dev/null 2>"$tmp/err"
  local st=$?
  [ $st = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$pattern" "$tmp/err" && [ ! -e "$out" ] && ok ||
    bad "$name: exit $st, $(cat "$tmp/err"), $(ls "$tmp")"
}
refused "slice as EXR" "not EXR" "$tmp/x.exr" render --params "$tmp/lam.json" --slice -o "$tmp/x.exr"
refused "sphere as SVG" "SVG and PDF are for --slice" "$tmp/x.svg" render --params "$tmp/lam.json" -o "$tmp/x.svg"
refused "sphere --to pdf" "SVG and PDF are for --slice" "$tmp/x.png" render --params "$tmp/lam.json" --to pdf -o "$tmp/x.png"

# --- render --half-diff as a figure: the sqrt theta_h axis in degrees, a colour bar ------
if "$BRDFIT" render --params "$tmp/wal.json" --half-diff -o "$tmp/hd.pdf" 2>"$tmp/err"; then
  pdftotext "$tmp/hd.pdf" "$tmp/hd.txt"
  for want in "half angle θh (√ scale)" "difference angle θd (°)" "BRDF f (sr${MINUS}1)" "2°" "45°"; do
    grep -qxF -- "$want" "$tmp/hd.txt" && ok || bad "half-diff PDF lacks '$want': $(tr '\n' '|' < "$tmp/hd.txt")"
  done
  pdfinfo "$tmp/hd.pdf" | grep -q 'Page size: *480 x 400 pts' && ok || bad "half-diff PDF page size"
  "$BRDFIT" render --params "$tmp/wal.json" --half-diff --size 300x250 -o "$tmp/hd.svg" 2>"$tmp/err" &&
    xmllint --noout "$tmp/hd.svg" && grep -q 'width="300pt" height="250pt"' "$tmp/hd.svg" && ok ||
    bad "half-diff SVG: $(cat "$tmp/err")"
else
  bad "render --half-diff to PDF failed: $(cat "$tmp/err")"
fi
refused "bad --to" "--to" "$tmp/x.png" render --params "$tmp/lam.json" --slice --to gif -o "$tmp/x.png"
refused "tradeoff gif" ".png, .svg or .pdf" "$tmp/t.gif" tradeoff "$tmp/w.csv" -m lambert --plot "$tmp/t.gif"
ls "$tmp" | grep -q '\.tmp\.' && bad "temporary file left: $(ls "$tmp")" || ok

# --- tradeoff --plot: the front named, its points labelled, the axes titled ----------------
if "$BRDFIT" tradeoff "$tmp/w.csv" -m walter --samples 400,all --methods ceres,LD_LBFGS --threads 2 --seed 3 \
     --plot "$tmp/t.pdf" >"$tmp/out" 2>"$tmp/err"; then
  pdftotext "$tmp/t.pdf" "$tmp/t.txt"
  for want in "Test error against fitting cost: walter" "test error (rmse_log), log scale" \
              "fitting work (sample evaluations), log scale" "#N: the setting's number in the table"; do
    grep -qxF -- "$want" "$tmp/t.txt" && ok || bad "tradeoff PDF lacks '$want': $(tr '\n' '|' < "$tmp/t.txt")"
  done
  grep -q '^Pareto front ([1-9][0-9]*)$' "$tmp/t.txt" && ok || bad "tradeoff PDF: no front in the legend"
  grep -q '^#[1-4]$' "$tmp/t.txt" && ok || bad "tradeoff PDF: no labelled front point"
  grep -q '^recommended (#[1-4])$' "$tmp/t.txt" && ok || bad "tradeoff PDF: no recommended entry"
  # The y range printed is padded around the errors and not collapsed (>= 0.1 decade).
  line=$(grep "^plot $tmp/t.pdf: " "$tmp/out")
  echo "$line" | awk '{ match($0, /log axis, [0-9.e+-]+ to [0-9.e+-]+\)/); s = substr($0, RSTART + 10, RLENGTH - 11);
                        split(s, a, " to "); exit !(a[2] / a[1] >= 1.25) }' && ok || bad "y range: $line"
else
  bad "tradeoff --plot failed: $(cat "$tmp/err")"
fi

# --- compare --html --plot-format pdf: PNG embedded, PDF beside it; model names on the
# points; shared y ------------------------------------------------------------------------
if "$BRDFIT" compare "$tmp/w.csv" -m lambert -m walter --quiet --plot-format pdf --html "$tmp/r" >/dev/null \
     2>"$tmp/err"; then
  for f in m1-k m1-work m1-slice-1 m1-slice-2; do
    [ -s "$tmp/r/$f.png" ] && [ -s "$tmp/r/$f.pdf" ] && ok || bad "report: $f.png / .pdf missing"
    grep -q "href=\"$f.pdf\"" "$tmp/r/index.html" && ok || bad "report: no link to $f.pdf"
  done
  pdftotext "$tmp/r/m1-k.pdf" "$tmp/k.txt"
  for want in lambert walter "Pareto front" "free parameters k" "models (labelled)"; do
    grep -qxF -- "$want" "$tmp/k.txt" && ok || bad "error-vs-k PDF lacks '$want': $(tr '\n' '|' < "$tmp/k.txt")"
  done
  # The two models' slices: the same tick labels (shared y range, same x axis).
  pdftotext "$tmp/r/m1-slice-1.pdf" - | grep -E '^(10|[−0-9.]+$)' | sort > "$tmp/t1"
  pdftotext "$tmp/r/m1-slice-2.pdf" - | grep -E '^(10|[−0-9.]+$)' | sort > "$tmp/t2"
  [ -s "$tmp/t1" ] && cmp -s "$tmp/t1" "$tmp/t2" && ok || bad "slices differ in ticks: $(paste -d' ' "$tmp/t1" "$tmp/t2" | tr '\n' '|')"
else
  bad "compare --html failed: $(cat "$tmp/err")"
fi

finish
