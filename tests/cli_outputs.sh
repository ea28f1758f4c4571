#!/usr/bin/env bash
# Outputs survive failures and never destroy an input, for every command that writes:
# - an output that is an input (same file by device and inode: the name itself, ./name,
#   a hard link, a symbolic link) or another output is refused before any work: exit 2,
#   one line naming both, the input unchanged;
# - an empty name is bad usage (exit 2, nothing created); a missing or read-only folder
#   fails before any fit (exit 1, one line, nothing printed by a fit);
# - a symbolic link is followed (the file it points to replaced, the link kept, regress
#   --update too); a device or FIFO is written through, never replaced;
# - a replaced file keeps its mode, a new one gets the umask's;
# - real write failures (/dev/full, a file size limit, a full tmpfs: ENOSPC, and a
#   read-only file system: outputs_full_disk.sh, where a tmpfs can be mounted) fail with
#   the cause, exit 1, the old file whole, no temporary;
# - a fatal signal in the middle of a write (SIGXFSZ at the size limit) leaves no
#   temporary, for a file, a PNG and an HTML report folder.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need unshare util-linux; need setpriv util-linux; need mount mount; need timeout coreutils
BRDFIT=$(cd "$(dirname "$BRDFIT")" && pwd)/$(basename "$BRDFIT") # the checks run from $tmp
HERE=$(cd "$(dirname "$0")" && pwd)
cd "$tmp" || exit 1

"$SYNTH" --params "$DATA/lambert_rgb.json" --pattern uniform --count 200 --noise 0.01 --seed 1 -o s.csv ||
  bad "brdfit-synth failed"
cp "$DATA/lambert_rgb.json" P.json
cp "$DATA/dirs_small.csv" D.csv
printf '{"brdfit_baseline": 1, "cases": [{"name": "lam", "data": "s.csv", "model": "lambert", "expected": {}}]}\n' \
  >base.json
"$BRDFIT" regress base.json --update >/dev/null || bad "making the baseline failed"
echo "not really a MERL table" >m.binary
cp P.json pic.png # parameter files named like an image, like a table
cp P.json pp.csv
ln s.csv hard.csv
ln -s s.csv soft.csv
inputs="s.csv P.json D.csv base.json m.binary pic.png pp.csv"
sums() { md5sum $inputs; }
before=$(sums)
no_temporaries() { [ -z "$(find "$tmp" -name '*.tmp.*')" ]; }

# --- output = input, or = another output: exit 2, one line naming both ----------------------
refused() { # what, the two names the message must hold, command...
  local what=$1 a=$2 b=$3
  shift 3
  "$BRDFIT" "$@" >out 2>err
  local st=$?
  [ $st = 2 ] && ok || bad "$what: exit status $st, want 2 ($(cat err))"
  [ "$(wc -l <err)" = 1 ] && ok || bad "$what: stderr is not one line: $(cat err)"
  grep -qF -- "$a " err && grep -qF -- " $b" err && grep -q 'same file' err && ok ||
    bad "$what: message does not name '$a' and '$b' as the same file: $(cat err)"
  [ -s out ] && bad "$what: work was done: $(head -2 out)" || ok
  [ "$(sums)" = "$before" ] && ok || bad "$what: an input changed"
}
refused "fit -o data" "-o s.csv" "data file s.csv" fit s.csv -m walter -o s.csv
refused "fit -o ./data" "-o ./s.csv" "data file s.csv" fit s.csv -m walter -o ./s.csv
refused "fit -o hard link" "-o hard.csv" "data file s.csv" fit s.csv -m walter -o hard.csv
refused "fit -o symlink" "-o soft.csv" "data file s.csv" fit s.csv -m walter -o soft.csv
refused "fit -o absolute" "-o $tmp/s.csv" "data file s.csv" fit s.csv -m walter -o "$tmp/s.csv"
refused "eval -o params" "-o P.json" "--params file P.json" eval --params P.json --dirs D.csv -o P.json
refused "eval -o dirs" "-o ./D.csv" "--dirs file D.csv" eval --params P.json --dirs D.csv -o ./D.csv
refused "select -o data" "-o s.csv" "data file s.csv" select s.csv -m lambert -o s.csv
refused "select --json = -o" "--json x.json" "-o ./x.json" select s.csv -m lambert --json x.json -o ./x.json
refused "compare --csv data" "--csv s.csv" "data file s.csv" compare s.csv -m lambert --csv s.csv
refused "compare --json = --csv" "--json y.json" "--csv $tmp/y.json" compare s.csv -m lambert --json y.json \
  --csv "$tmp/y.json"
refused "convert csv in place" "output soft.csv" "input s.csv" convert s.csv soft.csv
refused "convert merl in place" "output m.binary" "input m.binary" convert m.binary m.binary --max-theta 30
refused "regress --junit baseline" "--junit base.json" "baseline base.json" regress base.json --junit base.json
refused "regress --junit data" "--junit ./s.csv" "data file" regress base.json --junit ./s.csv
refused "tradeoff --csv = --plot" "--csv z.png" "--plot ./z.png" tradeoff s.csv -m lambert --csv z.png --plot ./z.png
refused "render -o params" "-o ./pic.png" "--params file pic.png" render --params pic.png -o ./pic.png
"$SYNTH" --params pp.csv --pattern uniform --count 5 -o ./pp.csv 2>err
[ $? = 2 ] && grep -q 'same file' err && ok || bad "brdfit-synth -o params: $(cat err)"
[ "$(sums)" = "$before" ] && ok || bad "brdfit-synth changed an input"
# Standard output twice is refused; devices may be shared (nothing is destroyed).
"$BRDFIT" compare s.csv -m lambert --json - --csv - >/dev/null 2>err
[ $? = 2 ] && grep -q 'both write to standard output' err && ok || bad "--json - --csv -: $(cat err)"
"$BRDFIT" compare s.csv -m lambert --json /dev/null --csv /dev/null >/dev/null 2>err && ok ||
  bad "two outputs to /dev/null refused: $(cat err)"
no_temporaries && ok || bad "temporaries left"

# --- bad names and unwritable folders: before any work ---------------------------------------
mkdir -p scratch
(cd scratch && "$BRDFIT" fit ../s.csv -m lambert -o '' >../out 2>../err)
st=$?
[ $st = 2 ] && [ "$(wc -l <err)" = 1 ] && grep -q -- '-o: the file name is empty' err && ok ||
  bad "-o '': exit status $st: $(cat err)"
[ -z "$(ls -A scratch)" ] && ok || bad "-o '' created: $(ls -A scratch)"
(cd scratch && "$BRDFIT" convert ../s.csv '' >/dev/null 2>../err)
[ $? = 2 ] && ok || bad "convert IN '': $(cat err)"
[ -z "$(ls -A scratch)" ] && ok || bad "convert IN '' created: $(ls -A scratch)"
unwritable() { # what, pattern, command...: exit 1, one line, no fit run (nothing on stdout)
  local what=$1 pattern=$2
  shift 2
  "$@" >out 2>err
  local st=$?
  [ $st = 1 ] && ok || bad "$what: exit status $st, want 1 ($(cat err))"
  [ "$(wc -l <err)" = 1 ] && grep -q -- "$pattern" err && ok || bad "$what: $(cat err)"
  [ -s out ] && bad "$what: work was done before the output was checked: $(head -2 out)" || ok
}
N=/nonexistent/x
nofolder="cannot write in the folder /nonexistent: No such file or directory"
unwritable "fit -o missing folder" "$N.json: $nofolder" "$BRDFIT" fit s.csv -m lambert -o $N.json
unwritable "select -o missing folder" "$N.json: $nofolder" "$BRDFIT" select s.csv -m lambert -o $N.json
unwritable "compare --csv missing folder" "$N.csv: $nofolder" "$BRDFIT" compare s.csv -m lambert --csv $N.csv
unwritable "compare --html missing folder" "$N: $nofolder" "$BRDFIT" compare s.csv -m lambert --html $N
unwritable "tradeoff --plot missing folder" "$N.png: $nofolder" "$BRDFIT" tradeoff s.csv -m lambert --plot $N.png
unwritable "regress --junit missing folder" "$N.xml: $nofolder" "$BRDFIT" regress base.json --junit $N.xml
unwritable "render missing folder" "$N.png: $nofolder" "$BRDFIT" render --params P.json -o $N.png
unwritable "convert missing folder" "$N.csv: $nofolder" "$BRDFIT" convert s.csv $N.csv
unwritable "fit -o folder" "scratch: is a folder" "$BRDFIT" fit s.csv -m lambert -o scratch

# A read-only folder. root may write anywhere, so as root the commands run as nobody.
mkdir ro
echo "old" >ro/old.json
sed "s|\"s.csv\"|\"$tmp/s.csv\"|" base.json >ro/base.json
chmod 666 ro/old.json ro/base.json # writable files: the folder is what stops the rename
chmod 555 ro
chmod 755 "$tmp"
as_user() {
  if [ "$(id -u)" = 0 ]; then setpriv --reuid=65534 --regid=65534 --clear-groups -- "$@"; else "$@"; fi
}
denied="cannot write in the folder ro: Permission denied"
unwritable "fit -o read-only folder" "ro/x.json: $denied" as_user "$BRDFIT" fit s.csv -m lambert -o ro/x.json
unwritable "fit -o over a file in a read-only folder" "ro/old.json: $denied" as_user "$BRDFIT" fit s.csv -m lambert \
  -o ro/old.json
unwritable "render -o read-only folder" "ro/x.png: $denied" as_user "$BRDFIT" render --params P.json -o ro/x.png
unwritable "compare --html in a read-only folder" "ro/rep: $denied" as_user "$BRDFIT" compare s.csv -m lambert \
  --html ro/rep
unwritable "regress --update in a read-only folder" "ro/base.json: $denied" as_user "$BRDFIT" regress ro/base.json \
  --update
[ "$(cat ro/old.json)" = old ] && [ "$(ls ro | tr '\n' ' ')" = "base.json old.json " ] && ok ||
  bad "read-only folder changed: $(ls ro)"

# --- symbolic links are followed, the link kept ---------------------------------------------
echo old >real.json
ln -s real.json link.json
"$BRDFIT" fit s.csv -m lambert -o link.json >/dev/null 2>err || bad "fit -o link: $(cat err)"
[ -L link.json ] && ok || bad "fit -o link.json replaced the link"
grep -q '"model":.*"lambert"' real.json && ok || bad "the link's file was not written"
mkdir -p sub
ln -s sub/made.json dangling.json
"$BRDFIT" fit s.csv -m lambert -o dangling.json >/dev/null 2>err || bad "fit -o dangling link: $(cat err)"
[ -L dangling.json ] && [ -f sub/made.json ] && ok || bad "a dangling link's file was not made"
# regress LINK --update rewrites the baseline the link points to.
printf '{"brdfit_baseline": 1, "cases": [{"name": "lam", "data": "%s", "model": "lambert", "expected": {}}]}\n' \
  "$tmp/s.csv" >sub/real_base.json
ln -s sub/real_base.json link_base.json
"$BRDFIT" regress link_base.json --update >/dev/null 2>err || bad "regress link --update: $(cat err)"
[ -L link_base.json ] && ok || bad "regress --update replaced the link"
grep -q '"rho_d"' sub/real_base.json && ok || bad "regress --update did not update the linked baseline"
"$BRDFIT" regress link_base.json >/dev/null 2>err && ok || bad "the updated baseline does not pass: $(cat err)"

# --- devices and FIFOs are written through ---------------------------------------------------
"$BRDFIT" fit s.csv -m lambert -o /dev/null >/dev/null 2>err && [ -c /dev/null ] && ok || bad "fit -o /dev/null: $(cat err)"
"$BRDFIT" eval --params P.json --dirs D.csv >want.csv
"$BRDFIT" eval --params P.json --dirs D.csv -o /dev/stdout >got.csv 2>err && cmp -s want.csv got.csv && ok ||
  bad "eval -o /dev/stdout: $(cat err)"
ln -s /dev/stdout to_stdout.csv
"$BRDFIT" eval --params P.json --dirs D.csv -o to_stdout.csv | cmp -s want.csv - && [ -L to_stdout.csv ] && ok ||
  bad "eval -o link to /dev/stdout"
mkfifo pipe.csv
# (timeout: a FIFO's open waits for the other end, so a failure must not hang the test.)
timeout 30 cat pipe.csv >from_pipe.csv &
reader=$!
timeout 30 "$BRDFIT" eval --params P.json --dirs D.csv -o pipe.csv 2>err || bad "eval -o FIFO: $(cat err)"
wait $reader
[ -p pipe.csv ] && cmp -s want.csv from_pipe.csv && ok || bad "eval -o FIFO: replaced, or wrong content"
"$BRDFIT" eval --params P.json --dirs D.csv -o /dev/full 2>err
[ $? = 1 ] && grep -q '/dev/full: write error: No space left on device' err && ok || bad "eval -o /dev/full: $(cat err)"
"$BRDFIT" fit s.csv -m lambert -o /dev/full >/dev/null 2>err
[ $? = 1 ] && grep -q 'No space left on device' err && ok || bad "fit -o /dev/full: $(cat err)"

# --- modes: kept when replaced, the umask's when new ------------------------------------------
echo old >m600.json
chmod 600 m600.json
"$BRDFIT" fit s.csv -m lambert -o m600.json >/dev/null && [ "$(stat -c %a m600.json)" = 600 ] && ok ||
  bad "a 0600 file became $(stat -c %a m600.json)"
(umask 027 && "$BRDFIT" render --params P.json --size 8 -o new.png) && [ "$(stat -c %a new.png)" = 640 ] && ok ||
  bad "a new image under umask 027 is $(stat -c %a new.png)"
chmod 604 new.png
"$BRDFIT" render --params P.json --size 16 -o new.png && [ "$(stat -c %a new.png)" = 604 ] && ok ||
  bad "a replaced image lost its mode 604: $(stat -c %a new.png)"

# --- a file size limit: EFBIG when SIGXFSZ is ignored, the signal's death otherwise ----------
"$BRDFIT" fit s.csv -m lambert,walter -o big.json >/dev/null || bad "fit -o big.json failed"
"$BRDFIT" render --params P.json --size 64 -o big.png || bad "render big.png failed"
cp big.json big.json.good
cp big.png big.png.good
limited() { # ignore|default, command...: runs it under a 1 kB file size limit
  local how=$1
  shift
  (
    [ "$how" = ignore ] && trap '' XFSZ
    ulimit -f 1
    exec "$@"
  ) >/dev/null 2>err
}
# (The shell's "File size limit exceeded" notes go to /dev/null with the function's stderr.)
limited ignore "$BRDFIT" fit s.csv -m lambert,walter -o big.json
[ $? = 1 ] && grep -q 'big.json: write error: File too large' err && ok || bad "fit under a size limit: $(cat err)"
limited ignore "$BRDFIT" render --params P.json --size 64 -o big.png
[ $? = 1 ] && grep -q 'big.png: write error: File too large' err && ok || bad "render under a size limit: $(cat err)"
limited default "$BRDFIT" fit s.csv -m lambert,walter -o big.json 2>/dev/null
st=$?
[ $st = $((128 + $(kill -l XFSZ))) ] && ok || bad "fit killed by SIGXFSZ: exit status $st"
limited default "$BRDFIT" render --params P.json --size 64 -o big.png 2>/dev/null
st=$?
[ $st = $((128 + $(kill -l XFSZ))) ] && ok || bad "render killed by SIGXFSZ: exit status $st"
cmp -s big.json big.json.good && cmp -s big.png big.png.good && ok || bad "a failed write changed the old file"
limited default "$BRDFIT" compare s.csv -m lambert --quiet --html report 2>/dev/null
st=$?
[ $st = $((128 + $(kill -l XFSZ))) ] && ok || bad "compare --html killed by SIGXFSZ: exit status $st"
[ -e report ] && bad "a killed report left its folder" || ok
no_temporaries && ok || bad "temporaries left: $(find "$tmp" -name '*.tmp.*')"

# --- a full disk (ENOSPC) and a read-only file system, on a tmpfs -----------------------------
mkdir -p probe
if [ "$(id -u)" = 0 ] && unshare -m sh -c "mount -t tmpfs -o size=4k tmpfs probe" 2>/dev/null; then
  "$SYNTH" --params P.json --pattern merl -o merl.binary || bad "brdfit-synth --pattern merl failed"
  if unshare -m bash "$HERE/outputs_full_disk.sh" "$BRDFIT" "$tmp" >full.out 2>&1; then
    ok
  else
    bad "full disk: $(cat full.out)"
  fi
  tail -1 full.out
else
  # Not fatal: /dev/full (ENOSPC on write-through) and the size limit (EFBIG on a
  # temporary, the same checked-write path) above fail real writes.
  echo "note: no tmpfs can be mounted here (needs root and CAP_SYS_ADMIN): ENOSPC on a full file system not run"
fi

finish
