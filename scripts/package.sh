#!/usr/bin/env bash
# Debian packages of brdfit into dist/: libbrdfit0 (the shared library and its image
# module), libbrdfit-dev (headers, static library, pkg-config file, CMake package) and
# brdfit (brdfit, brdfit-synth, man pages, bash completion), built by debhelper from
# debian/ in a copy of the working tree (tracked and untracked files, not the ignored
# ones), then checked with lintian, which must report no error.
#
# The version is the CMake project's (project() in CMakeLists.txt): debian/changelog is
# written here, for the copy, with that version and the git description beside it.
# Needs what scripts/setup.sh installs (debhelper, lintian and the build dependencies).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
fail() { echo "package.sh: $*" >&2; exit 1; }
for tool in dpkg-buildpackage:dpkg-dev dh:debhelper lintian:lintian git:git; do
  command -v "${tool%%:*}" >/dev/null || fail "${tool%%:*} is missing: install the Debian package ${tool##*:} (scripts/setup.sh does)"
done

version=$(sed -n 's/^project(brdfit VERSION \([0-9][0-9.]*\) .*/\1/p' CMakeLists.txt)
[ -n "$version" ] || fail "CMakeLists.txt: no project(brdfit VERSION x.y.z ...) line"
describe=$(git describe --always --dirty 2>/dev/null || true)
maintainer=$(sed -n 's/^Maintainer: //p' debian/control)

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src=$work/brdfit-$version
mkdir "$src"
# The working tree as git sees it: committed and uncommitted files, nothing ignored.
git ls-files -z --cached --others --exclude-standard | while IFS= read -r -d '' f; do
  [ -e "$f" ] || [ -L "$f" ] && printf '%s\0' "$f"
done | tar -C "$root" --null -T - -cf - | tar -C "$src" -xf -

# debian/changelog: one entry, this version (a native package: brdfit is its own upstream).
# Its date is the commit's, so the same commit packages to the same files.
date=$(git log -1 --format=%cD 2>/dev/null || date -R)
{
  echo "brdfit ($version) unstable; urgency=medium"
  echo
  echo "  * brdfit $version${describe:+ (git $describe)}, packaged by scripts/package.sh."
  echo "    What changed in each release: CHANGELOG.md."
  echo
  echo " -- $maintainer  $date"
} >"$src/debian/changelog"

echo "package.sh: building brdfit $version${describe:+ (git $describe)} (log: dist/build.log)"
mkdir -p dist
rm -f dist/*.deb dist/build.log dist/lintian.txt
export DEB_BUILD_OPTIONS="nocheck noddebs parallel=$(nproc)"
export BRDFIT_GIT_DESCRIPTION=$describe
if ! (cd "$src" && dpkg-buildpackage -b -us -uc) >dist/build.log 2>&1; then
  tail -n 30 dist/build.log >&2
  fail "dpkg-buildpackage failed (the whole log: dist/build.log)"
fi
cp "$work"/*.deb dist/
# Errors fail the build; warnings and notes are listed for whoever reads dist/lintian.txt.
if ! lintian --fail-on error --info dist/*.deb >dist/lintian.txt 2>&1; then
  cat dist/lintian.txt >&2
  fail "lintian reports errors (dist/lintian.txt)"
fi
echo "package.sh: lintian: no errors ($(grep -c '^W:' dist/lintian.txt || true) warnings, dist/lintian.txt)"
ls dist/*.deb
