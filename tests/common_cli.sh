# Sourced by every command-line test with the arguments ctest passes: the brdfit binary,
# tests/data, the brdfit-synth binary, the image module's directory. Gives BRDFIT, DATA,
# SYNTH, PLUGIN_DIR, a temporary directory $tmp removed at exit, ok / bad counters, and
# finish for the closing line and status.
BRDFIT=$1
DATA=$2
SYNTH=${3:-}
PLUGIN_DIR=${4:-}
tmp=$(mktemp -d)
trap 'chmod -R u+w "$tmp" 2>/dev/null; rm -rf "$tmp"' EXIT
pass=0
fails=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
finish() {
    echo "$pass passed, $fails failed"
    [ "$fails" = 0 ]
}
