#!/usr/bin/env bash
# brdfit convert between formats: byte-exact CSV and MERL round trips, the measured
# formats to CSV, column mapping, and bad input (one-line error, no output file).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq
rows() { tail -n +2 "$1" | wc -l; }

# CSV -> CSV gives back the same text (canonical numbers, weights kept).
cat > "$tmp/a.csv" <<'CSV'
theta_i,phi_i,theta_o,phi_o,r,g,b,weight
30,0,45,180,0.1,0.2,0.30000000000000004,1
89.5,-25.81760513,0,33.5,-0.001,1e-300,123456.789,0.5
CSV
"$BRDFIT" convert "$tmp/a.csv" "$tmp/b.csv" >/dev/null && cmp -s "$tmp/a.csv" "$tmp/b.csv" && ok || bad "CSV round trip"

# MERL -> MERL gives back the same bytes; MERL -> CSV (subsampled) -> MERL keeps the cells.
printf '{"model":"walter","channels":3,"params":{"rho_d":[0.2,0.3,0.4],"rho_s":[0.5,0.5,0.5],"alpha":0.2,"f0":0.04}}' > "$tmp/w.json"
"$SYNTH" --params "$tmp/w.json" --pattern merl --noise 0.01 --seed 3 -o "$tmp/t.binary" >/dev/null 2>&1 || bad "synth merl"
"$BRDFIT" convert "$tmp/t.binary" "$tmp/u.binary" >/dev/null && cmp -s "$tmp/t.binary" "$tmp/u.binary" && ok || bad "MERL round trip"
"$BRDFIT" convert "$tmp/t.binary" "$tmp/t.csv" --subsample 500 --seed 1 >/dev/null && [ "$(rows "$tmp/t.csv")" = 500 ] \
  && ok || bad "MERL to CSV subsample"
"$BRDFIT" convert "$tmp/t.csv" "$tmp/v.binary" >/dev/null && ok || bad "CSV at cell centres to MERL"
[ "$("$BRDFIT" info "$tmp/v.binary" --json | jq .samples)" = 500 ] && ok || bad "MERL from CSV holds the 500 samples"
"$BRDFIT" convert "$tmp/v.binary" "$tmp/v.csv" >/dev/null && cmp -s <(sort "$tmp/t.csv") <(sort "$tmp/v.csv") \
  && ok || bad "CSV -> MERL -> CSV keeps directions and values"

# Measured formats.
"$BRDFIT" convert "$DATA/cornell/cayman_head20.brdf" "$tmp/c.csv" >/dev/null && [ "$(rows "$tmp/c.csv")" = 20 ] \
  && [ "$(head -1 "$tmp/c.csv" | tr ',' '\n' | wc -l)" = 35 ] && ok || bad "Cornell to CSV: 20 rows, 4 + 31 columns"
"$BRDFIT" convert "$DATA/cornell/cayman_head20.brdf" "$tmp/c3.csv" --rgb >/dev/null \
  && head -1 "$tmp/c3.csv" | grep -qx 'theta_i,phi_i,theta_o,phi_o,r,g,b' && ok || bad "Cornell --rgb"
"$BRDFIT" convert "$DATA/alta/pink-felt-1d.alta" "$tmp/p.csv" >/dev/null && [ "$(rows "$tmp/p.csv")" = 90 ] \
  && ok || bad "ALTA to CSV: 90 rows"
"$BRDFIT" convert "$DATA/nist_ptfe/PTFE.data.random.head40.csv" "$tmp/n.csv" --angles thetai,phi,thetar,phir \
  --values f_r11 >/dev/null && head -2 "$tmp/n.csv" | tail -1 | grep -qx '39.76471842,-25.81760513,66.42507623,41.77096264,0.29269651' \
  && ok || bad "PTFE with column options"

# Bad input: one line on stderr naming the file, non-zero exit, no output file.
expect_error() { # status pattern out args...
  local want=$1 pat=$2 out=$3
  shift 3
  "$BRDFIT" convert "$@" >/dev/null 2>"$tmp/err"
  local rc=$?
  [ "$rc" = "$want" ] || bad "convert $*: exit $rc, expected $want"
  [ -e "$out" ] && bad "convert $*: output written"
  ls "$tmp" | grep -q '\.tmp\.' && bad "convert $*: temporary left"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$pat" "$tmp/err" && ok || bad "convert $*: stderr '$(cat "$tmp/err")'"
}
head -c 1000 "$tmp/t.binary" > "$tmp/short.binary"
expect_error 1 "short.binary: .*1000" "$tmp/o.csv" "$tmp/short.binary" "$tmp/o.csv"
expect_error 1 "o.binary: .*3 channels" "$tmp/o.binary" "$tmp/n.csv" "$tmp/o.binary"
expect_error 1 "o.binary: sample 1 (theta_i 30, phi_i 0, theta_o 45, phi_o 180) is not at a MERL cell centre" \
  "$tmp/o.binary" "$tmp/a.csv" "$tmp/o.binary"
printf 'theta_i,phi_i,theta_o,phi_o,v\n1,2,3\n' > "$tmp/ragged.csv"
expect_error 1 "ragged.csv:2: expected 5 fields, found 3" "$tmp/o.csv" "$tmp/ragged.csv" "$tmp/o.csv"
expect_error 2 "cannot tell the output format" "$tmp/o.txt" "$tmp/a.csv" "$tmp/o.txt"
expect_error 2 "unknown format 'xyz'" "$tmp/o.csv" "$tmp/a.csv" "$tmp/o.csv" --format xyz
expect_error 2 "needs IN and OUT" "$tmp/o.csv" "$tmp/a.csv"

finish
