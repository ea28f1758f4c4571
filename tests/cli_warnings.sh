#!/usr/bin/env bash
# Fit diagnostics where users see them: the Disney fit of the spectral Cornell garnet
# paint (undetermined parameters, parameters at bounds, 31 channels in one warning),
# ward_iso on a synthetic Walter MERL table (a diffuse colour pinned at 0), and the
# same warnings in compare's text, JSON and CSV and in a clean fit's absence of them; in the
# HTML report several warnings of a fit collapse to their count (expandable), one stays
# as it is.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq
EX="$DATA/../../examples"

if "$BRDFIT" fit "$EX/cornell/garnet_red.brdf" -m disney -o "$tmp/g.json" >"$tmp/out" 2>&1; then
  # One line per parameter and problem; the spectral base colour's 31 channels in one.
  jq -e '(.warnings | length) >= 6
    and (.warnings | index("clearcoat = 1 is at its upper bound 1")) != null
    and any(.warnings[]; test("^base_color is not determined by the data in [0-9]+ of 31 channels"))
    and ([.warnings[] | select(startswith("base_color"))] | length) <= 2
    and any(.warnings[]; test("^sheen = [0-9.]+ is not determined by the data"))' "$tmp/g.json" >/dev/null \
    && ok || bad "garnet disney warnings: $(jq -c .warnings "$tmp/g.json")"
  [ "$(grep -c '^  warning: ' "$tmp/out")" = "$(jq '.warnings | length' "$tmp/g.json")" ] && ok ||
    bad "garnet disney: text and JSON warnings differ: $(cat "$tmp/out")"
else
  bad "garnet disney fit: $(cat "$tmp/out")"
fi

"$SYNTH" --params "$EX/walter_rgb.json" --pattern merl --noise 0.02 -o "$tmp/w.binary" 2>/dev/null ||
  bad "brdfit-synth merl"
if "$BRDFIT" compare "$tmp/w.binary" -m ward_iso,walter --quiet --json "$tmp/c.json" --csv "$tmp/c.csv" \
     >"$tmp/out" 2>&1; then
  jq -e '.materials[0].fits[0].warnings as $w
    | ($w | index("rho_d: channels 1, 2 at the lower bound 0")) != null
    and ([$w[] | select(startswith("rho_d"))] | length) == 1
    and (.materials[0].fits[0].params.rho_d[0] - 0.23 | fabs) < 0.02
    and ([.materials[0].fits[1].warnings[] | select(test("bound|determined|correlated"))] | length) == 0' \
    "$tmp/c.json" >/dev/null && ok || bad "MERL ward_iso warnings: $(jq -c '[.materials[0].fits[].warnings]' "$tmp/c.json")"
  grep -q '^  warning: ward_iso: rho_d: channels 1, 2 at the lower bound 0$' "$tmp/out" && ok ||
    bad "compare text warnings: $(cat "$tmp/out")"
  # CSV: the warnings column, one field; parameter columns per channel
  awk -F'"' 'NR > 1 && /^[^,]*,ward_iso,/ { found = index($0, ",\"rho_d: channels 1, 2 at the lower bound 0\",") > 0 }
             END { exit !found }' "$tmp/c.csv" && ok || bad "compare CSV warnings: $(cat "$tmp/c.csv")"
  head -1 "$tmp/c.csv" | grep -q ',rho_d\[0\],rho_d\[1\],rho_d\[2\],' && head -1 "$tmp/c.csv" | grep -q ',alpha' && ok ||
    bad "compare CSV parameter columns: $(head -1 "$tmp/c.csv")"
else
  bad "MERL compare: $(cat "$tmp/out")"
fi


# The HTML report: the RGL paper's Disney fit (several warnings) collapsed to its count,
# every warning inside; the walter fit of the same material (one) as it is; and pictures
# of the measurement, the .bsdf evaluated on the MERL cells (a measured sphere and
# half/difference image beside the models').
if "$BRDFIT" compare "$EX/rgl/paper_white_rgb.bsdf" -m walter,disney --quiet --json "$tmp/r.json" --html "$tmp/r" \
     >"$tmp/out" 2>&1; then
  nd=$(jq '.materials[0].fits[1].warnings | length' "$tmp/r.json")
  nw=$(jq '.materials[0].fits[0].warnings | length' "$tmp/r.json")
  [ "$nd" -gt 1 ] && grep -q "<details><summary>$nd warnings</summary>" "$tmp/r/index.html" && ok ||
    bad "report: disney's $nd warnings not collapsed: $(grep -o '<td class="warn">.\{0,80\}' "$tmp/r/index.html")"
  [ "$(grep -o '<details>' "$tmp/r/index.html" | wc -l)" = "$(jq '[.materials[0].fits[] | select((.warnings | length) > 1)] | length' "$tmp/r.json")" ] &&
    ok || bad "report: a <details> per fit with several warnings"
  [ -s "$tmp/r/m1-sphere-measured.png" ] && [ -s "$tmp/r/m1-hd-measured.png" ] &&
    grep -q 'src="m1-sphere-measured.png"' "$tmp/r/index.html" && ok ||
    bad "report: no picture of the RGL measurement: $(ls "$tmp/r")"
  [ "$nw" != 1 ] || grep -q "<td class=\"warn\">$(jq -r '.materials[0].fits[0].warnings[0]' "$tmp/r.json" | sed 's/[][\.*^$]/\\&/g')</td>" "$tmp/r/index.html" && ok ||
    bad "report: walter's one warning not shown as it is"
else
  bad "RGL compare --html: $(cat "$tmp/out")"
fi
finish
