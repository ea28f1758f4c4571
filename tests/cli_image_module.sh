#!/usr/bin/env bash
# Image support is a module loaded on first use (libbrdfit-oiio.so): commands that write
# no image never map OpenImageIO; those that do find the module (BRDFIT_PLUGIN_DIR, else
# the build tree); a missing or broken module is a one-line error, exit 1, and no file.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need ldd libc-bin
P=$DATA/lambert_rgb.json
MOD=libbrdfit-oiio.so

# --- OpenImageIO stays out of commands without images -----------------------------------
[ "$(ldd "$BRDFIT" | grep -c OpenImageIO)" = 0 ] && ok || bad "brdfit links OpenImageIO"
# The dynamic loader names every object it maps (LD_DEBUG=files), dlopen'd ones too.
maps_oiio() { LD_DEBUG=files "$BRDFIT" "$@" 2>&1 >/dev/null | grep -c 'OpenImageIO'; }
[ "$(maps_oiio models)" = 0 ] && ok || bad "brdfit models maps OpenImageIO"
[ "$(maps_oiio eval --params "$P" --dirs "$DATA/dirs_small.csv")" = 0 ] && ok || bad "brdfit eval maps OpenImageIO"
# A render that stops at its arguments loads nothing either.
[ "$(maps_oiio render --params "$P" --size 0 -o "$tmp/n.png")" = 0 ] && ok || bad "bad render usage maps OpenImageIO"
# ... and one that writes does (the check above can see a dlopen'd module).
[ "$(maps_oiio render --params "$P" --size 8 -o "$tmp/y.png")" != 0 ] && ok || bad "render does not map OpenImageIO"
[ -s "$tmp/y.png" ] && ok || bad "render wrote no image"

# --- BRDFIT_PLUGIN_DIR names the module's directory --------------------------------------
if [ -n "$PLUGIN_DIR" ]; then
  BRDFIT_PLUGIN_DIR=$PLUGIN_DIR "$BRDFIT" render --params "$P" --size 8 -o "$tmp/d.exr" 2>"$tmp/err" &&
    [ -s "$tmp/d.exr" ] && ok || bad "render with BRDFIT_PLUGIN_DIR: $(cat "$tmp/err")"
fi

# --- a module that is not there, or not loadable: one line, exit 1, no output -------------
no_module() { # name, pattern, out, env dir, command and args (the output is the last)
  local name=$1 pattern=$2 out=$3 dir=$4
  shift 4
  rm -rf "$out"
  BRDFIT_PLUGIN_DIR=$dir "$BRDFIT" "$@" >/dev/null 2>"$tmp/err"
  local st=$?
  [ "$st" = 1 ] && ok || bad "$name: exit status $st, want 1"
  [ "$(grep -c . "$tmp/err")" = 1 ] && ok || bad "$name: not one line: $(cat "$tmp/err")"
  grep -qF -- "$pattern" "$tmp/err" && ok || bad "$name: message lacks '$pattern': $(cat "$tmp/err")"
  [ -e "$out" ] && bad "$name: output written" || ok
  ls "$tmp" | grep -q 'tmp' && bad "$name: temporary file left" || ok
}
missing="image support ($MOD) could not be loaded: /nonexistent/$MOD: cannot open shared object file"
no_module render-png "$missing" "$tmp/x.png" /nonexistent render --params "$P" --size 8 -o "$tmp/x.png"
no_module render-exr "$missing" "$tmp/x.exr" /nonexistent render --params "$P" --size 8 -o "$tmp/x.exr"
# Set, it is the only place looked at: a broken file there is the error, no other copy.
mkdir -p "$tmp/broken" && echo "not a shared object" >"$tmp/broken/$MOD"
no_module broken "image support ($MOD) could not be loaded: $tmp/broken/$MOD" "$tmp/x.png" "$tmp/broken" \
  render --params "$P" --size 8 -o "$tmp/x.png"
# Argument errors come first, without the module: the usual usage error.
BRDFIT_PLUGIN_DIR=/nonexistent "$BRDFIT" render --params "$P" -o "$tmp/x.gif" >/dev/null 2>"$tmp/err"
[ $? = 2 ] && grep -q '.png or .exr' "$tmp/err" && ok || bad "bad extension without the module: $(cat "$tmp/err")"
# A report needs images too: it fails as a whole and leaves no folder.
if [ -n "$SYNTH" ]; then
  echo '{"model": "lambert", "channels": 3, "params": {"rho_d": [0.6, 0.4, 0.2]}}' >"$tmp/lam.json"
  "$SYNTH" --params "$tmp/lam.json" --pattern uniform --count 200 --noise 0.01 --seed 1 -o "$tmp/lam.csv" ||
    bad "brdfit-synth failed"
  no_module compare-html "image support ($MOD)" "$tmp/report" /nonexistent \
    compare "$tmp/lam.csv" -m lambert --quiet --html "$tmp/report"
  rm -f "$tmp/lam.csv" "$tmp/lam.json"
fi

finish
