#!/usr/bin/env bash
# brdfit-synth from the shell: CSV and MERL output, determinism (two runs, same bytes),
# and bad usage or input (one line on stderr, exit 2 or 1, no output file).
# Arguments: the brdfit binary (unused), tests/data, the brdfit-synth binary.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"

P="$DATA/lambert_rgb.json"
printf '{"model":"walter","options":{"fresnel":"schlick"},"channels":3,\n"params":{"rho_d":[0.5,0.3,0.1],"rho_s":[0.6,0.6,0.6],"alpha":0.2,"f0":0.04}}\n' > "$tmp/walter.json"
W="$tmp/walter.json"
printf '{"model":"lambert","channels":1,"params":{"rho_d":0.5}}\n' > "$tmp/mono.json"

# run NAME ARGS...: must succeed
run() {
  local name=$1
  shift
  if "$SYNTH" "$@" 2>"$tmp/err"; then ok; else bad "$name failed: $(cat "$tmp/err")"; fi
}

# --- CSV output: header, row count, values ------------------------------------------
run "uniform" --params "$W" --pattern uniform --count 100 --seed 3 -o "$tmp/u.csv"
[ "$(head -1 "$tmp/u.csv")" = "theta_i,phi_i,theta_o,phi_o,r,g,b" ] && ok || bad "uniform header: $(head -1 "$tmp/u.csv")"
[ "$(wc -l < "$tmp/u.csv")" = 101 ] && ok || bad "uniform: $(wc -l < "$tmp/u.csv") lines, expected 101"
# every field numeric, angles in range, values positive (walter with rho_d > 0)
awk -F, 'NR > 1 { if (NF != 7 || $1 < 0 || $1 >= 90 || $3 < 0 || $3 >= 90 || $2 < 0 || $2 >= 360 || $4 < 0 || $4 >= 360) exit 1;
                   for (i = 5; i <= 7; i++) if ($i !~ /^[0-9.e+-]+$/ || $i <= 0) exit 1 }' "$tmp/u.csv" \
  && ok || bad "uniform: malformed or out-of-range rows"
ls "$tmp" | grep -q 'tmp' && bad "temporary file left behind" || ok

# Lambert without noise: every value is rho / pi, as brdfit eval gives.
run "lambert" --params "$P" --pattern cosine --count 20 -o "$tmp/l.csv"
[ "$(tail -n +2 "$tmp/l.csv" | cut -d, -f5-7 | sort -u)" = "0.25464790894703254,0.15915494309189535,0.06366197723675814" ] \
  && ok || bad "lambert values: $(tail -n +2 "$tmp/l.csv" | cut -d, -f5-7 | sort -u | head -3)"

# Determinism: same seed same bytes, other seed other bytes, for every random pattern and
# noise model.
for pattern in uniform cosine stratified random; do
  for noise in "" "--noise 0.05" "--noise 0.01 --noise-model additive --clamp" "--noise-model photon --counts 500" \
               "--noise 0.05 --outliers 0.1,20" "--outliers 0.1"; do
    # shellcheck disable=SC2086
    run "$pattern $noise" --params "$W" --pattern $pattern --count 256 --seed 77 $noise -o "$tmp/a.csv"
    # shellcheck disable=SC2086
    run "$pattern $noise" --params "$W" --pattern $pattern --count 256 --seed 77 $noise -o "$tmp/b.csv"
    # shellcheck disable=SC2086
    run "$pattern $noise" --params "$W" --pattern $pattern --count 256 --seed 78 $noise -o "$tmp/c.csv"
    cmp -s "$tmp/a.csv" "$tmp/b.csv" && ok || bad "$pattern $noise: same seed, different output"
    cmp -s "$tmp/a.csv" "$tmp/c.csv" && bad "$pattern $noise: different seeds, same output" || ok
  done
done
# The default seed is a fixed one too.
run "default seed" --params "$W" --pattern uniform --count 10 -o "$tmp/d1.csv"
run "default seed" --params "$W" --pattern uniform --count 10 --seed 0 -o "$tmp/d2.csv"
cmp -s "$tmp/d1.csv" "$tmp/d2.csv" && ok || bad "default seed is not seed 0"

# Gonio: defaults 0,30,60 at 5 degrees = 3 * 35 in-plane + 2 * 70 ring = 245 rows.
run "gonio defaults" --params "$W" --pattern gonio -o "$tmp/g.csv"
[ "$(tail -n +2 "$tmp/g.csv" | wc -l)" = 245 ] && ok || bad "gonio defaults: $(tail -n +2 "$tmp/g.csv" | wc -l) rows"
run "gonio" --params "$W" --pattern gonio --incidence 0,45 --step 45 -o "$tmp/g2.csv"
expected='0,0,45,0
0,0,0,0
0,0,45,180
45,0,45,0
45,0,0,0
45,0,45,180
45,0,45,45
45,0,45,90
45,0,45,135
45,0,45,225
45,0,45,270
45,0,45,315'
[ "$(tail -n +2 "$tmp/g2.csv" | cut -d, -f1-4)" = "$expected" ] && ok || bad "gonio angles: $(tail -n +2 "$tmp/g2.csv" | cut -d, -f1-4 | tr '\n' ' ')"

# MERL: a full table, 12 header bytes + 3 planes of 1458000 doubles; cells below the
# horizon written invalid (-1): the R plane's cell 0 (theta_h, theta_d, phi_d bins 0) is
# above it and holds rho_r / pi / (1/1500).
run "merl" --params "$P" --pattern merl --noise 0.01 --seed 1 -o "$tmp/m.binary"
[ "$(stat -c %s "$tmp/m.binary")" = 34992012 ] && ok || bad "merl size $(stat -c %s "$tmp/m.binary")"
[ "$(od -An -t d4 -N 12 "$tmp/m.binary" | tr -s ' ')" = " 90 90 180" ] && ok || bad "merl dims: $(od -An -t d4 -N 12 "$tmp/m.binary")"
# the last cell (theta_h, theta_d near 90, phi_d near 180) lies below the horizon
[ "$(tail -c 8 "$tmp/m.binary" | od -An -t f8 | tr -d ' ')" = "-1" ] && ok || bad "merl: last cell not invalid"
run "merl again" --params "$P" --pattern merl --noise 0.01 --seed 1 -o "$tmp/m2.binary"
cmp -s "$tmp/m.binary" "$tmp/m2.binary" && ok || bad "merl: same seed, different bytes"

# --- bad usage (exit 2) and bad input (exit 1): one line, no output ------------------
expect_error() { # name, status, pattern, output, args...
  local name=$1 want=$2 pattern=$3 out=$4
  shift 4
  rm -f "$out"
  "$SYNTH" "$@" -o "$out" 2>"$tmp/err" >/dev/null
  local got=$?
  [ "$got" = "$want" ] || bad "$name: exit status $got, expected $want"
  [ -e "$out" ] && bad "$name: output file written"
  ls "$(dirname "$out")" 2>/dev/null | grep -q "$(basename "$out")." && bad "$name: temporary file left"
  [ "$(wc -l < "$tmp/err")" = 1 ] || bad "$name: stderr is not one line: $(cat "$tmp/err")"
  grep -q -- "$pattern" "$tmp/err" && ok || bad "$name: message '$(cat "$tmp/err")' lacks '$pattern'"
}
O="$tmp/o.csv"
B="$tmp/o.binary"
expect_error "no pattern" 2 "--pattern is required" "$O" --params "$W" --count 10
expect_error "no params" 2 "--params P.json is required" "$O" --pattern uniform --count 10
expect_error "unknown pattern" 2 "unknown pattern 'gauss'" "$O" --params "$W" --pattern gauss --count 10
expect_error "no count" 2 "--count N is required for pattern uniform" "$O" --params "$W" --pattern uniform
expect_error "zero count" 2 "--count '0' is not a positive integer" "$O" --params "$W" --pattern uniform --count 0
expect_error "negative count" 2 "--count '-5'" "$O" --params "$W" --pattern uniform --count -5
expect_error "word count" 2 "--count '10x'" "$O" --params "$W" --pattern uniform --count 10x
expect_error "count for merl" 2 "--count does not apply to pattern merl" "$B" --params "$P" --pattern merl --count 10
expect_error "count for gonio" 2 "--count does not apply to pattern gonio" "$O" --params "$P" --pattern gonio --count 10
expect_error "step for uniform" 2 "apply to pattern gonio only" "$O" --params "$P" --pattern uniform --count 5 --step 5
expect_error "bad incidence" 2 "every angle must be in \[0, 90)" "$O" --params "$P" --pattern gonio --incidence 0,90
expect_error "bad incidence list" 2 "--incidence '0,,30'" "$O" --params "$P" --pattern gonio --incidence 0,,30
expect_error "bad step" 2 "--step '0'" "$O" --params "$P" --pattern gonio --step 0
expect_error "negative noise" 2 "--noise '-0.1' must be a number >= 0" "$O" --params "$W" --pattern uniform --count 5 --noise -0.1
expect_error "NaN noise" 2 "--noise 'nan'" "$O" --params "$W" --pattern uniform --count 5 --noise nan
expect_error "unknown noise model" 2 "unknown noise model 'pink'" "$O" --params "$W" --pattern uniform --count 5 --noise 0.1 --noise-model pink
expect_error "model without level" 2 "--noise-model additive needs --noise S" "$O" --params "$W" --pattern uniform --count 5 --noise-model additive
expect_error "photon without counts" 2 "needs either --noise S or --counts K" "$O" --params "$W" --pattern uniform --count 5 --noise-model photon
expect_error "counts without photon" 2 "--counts applies to --noise-model photon only" "$O" --params "$W" --pattern uniform --count 5 --noise 0.1 --counts 10
expect_error "bad outliers" 2 "--outliers '1.5'" "$O" --params "$W" --pattern uniform --count 5 --outliers 1.5
expect_error "bad outlier factor" 2 "--outliers '0.1,-3'" "$O" --params "$W" --pattern uniform --count 5 --outliers 0.1,-3
expect_error "bad seed" 2 "--seed '-1'" "$O" --params "$W" --pattern uniform --count 5 --seed -1
expect_error "huge seed" 2 "--seed '18446744073709551616'" "$O" --params "$W" --pattern uniform --count 5 --seed 18446744073709551616
expect_error "unknown option" 2 "unknown option '--frobnicate'" "$O" --params "$W" --pattern uniform --count 5 --frobnicate
expect_error "option twice" 2 "--seed given twice" "$O" --params "$W" --pattern uniform --count 5 --seed 1 --seed 2
expect_error "merl to csv" 2 "-o must end in .binary" "$O" --params "$P" --pattern merl
expect_error "binary from uniform" 2 "needs --pattern merl" "$B" --params "$P" --pattern uniform --count 5
expect_error "unknown extension" 2 "must end in .csv or .binary" "$tmp/o.txt" --params "$P" --pattern uniform --count 5
if "$SYNTH" --params "$P" --pattern uniform --count 5 2>"$tmp/err"; then bad "missing -o accepted"; else
  [ $? = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "-o OUT.csv|OUT.binary is required" "$tmp/err" && ok || bad "missing -o: $(cat "$tmp/err")"
fi
# bad input: the parameter file, named with its line
expect_error "missing params file" 1 "nothere.json: cannot open" "$O" --params "$tmp/nothere.json" --pattern uniform --count 5
printf '{"model":"lambert",\n"params":{"rho_d":0.5,\n}' > "$tmp/malformed.json"
expect_error "malformed params" 1 "malformed.json:3: malformed JSON" "$O" --params "$tmp/malformed.json" --pattern uniform --count 5
printf '{"model":"lambert",\n"params":{"rho_d":1.5}}' > "$tmp/range.json"
expect_error "params out of bounds" 1 "range.json:2: parameter rho_d = 1.5 is outside" "$O" --params "$tmp/range.json" --pattern uniform --count 5
expect_error "merl from one channel" 1 "mono.json: pattern merl needs a 3-channel (RGB) model, the file gives 1" "$B" --params "$tmp/mono.json" --pattern merl
expect_error "unwritable output" 1 "no/such/dir/o.csv: cannot write in the folder" "$tmp/no/such/dir/o.csv" --params "$P" --pattern uniform --count 5
"$SYNTH" --help | grep -q '^usage: brdfit-synth' && ok || bad "--help"

finish
