#!/usr/bin/env bash
# Conductor Fresnel end to end: a gold-like metal made by brdfit-synth (microfacet
# F=conductor) is recovered by brdfit fit to 1e-6 without noise, the result file gives
# its complex index n, k, and Schlick's Fresnel fits the same data worse (noiseless and
# with 2% noise).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

cat > "$tmp/gold.json" <<'JSON'
{"model": "microfacet", "options": {"D": "ggx", "G": "smith_ggx", "F": "conductor"}, "channels": 3,
 "params": {"rho_d": [0.02, 0.01, 0.005], "rho_s": [1, 1, 1], "alpha": 0.2,
            "r": [0.944, 0.776, 0.373], "g": [0.998, 0.981, 0.751]}}
JSON
"$SYNTH" --params "$tmp/gold.json" --pattern stratified --count 4096 -o "$tmp/gold.csv" -q && ok || bad "synth"
"$SYNTH" --params "$tmp/gold.json" --pattern stratified --count 4096 --noise 0.02 --seed 3 \
  -o "$tmp/gold_noisy.csv" -q && ok || bad "synth noisy"

"$BRDFIT" fit "$tmp/gold.csv" -m "microfacet:D=ggx,G=smith_ggx,F=conductor" -o "$tmp/c.json" -q && ok ||
  bad "conductor fit failed"
jq -e --slurpfile t "$tmp/gold.json" '
  def near($a; $b): ($a - $b | fabs) < 1e-6;
  .params as $p | $t[0].params as $w |
  .ok and ([range(3) as $i | near($p.r[$i]; $w.r[$i]) and near($p.g[$i]; $w.g[$i])
              and near($p.rho_s[$i]; 1) and near($p.rho_d[$i]; $w.rho_d[$i])] | all)
  and near($p.alpha; 0.2)' "$tmp/c.json" >/dev/null && ok || bad "gold not recovered: $(jq -c .params "$tmp/c.json")"
# n + ik of gold at the r, g, b primaries' wavelengths is about 0.17+3.3i, 0.42+2.4i,
# 1.4+1.8i (Johnson & Christy 1972: 0.16+3.5i at 650 nm, 0.43+2.5i at 550, 1.4+1.9i at 450).
jq -e '(.conductor.n | length) == 3 and .conductor.n[0] < 0.3 and .conductor.k[0] > 3 and
       .conductor.n[2] > 1 and .conductor.n[2] < 2 and .conductor.k[2] > 1.5' "$tmp/c.json" >/dev/null &&
  ok || bad "n, k: $(jq -c .conductor "$tmp/c.json")"

for data in gold gold_noisy; do
  "$BRDFIT" fit "$tmp/$data.csv" -m "walter:fresnel=conductor" -o "$tmp/wc.json" -q &&
    "$BRDFIT" fit "$tmp/$data.csv" -m "walter:fresnel=schlick" -o "$tmp/ws.json" -q && ok || bad "walter fits"
  c=$(jq .metrics.rmse "$tmp/wc.json") s=$(jq .metrics.rmse "$tmp/ws.json")
  awk -v c="$c" -v s="$s" 'BEGIN { exit !(c < 0.5 * s) }' && ok ||
    bad "$data: conductor rmse $c is not below half of Schlick's $s"
  jq -e 'has("conductor") | not' "$tmp/ws.json" >/dev/null && ok || bad "Schlick result has n, k"
done

finish
