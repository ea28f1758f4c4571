# Sourced by every command-line test with the arguments ctest passes: the brdfit binary,
# tests/data, the brdfit-synth binary, the image module's directory, and the test tools
# make_stack and normal_error (tests/CMakeLists.txt). Gives BRDFIT, DATA, SYNTH,
# PLUGIN_DIR, MAKE_STACK, NORMAL_ERROR, a temporary directory $tmp removed at exit, ok /
# bad counters, and finish for the closing line and status.
BRDFIT=$1
DATA=$2
SYNTH=${3:-}
PLUGIN_DIR=${4:-}
MAKE_STACK=${5:-}
NORMAL_ERROR=${6:-}
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
# need TOOL PACKAGE: a program the test runs, and the Debian package that has it
# (scripts/setup.sh installs them all). When it is missing the test fails at once with one
# line naming the package: a check is never skipped for want of a tool.
need() {
    command -v "$1" >/dev/null && return 0
    echo "FAIL: $1 is missing: install the Debian package $2 (scripts/setup.sh does)"
    exit 1
}
# need_python_module MODULE PACKAGE: a module of Debian's Python (/usr/bin/python3, which
# Debian's Blender runs too; python3 on PATH may be another interpreter).
need_python_module() {
    need /usr/bin/python3 python3
    /usr/bin/python3 -c "import $1" 2>/dev/null && return 0
    echo "FAIL: Debian's Python has no module $1: install the Debian package $2 (scripts/setup.sh does)"
    exit 1
}
