#!/usr/bin/env bash
# Hostile input from the shell, on the release build: the fuzz findings and the inputs of
# issue 12 each get one clean line on stderr (escaped, at most ~200 characters, naming
# file and line), exit 1, no output file and no signal; whatever convert writes reads
# back; JUnit and terminal output carry no control characters.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq; need xmllint libxml2-utils

printf 'theta_i,phi_i,theta_o,phi_o\n0,0,10,180\n30,0,30,180\n' > "$tmp/dirs.csv"

# CMD... must fail with exit 1 and one safe line matching PATTERN; OUT must not appear.
expect_clean() { # name pattern out cmd...
  local name=$1 pat=$2 out=$3
  shift 3
  "$@" >/dev/null 2>"$tmp/err"
  local rc=$?
  [ "$rc" = 1 ] || bad "$name: exit $rc (a signal is 128+N), expected 1"
  [ -n "$out" ] && [ -e "$out" ] && bad "$name: output written"
  local lines chars
  lines=$(wc -l < "$tmp/err")
  chars=$(head -1 "$tmp/err" | wc -m)
  if [ "$lines" = 1 ] && [ "$chars" -le 230 ] && ! LC_ALL=C grep -q '[[:cntrl:]]' <(tr -d '\n' < "$tmp/err") &&
     grep -q -- "$pat" "$tmp/err"; then
    ok
  else
    bad "$name: $lines lines, $chars characters: $(cat -v "$tmp/err")"
  fi
}

# --- parameter files (fuzz/fuzz_params.c): brdfit eval on each --------------------------
eval_clean() { # name json pattern
  printf '%s' "$2" > "$tmp/$1.json"
  expect_clean "eval $1" "$1.json:1: $3" "$tmp/o.csv" "$BRDFIT" eval --params "$tmp/$1.json" --dirs "$tmp/dirs.csv" -o "$tmp/o.csv"
}
eval_clean mono '{"model":"walter:mono=all","channels":2147483647,"params":{"rho_d":0.5,"rho_s":0.5,"alpha":0.1,"f0":0.04}}' \
  '"channels" must be an integer from 1 to 10000'
eval_clean count '{"model":"walter","channels":1073741824,"params":{}}' '"channels" must be'
eval_clean big '{"model":"walter","channels":1e30,"params":{}}' '"channels" must be'
eval_clean fresnel '{"model":"walter","options":{"fresnel":1e30},"params":{}}' 'option "fresnel" must be a string or an integer'
eval_clean long "{\"model\":\"walter$(printf 'x%.0s' $(seq 400))\",\"options\":{\"fresnel\":\"schlick\"},\"params\":{}}" \
  '"model" is too long'
expect_clean "brdfit-synth, the same reader" 'mono.json:1: "channels" must be' "$tmp/s.csv" \
  "$SYNTH" --params "$tmp/mono.json" --pattern uniform --count 10 -o "$tmp/s.csv"

# --- CSV: binary junk in the header, a 9 kB number -----------------------------------------
printf 'theta_i,phi_i,theta_o,phi_o,v\n0,0,10,180,\033[31m\377\376\n' > "$tmp/junk.csv"
expect_clean "binary cell" "junk.csv:2: column v: '\\\\x1b\\[31m\\\\xff\\\\xfe' is not a number" "" \
  "$BRDFIT" info "$tmp/junk.csv"
printf 'theta_i,phi_i,theta_o,phi_o,\033]0;title\007\n0,0,10,180,1\n' > "$tmp/hdr.csv"
expect_clean "binary header" "" "$tmp/o.csv" "$BRDFIT" convert "$tmp/hdr.csv" "$tmp/o.csv" --values nope
"$BRDFIT" info "$tmp/hdr.csv" > "$tmp/out" 2>&1 && grep -qF 'channels: 1 (\x1b]0;title\x07)' "$tmp/out" &&
  ! LC_ALL=C grep -q $'\033' "$tmp/out" && ok || bad "info shows a binary channel name escaped: $(cat -v "$tmp/out")"
{ printf 'theta_i,phi_i,theta_o,phi_o,v\n0,0,10,180,'; head -c 9000 /dev/zero | tr '\0' 7; printf 'x\n'; } > "$tmp/tok.csv"
expect_clean "9 kB token" "tok.csv:2: column v: '7777.*\.\.\..*777x' is not a number" "$tmp/o.csv" \
  "$BRDFIT" fit "$tmp/tok.csv" -m lambert -o "$tmp/o.csv"

# --- convert writes what it reads back ------------------------------------------------------
"$BRDFIT" convert "$DATA/cornell/cayman_head20.brdf" "$tmp/c.csv" >/dev/null &&
  "$BRDFIT" convert "$tmp/c.csv" "$tmp/c2.csv" >/dev/null && cmp -s "$tmp/c.csv" "$tmp/c2.csv" && ok ||
  bad "Cornell -> CSV (spectral headers) reads back"
[ "$("$BRDFIT" info "$tmp/c.csv" --rgb --json | jq -c '[.samples, (.channels | length)]')" = '[20,3]' ] && ok ||
  bad "the spectral CSV converts to RGB by its wavelength headers"
printf 'a,b,c,d,theta_i,weight,w\n10,20,30,40,0.5,0.25,2\n' > "$tmp/clash.csv"
"$BRDFIT" convert "$tmp/clash.csv" "$tmp/clash2.csv" --angles a,b,c,d --weight w >/dev/null &&
  [ "$(head -1 "$tmp/clash2.csv")" = 'theta_i,phi_i,theta_o,phi_o,theta_i_2,weight_2,weight' ] &&
  "$BRDFIT" convert "$tmp/clash2.csv" "$tmp/clash3.csv" >/dev/null && cmp -s "$tmp/clash2.csv" "$tmp/clash3.csv" &&
  ok || bad "value columns named theta_i and weight: $(cat "$tmp/clash2.csv")"

# --- regression baselines: control characters -----------------------------------------------
printf 'theta_i,phi_i,theta_o,phi_o,value\n0,0,10,180,0.3\n20,0,30,180,0.3\n40,90,10,0,0.3\n' > "$tmp/d.csv"
printf '{"brdfit_baseline": 1, "cases": [\n{"name": "a\\u001b[2J", "data": "d.csv", "model": "lambert"}]}' > "$tmp/b1.json"
"$BRDFIT" regress "$tmp/b1.json" --junit "$tmp/j1.xml" >/dev/null 2>"$tmp/err"
[ $? != 0 ] && [ ! -e "$tmp/j1.xml" ] && grep -qF "b1.json:2: 'a\\x1b[2J' holds control characters" "$tmp/err" &&
  ! LC_ALL=C grep -q $'\033' "$tmp/err" && ok || bad "control characters in a case name: $(cat -v "$tmp/err")"
# A baseline whose file name holds ESC (the JUnit classname), with a case that fails.
b2=$tmp/$'b\033[2J.json'
printf '{"brdfit_baseline": 1, "cases": [\n{"name": "b", "data": "d.csv", "model": "lambert",\n "expected": {"params": {"rho_d": 1}}}]}' > "$b2"
"$BRDFIT" regress "$b2" --junit "$tmp/j2.xml" >"$tmp/out" 2>&1
[ $? = 1 ] && grep -qF 'classname="'"$tmp"'/b\x1b[2J.json"' "$tmp/j2.xml" && grep -q 'params.rho_d: expected 1' "$tmp/j2.xml" &&
  ! LC_ALL=C grep -q $'\033' "$tmp/j2.xml" && xmllint --noout "$tmp/j2.xml" && ok ||
  bad "control characters in the JUnit classname: $(cat -v "$tmp/out" "$tmp/j2.xml")"

# --- the HTML report: a material whose file name holds ESC and invalid UTF-8 -------------------
m=$tmp/$'m\033[2J\377.csv'
cp "$tmp/d.csv" "$m"
if "$BRDFIT" compare "$m" -m lambert --quiet --html "$tmp/report" >/dev/null 2>"$tmp/err"; then
  grep -qF 'm\x1b[2J\xff.csv' "$tmp/report/index.html" && ! LC_ALL=C grep -q $'\033\|\377' "$tmp/report/index.html" &&
    ok || bad "HTML report: control characters not escaped"
else
  bad "compare --html: $(cat -v "$tmp/err")"
fi

# --- memory: input that outgrows the memory available gets an error, not the OOM killer --------
# BRDFIT_MEMORY lowers the limit the machine, control group and ulimit -v set, so a file
# of 12 MB stands for a 10 GB CSV on a small machine.
awk 'BEGIN { print "theta_i,phi_i,theta_o,phi_o,r,g,b"; for (i = 0; i < 300000; i++)
  printf "%.3f,0,%.3f,180,0.1,0.2,0.3\n", (i * 7) % 80, (i * 13) % 80 }' > "$tmp/huge.csv"
BRDFIT_MEMORY=8M expect_clean "CSV past BRDFIT_MEMORY" 'huge.csv:[0-9]*: not enough memory: [0-9.]* MiB needed, 8 MiB available (BRDFIT_MEMORY)' \
  "$tmp/huge.json" "$BRDFIT" fit "$tmp/huge.csv" -m lambert -o "$tmp/huge.json"
BRDFIT_MEMORY=20M expect_clean "samples past BRDFIT_MEMORY" 'out of memory for the geometry of 300000 samples' \
  "$tmp/huge.json" "$BRDFIT" fit "$tmp/huge.csv" -m lambert -o "$tmp/huge.json"
BRDFIT_MEMORY=1G "$BRDFIT" fit "$tmp/huge.csv" -m lambert -o "$tmp/huge.json" >/dev/null 2>"$tmp/err" && [ -s "$tmp/huge.json" ] &&
  ok || bad "fit within BRDFIT_MEMORY=1G: $(cat "$tmp/err")"
"$SYNTH" --params "$DATA/lambert_rgb.json" --pattern merl -o "$tmp/m.binary" >/dev/null
BRDFIT_MEMORY=8M expect_clean "MERL table past BRDFIT_MEMORY" 'm.binary: not enough memory: [0-9.]* MiB needed, 8 MiB available' \
  "$tmp/m.json" "$BRDFIT" fit "$tmp/m.binary" -m lambert -o "$tmp/m.json"
BRDFIT_MEMORY=100M "$BRDFIT" render --params "$DATA/lambert_rgb.json" --size 4096 -o "$tmp/r.png" >/dev/null 2>"$tmp/err"
[ $? = 1 ] && [ ! -e "$tmp/r.png" ] && grep -q 'a 4096x4096 image needs about 256 MiB, 100 MiB available (BRDFIT_MEMORY)' "$tmp/err" &&
  ok || bad "render past BRDFIT_MEMORY: $(cat "$tmp/err")"
for v in -3 4X ' 4G' 99999999999999999999T; do
  BRDFIT_MEMORY=$v "$BRDFIT" models >/dev/null 2>"$tmp/err"
  [ $? = 2 ] && grep -q 'BRDFIT_MEMORY=.* is not a byte count' "$tmp/err" && ok || bad "BRDFIT_MEMORY='$v' accepted"
done

# Devices are no data files, and some never end: refused at once, as data and as a scene.
for cmdline in "info /dev/zero" "fit /dev/zero -m lambert" "fit $DATA/cornell/cayman_head20.brdf -m lambert --scene /dev/zero"; do
  timeout 10 "$BRDFIT" $cmdline >/dev/null 2>"$tmp/err"
  [ $? = 1 ] && grep -q '/dev/zero: cannot open: a device, not a data file' "$tmp/err" && ok ||
    bad "$cmdline: not refused at once: $(head -c 200 "$tmp/err")"
done

finish
