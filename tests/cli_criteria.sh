#!/usr/bin/env bash
# Ranking criteria on nested models: lambert within walter within walter:lobes=2. Data
# from each, at two noise levels and two sample counts, with noise whose form the fit's
# residual matches (relative noise with --residual relative, additive noise with
# --residual linear: the Gaussian noise model of the criteria holds, docs/criteria.md).
# BIC must rank the generating model first and cross-validation's simplest model within
# tolerance must be it too (neither may pick a bigger one); the robust-loss refusal;
# select --rank.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

cat > "$tmp/lambert.json" <<'J'
{"model": "lambert", "channels": 1, "params": {"rho_d": [0.5]}}
J
cat > "$tmp/walter.json" <<'J'
{"model": "walter", "options": {"fresnel": "schlick"}, "channels": 1,
 "params": {"rho_d": [0.3], "rho_s": [0.6], "alpha": 0.25, "f0": 0.05}}
J
cat > "$tmp/walter2.json" <<'J'
{"model": "walter", "options": {"fresnel": "schlick", "lobes": 2}, "channels": 1,
 "params": {"rho_d": [0.3], "rho_s_1": [0.6], "alpha_1": 0.08, "f0_1": 0.05,
            "rho_s_2": [0.5], "alpha_2": 0.4, "f0_2": 0.05}}
J
MODELS=lambert,walter,walter:lobes=2
declare -A WANT=([lambert]=lambert [walter]=walter [walter2]=walter:lobes=2)

# model noise-model residual level count seed
check() {
  local g=$1 nm=$2 res=$3 level=$4 n=$5 seed=$6 what="$1 $2 noise $4, $5 samples, seed $6"
  "$SYNTH" --params "$tmp/$g.json" --pattern uniform --count "$n" --noise "$level" --noise-model "$nm" \
    --seed "$seed" -o "$tmp/d.csv" 2>/dev/null || { bad "$what: synth"; return; }
  if "$BRDFIT" compare "$tmp/d.csv" -m $MODELS --residual "$res" --quiet --json "$tmp/b.json" >/dev/null 2>&1; then
    local first
    first=$(jq -r '.materials[0].fits[] | select(.rank == 1) | .model' "$tmp/b.json")
    [ "$first" = "${WANT[$g]}" ] && ok || bad "$what: BIC ranks $first first"
  else
    bad "$what: compare --rank bic failed"
  fi
  if "$BRDFIT" compare "$tmp/d.csv" -m $MODELS --residual "$res" --rank cv --folds 4 --quiet --json "$tmp/c.json" \
       >/dev/null 2>&1; then
    local pick
    pick=$(jq -r '.materials[0].simplest' "$tmp/c.json")
    [ "$pick" = "${WANT[$g]}" ] && ok || bad "$what: cross-validation picks $pick"
  else
    bad "$what: compare --rank cv failed"
  fi
}
for g in lambert walter walter2; do
  for n in 1000 4000; do
    check $g relative relative 0.01 $n 1
    check $g relative relative 0.05 $n 2
    check $g additive linear 0.003 $n 3
    check $g additive linear 0.03 $n 4
  done
done

# select ranks the same way: --rank bic picks the lowest BIC, the default (error within
# tolerance) the smallest good enough.
"$SYNTH" --params "$tmp/walter.json" --pattern uniform --count 2000 --noise 0.01 --seed 5 -o "$tmp/w.csv" 2>/dev/null
if "$BRDFIT" select "$tmp/w.csv" -m $MODELS --residual relative --rank bic --quiet --json "$tmp/s.json" >"$tmp/out" 2>&1; then
  jq -e '.rank_by == "bic" and .chosen == "walter"
    and ([.candidates[] | select(.rank == 1) | .model] == ["walter"])
    and all(.candidates[]; (.criterion | type) == "number" and .criterion == .metrics.bic)' "$tmp/s.json" >/dev/null \
    && ok || bad "select --rank bic: $(jq -c '[.candidates[] | [.model, .rank, .criterion]]' "$tmp/s.json")"
  grep -q '^chosen: walter (k 4, lowest bic' "$tmp/out" && ok || bad "select --rank bic text: $(cat "$tmp/out")"
else
  bad "select --rank bic failed: $(cat "$tmp/out")"
fi
"$BRDFIT" select "$tmp/w.csv" -m $MODELS --residual relative --rank cv --folds 3 --quiet --json "$tmp/s.json" \
  >/dev/null 2>&1 && jq -e '.rank_by == "cv" and .folds == 3 and .chosen == "walter"
    and all(.candidates[]; .cv > 0 and .error == .cv)' "$tmp/s.json" >/dev/null && ok || bad "select --rank cv"
"$BRDFIT" select "$tmp/w.csv" -m lambert --loss cauchy --rank aic >/dev/null 2>"$tmp/err"
[ $? = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q 'robust loss' "$tmp/err" && ok ||
  bad "select: a criterion with a robust loss not refused: $(cat "$tmp/err")"
"$BRDFIT" select "$tmp/w.csv" -m lambert,walter --loss cauchy --rank cv --folds 2 --quiet >/dev/null 2>&1 && ok ||
  bad "select: a robust loss with --rank cv refused"

# The bundled Cornell paints (spectral, and cayman as RGB): among models with the same
# number of parameters, BIC and AIC order them as their fitted error does (the criteria
# come from the residuals the fit minimised).
EX="$DATA/../../examples/cornell"
PAINT_MODELS=lambert,blinn_phong,ward_iso,ashikhmin_shirley_iso,cook_torrance,walter
for args in "$EX/garnet_red.brdf $EX/cayman.brdf" "$EX/cayman.brdf --rgb"; do
  if "$BRDFIT" compare $args -m $PAINT_MODELS --quiet --json "$tmp/p.json" >/dev/null 2>&1; then
    jq -e '[.materials[] | .fits as $f | $f[] as $a | $f[] as $b
             | select($a.k == $b.k and $a.error < $b.error)
             | ($a.bic < $b.bic and $a.aic < $b.aic and $a.rank < $b.rank)] | length > 0 and all' "$tmp/p.json"       >/dev/null && ok || bad "Cornell ($args): criteria disagree with the error at equal k: \
$(jq -c '[.materials[].fits[] | [.model, .k, .error, .bic]]' "$tmp/p.json")"
  else
    bad "Cornell compare $args failed"
  fi
done

finish
