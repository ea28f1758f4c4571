#!/usr/bin/env bash
# Every command run on the bundled data (examples/, tests/data/) with fixed options, its
# stdout, stderr, exit status and files kept under OUTDIR: run it before and after a
# refactoring and `diff -r` the two folders (outputs must stay byte-identical but for
# changes made on purpose). Usage: scripts/snapshot_outputs.sh BUILD_DIR OUTDIR
set -uo pipefail
build=$(cd "$1" && pwd)
out=$2
root=$(cd "$(dirname "$0")/.." && pwd)
B=$build/cmd/brdfit
S=$build/data_synth/brdfit-synth
rm -rf "$out"
mkdir -p "$out"
out=$(cd "$out" && pwd)
cd "$root"
n=0
# run NAME CMD...: stdout, stderr and the status into OUTDIR/NAME.{out,err,rc}, run in
# OUTDIR/NAME.d (so relative outputs land there); paths in the texts are the tree's.
run() {
    local name=$1
    shift
    mkdir -p "$out/$name.d"
    (cd "$out/$name.d" && "$@" >"$out/$name.out" 2>"$out/$name.err")
    echo $? >"$out/$name.rc"
    n=$((n + 1))
}
E=$root/examples
T=$root/tests/data
fit_fast=(--threads 1 --starts 2 --screen 8)
run models "$B" models
run models_json "$B" models --json
run methods "$B" methods
for c in fit compare select tradeoff regress export batch report info convert eval render; do
    run "help_$c" "$B" help "$c"
done
for f in "$E/cornell/cayman.brdf" "$E/rgl/paper_white_rgb.bsdf" "$E/mdl/carpaint_red.mbsdf" "$T/alta/pink-felt-1d.alta" \
    "$T/nist_ptfe/PTFE.data.random.head40.csv"; do
    b=$(basename "$f")
    a=()
    case $b in PTFE*) a=(--angles thetai,phi,thetar,phir --values f_r11) ;; esac
    run "info_$b" "$B" info "$f" "${a[@]}" --json
    run "info_text_$b" "$B" info "$f" "${a[@]}"
done
run info_rgb_scene "$B" info "$E/cornell/cayman.brdf" --rgb --scene "$E/scenes/turntable.json" --subsample 200 --json
run convert_csv "$B" convert "$E/cornell/cayman.brdf" cayman.csv --rgb --max-theta 80
run fit_cayman "$B" fit "$E/cornell/cayman.brdf" --rgb -m lambert,walter,ashikhmin_shirley -o fit.json "${fit_fast[@]}"
run fit_cayman_scene "$B" fit "$E/cornell/cayman.brdf" --rgb --scene "$E/scenes/turntable.json" -m walter -o fit.json "${fit_fast[@]}"
run fit_cayman_accfast "$B" fit "$E/cornell/cayman.brdf" --rgb --accuracy fast -m cook_torrance -o fit.json --threads 1
run fit_ptfe "$B" fit "$T/nist_ptfe/PTFE.data.random.head40.csv" --angles thetai,phi,thetar,phir --values f_r11 -m "microfacet:D=ggx,G=smith_ggx,lambert" --residual linear --loss huber -o fit.json "${fit_fast[@]}"
run fit_fix "$B" fit "$E/cornell/cayman.brdf" --luminance -m walter --fix rho_d=0.1 --bound alpha=0.05:0.5 -o fit.json "${fit_fast[@]}"
run fit_nlopt "$B" fit "$E/cornell/cayman.brdf" --rgb -m ward_iso --backend nlopt -o fit.json --threads 1
run eval_fit "$B" eval --params "$out/fit_cayman_scene.d/fit.json" --dirs "$E/dirs_in_plane.csv"
run compare_cayman "$B" compare "$E/cornell/cayman.brdf" "$T/cornell/cayman_head20.brdf" --rgb -m lambert,walter,cook_torrance --json c.json --csv c.csv "${fit_fast[@]}"
run compare_scene "$B" compare "$E/cornell/cayman.brdf" --rgb --scene "$E/scenes/product_shot.json" -m lambert,walter --json c.json --rank error --tolerance 0.1 "${fit_fast[@]}"
run compare_cv "$B" compare "$E/cornell/cayman.brdf" --luminance -m lambert,walter --rank cv --folds 3 --json c.json "${fit_fast[@]}"
run compare_html "$B" compare "$E/rgl/paper_white_rgb.bsdf" -m lambert,walter --subsample 3000 --html rep "${fit_fast[@]}"
run select_cayman "$B" select "$E/cornell/cayman.brdf" --rgb --models lambert,walter,ward_iso,cook_torrance --json s.json -o r.json "${fit_fast[@]}"
run select_scene "$B" select "$E/cornell/cayman.brdf" --rgb --scene "$E/scenes/turntable.json" --json s.json "${fit_fast[@]}"
run tradeoff "$B" tradeoff "$E/cornell/cayman.brdf" --rgb -m walter --samples 200,all --json t.json --csv t.csv --threads 1
run regress "$B" regress "$E/regress/baseline.json" --junit j.xml
run export_gltf "$B" export "$out/fit_cayman_scene.d/fit.json" --to gltf -o m.gltf
run export_mitsuba "$B" export "$out/fit_cayman_scene.d/fit.json" --to mitsuba -o m.xml
run export_blender "$B" export "$out/fit_cayman_scene.d/fit.json" --to blender -o m.py
run render "$B" render --params "$E/walter_rgb.json" --size 64 -o r.png
run render_slice "$B" render --params "$E/walter_rgb.json" --slice -o r.svg
run render_slice_data "$B" render --params "$E/walter_rgb.json" --slice --data "$E/cornell/cayman.brdf" --rgb -o r.svg
run render_halfdiff "$B" render --params "$E/walter_rgb.json" --half-diff -o r.svg
run render_halfdiff_png "$B" render --params "$E/walter_rgb.json" --half-diff --size 200x160 -o r.png
run tradeoff_plot "$B" tradeoff "$E/cornell/cayman.brdf" --rgb -m walter --samples 200,all --plot t.svg --threads 1
run synth "$S" --params "$E/walter_rgb.json" --pattern stratified --count 500 --noise 0.02 --seed 3 -o s.csv
printf 'models: lambert walter\noptions: --rgb --starts 2 --screen 8 --seed 3\n%s\n%s --scene %s\n' "$E/cornell/cayman.brdf" \
    "$T/cornell/cayman_head20.brdf" "$E/scenes/turntable.json" >"$out/manifest.txt"
run batch "$B" batch "$out/manifest.txt" -o r.db --jobs 1
run report "$B" report "$out/batch.d/r.db" --json r.json --csv r.csv
# Usage errors (stderr and status).
run e_rgb_color "$B" fit "$E/cornell/cayman.brdf" --rgb --color xyz -m walter
run e_seed "$B" fit "$E/cornell/cayman.brdf" --seed -1 -m walter
run e_sub "$B" fit "$E/cornell/cayman.brdf" --subsample 0 -m walter
run e_model "$B" fit "$E/cornell/cayman.brdf" -m nosuch
run e_fix "$B" fit "$E/cornell/cayman.brdf" -m walter --fix nosuch=1
run e_rank "$B" compare "$E/cornell/cayman.brdf" -m walter --rank cv --loss huber --rank bic
run e_nofile "$B" fit /nonexistent.csv -m walter
run e_scene "$B" fit "$E/cornell/cayman.brdf" --rgb --scene /nonexistent.json -m walter
run e_maxtheta "$B" info "$E/cornell/cayman.brdf" --max-theta 95
run e_negative "$B" info "$E/cornell/cayman.brdf" --negative maybe
# The man pages and completion the build generated from the option tables.
cp -r "$build/doc" "$out/doc"
C=$E/cornell/cayman.brdf
run e_jobs "$B" compare "$C" -m walter --jobs 0
run e_tol "$B" compare "$C" -m walter --tolerance -1
run e_error "$B" compare "$C" -m walter --error rmse_x
run e_folds "$B" compare "$C" -m walter --rank cv --folds 1
run e_threads "$B" fit "$C" -m walter --threads 0
run e_starts "$B" fit "$C" -m walter --starts x
run e_presolve "$B" fit "$C" -m walter --presolve 10
run e_accuracy "$B" fit "$C" -m walter --accuracy slow
run e_backend "$B" fit "$C" -m walter --backend foo
run e_loss "$B" fit "$C" -m walter --loss bar
run e_residual "$B" fit "$C" -m walter --residual baz
run e_algorithm "$B" fit "$C" -m walter --algorithm nosuch
run e_bound "$B" fit "$C" -m walter --bound alpha=1
run e_fixrange "$B" fit "$C" -m walter --fix alpha=5
run e_color "$B" info "$C" --color nope
run e_illum "$B" info "$C" --illuminant nope
run e_format "$B" info "$C" --format nope
run e_angles "$B" info "$C" --angles a,b,c
run e_rgb_bands "$B" info "$C" --rgb --rgb-bands
run e_lum "$B" info "$C" --luminance --color xyz
run ok_rgb_srgb "$B" info "$C" --rgb --color srgb
run e_abs "$B" select "$C" --abs-tolerance x
run e_seltol "$B" select "$C" --tolerance x
run e_selrank "$B" select "$C" --rank nope
run e_selloss "$B" select "$C" --rank aic --loss huber
run e_mempty "$B" fit "$C" -m ''
run e_mcomma "$B" fit "$C" -m 'walter,,lambert'
run e_tradeoff_methods "$B" tradeoff "$C" -m walter --methods nosuch
run e_batch_threads "$B" batch "$out/manifest.txt" -o x.db --threads 0
printf 'models: walter\noptions: --rgb --error rmse_x\n%s\n' "$C" >"$out/bad_manifest.txt"
run e_batch_error "$B" batch "$out/bad_manifest.txt" -o x.db
printf 'models: walter\noptions: --rgb --tolerance -2\n%s\n' "$C" >"$out/bad_manifest2.txt"
run e_batch_tol "$B" batch "$out/bad_manifest2.txt" -o x.db
run compare_all_head "$B" compare "$T/cornell/cayman_head20.brdf" --rgb -m all --starts 1 --threads 1 --json c.json
run tradeoff_nlopt "$B" tradeoff "$C" --rgb -m walter --backend nlopt --samples 200 --json t.json --threads 1
run fit_v "$B" fit "$C" --rgb --scene "$E/scenes/turntable.json" --subsample 3 -m lambert -v --threads 1
run convert_merl "$B" convert "$T/cornell/cayman_head20.brdf" x.csv --rgb -v
run select_cv "$B" select "$C" --luminance --models lambert,walter --rank cv --folds 3 --json s.json --threads 1 --starts 1
# Drop what differs from run to run: wall times in summaries and files; databases as SQL.
for db in $(find "$out" -name '*.db'); do
    sqlite3 "$db" .dump | sed -E "s/,[0-9.e-]+,'[0-9T:.-]+Z'\);\$/,T,D);/" >"$db.sql" && rm "$db"
done
find "$out" -type f \( -name '*.out' -o -name '*.err' -o -name '*.json' -o -name '*.csv' -o -name '*.xml' -o -name '*.html' -o -name '*.sql' \) \
    -exec sed -i -E "s|$out|OUT|g" {} +
find "$out" -type f \( -name '*.out' -o -name '*.err' -o -name '*.json' -o -name '*.csv' -o -name '*.xml' -o -name '*.html' -o -name '*.sql' \) \
    -exec sed -i -E 's/[0-9]+\.[0-9]+ s\b/T s/g; s/"([a-z_]*seconds|time|timestamp|started|finished)":[[:space:]]*[0-9.e+-]+/"\1": T/g; s/(time=")[0-9.]+/\1T/g; s/\(git [0-9a-f]+(-dirty)?\)/(git X)/g' {} +
echo "$n runs into $out"
