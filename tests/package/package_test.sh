#!/usr/bin/env bash
# The Debian packages as a user gets them: builds them (scripts/package.sh: dist/*.deb,
# lintian without errors), installs them with apt-get, uses what they install (the
# commands on bundled data, a C program and a C++ program that includes every installed
# header, built against them with pkg-config and with find_package, man pages,
# completion), checks that every version agrees, then purges them and checks that the
# machine holds the same packages and none of their files, as before. Needs root
# (apt-get); refuses to run when a brdfit package is installed already, so that it never
# removes one it did not install.
# Arguments: the release build directory (its brdfit is the reference for the fit).
set -u
build=$(cd "${1:?usage: package_test.sh BUILD_DIR}" && pwd)
cd "$(dirname "$0")/../.."
src=$PWD
tmp=$(mktemp -d)
pass=0
fails=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
need() { command -v "$1" >/dev/null || { echo "FAIL: $1 is missing: install the Debian package $2 (scripts/setup.sh does)"; exit 1; }; }
need apt-get apt
need dpkg-query dpkg
need jq jq
need pkg-config pkg-config
need cmake cmake
need cc gcc
need c++ g++
need man man-db
[ "$(id -u)" = 0 ] || { echo "FAIL: the package test installs packages with apt-get: run it as root (CI does)"; exit 1; }

version=$(sed -n 's/^project(brdfit VERSION \([0-9][0-9.]*\) .*/\1/p' CMakeLists.txt)
soversion=$(sed -n 's/^set(BRDFIT_SOVERSION \([0-9][0-9]*\))$/\1/p' cmake/version.cmake)
[ -n "$version" ] && [ -n "$soversion" ] || { echo "FAIL: no version in CMakeLists.txt or soversion in cmake/version.cmake"; exit 1; }
lib=libbrdfit$soversion
packages="brdfit libbrdfit-dev $lib"
installed() { dpkg-query -W -f '${db:Status-Status}' "$1" 2>/dev/null | grep -qx installed; }
for p in $packages; do
  installed "$p" && { echo "FAIL: $p is installed already: remove it first (this test installs and purges its own)"; exit 1; }
done

# What the machine holds before: every package, its version and state.
state() { dpkg-query -W -f '${binary:Package} ${Version} ${db:Status-Abbrev}\n' | sort; }
state >"$tmp/before"
cleanup() {
  # Ours, and anything apt pulled in for them.
  local extra
  extra=$(comm -13 <(cut -d' ' -f1 "$tmp/before") <(state | cut -d' ' -f1) | sed 's/:.*//')
  # shellcheck disable=SC2086
  [ -z "$extra" ] || DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq $extra >"$tmp/purge.log" 2>&1
}
trap 'cleanup; rm -rf "$tmp"' EXIT

# ---- build -------------------------------------------------------------------------------
if ! scripts/package.sh >"$tmp/package.out" 2>&1; then
  cat "$tmp/package.out"
  echo "FAIL: scripts/package.sh"
  exit 1
fi
for p in $packages; do
  [ -f "dist/${p}_${version}_$(dpkg --print-architecture).deb" ] && ok || bad "dist/ has no $p $version package"
done
grep -q '^E:' dist/lintian.txt && bad "lintian errors: $(grep '^E:' dist/lintian.txt | head -n 3)"

# ---- install -------------------------------------------------------------------------------
if ! DEBIAN_FRONTEND=noninteractive apt-get install -y -qq ./dist/*.deb >"$tmp/install.log" 2>&1; then
  cat "$tmp/install.log"
  echo "FAIL: apt-get install ./dist/*.deb"
  exit 1
fi
for p in $packages; do
  v=$(dpkg-query -W -f '${Version}' "$p")
  [ "$v" = "$version" ] && ok || bad "$p is installed at version '$v', not $version"
done

# ---- one version everywhere --------------------------------------------------------------
describe=$(git describe --always --dirty 2>/dev/null || true)
want="$version${describe:+ (git $describe)}"
[ "$(/usr/bin/brdfit --version)" = "brdfit $want" ] && ok || bad "brdfit --version: '$(/usr/bin/brdfit --version)', not 'brdfit $want'"
[ "$(/usr/bin/brdfit-synth --version)" = "brdfit-synth $want" ] && ok || bad "brdfit-synth --version: '$(/usr/bin/brdfit-synth --version)'"
[ "$(pkg-config --modversion brdfit)" = "$version" ] && ok || bad "pkg-config --modversion brdfit: '$(pkg-config --modversion brdfit)'"
# brdfit.pc is relocatable: its libdir is found from its own place.
libdir=$(realpath -m "$(pkg-config --variable=libdir brdfit)")
[ "$libdir" = "/usr/lib/$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || gcc -print-multiarch)" ] && ok ||
  bad "pkg-config's libdir is '$libdir'"
readelf -d "$libdir/libbrdfit.so" | grep -q "SONAME.*\[libbrdfit\.so\.$soversion\]" && ok ||
  bad "the installed library's soname is not libbrdfit.so.$soversion"
[ "$(readlink "$libdir/libbrdfit.so.$soversion")" = "libbrdfit.so.$version" ] && ok ||
  bad "libbrdfit.so.$soversion -> '$(readlink "$libdir/libbrdfit.so.$soversion")'"
# CHANGELOG.md: the newest release it names is this version, or an older one while this
# version is still under "Unreleased" (docs/releasing.md).
newest=$(sed -n 's/^## \[\([0-9][0-9.]*\)\].*/\1/p' CHANGELOG.md | head -n 1)
if [ -n "$newest" ] && [ "$newest" != "$version" ]; then
  [ "$(printf '%s\n%s\n' "$newest" "$version" | sort -V | tail -n 1)" = "$version" ] &&
    grep -q '^## \[Unreleased\]' CHANGELOG.md && ok || bad "CHANGELOG.md's newest release is $newest, the build's version $version"
else
  grep -q "^## \[$version\]\|^## \[Unreleased\]" CHANGELOG.md && ok || bad "CHANGELOG.md has no section for $version"
fi
zcat "/usr/share/doc/brdfit/changelog.Debian.gz" | head -n 1 | grep -q "^brdfit ($version) " && ok ||
  bad "the package's Debian changelog does not start at $version"

# ---- the commands -------------------------------------------------------------------------
cd "$tmp" || exit 1
/usr/bin/brdfit fit "$src/examples/cornell/cayman.brdf" --rgb -m walter -q -o pkg.json >fit.out 2>&1 && ok ||
  bad "installed brdfit fit: $(cat fit.out)"
"$build/cmd/brdfit" fit "$src/examples/cornell/cayman.brdf" --rgb -m walter -q -o ref.json >ref.out 2>&1 ||
  bad "the build's brdfit fit: $(cat ref.out)"
# The same fit as the build's (the package is built with Debian's flags: -O2, hardening).
a=$(jq .metrics.rmse_log pkg.json 2>/dev/null) b=$(jq .metrics.rmse_log ref.json 2>/dev/null)
awk -v a="$a" -v b="$b" 'BEGIN { exit !(a > 0 && b > 0 && (a - b) / b < 1e-9 && (b - a) / b < 1e-9) }' && ok ||
  bad "the installed fit's rmse_log $a is not the build's $b"
[ "$(jq -r .brdfit_version pkg.json)" = "$want" ] && ok || bad "the fit file says version '$(jq -r .brdfit_version pkg.json)'"
# Pictures go through the image module, which the library package holds.
/usr/bin/brdfit render --params pkg.json -o sphere.png >render.out 2>&1 && [ -s sphere.png ] && ok ||
  bad "installed brdfit render: $(cat render.out)"
module=$(LD_DEBUG=files /usr/bin/brdfit render --params pkg.json -o s2.png 2>&1 >/dev/null |
  grep -o 'file=[^ ]*libbrdfit-oiio\.so' | head -n 1 | cut -c6-)
[ "$(realpath -m "$module")" = "$libdir/brdfit/libbrdfit-oiio.so" ] && ok || bad "the image module came from '$module'"
/usr/bin/brdfit-synth --params "$src/examples/walter_rgb.json" --pattern uniform --count 100 -o synth.csv >synth.out 2>&1 &&
  [ "$(grep -vc '^#' synth.csv)" = 101 ] && ok || bad "installed brdfit-synth: $(cat synth.out)"
for page in brdfit brdfit-fit brdfit-synth; do
  [ "$(man -w "$page" 2>/dev/null)" = "/usr/share/man/man1/$page.1.gz" ] && ok || bad "man -w $page: '$(man -w "$page" 2>&1)'"
done
MANWIDTH=80 man brdfit-fit 2>/dev/null | grep -q -- '--residual' && ok || bad "man brdfit-fit does not list --residual"
words=$(bash -c 'source /usr/share/bash-completion/completions/brdfit; COMP_WORDS=(brdfit fit --res); COMP_CWORD=2; _brdfit; echo "${COMPREPLY[*]}"')
[ "$words" = "--residual" ] && ok || bad "completion of 'brdfit fit --res': '$words'"

# ---- a program against the installed library ------------------------------------------------
cp "$src/tests/install/consumer.c" "$src/tests/install/consumer_cxx.cc" "$src/tests/install/CMakeLists.txt" .
expect_consumer() { # $1: what, $2: output
  grep -qx 'rho_d 0.300000' "$2" && grep -qxF "version $want (headers $version, $version)" "$2" && ok ||
    bad "$1: unexpected output: $(cat "$2")"
}
# The C++ program (tests/install/consumer_cxx.cc): exit 0 and a line "header NAME: ok
# (...)" for every header the -dev package installed.
expect_cxx() { # $1: what, $2: the program
  local h missing=""
  if ! "$2" >cxx.out 2>&1; then
    bad "$1: failed: $(cat cxx.out)"
    return
  fi
  for h in /usr/include/brdfit/*; do
    grep -q "^header $(basename "$h"): ok" cxx.out || missing="$missing $(basename "$h")"
  done
  [ -z "$missing" ] && ok || bad "$1: no ok line for$missing: $(cat cxx.out)"
}
# shellcheck disable=SC2046
if cc consumer.c -o app $(pkg-config --cflags --libs brdfit) -lm 2>cc.err; then
  mkdir exports
  ./app app.png exports >app.out 2>&1 && expect_consumer "pkg-config consumer" app.out || bad "pkg-config consumer failed: $(cat app.out)"
  [ -s app.png ] && ok || bad "the pkg-config consumer wrote no PNG"
  # The library's export (brdfit/export.h): glTF, Blender and Mitsuba files from the program.
  [ -s exports/brdfit.gltf ] && [ -s exports/brdfit.blender ] && [ -s exports/brdfit.mitsuba ] &&
    [ "$(grep -c '^exported [a-z]* (converted' app.out)" = 3 ] && ok || bad "the consumer's exports: $(ls exports; cat app.out)"
  used=$(ldd ./app | sed -n "s/^[[:space:]]*libbrdfit\.so\.$soversion => \([^ ]*\) .*/\1/p")
  [ -n "$used" ] && [ "$(realpath "$used")" = "$libdir/libbrdfit.so.$version" ] && ok || bad "app uses '$used', not $libdir's library"
else
  bad "cc consumer.c \$(pkg-config --cflags --libs brdfit): $(cat cc.err)"
fi
# shellcheck disable=SC2046
if c++ -std=c++17 -Wall -Wextra -Werror consumer_cxx.cc -o app_cxx $(pkg-config --cflags --libs brdfit) 2>cxx.err; then
  expect_cxx "pkg-config C++ consumer" ./app_cxx
else
  bad "c++ consumer_cxx.cc \$(pkg-config --cflags --libs brdfit): $(cat cxx.err)"
fi
# shellcheck disable=SC2046
if cc consumer.c -o app_static $(pkg-config --cflags brdfit) "$libdir/libbrdfit.a" $(pkg-config --static --libs-only-l brdfit | sed 's/-lbrdfit\b//') -lm 2>cc.err; then
  ./app_static >static.out 2>&1 && expect_consumer "static consumer" static.out || bad "static consumer failed: $(cat static.out)"
else
  bad "the static consumer did not build: $(head -n 5 cc.err)"
fi
# shellcheck disable=SC2046
if c++ -std=c++17 -Wall -Wextra -Werror consumer_cxx.cc -o app_cxx_static $(pkg-config --cflags brdfit) "$libdir/libbrdfit.a" \
     $(pkg-config --static --libs-only-l brdfit | sed 's/-lbrdfit\b//') 2>cxx.err; then
  expect_cxx "static C++ consumer" ./app_cxx_static
else
  bad "the static C++ consumer did not build: $(head -n 5 cxx.err)"
fi
printf 'cmake_minimum_required(VERSION 3.18)\nproject(v LANGUAGES C)\nfind_package(brdfit REQUIRED)\nmessage(STATUS "brdfit_VERSION=${brdfit_VERSION}")\n' >v.cmake
mkdir v && cp v.cmake v/CMakeLists.txt
cmake -S v -B v/build >v.log 2>&1 && grep -q "brdfit_VERSION=$version\$" v.log && ok || bad "find_package(brdfit) version: $(grep -i brdfit v.log | head -n 3)"
if cmake -S . -B cbuild >cmake.log 2>&1 && cmake --build cbuild >>cmake.log 2>&1; then
  ./cbuild/consumer >cm.out 2>&1 && expect_consumer "find_package consumer" cm.out || bad "find_package consumer failed: $(cat cm.out)"
  ./cbuild/consumer_static >cms.out 2>&1 && expect_consumer "find_package static consumer" cms.out || bad "brdfit::brdfit_static consumer failed: $(cat cms.out)"
  expect_cxx "find_package C++ consumer" ./cbuild/consumer_cxx
  expect_cxx "find_package static C++ consumer" ./cbuild/consumer_cxx_static
else
  bad "find_package build: $(tail -n 20 cmake.log)"
fi
cd "$src" || exit 1

# ---- remove: the machine as it was ---------------------------------------------------------
files=$(dpkg -L $packages 2>/dev/null | grep -v '^/usr/share/doc$\|^/usr$\|^/usr/share$\|^/\.$' | sort)
DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq $packages >"$tmp/purge.log" 2>&1 && ok || bad "apt-get purge: $(cat "$tmp/purge.log")"
state >"$tmp/after"
diff "$tmp/before" "$tmp/after" >"$tmp/state.diff" && ok || bad "the machine's packages differ after the purge: $(head -n 5 "$tmp/state.diff")"
left=""
for f in $files; do
  case $f in /usr/bin/brdfit* | /usr/include/brdfit* | */libbrdfit* | */brdfit/* | */brdfit | /usr/share/doc/*brdfit*)
    [ -e "$f" ] || [ -L "$f" ] && left="$left $f" ;;
  esac
done
[ -z "$left" ] && ok || bad "left behind by the purge:$left"

echo "package: $pass passed, $fails failed"
[ "$fails" = 0 ]
