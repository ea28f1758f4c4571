#!/usr/bin/env bash
# One command-line grammar (cmd/cli.c): every command's --help and brdfit help COMMAND,
# --name=value, -mvalue, --, bundled short flags, '-' for inputs and outputs, -q and -v,
# bad options (exit 2, one line), outputs checked before any data is read, and the man
# pages and bash completion generated from the same tables (build/doc).
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need man man-db; need groff groff-base
doc=$(cd "$(dirname "$BRDFIT")/.." && pwd)/doc

awk 'BEGIN { print "theta_i,phi_i,theta_o,phi_o,value"; for (i = 0; i < 400; i++)
  printf "%d,0,%d,180,%.6f\n", (i * 7) % 80, (i * 13) % 80, 0.1 + 0.02 * ((i * 7) % 5) }' > "$tmp/d.csv"

# --- help ---------------------------------------------------------------------------------
commands=$("$BRDFIT" --help | awk '/^  [a-z]/ { print $1 }' | grep -v '^help$')
[ "$(echo "$commands" | wc -l)" = 17 ] && ok || bad "brdfit --help lists: $commands"
for c in $commands; do
  "$BRDFIT" "$c" --help >"$tmp/h1" 2>&1 && "$BRDFIT" "$c" -h >"$tmp/h2" 2>&1 && "$BRDFIT" help "$c" >"$tmp/h3" 2>&1 &&
    head -1 "$tmp/h1" | grep -q "^usage: brdfit $c " && cmp -s "$tmp/h1" "$tmp/h2" && cmp -s "$tmp/h1" "$tmp/h3" &&
    grep -q -- '-q, --quiet' "$tmp/h1" && ok || bad "$c --help: $(head -2 "$tmp/h1")"
  "$BRDFIT" "$c" --no-such-option >/dev/null 2>"$tmp/err"
  [ $? = 2 ] && [ "$(wc -l < "$tmp/err")" = 1 ] && grep -q "brdfit $c: unknown option '--no-such-option'" "$tmp/err" &&
    ok || bad "$c --no-such-option: $(cat "$tmp/err")"
  # A man page per command that man renders without complaint.
  MANWIDTH=80 man -l "$doc/man1/brdfit-$c.1" >"$tmp/man" 2>"$tmp/man.err" && [ ! -s "$tmp/man.err" ] &&
    grep -Eq "brdfit-$c +- " "$tmp/man" && ok || bad "man page of $c: $(head -3 "$tmp/man.err")"
done
"$BRDFIT" help >/dev/null && ok || bad "brdfit help"
"$BRDFIT" help nope >/dev/null 2>&1; [ $? = 2 ] && ok || bad "brdfit help nope: not exit 2"
v=$("$BRDFIT" --version) && [[ $v =~ ^brdfit\ [0-9]+\.[0-9]+\.[0-9]+ ]] && ok || bad "--version: $v"
v=$("$SYNTH" --version) && [[ $v =~ ^brdfit-synth\ [0-9]+\.[0-9]+\.[0-9]+ ]] && ok || bad "synth --version: $v"
"$SYNTH" --help | grep -q -- '--noise-model relative|additive|photon' && ok || bad "brdfit-synth --help"

# --- option forms give the same result -----------------------------------------------------
same() { cmp -s <(grep -v '"seconds"' "$1") <(grep -v '"seconds"' "$2"); } # result files but for wall times
"$BRDFIT" fit "$tmp/d.csv" -m lambert -o "$tmp/a.json" --threads 1 >/dev/null &&
  "$BRDFIT" fit "$tmp/d.csv" --model=lambert --output="$tmp/b.json" --threads=1 >/dev/null &&
  "$BRDFIT" fit -mlambert -o"$tmp/c.json" --threads 1 -- "$tmp/d.csv" >/dev/null &&
  same "$tmp/a.json" "$tmp/b.json" && same "$tmp/a.json" "$tmp/c.json" && ok ||
  bad "-m X, --model=X and -mX differ"
cp "$tmp/d.csv" "$tmp/-d.csv"
(cd "$tmp" && "$BRDFIT" info -- -d.csv >/dev/null) && ok || bad "-- then a file named -d.csv"
"$BRDFIT" fit "$tmp/d.csv" -m lambert --radians=1 >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q -- '--radians takes no value' "$tmp/err" && ok || bad "--radians=1: $(cat "$tmp/err")"
"$BRDFIT" fit "$tmp/d.csv" -m >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q -- '-m needs a value' "$tmp/err" && ok || bad "-m without value: $(cat "$tmp/err")"
"$BRDFIT" fit "$tmp/d.csv" -mx -Z >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q "unknown option '-Z'" "$tmp/err" && ok || bad "-Z: $(cat "$tmp/err")"

# --- standard input and output ------------------------------------------------------------------
"$BRDFIT" fit - -m lambert --threads 1 -o - < "$tmp/d.csv" >"$tmp/s.json" 2>"$tmp/summary" &&
  same <(grep -v '"data"' "$tmp/a.json") <(grep -v '"data"' "$tmp/s.json") && grep -q '^lambert  ok' "$tmp/summary" &&
  ok || bad "fit - -o -: $(diff "$tmp/a.json" "$tmp/s.json" | head -5)"
"$BRDFIT" eval --params - --dirs "$tmp/d.csv" < "$tmp/a.json" >"$tmp/e1.csv" &&
  "$BRDFIT" eval --params "$tmp/a.json" --dirs - < "$tmp/d.csv" >"$tmp/e2.csv" && cmp -s "$tmp/e1.csv" "$tmp/e2.csv" &&
  [ "$(wc -l < "$tmp/e1.csv")" = 401 ] && ok || bad "eval --params - / --dirs -"
"$BRDFIT" info - < "$tmp/d.csv" | grep -q '^-: 400 samples read' && ok || bad "info -"
"$BRDFIT" convert - - --to csv < "$tmp/d.csv" 2>/dev/null | "$BRDFIT" info - | grep -q '^-: 400 samples read' &&
  ok || bad "convert - - --to csv | info -"
"$SYNTH" --params "$DATA/lambert_rgb.json" --pattern merl -o "$tmp/m.binary" >/dev/null &&
  "$BRDFIT" info - < "$tmp/m.binary" | grep -q '^-: [0-9]\{7\} samples read' && ok || bad "a MERL table on standard input"
"$BRDFIT" fit - --scene - -m lambert < "$tmp/d.csv" >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q 'both read standard input' "$tmp/err" && ok || bad "two inputs from -: $(cat "$tmp/err")"
"$SYNTH" --params "$DATA/lambert_rgb.json" --pattern uniform --count 5 -o - | "$BRDFIT" info - | grep -q '^-: 5 samples' &&
  ok || bad "brdfit-synth -o -"
"$BRDFIT" render --params "$tmp/a.json" --size 16 --to png -o - | head -c 8 | od -An -c | grep -q 'P   N   G' &&
  ok || bad "render --to png -o -"

# --- quiet, verbose, outputs checked first -------------------------------------------------------
[ -z "$("$BRDFIT" fit "$tmp/d.csv" -m lambert -q)" ] && ok || bad "fit -q printed a summary"
"$BRDFIT" fit "$tmp/d.csv" -m lambert -v 2>&1 >/dev/null | grep -q 'read .*d.csv: 400 samples x 1 channels' && ok ||
  bad "fit -v says nothing of the data"
"$BRDFIT" fit "$tmp/d.csv" -m lambert -v -o /nonexistent/x.json >/dev/null 2>"$tmp/err"
[ $? = 1 ] && ! grep -q 'read \|fitting' "$tmp/err" && grep -q '/nonexistent/x.json' "$tmp/err" && ok ||
  bad "an unwritable -o is found after reading or fitting: $(cat "$tmp/err")"

# --- completion ---------------------------------------------------------------------------------
complete_words() { # WORD... : what _brdfit offers for the last word
  bash -c 'source "$1"; shift; COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _brdfit; echo "${COMPREPLY[*]}"' _ \
    "$doc/completions/brdfit" "$@"
}
[ "$(complete_words brdfit fit --format '')" = "csv merl cornell alta rgl mbsdf" ] && ok || bad "completion of --format"
[ "$(complete_words brdfit fit -m walter)" = "walter walter_aniso" ] && ok || bad "completion of -m walter"
[ "$(complete_words brdfit compare --rank a)" = "aic aicc" ] && ok || bad "completion of --rank"
[ "$(complete_words brdfit help re)" = "render regress report" ] && ok || bad "completion of help"

finish
