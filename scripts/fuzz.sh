#!/usr/bin/env bash
# Fuzzes the readers of user files with libFuzzer (clang, AddressSanitizer and
# UndefinedBehaviorSanitizer; harnesses in fuzz/). Builds them into build-fuzz/, then
# runs each target for SECONDS on its corpus in build-fuzz/corpus/TARGET (kept between
# runs), seeded from fuzz/seeds, the bundled data (tests/data, examples) and the
# target's dictionary (fuzz/dict). Fails on any crash, leak, timeout or sanitizer
# report; the input that caused it is left in build-fuzz/findings/TARGET/.
#
#   scripts/fuzz.sh [TARGET|all] [SECONDS]     (default: all, 10 seconds each)
#   targets: csv csv_map merl merl_file cornell alta rgl mbsdf params reference scene regress manifest
#            stack diligent
#   FUZZ_RUNS=N runs each target for N executions instead of SECONDS.
set -euo pipefail
cd "$(dirname "$0")/.."
all=(csv csv_map merl merl_file cornell alta rgl mbsdf params reference scene regress manifest stack diligent)
target=${1:-all}
seconds=${2:-10}
if [ "$target" = all ]; then
    targets=("${all[@]}")
elif [[ " ${all[*]} " == *" $target "* ]]; then
    targets=("$target")
else
    echo "fuzz.sh: unknown target '$target' (one of: ${all[*]}, all)" >&2
    exit 2
fi
if ! [[ "$seconds" =~ ^[1-9][0-9]*$ ]]; then
    echo "fuzz.sh: SECONDS must be a positive integer, not '$seconds'" >&2
    exit 2
fi
command -v clang >/dev/null || { echo "fuzz.sh: clang is missing (scripts/setup.sh installs it)" >&2; exit 1; }

build=build-fuzz
CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRDFIT_FUZZ=ON \
    -DBRDFIT_TESTS=OFF >/dev/null
cmake --build "$build" -j "$(nproc)" --target "${targets[@]/#/fuzz_}" >/dev/null

# Bundled files that seed each target (besides fuzz/seeds/TARGET).
seed_files() {
    case $1 in
    csv) echo tests/data/dirs_small.csv examples/dirs_in_plane.csv tests/data/nist_ptfe/PTFE.data.random.head40.csv ;;
    cornell) echo tests/data/cornell/cayman_head20.brdf ;;
    alta) echo tests/data/alta/pink-felt-1d.alta ;;
    params) echo examples/walter_rgb.json tests/data/lambert_rgb.json ;;
    reference) echo examples/walter_rgb.json tests/data/lambert_rgb.json ;;
    scene) echo examples/scenes/*.json ;;
    regress) echo examples/regress/baseline.json ;;
    esac
}

status=0
summary=()
for t in "${targets[@]}"; do
    corpus=$build/corpus/$t seeds=$build/seeds/$t findings=$build/findings/$t
    mkdir -p "$corpus" "$seeds" "$findings"
    cp fuzz/seeds/"$t"/* "$seeds"/
    for f in $(seed_files "$t"); do cp "$f" "$seeds"/; done
    if [ "$t" = csv_map ]; then # the NIST goniometer file under two mappings
        { echo 'thetai,phi,thetar,phir|f_r11||'; cat tests/data/nist_ptfe/PTFE.data.random.head40.csv; } >"$seeds/nist1.csv"
        { echo 'thetai,phi,thetar,phir|f_r11,f_r12/f_r11|lambda|'; cat tests/data/nist_ptfe/PTFE.data.random.head40.csv; } >"$seeds/nist2.csv"
    fi
    # A MERL input is a header and a pattern repeated to 35 MB, about a second per
    # execution; libFuzzer runs its whole corpus before it looks at the time, so a short
    # run (CI) starts from the seeds alone and keeps nothing.
    max_len=16384 timeout=10
    if [ "$t" = merl ]; then
        max_len=4096 timeout=30
        if [ -z "${FUZZ_RUNS:-}" ] && [ "$seconds" -lt 120 ]; then
            corpus=$build/corpus/merl-short
            rm -rf "$corpus" && mkdir -p "$corpus"
        fi
    fi
    # The manifest reader prints its one-line errors on stderr, as the command does:
    # closed for the target (libFuzzer keeps its own reports and the sanitizers').
    quiet=()
    [ "$t" = manifest ] && quiet=(-close_fd_mask=2)
    # The dictionary: the target's, or its family's (csv_map: csv.dict); the DiLiGenT
    # folders share the stack files' (image names, numbers).
    dict=fuzz/dict/${t%_*}.dict
    [ "$t" = diligent ] && dict=fuzz/dict/stack.dict
    limit=(-max_total_time="$seconds")
    [ -n "${FUZZ_RUNS:-}" ] && limit=(-runs="$FUZZ_RUNS")
    log=$build/fuzz_$t.log
    echo "fuzz $t: ${FUZZ_RUNS:+$FUZZ_RUNS runs}${FUZZ_RUNS:-$seconds s} ..."
    start=$(date +%s)
    if "$build/fuzz/fuzz_$t" "${limit[@]}" "${quiet[@]}" -max_len=$max_len -timeout=$timeout -rss_limit_mb=4096 \
        -use_value_profile=1 -print_final_stats=1 -dict="$dict" -artifact_prefix="$findings/" \
        "$corpus" "$seeds" >"$log" 2>&1; then
        result="no findings"
    else
        result="FAILED (log: $log, input: $(ls -t "$findings" | head -1))"
        status=1
        tail -40 "$log" >&2
    fi
    secs=$(($(date +%s) - start))
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
    rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
    files=$(find "$corpus" -type f | wc -l)
    summary+=("$(printf '%-8s %10s executions %6s s %8s exec/s  corpus %5s files  %s' "$t" "${runs:-?}" "$secs" "${rate:-?}" "$files" "$result")")
done
printf '%s\n' "${summary[@]}"
exit $status
