#!/usr/bin/env bash
# brdfit render from the shell: sphere, slice and half/difference images of the requested
# size that OpenImageIO reads back (iinfo), and bad usage / bad input: a one-line error,
# exit 2 or 1, and no image file.
set -u
source "$(dirname "$0")/common_cli.sh" "$@"
need iinfo openimageio-tools; need oiiotool openimageio-tools
P=$DATA/lambert_rgb.json

# --- good input: the image exists, has the size asked for, and nothing else is left ---
render_ok() { # name, expected "W x H", args...
  local name=$1 size=$2
  shift 2
  if "$BRDFIT" render "$@" 2>"$tmp/err"; then
    local out=${*: -1}
    iinfo "$out" 2>&1 | grep -Eq ": +${size% x *} x +${size#* x }, 3 channel" && ok || bad "$name: size is not $size: $(iinfo "$out" 2>&1)"
  else
    bad "$name failed: $(cat "$tmp/err")"
  fi
}
render_ok sphere-png "64 x 64" --params "$P" --size 64 -o "$tmp/s.png"
render_ok sphere-exr "33 x 33" --params "$P" --light 0,0 --light 60,90 --view 10,0 --size 33 -o "$tmp/s.exr"
render_ok slice "300 x 200" --params "$P" --slice --incidence 0,45 --size 300x200 -o "$tmp/sl.png"
render_ok slice-data "320 x 240" --params "$P" --slice --data "$DATA/dirs_small.csv" --values theta_o --size 320x240 -o "$tmp/sld.png"
render_ok half-diff "90 x 45" --params "$P" --half-diff --phi-d 45 --size 90x45 -o "$tmp/hd.exr"
render_ok half-diff-png "50 x 50" --params "$P" --half-diff --tonemap reinhard --size 50 -o "$tmp/hd.png"
# Lambert sphere lit along the view: the centre pixel of the EXR is rho/pi = 0.2546479 (red).
"$BRDFIT" render --params "$P" --light 0,0 --size 33 -o "$tmp/c.exr" 2>/dev/null
v=$(oiiotool "$tmp/c.exr" --cut 1x1+16+16 --printstats 2>&1 | grep -i "Stats Avg" | head -1)
echo "$v" | grep -q "0.25464" && ok || bad "sphere centre: $v"
ls "$tmp" | grep -q tmp && bad "temporary file left behind" || ok

# --- bad input: one line on stderr naming the problem, exit status, no output ----------
expect_error() { # name, status, pattern, out, args...
  local name=$1 want=$2 pattern=$3 out=$4
  shift 4
  rm -f "$out"
  "$BRDFIT" render "$@" -o "$out" 2>"$tmp/err" >/dev/null
  local st=$?
  [ "$st" = "$want" ] && ok || bad "$name: exit status $st, want $want"
  [ "$(wc -l <"$tmp/err")" = 1 ] && ok || bad "$name: not one line: $(cat "$tmp/err")"
  grep -q -- "$pattern" "$tmp/err" && ok || bad "$name: message lacks '$pattern': $(cat "$tmp/err")"
  [ -e "$out" ] && bad "$name: output file written" || ok
  ls "$tmp" | grep -q 'tmp' && bad "$name: temporary file left" || ok
}
expect_error no-params 2 "params" "$tmp/e.png"
expect_error bad-ext 2 "e.jpg" "$tmp/e.jpg" --params "$P"
expect_error bad-light 2 "--light" "$tmp/e.png" --params "$P" --light 45
expect_error bad-size 2 "--size" "$tmp/e.png" --params "$P" --size 0
expect_error non-square 2 "square" "$tmp/e.png" --params "$P" --size 10x20
expect_error bad-incidence 2 "--incidence" "$tmp/e.png" --params "$P" --slice --incidence 30,95
expect_error bad-tonemap 2 "--tonemap" "$tmp/e.png" --params "$P" --tonemap gamma
expect_error both-modes 2 "exclude" "$tmp/e.png" --params "$P" --slice --half-diff
expect_error unknown-opt 2 "--frobnicate" "$tmp/e.png" --params "$P" --frobnicate 1
expect_error missing-params 1 "nope.json" "$tmp/e.png" --params "$tmp/nope.json"
echo '{"model": "lambert", "channels": 3, "params": {"rho_d": [0.8, 0.5]}}' >"$tmp/short.json"
expect_error bad-params 1 "short.json" "$tmp/e.png" --params "$tmp/short.json"
expect_error half-diff-not-merl 1 "dirs_small.csv" "$tmp/e.exr" --half-diff --data "$DATA/dirs_small.csv"
expect_error unwritable 1 "no-such-dir" "$tmp/no-such-dir/e.png" --params "$P"

finish
