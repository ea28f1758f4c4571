#!/usr/bin/env bash
# brdfit compare --reference from the shell: a synthetic material made from a parameter
# file, compared with that file as the reference (its objective is the noise's, brdfit's
# no higher, no warning); a reference set with a deliberately bad fit of the material
# (brdfit better) whose values lie outside the bounds (named); a crippled fit
# (--max-iterations 1 --starts 1) that the true parameters beat (the reference_better
# warning, in the summary, the JSON, the CSV and the report); a folder of references in
# name order; bad reference files (one line naming file and line, exit 1, no output).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

mkdir -p "$tmp/refs"
cat > "$tmp/refs/gold.json" <<'EOF'
{"model": "ward_iso", "channels": 3,
 "params": {"rho_d": [0.3, 0.2, 0.1], "rho_s": [0.2, 0.2, 0.2], "alpha": 0.12}}
EOF
cat > "$tmp/set.json" <<'EOF'
{"source": "A Test Lab 2024", "table": "ward_fits",
 "materials": {
  "silver": {"model": "ward_iso", "channels": 3,
    "params": {"rho_d": [0.1, 0.1, 0.1], "rho_s": [0.5, 0.5, 0.5], "alpha": 0.05}},
  "gold": {"model": "ward_iso", "channels": 3,
    "params": {"rho_d": [0.5, 0.2, 0.1], "rho_s": [1.3, 0.2, 0.2], "alpha": 0.3}},
  "gold ": {"model": "lambert", "channels": 3, "params": {"rho_d": [0.5, 0.2, 0.1]}}
 }}
EOF
"$SYNTH" --params "$tmp/refs/gold.json" --pattern stratified --count 2000 --noise 0.02 --seed 3 \
  -o "$tmp/gold.csv" || bad "brdfit-synth failed"
FAST=(--threads 2 --starts 2 --screen 8)

# --- the generating parameters as the reference -----------------------------------------
if "$BRDFIT" compare "$tmp/gold.csv" -m ward_iso,lambert "${FAST[@]}" --reference "$tmp/refs/gold.json" \
     --reference "$tmp/set.json" --json "$tmp/r.json" --csv "$tmp/r.csv" -q >"$tmp/out" 2>"$tmp/err"; then
  ok
  # The truth's objective is the noise's: within a few per cent of brdfit's optimum, and
  # not below it; the bad published fit is far above, its values outside the bounds named.
  jq -e --arg f "$tmp/refs/gold.json" '
      .materials[0].fits[0] as $w
      | ($w.references | length) == 2
      and $w.references[0].file == $f and $w.references[0].source == $f and $w.references[0].table == null
      and $w.references[0].material == "gold" and $w.references[0].spec == "ward_iso"
      and $w.references[0].brdfit_cost <= $w.references[0].cost
      and $w.references[0].cost < 1.05 * $w.references[0].brdfit_cost
      and ($w.references[0].rmse_log - $w.rmse_log | fabs) < 0.05 * $w.rmse_log
      and $w.references[0].error == $w.references[0].rmse_log
      and $w.references[0].outside_bounds == false and $w.references[0].outside == []
      and $w.references[0].brdfit_worse == false and $w.references[0].message == null
      and $w.references[0].params.alpha == 0.12
      and $w.references[1].source == "A Test Lab 2024" and $w.references[1].table == "ward_fits"
      and $w.references[1].line == 5
      and $w.references[1].cost > 10 * $w.references[1].brdfit_cost
      and $w.references[1].outside_bounds == true and $w.references[1].outside == ["rho_s[0]"]
      and $w.references[1].brdfit_worse == false
      and ([$w.warnings[] | select(test("reference"))] | length) == 0
      and .materials[0].fits[1].references == []' "$tmp/r.json" >/dev/null && ok || bad "JSON: $(jq -c '.materials[0].fits[0].references' "$tmp/r.json")"
  grep -q "reference ward_iso: A Test Lab 2024, ward_fits: objective .*outside the bounds: rho_s\[0\]" "$tmp/out" &&
    ok || bad "summary: $(cat "$tmp/out")"
  ! grep -q "worse" "$tmp/out" && ok || bad "a warning where brdfit is better: $(cat "$tmp/out")"
  head -1 "$tmp/r.csv" | grep -q ',references,reference_cost,reference_rmse_log,reference_outside_bounds,brdfit_worse,' &&
    ok || bad "CSV header: $(head -1 "$tmp/r.csv")"
  grep -q "^$tmp/gold.csv,ward_iso,.*A Test Lab 2024 (ward_fits).*,\"\?0; 1\"\?,\"\?0; 0\"\?," "$tmp/r.csv" && ok ||
    bad "CSV row: $(grep ward_iso "$tmp/r.csv")"
else
  bad "compare with references: $(cat "$tmp/err")"
fi

# --- a crippled fit: the reference is better, and says so -------------------------------
if "$BRDFIT" compare "$tmp/gold.csv" -m ward_iso --threads 2 --starts 1 --max-iterations 1 --reference "$tmp/refs" \
     --json "$tmp/c.json" --csv "$tmp/c.csv" --html "$tmp/html" >"$tmp/out" 2>"$tmp/err"; then
  ok
  jq -e '.materials[0].fits[0] as $w | $w.references[0].brdfit_worse == true
      and $w.references[0].brdfit_cost > $w.references[0].cost
      and ([$w.warnings[] | select(startswith("gold, ward_iso: brdfit'"'"'s objective "))] | length) == 1' \
    "$tmp/c.json" >/dev/null && ok || bad "crippled JSON: $(jq -c '.materials[0].fits[0].warnings' "$tmp/c.json")"
  grep -q "warning: ward_iso: gold, ward_iso: brdfit's objective [0-9.e-]* is above [0-9.e-]*, the reference's ($tmp/refs/gold.json): the search missed a better optimum" \
    "$tmp/out" && ok || bad "crippled summary: $(cat "$tmp/out")"
  grep -q "objective [0-9.e-]* (brdfit [0-9.e-]*, worse)" "$tmp/out" && ok || bad "worse not shown: $(cat "$tmp/out")"
  grep -q ',1$\|,1,' "$tmp/c.csv" && ok || bad "CSV brdfit_worse"
  grep -q 'class="worse"' "$tmp/html/index.html" && grep -q "its search missed a better optimum" "$tmp/html/index.html" &&
    ok || bad "the report shows no reference"
else
  bad "crippled compare: $(cat "$tmp/err")"
fi

# --- a folder, read in name order -------------------------------------------------------
cp "$tmp/set.json" "$tmp/refs/a_set.json"
echo "not json" > "$tmp/refs/notes.txt"
if "$BRDFIT" compare "$tmp/gold.csv" -m ward_iso "${FAST[@]}" --reference "$tmp/refs" --json "$tmp/d.json" -q \
     >/dev/null 2>"$tmp/err"; then
  jq -e '[.materials[0].fits[0].references[].source] | .[0] == "A Test Lab 2024" and (.[1] | endswith("gold.json"))' \
    "$tmp/d.json" >/dev/null && ok || bad "folder order: $(jq -c '[.materials[0].fits[0].references[].file]' "$tmp/d.json")"
else
  bad "folder: $(cat "$tmp/err")"
fi

# --- bad reference files: one line, exit 1, no output ------------------------------------
printf '{"source": "x",\n "materials": {\n  "gold": {"model": "ward_iso",\n   "params": {"rho_d": 0.1, "rho_s": 0.1, "alpha": "wide"}}}}\n' \
  > "$tmp/bad.json"
printf '{"source": "x", "materials": ' > "$tmp/cut.json"
check_bad() { # FILE EXPECTED-FRAGMENT
  rm -f "$tmp/x.json"
  "$BRDFIT" compare "$tmp/gold.csv" -m ward_iso "${FAST[@]}" --reference "$1" --json "$tmp/x.json" -q \
    >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [ $rc = 1 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -qF "$2" "$tmp/err" && [ ! -e "$tmp/x.json" ] &&
    [ ! -s "$tmp/out" ] && ok || bad "bad reference $1: exit $rc, $(cat "$tmp/err")"
}
check_bad "$tmp/bad.json" "brdfit compare: $tmp/bad.json:4: materials/gold: parameter alpha: expected a number"
check_bad "$tmp/cut.json" "brdfit compare: $tmp/cut.json:1: malformed JSON"
check_bad "$tmp/nosuch.json" "$tmp/nosuch.json: cannot open"
mkdir -p "$tmp/empty"
check_bad "$tmp/empty" "$tmp/empty: a folder without a *.json reference file"
"$BRDFIT" compare "$tmp/gold.csv" -m ward_iso --reference "" -q >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q -- "--reference needs a file or a folder" "$tmp/err" && ok || bad "empty --reference: $(cat "$tmp/err")"

finish
