#!/usr/bin/env bash
# brdfit eval and brdfit models from the shell: values, JSON listing, and bad input
# (one-line error naming the file and problem, non-zero exit, no output file).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq

# --- good input --------------------------------------------------------------
if "$BRDFIT" eval --params "$DATA/lambert_rgb.json" --dirs "$DATA/dirs_small.csv" -o "$tmp/out.csv" 2>"$tmp/err"; then
  ok
  expected='theta_i,phi_i,theta_o,phi_o,r,g,b
0,0,0,0,0.25464790894703254,0.15915494309189535,0.06366197723675814
30,0,45,180,0.25464790894703254,0.15915494309189535,0.06366197723675814
90,0,10,0,0,0,0
89.999,0.1,60,33,0.25464790894703254,0.15915494309189535,0.06366197723675814'
  [ "$(cat "$tmp/out.csv")" = "$expected" ] && ok || bad "lambert output differs: $(cat "$tmp/out.csv")"
  ls "$tmp" | grep -q tmp && bad "temporary file left behind" || ok
else
  bad "eval on good input failed: $(cat "$tmp/err")"
fi
# stdout when -o is absent
[ "$("$BRDFIT" eval --params "$DATA/lambert_rgb.json" --dirs "$DATA/dirs_small.csv" | wc -l)" = 5 ] && ok || bad "stdout output"

# --- models -----------------------------------------------------------------------
"$BRDFIT" models --json > "$tmp/models.json" && ok || bad "models --json failed"
jq -e '.models | length >= 1' "$tmp/models.json" >/dev/null && ok || bad "models --json is not the expected JSON"
jq -e '.models[] | select(.name == "lambert") | .free_params["3"] == 3 and .params[0].name == "rho_d" and .params[0].kind == "colour"' \
  "$tmp/models.json" >/dev/null && ok || bad "models --json: lambert entry"
n_text=$("$BRDFIT" models | grep -c '^[a-z]')
n_json=$(jq '.models | length' "$tmp/models.json")
[ "$n_text" = "$n_json" ] && ok || bad "models text lists $n_text, json $n_json"
# Every listed model can be evaluated from a parameter file built from its defaults.
for name in $(jq -r '.models[].name' "$tmp/models.json"); do
  jq --arg n "$name" '.models[] | select(.name == $n) |
      {model: .name, channels: 3,
       params: (.params | map({(.name): (if .kind == "colour" then [.default, .default, .default] else .default end)}) | add)}' \
    "$tmp/models.json" > "$tmp/p_$name.json"
  if out=$("$BRDFIT" eval --params "$tmp/p_$name.json" --dirs "$DATA/dirs_small.csv" 2>&1); then
    # 4 rows + header, finite non-negative values
    echo "$out" | tail -n +2 | awk -F, '{for (i = 5; i <= NF; i++) if ($i !~ /^[0-9.e+-]+$/ || $i < 0) exit 1}' \
      && [ "$(echo "$out" | wc -l)" = 5 ] && ok || bad "eval $name with defaults: $out"
  else
    bad "eval $name with defaults failed: $out"
  fi
done

# --- bad input: one line on stderr naming the file, non-zero exit, no output -------
expect_error() { # name, pattern, args...
  local name=$1 pattern=$2
  shift 2
  rm -f "$tmp/o.csv"
  if "$BRDFIT" "$@" -o "$tmp/o.csv" 2>"$tmp/err" >/dev/null; then
    bad "$name: exit status 0"
    return
  fi
  [ -e "$tmp/o.csv" ] && bad "$name: output file written"
  ls "$tmp" | grep -q 'o.csv.tmp' && bad "$name: temporary file left"
  [ "$(wc -l < "$tmp/err")" = 1 ] || bad "$name: stderr is not one line: $(cat "$tmp/err")"
  grep -q -- "$pattern" "$tmp/err" && ok || bad "$name: message '$(cat "$tmp/err")' lacks '$pattern'"
}
D="$DATA/dirs_small.csv"
P="$DATA/lambert_rgb.json"
printf '{"model":"nosuch","params":{"rho_d":0.5}}' > "$tmp/unknown.json"
expect_error "unknown model" "unknown.json:1: unknown model 'nosuch'" eval --params "$tmp/unknown.json" --dirs "$D"
printf '{"model":"lambert",\n"params":{}}' > "$tmp/missing.json"
expect_error "missing parameter" 'missing.json:2: missing parameter "rho_d"' eval --params "$tmp/missing.json" --dirs "$D"
printf '{"model":"lambert",\n"params":{"rho_d":0.5,\n"alpha":0.1}}' > "$tmp/extra.json"
expect_error "extra parameter" 'extra.json:3: model lambert has no parameter "alpha"' eval --params "$tmp/extra.json" --dirs "$D"
printf '{"model":"lambert","channels":3,\n"params":{"rho_d":[0.5,0.5]}}' > "$tmp/len.json"
expect_error "wrong array length" 'len.json:2: colour parameter rho_d has 2 values for 3 channels' eval --params "$tmp/len.json" --dirs "$D"
printf '{"model":"lambert","channels":3,\n"params":{"rho_d":0.5}}' > "$tmp/scalar.json"
expect_error "scalar for colour" 'scalar.json:2: colour parameter rho_d needs an array of 3 values' eval --params "$tmp/scalar.json" --dirs "$D"
printf '{"model":"lambert",\n"params":{"rho_d":1.5}}' > "$tmp/range.json"
expect_error "out of bounds" 'range.json:2: parameter rho_d = 1.5 is outside \[0, 1\]' eval --params "$tmp/range.json" --dirs "$D"
printf '{"model":"lambert",\n"params":{"rho_d":1e999}}' > "$tmp/inf.json"
expect_error "infinite value" 'inf.json:2: parameter rho_d is not finite' eval --params "$tmp/inf.json" --dirs "$D"
printf '{"model":"lambert",\n"params":{"rho_d":"x"}}' > "$tmp/str.json"
expect_error "string value" 'str.json:2: parameter rho_d: expected a number' eval --params "$tmp/str.json" --dirs "$D"
printf '{"model":"lambert",\n"params":{"rho_d":0.5,"rho_d":0.6}}' > "$tmp/dup.json"
expect_error "duplicate parameter" 'dup.json:2: parameter "rho_d" given twice' eval --params "$tmp/dup.json" --dirs "$D"
printf '{"model":"lambert",\n"params":{"rho_d":0.5,\n}' > "$tmp/malformed.json"
expect_error "malformed JSON" 'malformed.json:3: malformed JSON' eval --params "$tmp/malformed.json" --dirs "$D"
printf '{"model":"lambert:lobes=2","params":{"rho_d":0.5}}' > "$tmp/opt.json"
expect_error "bad option" 'opt.json:1: model lambert does not accept lobes' eval --params "$tmp/opt.json" --dirs "$D"
expect_error "missing params file" 'nothere.json: cannot open' eval --params "$tmp/nothere.json" --dirs "$D"
printf 'theta_i,phi_i,theta_o,phi_o\n0,0,0,0\n0,0,0\n' > "$tmp/short.csv"
expect_error "short row" 'short.csv:3: expected 4 fields, found 3' eval --params "$P" --dirs "$tmp/short.csv"
printf 'theta_i,phi_i,theta_o,phi_o\n0,0,NaN,0\n' > "$tmp/nan.csv"
expect_error "NaN angle" 'nan.csv:2: column theta_o: NaN is not a finite number' eval --params "$P" --dirs "$tmp/nan.csv"
printf 'theta_i,phi_i,theta_o,phi_o\n0,0,abc,0\n' > "$tmp/word.csv"
expect_error "not a number" "word.csv:2: column theta_o: 'abc' is not a number" eval --params "$P" --dirs "$tmp/word.csv"
printf 'theta_i,phi_i,theta_o\n0,0,0\n' > "$tmp/cols.csv"
expect_error "missing column" 'cols.csv: missing column phi_o' eval --params "$P" --dirs "$tmp/cols.csv"
printf 'theta_i,phi_i,theta_o,phi_o\n' > "$tmp/norows.csv"
expect_error "no rows" 'norows.csv: no direction rows' eval --params "$P" --dirs "$tmp/norows.csv"
: > "$tmp/empty.csv"
expect_error "empty file" 'empty.csv: empty file' eval --params "$P" --dirs "$tmp/empty.csv"
if "$BRDFIT" eval --params "$P" --dirs "$D" -o "$tmp/no/such/dir/x.csv" 2>"$tmp/err"; then
  bad "unwritable output accepted"
else
  grep -q 'no/such/dir/x.csv: cannot write in the folder .*no/such/dir: No such file or directory' "$tmp/err" && ok || bad "unwritable output: $(cat "$tmp/err")"
fi
if "$BRDFIT" eval --params "$P" 2>"$tmp/err"; then bad "missing --dirs accepted"; else
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q 'are required' "$tmp/err" && ok || bad "missing --dirs: $(cat "$tmp/err")"
fi
if "$BRDFIT" frobnicate 2>/dev/null; then bad "unknown command accepted"; else ok; fi

finish
