#!/usr/bin/env bash
# Installs the build into a temporary prefix and uses it as another project would: the
# installed tree's contents, a C program (consumer.c) and a C++ program that includes
# every public header (consumer_cxx.cc), both copied out of the source tree and built
# with pkg-config (shared and static) and with find_package(brdfit), and the installed
# commands, the image module found from the installed library and commands.
# Arguments: the build directory, the source directory, cmake, the C compiler, the C++
# compiler, the project version and the soname's number (cmake/version.cmake), extra
# compile and link flags for the consumers, C and C++ alike (the sanitizer build's).
set -u
build=$1 src=$2 cmake=$3 cc=$4 cxx=$5 version=$6 so=$7 flags=${8:-}
major=${version%%.*}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fails=0
ok() { :; }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
# The image module a run loaded (the dynamic linker's log of what it opens).
module_loaded() { LD_DEBUG=files "$@" 2>&1 >/dev/null | grep -o 'file=[^ ]*libbrdfit-oiio\.so' | head -n 1 | cut -c6-; }

prefix=$tmp/prefix
if ! "$cmake" --install "$build" --prefix "$prefix" >"$tmp/install.log" 2>&1; then
  cat "$tmp/install.log"
  echo "FAIL: cmake --install"
  exit 1
fi
unset BRDFIT_PLUGIN_DIR LD_LIBRARY_PATH

# ---- the installed tree -------------------------------------------------------------
pc=$(find "$prefix" -name brdfit.pc)
[ -n "$pc" ] || { echo "FAIL: no brdfit.pc"; exit 1; }
libdir=$(dirname "$(dirname "$pc")")
for f in bin/brdfit bin/brdfit-synth include/brdfit/version.h include/brdfit/fit.h; do
  [ -f "$prefix/$f" ] && ok || bad "$f not installed"
done
for f in libbrdfit.a libbrdfit.so libbrdfit.so.$so brdfit/libbrdfit-oiio.so cmake/brdfit/brdfitConfig.cmake \
         cmake/brdfit/brdfitConfigVersion.cmake cmake/brdfit/brdfitTargets.cmake; do
  [ -e "$libdir/$f" ] && ok || bad "$libdir/$f not installed"
done
for h in "$src"/lib/include/brdfit/*.h; do
  cmp -s "$h" "$prefix/include/brdfit/$(basename "$h")" && ok || bad "header $(basename "$h") not installed"
done
readelf -d "$libdir/libbrdfit.so" | grep -q "SONAME.*\[libbrdfit\.so\.$so\]" && ok || bad "SONAME is not libbrdfit.so.$so"
[ "$(readlink "$libdir/libbrdfit.so.$so")" = "libbrdfit.so.$version" ] && ok || bad "libbrdfit.so.$so -> $(readlink "$libdir/libbrdfit.so.$so")"
# C headers only: each compiles alone as C11 and as C++17, and none includes a back end's
# header.
[ -z "$(find "$prefix/include" -type f ! -name '*.h')" ] && ok || bad "non-C headers: $(find "$prefix/include" -type f ! -name '*.h')"
if grep -lE '#include *<(cjson|nlopt|ceres|libxml|Eigen|glog|OpenImageIO)' "$prefix"/include/brdfit/*.h; then
  bad "a public header includes a back end's header"
fi
for h in "$prefix"/include/brdfit/*.h; do
  echo "#include <brdfit/$(basename "$h")>" |
    "$cc" -std=c11 -Wall -Wextra -Werror -fsyntax-only -I"$prefix/include" -x c - 2>"$tmp/h.err" && ok ||
    bad "$(basename "$h") does not compile alone as C11: $(head -n 3 "$tmp/h.err")"
  echo "#include <brdfit/$(basename "$h")>" |
    "$cxx" -std=c++17 -Wall -Wextra -Werror -fsyntax-only -I"$prefix/include" -x c++ - 2>"$tmp/h.err" && ok ||
    bad "$(basename "$h") does not compile alone as C++17: $(head -n 3 "$tmp/h.err")"
done
# The C++ consumer includes every installed header (a new one must be added there too),
# and nothing that is not installed.
for h in "$prefix"/include/brdfit/*; do basename "$h"; done | sort >"$tmp/headers.installed"
sed -n 's|^#include <brdfit/\([^>]*\)>.*|\1|p' "$src/tests/install/consumer_cxx.cc" | sort >"$tmp/headers.cxx"
comm -23 "$tmp/headers.installed" "$tmp/headers.cxx" | grep . >"$tmp/headers.missing" &&
  bad "tests/install/consumer_cxx.cc does not include: $(tr '\n' ' ' <"$tmp/headers.missing")"
comm -13 "$tmp/headers.installed" "$tmp/headers.cxx" | grep . >"$tmp/headers.extra" &&
  bad "tests/install/consumer_cxx.cc includes headers not installed: $(tr '\n' ' ' <"$tmp/headers.extra")"
# The shared library exports the public API and nothing else.
nm -D --defined-only "$libdir/libbrdfit.so" | awk '{print $3}' | sort >"$tmp/exports"
grep -vq '^bf_' "$tmp/exports" && bad "exports beyond bf_*: $(grep -v '^bf_' "$tmp/exports" | head -n 5 | tr '\n' ' ')"
for s in bf_version bf_fit bf_model_new bf_regress_metric_names; do
  grep -qx "$s" "$tmp/exports" && ok || bad "$s not exported"
done
for s in bf_json_number bf_image_plugin_get; do # internal
  grep -qx "$s" "$tmp/exports" && bad "internal $s exported"
done

# ---- a C program and a C++ program against the installed library -----------------------
mkdir "$tmp/consumer"
cp "$src/tests/install/consumer.c" "$src/tests/install/consumer_cxx.cc" "$src/tests/install/CMakeLists.txt" "$tmp/consumer/"
cd "$tmp/consumer" || exit 1
expect_fit() { # $1: what, $2: output file
  grep -qx 'rho_d 0.300000' "$2" && grep -qE "^version ${version//./\\.}( \(git [^)]+\))? \(headers ${version//./\\.}, ${version//./\\.}\)\$" "$2" && ok ||
    bad "$1: unexpected output: $(cat "$2")"
}
# The library's export (brdfit/export.h), used by a program: the three renderers' files.
expect_exports() { # $1: what, $2: folder, $3: the program's output
  grep -q '"generator":[[:space:]]*"brdfit export"' "$2/brdfit.gltf" 2>/dev/null &&
    grep -qx 'import bpy' "$2/brdfit.blender" 2>/dev/null && grep -q '<bsdf type="principled">' "$2/brdfit.mitsuba" 2>/dev/null &&
    [ "$(grep -c '^exported [a-z]* (converted, rmse_log ' "$3")" = 3 ] && ok ||
    bad "$1: exports: $(ls "$2") $(grep export "$3")"
}
# The C++ program: a line "header NAME: ok (...)" for every installed header, and exit 0.
expect_cxx() { # $1: what, $2: the program
  local h missing=""
  if ! "$2" >"$tmp/cxx.out" 2>&1; then
    bad "$1: failed: $(cat "$tmp/cxx.out")"
    return
  fi
  while read -r h; do
    grep -q "^header $h: ok" "$tmp/cxx.out" || missing="$missing $h"
  done <"$tmp/headers.installed"
  [ -z "$missing" ] && ok || bad "$1: no ok line for$missing: $(cat "$tmp/cxx.out")"
}
cxxflags="-std=c++17 -Wall -Wextra -Werror $flags"
export PKG_CONFIG_PATH=$libdir/pkgconfig
# (a) pkg-config, shared. A .pc file carries no run path: a program of a non-system
# prefix names one (or LD_LIBRARY_PATH does).
# shellcheck disable=SC2046,SC2086
if "$cc" $flags consumer.c -o app_pc $(pkg-config --cflags --libs brdfit) -lm \
     -Wl,-rpath,"$(pkg-config --variable=libdir brdfit)" 2>"$tmp/cc.err"; then
  mkdir "$tmp/exports.pc"
  ./app_pc "$tmp/pc.png" "$tmp/exports.pc" >"$tmp/pc.out" 2>&1 && expect_fit "pkg-config" "$tmp/pc.out" ||
    bad "pkg-config consumer failed: $(cat "$tmp/pc.out")"
  [ -s "$tmp/pc.png" ] && ok || bad "the pkg-config consumer wrote no PNG"
  expect_exports "pkg-config consumer" "$tmp/exports.pc" "$tmp/pc.out"
  used=$(ldd ./app_pc | sed -n "s/^[[:space:]]*libbrdfit\.so\.$so => \([^ ]*\) .*/\1/p")
  [ -n "$used" ] && [ "$(realpath "$used")" = "$(realpath "$libdir/libbrdfit.so.$so")" ] && ok ||
    bad "app_pc uses '$used', not $libdir/libbrdfit.so.$so"
  # The module beside the installed library, even with the build tree's copy present.
  [ "$(module_loaded ./app_pc "$tmp/pc2.png")" = "$libdir/brdfit/libbrdfit-oiio.so" ] && ok ||
    bad "app_pc loaded the image module from '$(module_loaded ./app_pc "$tmp/pc2.png")'"
else
  bad "pkg-config build: $(cat "$tmp/cc.err")"
fi
# shellcheck disable=SC2046,SC2086
if "$cxx" $cxxflags consumer_cxx.cc -o app_cxx_pc $(pkg-config --cflags --libs brdfit) \
     -Wl,-rpath,"$(pkg-config --variable=libdir brdfit)" 2>"$tmp/cxx.err"; then
  expect_cxx "pkg-config C++ consumer" ./app_cxx_pc
  used=$(ldd ./app_cxx_pc | sed -n "s/^[[:space:]]*libbrdfit\.so\.$so => \([^ ]*\) .*/\1/p")
  [ -n "$used" ] && [ "$(realpath "$used")" = "$(realpath "$libdir/libbrdfit.so.$so")" ] && ok ||
    bad "app_cxx_pc uses '$used', not $libdir/libbrdfit.so.$so"
else
  bad "pkg-config C++ build: $(cat "$tmp/cxx.err")"
fi
# (c) pkg-config --static: libbrdfit.a and its dependencies, still with a C compiler.
libs=$(pkg-config --static --libs brdfit | sed "s|-lbrdfit\b|$libdir/libbrdfit.a|")
# shellcheck disable=SC2046,SC2086
if "$cc" $flags consumer.c -o app_static $(pkg-config --cflags brdfit) $libs -lm 2>"$tmp/cc.err"; then
  ./app_static >"$tmp/static.out" 2>&1 && expect_fit "pkg-config --static" "$tmp/static.out" ||
    bad "static consumer failed: $(cat "$tmp/static.out")"
  readelf -d app_static | grep -q 'NEEDED.*libbrdfit' && bad "app_static needs libbrdfit.so"
else
  bad "pkg-config --static build: $(cat "$tmp/cc.err")"
fi
# shellcheck disable=SC2046,SC2086
if "$cxx" $cxxflags consumer_cxx.cc -o app_cxx_static $(pkg-config --cflags brdfit) $libs 2>"$tmp/cxx.err"; then
  expect_cxx "pkg-config --static C++ consumer" ./app_cxx_static
  readelf -d app_cxx_static | grep -q 'NEEDED.*libbrdfit' && bad "app_cxx_static needs libbrdfit.so"
else
  bad "pkg-config --static C++ build: $(cat "$tmp/cxx.err")"
fi
# (b) find_package(brdfit) in a C and C++ project: brdfit::brdfit and brdfit::brdfit_static.
if "$cmake" -S . -B cbuild -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_C_COMPILER="$cc" -DCMAKE_C_FLAGS="$flags" \
     -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" >"$tmp/cmake.log" 2>&1 &&
   "$cmake" --build cbuild >>"$tmp/cmake.log" 2>&1; then
  mkdir "$tmp/exports.cmake"
  ./cbuild/consumer "$tmp/cmake.png" "$tmp/exports.cmake" >"$tmp/cmake.out" 2>&1 &&
    expect_fit "find_package" "$tmp/cmake.out" ||
    bad "find_package consumer failed: $(cat "$tmp/cmake.out")"
  [ -s "$tmp/cmake.png" ] && ok || bad "the find_package consumer wrote no PNG"
  expect_exports "find_package consumer" "$tmp/exports.cmake" "$tmp/cmake.out"
  ./cbuild/consumer_static >"$tmp/cs.out" 2>&1 && expect_fit "find_package static" "$tmp/cs.out" ||
    bad "brdfit::brdfit_static consumer failed: $(cat "$tmp/cs.out")"
  expect_cxx "find_package C++ consumer" ./cbuild/consumer_cxx
  expect_cxx "find_package static C++ consumer" ./cbuild/consumer_cxx_static
else
  bad "find_package build: $(tail -n 20 "$tmp/cmake.log")"
fi
# A newer major version is not offered as compatible (SameMajorVersion).
printf 'cmake_minimum_required(VERSION 3.18)\nproject(v LANGUAGES C)\nfind_package(brdfit %s.0 REQUIRED)\n' $((major + 1)) >"$tmp/v.txt"
mkdir v && cp "$tmp/v.txt" v/CMakeLists.txt
"$cmake" -S v -B v/build -DCMAKE_PREFIX_PATH="$prefix" >/dev/null 2>&1 && bad "find_package(brdfit $((major + 1)).0) accepted $version"

# ---- the installed commands ------------------------------------------------------------
"$prefix/bin/brdfit" --help >"$tmp/help" 2>&1 && grep -q usage "$tmp/help" && ok || bad "brdfit --help: $(head -n 3 "$tmp/help")"
out=$("$prefix/bin/brdfit-synth" --version) && [[ "$out" =~ ^brdfit-synth\ ${version//./\\.}( \(git [^\)]+\))?$ ]] && ok ||
  bad "brdfit-synth --version: '$out'"
"$prefix/bin/brdfit" render --params "$src/examples/walter_rgb.json" -o "$tmp/x.png" >"$tmp/render.out" 2>&1 &&
  [ -s "$tmp/x.png" ] && ok || bad "installed brdfit render: $(cat "$tmp/render.out")"
m=$(module_loaded "$prefix/bin/brdfit" render --params "$src/examples/walter_rgb.json" -o "$tmp/y.png")
[ "$m" = "$prefix/bin/../lib/brdfit/libbrdfit-oiio.so" ] || [ "$(realpath "$m")" = "$(realpath "$libdir/brdfit/libbrdfit-oiio.so")" ] && ok ||
  bad "installed brdfit loaded the image module from '$m'"

# Man pages render, and the completion lists subcommands and a command's options.
for page in brdfit brdfit-fit brdfit-compare brdfit-synth; do
  f=$prefix/share/man/man1/$page.1
  [ -f "$f" ] && MANWIDTH=80 man -l "$f" 2>"$tmp/man.err" | grep -q "^NAME" && [ ! -s "$tmp/man.err" ] && ok ||
    bad "man -l $page.1: $(head -n 3 "$tmp/man.err")"
done
comp=$prefix/share/bash-completion/completions/brdfit
# shellcheck disable=SC1090
words=$(bash -c 'source "$1"; COMP_WORDS=(brdfit co); COMP_CWORD=1; _brdfit; echo "${COMPREPLY[*]}"' _ "$comp")
[ "$words" = "convert compare" ] && ok || bad "completion of 'brdfit co': '$words'"
words=$(bash -c 'source "$1"; COMP_WORDS=(brdfit fit --res); COMP_CWORD=2; _brdfit; echo "${COMPREPLY[*]}"' _ "$comp")
[ "$words" = "--residual" ] && ok || bad "completion of 'brdfit fit --res': '$words'"
[ -f "$prefix/share/bash-completion/completions/brdfit-synth" ] && ok || bad "no brdfit-synth completion"

[ "$fails" = 0 ] && echo "install: all checks passed" || { echo "install: $fails failed"; exit 1; }
