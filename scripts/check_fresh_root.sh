#!/usr/bin/env bash
# The README's two commands on a fresh Debian 12 root, as a new user runs them: makes DIR
# with debootstrap (minbase, git and ca-certificates only), clones this repository's
# current commit into DIR/root/brdfit, and runs there, as root, first the quick start
# command, then the test suite command. A tool the suite uses and scripts/setup.sh does not
# install fails here, where a developer's machine would hide it (docs/releasing.md).
#
#   scripts/check_fresh_root.sh [--ca FILE]... DIR
#
# --ca FILE: a certificate authority to trust inside the root (a network whose HTTPS goes
# through a proxy of its own needs it for npm). Needs root and debootstrap; the logs are
# DIR.readme1.log and DIR.readme2.log. The mounts it makes under DIR are undone at exit;
# DIR itself is left for inspection (remove it with rm -rf once done).
set -euo pipefail
cas=()
while [ $# -gt 1 ]; do
  case $1 in
    --ca) cas+=("$(realpath "$2")"); shift 2 ;;
    *) break ;;
  esac
done
[ $# = 1 ] || { echo "usage: check_fresh_root.sh [--ca FILE]... DIR" >&2; exit 2; }
[ "$(id -u)" = 0 ] || { echo "check_fresh_root.sh: run as root (debootstrap, chroot, mounts)" >&2; exit 1; }
command -v debootstrap >/dev/null || { echo "check_fresh_root.sh: install the Debian package debootstrap" >&2; exit 1; }
repo=$(cd "$(dirname "$0")/.." && pwd)
dir=$(realpath -m "$1")
[ ! -e "$dir" ] || { echo "check_fresh_root.sh: $dir exists: give a new folder" >&2; exit 2; }

debootstrap --variant=minbase --include=git,ca-certificates bookworm "$dir" http://deb.debian.org/debian >"$dir.debootstrap.log" 2>&1 ||
  { tail -n 20 "$dir.debootstrap.log" >&2; echo "check_fresh_root.sh: debootstrap failed" >&2; exit 1; }
git clone -q "$repo" "$dir/root/brdfit"

# /proc, and /sys and /dev with what is mounted below them (slurmd needs the cgroup file
# system); slaves, so that undoing them here never reaches the host's.
cleanup() {
  for m in dev sys proc; do umount -R "$dir/$m" 2>/dev/null || umount -l "$dir/$m" 2>/dev/null || true; done
}
trap cleanup EXIT
mount -t proc proc "$dir/proc"
for m in sys dev; do
  mount --rbind "/$m" "$dir/$m"
  mount --make-rslave "$dir/$m"
done
cp /etc/resolv.conf "$dir/etc/resolv.conf"
if [ ${#cas[@]} -gt 0 ]; then
  mkdir -p "$dir/usr/local/share/ca-certificates"
  for ca in "${cas[@]}"; do cp "$ca" "$dir/usr/local/share/ca-certificates/$(basename "${ca%.*}").crt"; done
  chroot "$dir" update-ca-certificates >/dev/null
fi

# The two commands exactly as the README writes them (the first line of each sh block).
readme_command() { awk -v h="$1" 'index($0, h) == 1 { f = 1 } f && /^```sh/ { getline; print; exit }' "$repo/README.md"; }
quick=$(readme_command "## Quick start")
suite=$(readme_command "Run the whole test suite")
[ -n "$quick" ] && [ -n "$suite" ] || { echo "check_fresh_root.sh: README.md: the two commands not found" >&2; exit 1; }
run() {
  chroot "$dir" /usr/bin/env -i HOME=/root TERM=dumb LANG=C.UTF-8 \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin bash -c "cd /root/brdfit && $1"
}
status=0
echo "1/2: $quick"
if run "$quick" >"$dir.readme1.log" 2>&1; then echo "    passed"; else echo "    FAILED (log: $dir.readme1.log)"; status=1; fi
echo "2/2: $suite"
if run "$suite" >"$dir.readme2.log" 2>&1; then echo "    passed"; else echo "    FAILED (log: $dir.readme2.log)"; status=1; fi
exit $status
