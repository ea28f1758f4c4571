#!/usr/bin/env bash
# --scene from the shell: info reports what a scene kept (and --subsample counts inside
# it); fit and compare run on the scene's samples, and the model selection follows the
# scene; a bad scene file is one line naming file:line, exit 1, and no output file.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq
EXAMPLES=$(cd "$DATA/../../examples" && pwd)
CAYMAN=$EXAMPLES/cornell/cayman.brdf
SHOT=$EXAMPLES/scenes/product_shot.json
TURN=$EXAMPLES/scenes/turntable.json

# --- info: the product shot keeps the samples with both angles inside its ranges ------
out=$("$BRDFIT" info "$CAYMAN" --rgb --json) || bad "info without scene"
all=$(echo "$out" | jq .samples)
out=$("$BRDFIT" info "$CAYMAN" --rgb --scene "$SHOT" --json) || bad "info --scene failed"
echo "$out" | jq -e --argjson all "$all" --arg f "$SHOT" '
    .samples < $all and .samples > 0 and .scene.file == $f and .scene.samples_in == $all
    and .scene.kept == .samples and .prep.kept == .samples and .weighted == false
    and .coverage_deg.theta_i.max <= 60 and .coverage_deg.theta_o.max <= 60' >/dev/null \
  && ok || bad "info --scene: $(echo "$out" | jq -c '{samples, scene, coverage_deg}')"
kept=$(echo "$out" | jq .scene.kept)
"$BRDFIT" info "$CAYMAN" --rgb --scene "$SHOT" | grep -q "^scene $SHOT: kept $kept of $all samples" \
  && ok || bad "info text: no scene line"
# Subsampling happens inside the scene.
"$BRDFIT" info "$CAYMAN" --rgb --scene "$SHOT" --subsample 100 --seed 3 --json |
  jq -e --argjson k "$kept" '.samples == 100 and .scene.kept == $k and .prep.subsampled_out == $k - 100' \
  >/dev/null && ok || bad "info --scene --subsample"
# Explicit directions weigh the samples they keep.
"$BRDFIT" info "$CAYMAN" --rgb --scene "$TURN" --json |
  jq -e --argjson all "$all" '.weighted == true and .samples < $all and .scene.kept == .samples' >/dev/null \
  && ok || bad "info --scene turntable"

# --- fit: on the scene's samples only --------------------------------------------------
if "$BRDFIT" fit "$CAYMAN" --rgb --scene "$SHOT" -m ward --threads 2 -o "$tmp/fit.json" >/dev/null 2>"$tmp/err"; then
  jq -e --argjson k "$kept" '.metrics.n == 3 * $k' "$tmp/fit.json" >/dev/null && ok || bad "fit --scene: n"
else
  bad "fit --scene: $(cat "$tmp/err")"
fi

# --- compare: the selection follows the scene ------------------------------------------
# Walter data everywhere, except that inside the product shot the material is exactly
# Lambertian: over all directions Walter is needed, over the scene Lambert suffices.
cat > "$tmp/wal.json" <<'JSON'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 1,
 "params": {"rho_d": 0.3, "rho_s": 0.8, "alpha": 0.1, "f0": 0.05}}
JSON
"$SYNTH" --params "$tmp/wal.json" --pattern uniform --count 1500 --seed 4 -o "$tmp/w.csv" || bad "synth failed"
awk -F, 'NR == 1 || /^#/ { print; next }
  { ti = $1; to = $3; inside = (ti <= 45 && to <= 60) || (to <= 45 && ti <= 60)
    if (inside) $5 = 0.3 / 3.141592653589793; print }' OFS=, "$tmp/w.csv" > "$tmp/mix.csv"
"$BRDFIT" compare "$tmp/mix.csv" -m lambert,walter --threads 2 --quiet --json "$tmp/all.json" >/dev/null 2>&1 \
  && ok || bad "compare without scene"
if "$BRDFIT" compare "$tmp/mix.csv" -m lambert,walter --threads 2 --quiet --scene "$SHOT" --json "$tmp/shot.json" \
     >"$tmp/out" 2>"$tmp/err"; then
  ok
  grep -q "^scene $SHOT: errors" "$tmp/out" && ok || bad "compare: no scene line: $(cat "$tmp/out")"
  jq -e '.materials[0].simplest == "walter"' "$tmp/all.json" >/dev/null && ok \
    || bad "compare without scene: $(jq -c '.materials[0] | {simplest, samples}' "$tmp/all.json")"
  jq -e --slurpfile a "$tmp/all.json" '.materials[0].simplest == "lambert"
      and .materials[0].samples < $a[0].materials[0].samples
      and .materials[0].fits[0].error < 1e-6' "$tmp/shot.json" >/dev/null && ok \
    || bad "compare --scene: $(jq -c '.materials[0] | {simplest, samples, e: [.fits[].error]}' "$tmp/shot.json")"
else
  bad "compare --scene: $(cat "$tmp/err")"
fi

# --- bad scene files: exit 1, file:line, no output -------------------------------------
printf '{\n  "light": {"theta": [0, 45]},\n  "view": {"theta": [70, 60]}\n}\n' > "$tmp/lohi.json"
printf '{\n  "lights": [{"theta": 30, "weight": 0}]\n}\n' > "$tmp/w0.json"
printf '{\n  "radius": 5,,\n}\n' > "$tmp/syntax.json"
printf '{\n  "description": "x",\n  "camera": {}\n}\n' > "$tmp/key.json"
printf '{"light": {"theta": [89, 90]}, "view": {"theta": [89, 90]}}\n' > "$tmp/none.json"
expect() { # status pattern command args...
  local want=$1 pat=$2; shift 2
  rm -f "$tmp/o.json"
  "$BRDFIT" "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [ "$rc" = "$want" ] || bad "$*: exit $rc, expected $want"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$pat" "$tmp/err" && ok || bad "$*: stderr '$(cat "$tmp/err")'"
  [ -e "$tmp/o.json" ] && bad "$*: left an output file"
  ok
}
expect 1 "lohi.json:3: view.theta: lower bound 70 > upper bound 60" info "$CAYMAN" --scene "$tmp/lohi.json"
expect 1 "w0.json:2: lights\[0\].weight = 0 must be > 0" fit "$CAYMAN" --rgb -m lambert --scene "$tmp/w0.json" -o "$tmp/o.json"
expect 1 "syntax.json:2: malformed JSON" compare "$CAYMAN" --rgb -m lambert --scene "$tmp/syntax.json" --json "$tmp/o.json"
expect 1 "key.json:3: unknown key \"camera\"" fit "$CAYMAN" --rgb -m lambert --scene "$tmp/key.json" -o "$tmp/o.json"
expect 1 "no sample lies in the scene" compare "$CAYMAN" --rgb -m lambert --scene "$tmp/none.json" --json "$tmp/o.json"
expect 1 "missing.json: cannot open" info "$CAYMAN" --scene "$tmp/missing.json"
expect 2 "--scene needs a value" info "$CAYMAN" --scene

finish
