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
  libcjson-dev libcmocka-dev libxml2-dev jq >/dev/null
# jq and openimageio-tools (iinfo, oiiotool): the command-line tests check brdfit's JSON
# output and images with them.
