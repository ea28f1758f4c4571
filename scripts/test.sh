#!/usr/bin/env bash
# The whole test suite: a release build and an ASan+UBSan build, each under ctest; then a
# build without MPI (a machine without Open MPI), where brdfit batch runs as one process;
# then docs/adding-a-model.md followed in a copy of the tree (tests/guide/add_model.sh);
# then the Debian packages (scripts/package.sh), installed with apt-get, used and removed
# (tests/package/package_test.sh: as root, as CI runs).
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc)
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs" >/dev/null
ctest --test-dir build --output-on-failure -j "$jobs"
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DBRDFIT_SANITIZE=ON >/dev/null
cmake --build build-sanitize -j "$jobs" >/dev/null
ctest --test-dir build-sanitize --output-on-failure -j "$jobs"
cmake -S . -B build-nompi -DCMAKE_BUILD_TYPE=Release -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON >/dev/null
cmake --build build-nompi -j "$jobs" --target brdfit_cmd >/dev/null
echo "batch without MPI:"
bash tests/cli_batch.sh "$PWD/build-nompi/cmd/brdfit" "$PWD/tests/data" "$PWD/build/data_synth/brdfit-synth" "$PWD/build/lib"
echo "adding a model by the guide:"
bash tests/guide/add_model.sh
echo "Debian packages:"
bash tests/package/package_test.sh build
