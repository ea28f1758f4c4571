#!/usr/bin/env bash
# brdfit regress from the shell: the example baseline over the bundled data passes (and
# writes JUnit XML); a perturbed copy fails naming the parameter; --update restores the
# exact values and keeps the tolerances; --case, --verbose; a case that cannot run; bad
# baselines (exit 2, file:line on stderr, no JUnit file).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need jq jq; need xmllint libxml2-utils

BRDFIT=$(cd "$(dirname "$BRDFIT")" && pwd)/$(basename "$BRDFIT") # the example runs from $tmp
EXAMPLE=$(cd "$DATA/../../examples/regress" && pwd)/baseline.json
# Copies live in $tmp: their data paths are made absolute.
jq --arg d "$(dirname "$EXAMPLE")" '.cases[].data |= ($d + "/" + .)' "$EXAMPLE" > "$tmp/base.json" ||
  bad "cannot copy the example baseline"
ncases=$(jq '.cases | length' "$EXAMPLE")

junit_counts() { # FILE TESTS FAILURES ERRORS
  grep -q "<testsuite name=\"brdfit regress\" tests=\"$2\" failures=\"$3\" errors=\"$4\"" "$1" &&
    [ "$(grep -c '<testcase ' "$1")" = "$2" ] &&
    xmllint --noout "$1"
}

# --- the example, run from another directory: relative data paths follow the file -------
if (cd "$tmp" && "$BRDFIT" regress "$EXAMPLE" --junit "$tmp/j.xml") >"$tmp/out" 2>"$tmp/err"; then
  ok
  grep -qx "regress: $ncases passed, 0 failed" "$tmp/out" && ok || bad "summary: $(cat "$tmp/out")"
  [ "$(grep -c '^PASS .* s)$' "$tmp/out")" = "$ncases" ] && ok || bad "PASS lines: $(cat "$tmp/out")"
  [ -s "$tmp/err" ] && bad "stderr: $(cat "$tmp/err")" || ok
  junit_counts "$tmp/j.xml" "$ncases" 0 0 && ok || bad "JUnit: $(cat "$tmp/j.xml")"
  grep -q "classname=\"$EXAMPLE\"" "$tmp/j.xml" && ok || bad "JUnit classname"
  grep -q '<property name="brdfit_version" value="0\.' "$tmp/j.xml" && ok || bad "JUnit: no brdfit_version property"
  ls "$tmp" | grep -q '\.tmp\.' && bad "temporary file left behind" || ok
else
  bad "example baseline failed: $(cat "$tmp/out" "$tmp/err")"
fi

# --- a perturbed parameter fails, named, with exit 1 --------------------------------------
jq '(.cases[] | select(.name == "cayman-walter") | .expected.params.alpha) |= . * 1.01' "$tmp/base.json" \
  > "$tmp/pert.json"
"$BRDFIT" regress "$tmp/pert.json" --junit "$tmp/p.xml" >"$tmp/out" 2>"$tmp/err"
[ $? = 1 ] && ok || bad "perturbed baseline: exit status not 1"
grep -q "^FAIL cayman-walter (" "$tmp/out" && ok || bad "no FAIL line: $(cat "$tmp/out")"
grep -q '^  params\.alpha: expected .*, got .* (|diff| .* > tol .*)$' "$tmp/out" && ok ||
  bad "diff line: $(cat "$tmp/out")"
[ "$(grep -c '^  [][a-z_.0-9]*: expected ' "$tmp/out")" = 1 ] && ok || bad "only alpha should move: $(cat "$tmp/out")"
# the fit's warnings, on stdout and in the JUnit case's system-out
grep -q '^  warning: lobe 1 is .* deg wide' "$tmp/out" && ok || bad "no warning lines: $(cat "$tmp/out")"
grep -q '<system-out>warning: ' "$tmp/p.xml" && grep -q '^warning: lobe 1 is ' "$tmp/p.xml" && ok ||
  bad "no warnings in the JUnit XML: $(cat "$tmp/p.xml")"
grep -qx "regress: $((ncases - 1)) passed, 1 failed" "$tmp/out" && ok || bad "summary: $(cat "$tmp/out")"
junit_counts "$tmp/p.xml" "$ncases" 1 0 && grep -q '<failure message=.*params\.alpha: expected' "$tmp/p.xml" && ok ||
  bad "JUnit failure: $(cat "$tmp/p.xml")"

# --verbose shows every compared value; --case runs one case
"$BRDFIT" regress "$tmp/pert.json" --case ptfe-ward_iso --verbose >"$tmp/out" 2>&1 &&
  grep -qx "regress: 1 passed, 0 failed" "$tmp/out" && grep -q '^  params\.alpha: .* <= tol' "$tmp/out" &&
  grep -q '^  metrics\.bic: ' "$tmp/out" && ok || bad "--case/--verbose: $(cat "$tmp/out")"

# --- --update restores the values (deterministic fits), keeps names, options, tolerances -
"$BRDFIT" regress "$tmp/pert.json" --update >"$tmp/out" 2>"$tmp/err" && ok || bad "--update: $(cat "$tmp/err")"
grep -q '^  params\.alpha: .* -> ' "$tmp/out" && grep -qx "UPDATED cayman-walter.*" "$tmp/out" && ok ||
  bad "--update output: $(cat "$tmp/out")"
[ "$(jq -cS 'del(.brdfit_version)' "$tmp/pert.json")" = "$(jq -cS . "$tmp/base.json")" ] && ok ||
  bad "--update did not give back the original baseline"
# ... and names the build that wrote it, second (after what the file is); readers skip it.
sed -n 3p "$tmp/pert.json" | grep -q '^  "brdfit_version": "0\.[0-9.]*\( (git [^)]*)\)\?",$' && ok ||
  bad "--update wrote no brdfit_version: $(head -n 3 "$tmp/pert.json")"
"$BRDFIT" regress "$tmp/pert.json" >/dev/null 2>&1 && ok || bad "updated baseline does not pass"

# --- a case that cannot run: exit 1, JUnit <error>, --update writes nothing --------------
printf 'theta_i,phi_i,theta_o,phi_o,value\n10,0,oops,180,0.3\n' > "$tmp/broken.csv"
jq --arg b "$tmp/broken.csv" '.cases += [{"name": "broken", "data": $b, "model": "lambert"}]' "$tmp/base.json" \
  > "$tmp/err.json"
cp "$tmp/err.json" "$tmp/err0.json"
"$BRDFIT" regress "$tmp/err.json" --case broken --case ptfe-ward_iso --junit "$tmp/e.xml" >"$tmp/out" 2>"$tmp/err"
[ $? = 1 ] && ok || bad "unrunnable case: exit status not 1"
grep -q "^brdfit regress: $tmp/err.json:[0-9]*: case 'broken': .*broken.csv:2" "$tmp/err" && ok ||
  bad "unrunnable case message: $(cat "$tmp/err")"
junit_counts "$tmp/e.xml" 2 0 1 && grep -q '<error message=' "$tmp/e.xml" && ok ||
  bad "JUnit error: $(cat "$tmp/e.xml")"
"$BRDFIT" regress "$tmp/err.json" --case broken --update >"$tmp/out" 2>&1
[ $? = 1 ] && cmp -s "$tmp/err.json" "$tmp/err0.json" && grep -q "not updated" "$tmp/out" && ok ||
  bad "--update with an unrunnable case: $(cat "$tmp/out")"

# --- bad baselines: exit 2, FILE:LINE on stderr, no JUnit file -------------------------------
bad_baseline() { # WHAT FILE LINE PATTERN
  rm -f "$tmp/x.xml"
  "$BRDFIT" regress "$2" --junit "$tmp/x.xml" >/dev/null 2>"$tmp/err"
  local rc=$?
  [ $rc = 2 ] && ok || bad "$1: exit $rc"
  [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q "^brdfit regress: $2:$3: .*$4" "$tmp/err" && ok ||
    bad "$1: message $(cat "$tmp/err")"
  [ -e "$tmp/x.xml" ] && bad "$1: JUnit file written" || ok
}
head -c 200 "$tmp/base.json" > "$tmp/trunc.json"
bad_baseline "truncated JSON" "$tmp/trunc.json" '[0-9]*' "malformed JSON"
jq '.cases[1].options += ["--frobnicate"]' "$tmp/base.json" > "$tmp/opt.json"
bad_baseline "unknown option" "$tmp/opt.json" "$(grep -n -- '--frobnicate' "$tmp/opt.json" | cut -d: -f1)" \
  "unknown option '--frobnicate'"
jq '.cases[2].options += ["--residual", "square"]' "$tmp/base.json" > "$tmp/res.json"
# jq writes one option a line: the message names the line of --residual, the one before the value
bad_baseline "bad option value" "$tmp/res.json" "$(($(grep -n '"square"' "$tmp/res.json" | cut -d: -f1) - 1))" \
  "--residual: .*square"
jq --arg m "$tmp/missing.csv" '.cases[3].data = $m' "$tmp/base.json" > "$tmp/miss.json"
bad_baseline "missing data file" "$tmp/miss.json" "$(grep -n 'missing.csv' "$tmp/miss.json" | cut -d: -f1)" \
  "data file .*missing.csv"
jq '.cases[0].model = "waltr"' "$tmp/base.json" > "$tmp/model.json"
bad_baseline "unknown model" "$tmp/model.json" "$(grep -n '"waltr"' "$tmp/model.json" | cut -d: -f1)" "waltr"

# --- bad usage ----------------------------------------------------------------------------
"$BRDFIT" regress >/dev/null 2>&1; [ $? = 2 ] && ok || bad "no baseline: not exit 2"
"$BRDFIT" regress "$tmp/base.json" --bogus >/dev/null 2>&1; [ $? = 2 ] && ok || bad "unknown option: not exit 2"
"$BRDFIT" regress "$tmp/base.json" --case nosuch >/dev/null 2>&1; [ $? = 2 ] && ok || bad "--case nosuch: not exit 2"
"$BRDFIT" regress --help | grep -q -- '--junit' && ok || bad "--help"

finish
