#!/usr/bin/env bash
# Renders a brdfit HTML report in a real browser and saves a screenshot, to check by eye
# that the page lays out and every image loads (not run in CI: it needs Chromium).
#
#   scripts/check_report.sh REPORT_DIR [OUT.png]
#
# REPORT_DIR is a folder written by `brdfit compare ... --html REPORT_DIR`. The page is
# opened from disk (file://, no server, as a reader would) in headless Chromium at
# 1280x2000 and the screenshot is written to OUT.png (default: a new temporary file).
# Chromium is Debian's `chromium` package; if it is missing and we run as root it is
# installed with apt-get. Prints the screenshot's path; exit 1 if Chromium fails.
set -eu
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 REPORT_DIR [OUT.png]" >&2
  exit 2
fi
dir=$1
[ -f "$dir/index.html" ] || { echo "$0: $dir/index.html: no such file" >&2; exit 1; }
out=${2:-$(mktemp --suffix=.png)}
case $out in /*) ;; *) out=$PWD/$out ;; esac
page=$(cd "$dir" && pwd)/index.html

browser=$(command -v chromium || command -v chromium-browser || true)
if [ -z "$browser" ]; then
  if [ "$(id -u)" = 0 ]; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y chromium >/dev/null
    browser=$(command -v chromium)
  else
    echo "$0: chromium is not installed (apt-get install chromium)" >&2
    exit 1
  fi
fi

profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
# --no-sandbox: Chromium refuses to run as root with its sandbox; the page is our own file.
"$browser" --headless --no-sandbox --disable-gpu --disable-background-networking \
  --disable-component-update --disable-sync --no-first-run --user-data-dir="$profile" \
  --screenshot="$out" --window-size=1280,2000 "file://$page" >/dev/null 2>&1 || {
  echo "$0: chromium failed on $page" >&2
  exit 1
}
[ -s "$out" ] || { echo "$0: no screenshot written" >&2; exit 1; }
echo "$out"
