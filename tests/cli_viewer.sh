#!/usr/bin/env bash
# The report's viewer in a real browser: a report of a synthetic MERL table, an RGL
# .bsdf file, an NVIDIA .mbsdf file and a Cornell file (scattered samples) x lambert and
# walter, opened from disk in Debian's Chromium (headless, through puppeteer-core:
# tests/browser/viewer_check.js). Every sphere draws, dragging moves the light, the
# slider moves the slice, the table's links select a model, no console error; and the
# viewer's values agree with brdfit eval (each fitted model), with the generating model
# (the MERL table) and with the RGL reader (--grid at the same directions) within the
# tabulation's stated error (docs/report.md), away from the highlight's peak. Then the
# same checks on brdfit report's page of a batch database (models only).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need node nodejs; need jq jq
here=$(cd "$(dirname "$0")" && pwd)
chromium=$(command -v chromium || true)
[ -n "$chromium" ] || { echo "FAIL: chromium is missing: install the Debian package chromium (scripts/setup.sh does)"; exit 1; }
[ -d "$here/../tools/node_modules/puppeteer-core" ] ||
  { echo "FAIL: puppeteer-core is missing from tools/: run scripts/setup.sh"; exit 1; }
EX=$here/../examples

# A MERL table from a known walter material (no noise, so the table is the model).
printf '{"model":"walter","channels":3,"params":{"rho_d":[0.5,0.3,0.1],"rho_s":[0.6,0.6,0.6],"alpha":0.2,"f0":0.04}}' \
  > "$tmp/wm.json"
"$SYNTH" --params "$tmp/wm.json" --pattern merl --seed 1 -o "$tmp/wm.binary" >/dev/null 2>&1 || bad "brdfit-synth failed"
R=$tmp/report
if "$BRDFIT" compare "$tmp/wm.binary" "$EX/rgl/cc_ibiza_sunset_rgb.bsdf" "$EX/mdl/carpaint_red.mbsdf" \
     "$EX/cornell/cayman.brdf" -m lambert,walter --subsample 20000 --quiet --html "$R" --json "$tmp/r.json" \
     >/dev/null 2>"$tmp/err"; then
  ok
else
  bad "compare --html failed: $(cat "$tmp/err")"
fi
for f in viewer.js m1-viewer.js m2-viewer.js m3-viewer.js m4-viewer.js; do
  [ -s "$R/$f" ] && ok || bad "no $f in the report"
done
grep -q '<script src="viewer.js"></script>' "$R/index.html" && ok || bad "the page does not load viewer.js"
# The page names nothing off the disk.
grep -Eq '(src|href)="(https?:)?//' "$R/index.html" "$R"/*.js && bad "the report refers to the network" || ok

# Directions: incidence and view from 10 to 80 degrees, azimuths around; the check keeps
# those within 75 degrees of the normal and 8 degrees or more from the half-vector's peak.
{
  echo theta_i,phi_i,theta_o,phi_o
  for ti in 10 25 40 55 70; do
    for to in 5 20 35 50 65 80; do
      for po in 0 45 110 180 250 320; do echo "$ti,15,$to,$po"; done
    done
  done
} > "$tmp/dirs.csv"

values='[]'
add_check() { # material model expected.csv [expected-at-o,i.csv]
  values=$(jq -c --arg m "$1" --arg n "$2" --arg d "$tmp/dirs.csv" --arg e "$3" --arg s "${4:-}" \
    '. + [{material: $m, model: $n, dirs: $d, expected: $e} + (if $s == "" then {} else {expected_swapped: $s} end)]' \
    <<<"$values")
}
# Every fitted model of every material, against brdfit eval of its parameters.
for i in 0 1 2 3; do
  for j in 0 1; do
    jq ".materials[$i].fits[$j] | {model: .spec, params}" "$tmp/r.json" > "$tmp/p$i$j.json"
    name=$(jq -r ".materials[$i].fits[$j].model" "$tmp/r.json")
    if "$BRDFIT" eval --params "$tmp/p$i$j.json" --dirs "$tmp/dirs.csv" -o "$tmp/e$i$j.csv" 2>"$tmp/err"; then
      add_check "m$((i + 1))" "$name" "$tmp/e$i$j.csv"
    else
      bad "eval m$((i + 1)) $name: $(cat "$tmp/err")"
    fi
  done
done
# The measurements: the MERL table against the model that made it; the RGL file against
# its own reader at the same directions.
"$BRDFIT" eval --params "$tmp/wm.json" --dirs "$tmp/dirs.csv" -o "$tmp/m1.csv" && add_check m1 measured "$tmp/m1.csv" ||
  bad "eval of the MERL table's model"
# The RGL file is not reciprocal near its highlight: the reader at (o, i) too.
awk -F, 'NR == 1 {print; next} {print $3 "," $4 "," $1 "," $2}' "$tmp/dirs.csv" > "$tmp/dirs_swapped.csv"
"$BRDFIT" convert "$EX/rgl/cc_ibiza_sunset_rgb.bsdf" "$tmp/m2.csv" --grid "$tmp/dirs.csv" 2>"$tmp/err" &&
  "$BRDFIT" convert "$EX/rgl/cc_ibiza_sunset_rgb.bsdf" "$tmp/m2s.csv" --grid "$tmp/dirs_swapped.csv" 2>"$tmp/err" &&
  add_check m2 measured "$tmp/m2.csv" "$tmp/m2s.csv" || bad "RGL reader at the directions: $(cat "$tmp/err")"

mkdir -p "$tmp/shots"
jq -n --arg r "$R" --arg c "$chromium" --arg s "${BRDFIT_VIEWER_SHOTS:-}" --argjson v "$values" \
  '{report: $r, chromium: $c, shots: (if $s == "" then null else $s end), tolerance: {model: {p95: 0.03, max: 0.06}, measured: {p95: 0.10, max: 0.20}},
    min_theta_h: 8, max_theta: 75, values: $v}' > "$tmp/spec.json"
if node "$here/browser/viewer_check.js" "$tmp/spec.json" > "$tmp/check.out" 2>&1; then
  ok
else
  bad "the viewer in Chromium:"
fi
n=$(grep -c '^ok ' "$tmp/check.out")
[ "$n" -ge 40 ] && ok || bad "only $n browser checks passed"
sed "s/^/  /" "$tmp/check.out" | grep -E "FAIL|relative error"

# brdfit report of a batch database: no measurement (the data is not read again), the
# models' views work the same.
printf '{"models": ["lambert", "walter"], "options": ["--threads", "1", "--subsample", "5000"], "materials": ["%s"]}' \
  "$tmp/wm.binary" > "$tmp/batch.json"
if "$BRDFIT" batch "$tmp/batch.json" -o "$tmp/b.db" 2>"$tmp/err" &&
   "$BRDFIT" report "$tmp/b.db" --html "$tmp/brep" >/dev/null 2>"$tmp/err"; then
  jq '.report = $r | .values = [] | .shots = null' --arg r "$tmp/brep" "$tmp/spec.json" > "$tmp/spec2.json"
  node "$here/browser/viewer_check.js" "$tmp/spec2.json" > "$tmp/check2.out" 2>&1 && ok || bad "brdfit report's viewer:"
  grep -q 'no measured data was given to the report' "$tmp/brep/m1-viewer.js" && ok || bad "report: no reason for no measurement"
  sed "s/^/  /" "$tmp/check2.out" | grep FAIL
else
  bad "batch and report: $(cat "$tmp/err")"
fi
finish
