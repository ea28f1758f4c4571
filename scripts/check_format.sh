#!/usr/bin/env bash
# Every tracked C and C++ file formatted as .clang-format says (Debian's clang-format 14):
# lists the files that are not and fails. `scripts/check_format.sh --fix` formats them.
set -euo pipefail
cd "$(dirname "$0")/.."
command -v clang-format >/dev/null || { echo "check_format.sh: clang-format is missing (scripts/setup.sh installs it)" >&2; exit 1; }
mapfile -t files < <(git ls-files '*.c' '*.h' '*.cc' '*.cpp')
if [ "${1:-}" = --fix ]; then
    clang-format -i "${files[@]}"
    exit 0
fi
bad=$(clang-format --dry-run "${files[@]}" 2>&1 | sed -n 's/^\([^:]*\):[0-9]*:[0-9]*: warning: code should be clang-formatted.*/\1/p' | sort -u)
if [ -n "$bad" ]; then
    echo "check_format.sh: not formatted as .clang-format says (scripts/check_format.sh --fix):" >&2
    echo "$bad" | sed 's/^/  /' >&2
    exit 1
fi
echo "check_format.sh: ${#files[@]} files formatted"
