#!/usr/bin/env bash
# Run by cli_outputs.sh inside a private mount namespace (unshare -m), as root: mounts a
# 256 kB tmpfs on FOLDER/full, puts good outputs there, fills it, and checks that every
# kind of output (result JSON, PNG and EXR images, CSV, a baseline on --update, JUnit
# XML, an HTML report, a MERL table) fails with one line naming ENOSPC, exit 1, the old file whole and
# no temporary left; then remounts it read-only and checks EROFS is found before any
# fit. Prints FAIL lines and "N passed, M failed"; exit 0 only when all passed.
#   outputs_full_disk.sh BRDFIT FOLDER   (FOLDER holds s.csv, P.json, D.csv, merl.binary)
set -u
BRDFIT=$1
cd "$2" || exit 1
full=$PWD/full
pass=0
fails=0
ok() { pass=$((pass + 1)); }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }

mkdir -p "$full" good
mount -t tmpfs -o size=256k tmpfs "$full" || { echo "FAIL: cannot mount a tmpfs"; exit 1; }

# --- good outputs, kept twice: on the small disk and aside for comparison --------------
"$BRDFIT" fit s.csv -m lambert -o "$full/r.json" >/dev/null &&
  "$BRDFIT" render --params P.json --size 64 -o "$full/img.png" &&
  "$BRDFIT" convert s.csv "$full/c.csv" >/dev/null &&
  "$BRDFIT" eval --params P.json --dirs D.csv -o "$full/e.csv" &&
  "$BRDFIT" compare s.csv -m lambert --quiet --html "$full/rep" >/dev/null ||
  bad "writing the good outputs failed"
printf '{"brdfit_baseline": 1, "cases": [{"name": "lam", "data": "%s", "model": "lambert", "expected": {}}]}\n' \
  "$PWD/s.csv" >"$full/base.json"
"$BRDFIT" regress "$full/base.json" --update >/dev/null || bad "baseline --update failed"
"$BRDFIT" regress "$full/base.json" --junit "$full/j.xml" >/dev/null || bad "regress --junit failed"
cp -a "$full"/. good/
# Everything left is taken.
dd if=/dev/zero of="$full/filler" bs=4k 2>/dev/null
[ "$(df --output=avail "$full" | tail -1 | tr -d ' ')" = 0 ] && ok || bad "the tmpfs is not full: $(df "$full")"

# name, old file (in full/), then the command: exit 1, one line naming ENOSPC and the
# file, the old file as it was, no temporary.
no_space() {
  local name=$1 file=$2
  shift 2
  "$@" >/dev/null 2>err
  local st=$?
  [ $st = 1 ] && ok || bad "$name: exit status $st, want 1 ($(cat err))"
  [ "$(wc -l <err)" = 1 ] && ok || bad "$name: stderr is not one line: $(cat err)"
  grep -q "$file.*No space left on device" err && ok || bad "$name: message lacks '$file ... No space': $(cat err)"
  if [ -d "good/$file" ]; then
    diff -r "good/$file" "$full/$file" >/dev/null && ok || bad "$name: the old $file changed"
  elif [ -e "good/$file" ]; then
    cmp -s "good/$file" "$full/$file" && ok || bad "$name: the old $file changed"
  else
    [ -e "$full/$file" ] && bad "$name: a new $file was left" || ok
  fi
  [ -z "$(find "$full" -name '*.tmp.*')" ] && ok || bad "$name: temporary left: $(find "$full" -name '*.tmp.*')"
}
no_space "fit -o" r.json "$BRDFIT" fit s.csv -m lambert,walter -o "$full/r.json"
# OpenImageIO's PNG writer used to report success here and leave a truncated image.
no_space "render png" img.png "$BRDFIT" render --params P.json --size 64 -o "$full/img.png"
no_space "render exr" img.exr "$BRDFIT" render --params P.json --size 64 -o "$full/img.exr"
no_space "convert csv" c.csv "$BRDFIT" convert s.csv "$full/c.csv"
no_space "eval -o" e.csv "$BRDFIT" eval --params P.json --dirs D.csv -o "$full/e.csv"
no_space "regress --update" base.json "$BRDFIT" regress "$full/base.json" --update
no_space "regress --junit" j.xml "$BRDFIT" regress "$full/base.json" --junit "$full/j.xml"
no_space "convert merl" m.binary "$BRDFIT" convert merl.binary "$full/m.binary" --max-theta 30
no_space "compare --html" rep "$BRDFIT" compare s.csv -m lambert,walter --quiet --html "$full/rep"

# --- a read-only file system: found before the fit, nothing printed, exit 1 -------------
mount -o remount,ro "$full" || bad "cannot remount read-only"
"$BRDFIT" fit s.csv -m lambert -o "$full/new.json" >out 2>err
st=$?
[ $st = 1 ] && ok || bad "read-only fs: exit status $st, want 1"
grep -q 'new.json: cannot write in the folder .*: Read-only file system' err && ok || bad "read-only fs: $(cat err)"
[ -s out ] && bad "read-only fs: the fit ran: $(cat out)" || ok

umount "$full"
echo "$pass passed, $fails failed"
[ "$fails" = 0 ]
