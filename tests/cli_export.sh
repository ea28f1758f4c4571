#!/usr/bin/env bash
# brdfit export: exact mapping of native results (glTF, Blender, Mitsuba), the Khronos validator on
# the .gltf, a conversion whose reported error matches brdfit eval of source against
# converted parameters, refusals (anisotropic, multi-lobe, channels, target) with no
# output left behind, and byte-identical reruns.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq; need xmllint libxml2-utils; need node nodejs; need /usr/bin/python3 python3
here=$(cd "$(dirname "$0")" && pwd)
validator="$here/../tools/node_modules/gltf-validator"

cat > "$tmp/g.json" <<'EOF'
{"model":"gltf","channels":3,"params":{"base_color":[0.8,0.3,0.1],"metallic":0.2,"roughness":0.4,"specular":0.9,"specular_color":[1,1.2,0.9],"ior":1.6}}
EOF
cat > "$tmp/b.json" <<'EOF'
{"model":"blender_principled","channels":3,"params":{"base_color":[0.7,0.5,0.2],"metallic":0.1,"specular":0.6,"specular_tint":0.25,"roughness":0.3,"sheen":0.2,"sheen_tint":0.4,"clearcoat":0.5,"clearcoat_roughness":0.1}}
EOF
cat > "$tmp/w.json" <<'EOF'
{"model":"walter","channels":3,"params":{"rho_d":[0.3,0.2,0.1],"rho_s":[0.5,0.5,0.5],"alpha":0.2,"f0":0.04}}
EOF
cat > "$tmp/l1.json" <<'EOF'
{"model":"lambert","channels":1,"params":{"rho_d":0.4}}
EOF

# --- glTF, exact ----------------------------------------------------------------
"$BRDFIT" export "$tmp/g.json" --to gltf -o "$tmp/g.gltf" 2>"$tmp/err" && ok || bad "export gltf: $(cat "$tmp/err")"
[ ! -s "$tmp/err" ] && ok || bad "an exact export reports a conversion: $(cat "$tmp/err")"
jq -e '.materials[0] as $m
  | $m.pbrMetallicRoughness.baseColorFactor == [0.8,0.3,0.1,1]
  and $m.pbrMetallicRoughness.metallicFactor == 0.2 and $m.pbrMetallicRoughness.roughnessFactor == 0.4
  and $m.extensions.KHR_materials_specular.specularFactor == 0.9
  and $m.extensions.KHR_materials_specular.specularColorFactor == [1,1.2,0.9]
  and $m.extensions.KHR_materials_ior.ior == 1.6
  and (.extensionsUsed | sort) == ["KHR_materials_ior","KHR_materials_specular"]
  and .asset.version == "2.0" and .asset.extras.brdfit.converted == false
  and .meshes[0].primitives[0].material == 0
  and (.buffers[0].uri | startswith("data:application/octet-stream;base64,"))' "$tmp/g.gltf" >/dev/null &&
  ok || bad "glTF material is not the exact copy of the gltf parameters"
# The embedded buffer decodes to its declared length.
len=$(jq -r '.buffers[0].uri' "$tmp/g.gltf" | sed 's/^data:[^,]*,//' | base64 -d | wc -c)
[ "$len" = "$(jq '.buffers[0].byteLength' "$tmp/g.gltf")" ] && ok || bad "buffer decodes to $len bytes"

# --- the Khronos validator ------------------------------------------------------------
if [ -d "$validator" ]; then
  for f in g; do
    node "$here/gltf_validate.js" "$validator" "$tmp/$f.gltf" > "$tmp/issues" 2>&1 && ok ||
      bad "glTF validator reports errors on $f.gltf: $(cat "$tmp/issues")"
    jq -e '.numErrors == 0 and .numWarnings == 0' "$tmp/issues" >/dev/null && ok ||
      bad "glTF validator issues on $f.gltf: $(cat "$tmp/issues")"
  done
else
  bad "the glTF validator is not installed ($validator, node): run scripts/setup.sh"
fi

# --- Blender, exact ---------------------------------------------------------------------
"$BRDFIT" export "$tmp/b.json" --to blender -o "$tmp/b.py" 2>"$tmp/err" && ok || bad "export blender: $(cat "$tmp/err")"
for line in 'bsdf.distribution = "GGX"' \
            'bsdf.inputs["Base Color"].default_value = (0.7, 0.5, 0.2, 1.0)' \
            'bsdf.inputs["Metallic"].default_value = 0.1' 'bsdf.inputs["Specular"].default_value = 0.6' \
            'bsdf.inputs["Specular Tint"].default_value = 0.25' 'bsdf.inputs["Roughness"].default_value = 0.3' \
            'bsdf.inputs["Sheen"].default_value = 0.2' 'bsdf.inputs["Sheen Tint"].default_value = 0.4' \
            'bsdf.inputs["Clearcoat"].default_value = 0.5' \
            'bsdf.inputs["Clearcoat Roughness"].default_value = 0.1' '# Source model: blender_principled (exact)'; do
  grep -qxF -- "$line" "$tmp/b.py" && ok || bad "blender script lacks: $line"
done
/usr/bin/python3 -c "import ast, sys; ast.parse(open(sys.argv[1]).read())" "$tmp/b.py" && ok || bad "blender script is not Python"

# --- conversion: the reported error is that of the converted parameters -----------------
"$BRDFIT" export "$tmp/w.json" --to gltf -o "$tmp/w.gltf" 2>"$tmp/err" && ok || bad "convert walter: $(cat "$tmp/err")"
grep -q '^brdfit export: converted walter.* to gltf, conversion over 11664 direction pairs: rmse ' "$tmp/err" && ok ||
  bad "conversion not reported: $(cat "$tmp/err")"
jq '.materials[0] | {model: "gltf", channels: 3, params: {
      base_color: .pbrMetallicRoughness.baseColorFactor[0:3], metallic: .pbrMetallicRoughness.metallicFactor,
      roughness: .pbrMetallicRoughness.roughnessFactor, specular: .extensions.KHR_materials_specular.specularFactor,
      specular_color: .extensions.KHR_materials_specular.specularColorFactor, ior: .extensions.KHR_materials_ior.ior}}' \
  "$tmp/w.gltf" > "$tmp/wg.json"
awk 'BEGIN { print "theta_i,phi_i,theta_o,phi_o";
             for (i = 0; i < 18; i++) for (o = 0; o < 18; o++) for (p = 0; p < 36; p++)
               printf "%g,0,%g,%g\n", 2.5 + 5 * i, 2.5 + 5 * o, 10 * p }' > "$tmp/grid.csv"
"$BRDFIT" eval --params "$tmp/w.json" --dirs "$tmp/grid.csv" -o "$tmp/src.csv" &&
  "$BRDFIT" eval --params "$tmp/wg.json" --dirs "$tmp/grid.csv" -o "$tmp/dst.csv" && ok || bad "eval on the grid"
paste -d, "$tmp/src.csv" "$tmp/dst.csv" | awk -F, 'NR > 1 { for (c = 5; c <= 7; c++) { d = $(c + 7) - $c;
    s += d * d; n++; if (d < 0) d = -d; if (d > m) m = d } } END { printf "%.17g %.17g\n", sqrt(s / n), m }' > "$tmp/own"
read -r own_rmse own_max < "$tmp/own"
jq -e --argjson r "$own_rmse" --argjson m "$own_max" '.asset.extras.brdfit as $b | $b.converted and
   ($b.source_model | startswith("walter:")) and $b.conversion.directions == 11664
   and (($b.conversion.rmse - $r) | fabs) <= 1e-6 * $r and (($b.conversion.max_err - $m) | fabs) <= 1e-6 * $m
   and $r > 0' "$tmp/w.gltf" >/dev/null && ok ||
  bad "conversion error in the file ($(jq -c .asset.extras "$tmp/w.gltf")) is not brdfit eval's ($own_rmse, $own_max)"
# A Lambertian source is held exactly: specular 0, the albedo as base colour, grey for C = 1.
"$BRDFIT" export "$tmp/l1.json" --to gltf -o "$tmp/l1.gltf" 2>/dev/null && ok || bad "convert lambert"
jq -e '.materials[0] as $m | ([$m.pbrMetallicRoughness.baseColorFactor[0:3][] | (. - 0.4) | fabs] | max) < 1e-6
  and .asset.extras.brdfit.conversion.rmse_rel < 1e-6' "$tmp/l1.gltf" >/dev/null && ok ||
  bad "lambert 0.4 not held exactly: $(jq -c '.materials[0], .asset.extras' "$tmp/l1.gltf")"
"$BRDFIT" export "$tmp/w.json" --to blender -o "$tmp/w.py" 2>/dev/null && ok || bad "convert walter to blender"
grep -q '^# conversion over 11664 direction pairs: rmse ' "$tmp/w.py" && ok || bad "blender script lacks the conversion"

# --- Mitsuba, exact ----------------------------------------------------------------------
cat > "$tmp/m.json" <<'EOF'
{"model":"mitsuba_principled","channels":3,"params":{"base_color":[0.7,0.5,0.2],"metallic":0.1,"specular":0.6,"spec_tint":0.25,"roughness":0.3,"sheen":0.2,"sheen_tint":0.4,"flatness":0.3,"clearcoat":0.5,"clearcoat_gloss":0.7}}
EOF
"$BRDFIT" export "$tmp/m.json" --to mitsuba -o "$tmp/m.xml" 2>"$tmp/err" && ok || bad "export mitsuba: $(cat "$tmp/err")"
xmllint --noout "$tmp/m.xml" && ok || bad "mitsuba scene is not well-formed XML"
[ "$(xmllint --xpath 'string(/scene/@version)' "$tmp/m.xml")" = 3.0.0 ] && ok || bad "scene version"
[ "$(xmllint --xpath 'string(//shape[@type="sphere"]/bsdf/@type)' "$tmp/m.xml")" = principled ] && ok ||
  bad "no principled bsdf on a sphere"
[ "$(xmllint --xpath 'string(//bsdf/rgb[@name="base_color"]/@value)' "$tmp/m.xml")" = "0.7, 0.5, 0.2" ] && ok ||
  bad "mitsuba base_color"
for kv in metallic=0.1 specular=0.6 spec_tint=0.25 roughness=0.3 sheen=0.2 sheen_tint=0.4 flatness=0.3 \
          clearcoat=0.5 clearcoat_gloss=0.7; do
  [ "$(xmllint --xpath "string(//bsdf/float[@name=\"${kv%%=*}\"]/@value)" "$tmp/m.xml")" = "${kv#*=}" ] && ok ||
    bad "mitsuba $kv"
done
"$BRDFIT" export "$tmp/w.json" --to mitsuba -o "$tmp/wm.xml" 2>/dev/null && xmllint --noout "$tmp/wm.xml" &&
  grep -q ' conversion over 11664 direction pairs: rmse ' "$tmp/wm.xml" && ok || bad "walter to mitsuba"

# --- deterministic bytes ------------------------------------------------------------------
"$BRDFIT" export "$tmp/w.json" --to gltf -o "$tmp/w2.gltf" 2>/dev/null && cmp -s "$tmp/w.gltf" "$tmp/w2.gltf" &&
  ok || bad "two conversions differ"

# --- refusals: one line, non-zero exit, no file -------------------------------------------
refuse() { # expected status, message fragment, args...
  local want=$1 frag=$2
  shift 2
  "$BRDFIT" export "$@" -o "$tmp/no.out" 2>"$tmp/err"
  local st=$?
  [ "$st" = "$want" ] && ok || bad "export $*: status $st, want $want"
  grep -q -- "$frag" "$tmp/err" && [ "$(wc -l < "$tmp/err")" = 1 ] && ok || bad "export $*: message $(cat "$tmp/err")"
  [ ! -e "$tmp/no.out" ] && ok || bad "export $*: left an output"
}
cat > "$tmp/ward.json" <<'EOF'
{"model":"ward","channels":3,"params":{"rho_d":[0.3,0.2,0.1],"rho_s":[0.1,0.1,0.1],"alpha_x":0.1,"alpha_y":0.3}}
EOF
cat > "$tmp/w2l.json" <<'EOF'
{"model":"walter:lobes=2","channels":1,"params":{"rho_d":0.3,"rho_s_1":0.2,"alpha_1":0.1,"f0_1":0.04,"rho_s_2":0.3,"alpha_2":0.4,"f0_2":0.04}}
EOF
cat > "$tmp/l5.json" <<'EOF'
{"model":"lambert","channels":5,"params":{"rho_d":[0.1,0.2,0.3,0.4,0.5]}}
EOF
refuse 1 "ward.* is anisotropic; gltf holds one isotropic lobe (--convert" "$tmp/ward.json" --to gltf
refuse 1 "is multi-lobe; blender_principled holds one isotropic lobe" "$tmp/w2l.json" --to blender
refuse 1 "5 channels" "$tmp/l5.json" --to gltf
refuse 2 "not a target" "$tmp/g.json" --to renderman
refuse 2 "are required" "$tmp/g.json"
"$BRDFIT" export "$tmp/ward.json" --to gltf --convert -o "$tmp/ward.gltf" 2>"$tmp/err" &&
  grep -q "over 69984 direction pairs" "$tmp/err" && ok || bad "--convert of an anisotropic source: $(cat "$tmp/err")"

finish
