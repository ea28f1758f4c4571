#!/usr/bin/env bash
# brdfit info from the shell: counts, channels and coverage on small data, the prep
# report, JSON output, and bad input (one-line error, exit 1 bad data, 2 bad usage).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

# Five samples: one on the horizon, one negative, one with a zero.
cat > "$tmp/s.csv" <<'CSV'
theta_i,phi_i,theta_o,phi_o,r,g,b
10,0,10,180,0.5,0.25,0.125
20,0,40,180,1,2,3
90,0,10,0,7,7,7
30,0,30,180,-0.01,0.2,0.3
50,0,10,180,0,0.1,0.2
CSV
out=$("$BRDFIT" info "$tmp/s.csv" --json) || bad "info --json failed"
echo "$out" | jq -e '.samples_read == 5 and .samples == 4 and .prep.below_horizon == 1
  and .prep.negative == 1 and .prep.negative_action == "keep" and .channels == ["r","g","b"]
  and .counts.zero == 1 and .counts.negative == 1
  and .coverage_deg.theta_i.min == 10 and .coverage_deg.theta_i.max == 50
  and .values[0].min == -0.01 and .values[2].max == 3' >/dev/null && ok || bad "info --json: $out"
out=$("$BRDFIT" info "$tmp/s.csv" --negative clamp --luminance --json)
echo "$out" | jq -e '.channels == ["luminance"] and .prep.negative_action == "clamp" and .counts.negative == 0' \
  >/dev/null && ok || bad "info --negative clamp --luminance: $out"
"$BRDFIT" info "$tmp/s.csv" | grep -q '^channels: 3 (r, g, b)' && ok || bad "info text: channels line"
"$BRDFIT" info "$tmp/s.csv" --subsample 2 --seed 5 --json | jq -e '.samples == 2 and .prep.subsampled_out == 2' \
  >/dev/null && ok || bad "info --subsample"

# Bad usage: exit 2; bad data: exit 1; one line on stderr, nothing on stdout.
expect() { # expected-status pattern args...
  local want=$1 pat=$2; shift 2
  "$BRDFIT" info "$@" >"$tmp/out" 2>"$tmp/err"
  local rc=$?
  [ "$rc" = "$want" ] || bad "info $*: exit $rc, expected $want"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q -- "$pat" "$tmp/err" || bad "info $*: stderr '$(cat "$tmp/err")'"
  [ -s "$tmp/out" ] && bad "info $*: wrote to stdout"
  ok
}
expect 2 "no data file"
expect 2 "unknown option '--bogus'" "$tmp/s.csv" --bogus
expect 2 "one data file" "$tmp/s.csv" "$tmp/s.csv"
expect 2 "--negative takes" "$tmp/s.csv" --negative maybe
expect 1 "unknown channel 'q'" "$tmp/s.csv" --channels q
expect 1 "no sample left" "$tmp/s.csv" --max-theta 5
expect 1 "s.csv: cannot make RGB" "$tmp/s.csv" --rgb
expect 1 "s.csv: cannot make RGB" "$tmp/s.csv" --rgb-bands
expect 1 "missing.csv" "$tmp/missing.csv"

# Colour: a flat spectrum (wavelength columns) is neutral in sRGB under any illuminant,
# Y = 1 in XYZ; the spectral options exclude each other.
cat > "$tmp/flat.csv" <<'CSV'
theta_i,phi_i,theta_o,phi_o,400,500,600,700
10,0,10,180,0.5,0.5,0.5,0.5
CSV
"$BRDFIT" info "$tmp/flat.csv" --rgb --illuminant a --json |
  jq -e '.channels == ["r","g","b"] and ([.values[].mean | . - 0.5 | fabs < 1e-12] | all)' >/dev/null &&
  ok || bad "flat spectrum not neutral"
"$BRDFIT" info "$tmp/flat.csv" --color xyz --json |
  jq -e '.channels == ["X","Y","Z"] and (.values[1].mean - 0.5 | fabs < 1e-12)' >/dev/null && ok || bad "flat Y"
expect 2 "--rgb and --rgb-bands exclude each other" "$tmp/flat.csv" --rgb --rgb-bands
expect 2 "--color and --luminance exclude each other" "$tmp/flat.csv" --color xyz --luminance
expect 2 "--color takes srgb, acescg or xyz" "$tmp/flat.csv" --color rec2020
expect 1 "applies only to a colour conversion" "$tmp/flat.csv" --illuminant e
# --luminance of spectral data is CIE Y under the illuminant: a flat spectrum keeps its value.
"$BRDFIT" info "$tmp/flat.csv" --luminance --illuminant a --json |
  jq -e '.channels == ["luminance"] and (.values[0].mean - 0.5 | fabs < 1e-12)' >/dev/null && ok || bad "flat luminance"
expect 1 "applies only to a colour conversion or the luminance of spectral data" "$tmp/s.csv" --luminance --illuminant a

finish
