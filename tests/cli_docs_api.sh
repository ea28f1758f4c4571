#!/usr/bin/env bash
# The programs docs/api.md and the README show are real: each ```c block is built as a
# program's body against this build's headers and shared library, and the first (the
# fit) is run on the bundled Cayman paint with the turntable scene: it must print the
# result JSON, with the command's parameters and scene-weighted metrics.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need cc gcc
need jq jq

src=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$(dirname "$BRDFIT")/.." && pwd)
# The blocks of a Markdown file, one file each: $tmp/<name>-<k>.c.
blocks() {
  awk -v out="$tmp/$2" 'BEGIN { k = 0 } /^```c$/ { k++; f = out "-" k ".c"; on = 1; next }
       /^```/ { on = 0; next } on { print > f }' "$1"
}
blocks "$src/docs/api.md" api
blocks "$src/README.md" readme
ls "$tmp"/api-*.c >/dev/null 2>&1 && ok || bad "docs/api.md has no C block"
ls "$tmp"/readme-*.c >/dev/null 2>&1 && ok || bad "README.md has no C block"

# A block is a body: it goes into main(), with every public header and the variables the
# README's evaluation uses (n directions of the in-plane sweep).
wrap() {
  {
    for h in "$src"/lib/include/brdfit/*.h; do echo "#include <brdfit/$(basename "$h")>"; done
    echo "#include <brdfit/version.h>"
    cat <<'C'
#include <stdio.h>
#include <stdlib.h>
int main(void)
{
    enum { n = 3 };
    double theta_i[n] = {10, 30, 50}, phi_i[n] = {0, 0, 0}, theta_o[n] = {10, 30, 50}, phi_o[n] = {180, 180, 180};
    (void)theta_i, (void)phi_i, (void)theta_o, (void)phi_o;
C
    cat "$1"
    echo "    return 0;"
    echo "}"
  } >"$2"
}
# A sanitizer build's library needs its runtime first in the program.
sanitize=()
ldd "$build/lib/libbrdfit.so" 2>/dev/null | grep -q libasan && sanitize=(-fsanitize=address,undefined)
for b in "$tmp"/api-*.c "$tmp"/readme-*.c; do
  [ -e "$b" ] || continue
  name=$(basename "$b" .c)
  wrap "$b" "$tmp/$name-main.c"
  if cc -std=c11 "${sanitize[@]}" -Wall -Wextra -Werror -Wno-unused-variable -Wno-misleading-indentation \
      -I"$src/lib/include" -I"$build/lib/include" \
      "$tmp/$name-main.c" -L"$build/lib" -lbrdfit -Wl,-rpath,"$build/lib" -lm -o "$tmp/$name" 2>"$tmp/$name.err"; then
    ok
  else
    bad "$name does not build: $(head -n 5 "$tmp/$name.err")"
  fi
done

# docs/api.md's first block, run where its file names are: the fit's JSON, equal to the
# command's.
mkdir "$tmp/run" && cp "$src/examples/cornell/cayman.brdf" "$src/examples/scenes/turntable.json" "$tmp/run/"
if [ -x "$tmp/api-1" ] && (cd "$tmp/run" && "$tmp/api-1" >"$tmp/api.json" 2>"$tmp/api.err"); then
  "$BRDFIT" fit "$tmp/run/cayman.brdf" --rgb --scene "$tmp/run/turntable.json" -m walter -q -o "$tmp/cli.json"
  [ "$(jq -c .params "$tmp/api.json")" = "$(jq -c .params "$tmp/cli.json")" ] &&
    [ "$(jq -c .metrics "$tmp/api.json")" = "$(jq -c .metrics "$tmp/cli.json")" ] && ok ||
    bad "docs/api.md's fit differs from brdfit fit's: $(jq -c .metrics "$tmp/api.json" 2>&1 | head -c 300)"
else
  bad "docs/api.md's first program failed: $(cat "$tmp/api.err" 2>/dev/null | head -n 3)"
fi
# Every public struct is one of docs/api.md's kinds, and a sized one (kind 3) starts with
# its size and has its init: a struct added without a place in the rule fails here.
row() { grep -E "^\| $1\. " "$src/docs/api.md" | awk -F'|' '{print $3}' | grep -oE '`bf_[a-z_]+`' | tr -d '`'; }
kinds=$(for k in 1 2 3 4; do row $k; done)
for t in $(grep -ohE '^typedef struct bf_[a-z_]+ \{' "$src"/lib/include/brdfit/*.h | awk '{print $3}'); do
  grep -qx "$t" <<<"$kinds" && ok || bad "$t is in no kind of docs/api.md's table"
done
for t in $(row 3); do
  h=$(grep -lE "^typedef struct $t \{" "$src"/lib/include/brdfit/*.h)
  first=$(awk -v t="$t" '$0 ~ "^typedef struct " t " \\{" {getline; print; exit}' "$h")
  [[ $first =~ ^[[:space:]]*size_t\ size\; ]] && ok || bad "$t's first member is not its size: $first"
  grep -q "static inline void ${t}_init($t \*" "$h" && grep -q "BF_API void ${t}_init_size(" "$h" && ok ||
    bad "$t has no static inline ${t}_init and ${t}_init_size in $(basename "$h")"
done
finish
