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
  libcairo2-dev fonts-dejavu-core poppler-utils \
  clang libclang-rt-14-dev man-db groff-base >/dev/null
# libsqlite3-dev: brdfit batch's results database; sqlite3 (the shell): its tests and
# docs/batch.md read the database with it.
# jq, openimageio-tools (iinfo, oiiotool) and libxml2-utils (xmllint): the command-line
# tests check brdfit's JSON output, images and JUnit XML with them. clang and
# libclang-rt-14-dev (libFuzzer, the sanitizer runtimes): scripts/fuzz.sh.
# man-db and groff-base: the tests render the generated man pages with man -l.
# libcairo2-dev draws the plots (PNG, SVG, PDF) with the DejaVu fonts (fonts-dejavu-core);
# poppler-utils (pdftotext, pdftoppm): the tests read the plots' PDFs.
