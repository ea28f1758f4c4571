#!/usr/bin/env bash
# Installs everything brdfit needs to build and test, from Debian packages.
set -euo pipefail
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  build-essential cmake pkg-config \
  libceres-dev libnlopt-dev libopenimageio-dev openimageio-tools \
  libcjson-dev libsqlite3-dev sqlite3 libcmocka-dev libxml2-dev jq libxml2-utils \
  libcairo2-dev fonts-dejavu-core poppler-utils libopenmpi-dev openmpi-bin \
  clang libclang-rt-14-dev man-db groff-base blender \
  slurmctld slurmd slurm-client munge python3 >/dev/null
# Node.js and npm from Debian unless the machine has them already (a Node.js from
# elsewhere, such as NodeSource's, bundles npm and conflicts with Debian's npm package).
if ! command -v node >/dev/null || ! command -v npm >/dev/null; then
  $SUDO apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi
# The Khronos glTF validator (tests/cli_export.sh checks brdfit export's .gltf with it),
# pinned, into the checkout's ignored tools/ folder: a test dependency only.
root=$(cd "$(dirname "$0")/.." && pwd)
npm install --no-audit --no-fund --silent --prefix "$root/tools" gltf-validator@2.0.0-dev.3.10 >/dev/null
# libsqlite3-dev: brdfit batch's results database; sqlite3 (the shell): its tests and
# docs/batch.md read the database with it.
# jq, openimageio-tools (iinfo, oiiotool) and libxml2-utils (xmllint): the command-line
# tests check brdfit's JSON output, images and JUnit XML with them. clang and
# libclang-rt-14-dev (libFuzzer, the sanitizer runtimes): scripts/fuzz.sh.
# man-db and groff-base: the tests render the generated man pages with man -l.
# nodejs and npm: the glTF validator above; blender (3.4, run headless with Cycles on the
# CPU): tests/cli_blender.sh renders exported materials. Tests only: brdfit needs neither.
# libcairo2-dev draws the plots (PNG, SVG, PDF) with the DejaVu fonts (fonts-dejavu-core);
# poppler-utils (pdftotext, pdftoppm): the tests read the plots' PDFs.
# libopenmpi-dev and openmpi-bin (mpirun): brdfit batch under MPI (cmd/batch_mpi.c, built
# only where CMake finds MPI) and tests/cli_batch_mpi.sh, which fails without mpirun.
# slurmctld, slurmd, slurm-client and munge: tests/cli_batch_slurm.sh runs the Slurm
# examples (examples/slurm) on a one-node cluster of its own. Tests only.
# python3: tests/cli_export.sh parses the Blender script it exports.
