#!/usr/bin/env bash
# The whole test suite: a release build and an ASan+UBSan build, each under ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs" >/dev/null
ctest --test-dir build --output-on-failure -j "$jobs"
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRDFIT_SANITIZE=ON >/dev/null
cmake --build build-sanitize -j "$jobs" >/dev/null
ctest --test-dir build-sanitize --output-on-failure -j "$jobs"
