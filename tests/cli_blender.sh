#!/usr/bin/env bash
# Exports checked in the real renderer: materials exported with `brdfit export --to blender`
# rendered by Blender 3.4 (headless, Cycles on the CPU) on the sphere `brdfit render` draws
# (tests/blender/render_sphere.py sets up the same camera, light and units), compared as
# mean radiance over three regions: centre, highlight and lit limb. A diffuse, a glossy
# dielectric, a metal and a coated material, each exact (blender_principled results).
# Then glTF exports imported by Blender's own glTF importer, against brdfit's gltf model.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need blender blender; need jq jq
here=$(cd "$(dirname "$0")" && pwd)
# Blender's glTF importer imports NumPy (Debian's Blender runs Debian's Python).
need_python_module numpy python3-numpy
size=128

# compare NAME TOLERANCE: every region's mean, every channel, within TOLERANCE relative
# (of the larger of the two, with a floor of 1e-3 so a black channel compares absolutely).
compare() {
    jq -e --argjson tol "$2" '[to_entries[] | .value as $r | range(3) as $c
        | (($r.blender[$c] - $r.brdfit[$c]) | fabs) / ([$r.blender[$c], $r.brdfit[$c], 1e-3] | max)]
        | max <= $tol' "$tmp/$1.json" >/dev/null &&
        ok || bad "$1: Blender and brdfit differ by more than $2: $(jq -c . "$tmp/$1.json")"
    jq -e 'has("centre") and has("highlight") and has("limb") and ([.[].pixels] | min) >= 20' \
        "$tmp/$1.json" >/dev/null && ok || bad "$1: a region is missing or too small: $(jq -c . "$tmp/$1.json")"
}

# render NAME PARAMS TARGET: export PARAMS, brdfit's EXR of them, Blender's render of the
# export, and the region means of both in $tmp/NAME.json.
render() {
    "$BRDFIT" export "$2" --to "$3" -o "$tmp/$1.$3" 2>"$tmp/err" ||
        { bad "export $1: $(cat "$tmp/err")"; return 1; }
    "$BRDFIT" render --params "$2" --size $size -o "$tmp/$1.exr" || { bad "render $1"; return 1; }
    blender --background --factory-startup --python-exit-code 1 --python "$here/blender/render_sphere.py" -- \
        "$tmp/$1.$3" "$tmp/$1.exr" "$tmp/$1.json" $size 64 >"$tmp/$1.log" 2>&1 || { bad "blender $1: $(tail -5 "$tmp/$1.log")"; return 1; }
}

cat > "$tmp/diffuse.p" <<'P'
{"model":"blender_principled","channels":3,"params":{"base_color":[0.6,0.4,0.2],"metallic":0,"specular":0,"specular_tint":0,"roughness":1,"sheen":0,"sheen_tint":0.5,"clearcoat":0,"clearcoat_roughness":0.03}}
P
cat > "$tmp/glossy.p" <<'P'
{"model":"blender_principled","channels":3,"params":{"base_color":[0.1,0.2,0.5],"metallic":0,"specular":0.5,"specular_tint":0,"roughness":0.3,"sheen":0,"sheen_tint":0.5,"clearcoat":0,"clearcoat_roughness":0.03}}
P
cat > "$tmp/metal.p" <<'P'
{"model":"blender_principled","channels":3,"params":{"base_color":[0.95,0.64,0.54],"metallic":1,"specular":0.5,"specular_tint":0,"roughness":0.25,"sheen":0,"sheen_tint":0.5,"clearcoat":0,"clearcoat_roughness":0.03}}
P
cat > "$tmp/coated.p" <<'P'
{"model":"blender_principled","channels":3,"params":{"base_color":[0.7,0.5,0.2],"metallic":0.1,"specular":0.6,"specular_tint":0.25,"roughness":0.4,"sheen":0.3,"sheen_tint":0.4,"clearcoat":0.5,"clearcoat_roughness":0.1}}
P
# The stated tolerance: 2% per region mean (measured: below 0.6%; the highlight region
# is where pixel filtering and the mesh's interpolated normals differ most).
for m in diffuse glossy metal coated; do
    render "$m" "$tmp/$m.p" blender && compare "$m" 0.02
done

# glTF through Blender's own importer (Blender 3.4), against brdfit's gltf model. A metal
# (metallic 1: base colour is F0, Schlick to white) maps exactly onto the Principled BSDF
# (measured 0.2%). A dielectric does not: the importer turns KHR_materials_specular into
# Principled's Specular and Specular Tint (tinted towards the base colour) and Principled's
# diffuse is not glTF's Lambert, so the highlight's colour moves (measured: -30% red, +42%
# blue in the highlight, -7% to +12% at the centre); only the import itself is held to
# 50% there, and the figures are printed.
cat > "$tmp/gltf_metal.p" <<'P'
{"model":"gltf","channels":3,"params":{"base_color":[0.95,0.64,0.54],"metallic":1,"roughness":0.5,"specular":1,"specular_color":[1,1,1],"ior":1.5}}
P
cat > "$tmp/gltf_dielectric.p" <<'P'
{"model":"gltf","channels":3,"params":{"base_color":[0.1,0.2,0.5],"metallic":0,"roughness":0.5,"specular":1,"specular_color":[1,1,1],"ior":1.5}}
P
render gltf_metal "$tmp/gltf_metal.p" gltf && compare gltf_metal 0.02
render gltf_dielectric "$tmp/gltf_dielectric.p" gltf && compare gltf_dielectric 0.5

for m in diffuse glossy metal coated gltf_metal gltf_dielectric; do
    jq -r --arg m "$m" '[to_entries[] | .key as $k | .value as $r | range(3) as $c
        | (($r.blender[$c] - $r.brdfit[$c]) | fabs) / ([$r.blender[$c], $r.brdfit[$c], 1e-3] | max)] | max
        | "\($m): largest region difference \(. * 1000 | round / 10)%"' "$tmp/$m.json"
done
finish
