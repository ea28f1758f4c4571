#!/usr/bin/env bash
# Installs everything brdfit needs to build, test and package, from Debian packages (and
# the glTF validator and puppeteer-core from npm). Checked on a fresh Debian 12 root (docs/releasing.md says
# how): a tool a test uses and this script does not install is a bug of this script.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
fail() { echo "setup.sh: $*" >&2; exit 1; }

# To build brdfit: the compilers, CMake and the libraries it links; for its Python package
# (python/, docs/python.md), Debian's Python with cffi, NumPy and setuptools.
build=(build-essential cmake pkg-config git
  libceres-dev libnlopt-dev libopenimageio-dev libcjson-dev libsqlite3-dev libxml2-dev
  libcairo2-dev zlib1g-dev fonts-dejavu-core libopenmpi-dev openmpi-bin libcmocka-dev
  python3-dev python3-cffi python3-numpy python3-setuptools)
# To test it (tests only: brdfit needs none of these at run time):
#  - jq, openimageio-tools (iinfo, oiiotool), libxml2-utils (xmllint), poppler-utils
#    (pdftotext, pdftoppm, pdfinfo), sqlite3 (the shell): the command-line tests read
#    brdfit's JSON, images, JUnit XML, PDF plots and batch databases with them;
#  - man-db and groff-base: the generated man pages are rendered with man;
#  - procps (pgrep): the batch tests find the fitting processes they kill;
#  - python3 (Debian's /usr/bin/python3) parses the exported Blender script;
#  - blender (3.4, headless Cycles on the CPU) renders exported materials; its glTF
#    importer needs NumPy (python3-numpy; Debian's Blender runs Debian's Python);
#  - slurmctld, slurmd, slurm-client and munge: a one-node Slurm cluster runs the examples
#    of examples/slurm (tests/cli_batch_slurm.sh);
#  - clang and libclang-rt-14-dev (libFuzzer, the sanitizer runtimes): scripts/fuzz.sh;
#  - debhelper and lintian: scripts/package.sh builds and checks the Debian packages,
#    which tests/package/package_test.sh installs with apt-get and removes again;
#  - python3-pytest, python3-hypothesis, python3-matplotlib (the example), python3-venv
#    and python3-pip (the pip route into a virtual environment): the Python package's
#    tests (python/tests);
#  - python3-pandas (CompareResult.to_dataframe), mypy and python3-typeshed (cffi's types,
#    which mypy only recommends): the package and its examples type-check with mypy
#    --strict (python/tests/test_types.py);
#  - chromium: the report viewer's test (tests/browser) drives it headless;
#  - clang-format (14): CI checks that every C and C++ file is formatted as .clang-format
#    says (scripts/check_format.sh).
tests=(jq openimageio-tools libxml2-utils poppler-utils sqlite3 man-db groff-base procps
  python3 python3-numpy blender slurmctld slurmd slurm-client munge clang libclang-rt-14-dev
  debhelper lintian python3-pytest python3-hypothesis python3-matplotlib python3-venv python3-pip
  python3-pandas mypy python3-typeshed chromium clang-format)

$SUDO apt-get update -qq || fail "apt-get update failed"
if ! out=$($SUDO apt-get install -y -qq --no-install-recommends "${build[@]}" "${tests[@]}" 2>&1); then
  echo "$out" | tail -n 20 >&2
  fail "apt-get install failed (above: its last lines)"
fi

# Node.js and npm from Debian unless the machine has them already (a Node.js from
# elsewhere, such as NodeSource's, bundles npm and conflicts with Debian's npm package).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  $SUDO apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null || fail "apt-get install nodejs npm failed"
fi
# Test dependencies only, pinned, into the checkout's ignored tools/ folder: the Khronos
# glTF validator (tests/cli_export.sh checks brdfit export's .gltf with it) and
# puppeteer-core (tests/browser drives Debian's Chromium with it; it downloads no browser).
root=$(cd "$(dirname "$0")/.." && pwd)
if ! out=$(npm install --no-audit --no-fund --prefix "$root/tools" gltf-validator@2.0.0-dev.3.10 \
  puppeteer-core@24.43.1 2>&1); then
  echo "$out" | tail -n 20 >&2
  fail "npm install gltf-validator puppeteer-core failed (above: npm's last lines)"
fi
