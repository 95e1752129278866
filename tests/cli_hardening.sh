#!/usr/bin/env bash
# The `pfill` program refuses what issue 21 found it accepting: outputs that
# name an input or each other, options out of range, a mesh with --builtin.
# Each is refused at once (exit 1 or 2, one line naming the option) and
# nothing is written. Usage: cli_hardening.sh PFILL_BINARY
set -uo pipefail
source "$(dirname "$0")/cli_test_lib.sh" "$1"

# refused PATTERN COMMAND...: non-zero exit within seconds, PATTERN on stderr.
refused() {
  local pattern="$1"
  shift
  timeout 20 "$@" >out.txt 2>err.txt
  local got=$?
  [ "$got" -eq 1 ] || [ "$got" -eq 2 ] || fail "$* exited $got, expected 1 or 2: $(cat err.txt)"
  grep -q -- "$pattern" err.txt || fail "$*: stderr does not mention '$pattern': $(cat err.txt)"
  [ "$(grep -c . err.txt)" -le 3 ] || fail "$*: more than a line or two on stderr: $(cat err.txt)"
}

"$pfill" fill --builtin sphere -n 60 -q --hole-rounds 0 -o mesh.ply >/dev/null || fail "a small fill"
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' > same.obj
cp same.obj keep.obj
mkdir -p sub frames
refused "the mesh" "$pfill" fill same.obj -n 50 -o same.obj
refused "the mesh" "$pfill" fill same.obj -n 50 -o ./sub/../same.obj
ln -s same.obj link.obj
refused "the mesh" "$pfill" fill same.obj -n 50 -o link.obj
refused "the mesh" "$pfill" fill same.obj -n 50 -o out.ply --report same.obj
refused "the mesh" "$pfill" fill same.obj -n 50 -o out.ply --preview same.obj
refused "same file" "$pfill" fill same.obj -n 50 -o out.ply --report out.ply
refused "frames" "$pfill" fill same.obj -n 50 -o frames/frame_000001.ply --frames frames
refused "-o" "$pfill" render mesh.ply -o mesh.ply
cmp -s same.obj keep.obj || fail "the mesh was overwritten"
[ ! -e out.ply ] || fail "an output was written after a refusal"

refused "count" "$pfill" fill -n 0
refused "count" "$pfill" fill -n -5
refused "radius" "$pfill" fill -r 0
refused "radius" "$pfill" fill -r -1
refused "seed" "$pfill" fill --seed -1
refused "seed" "$pfill" fill --seed 18446744073709551616
refused "not both" "$pfill" fill -n 300 -r 0.05
refused "not both" "$pfill" fill same.obj --builtin cube
refused "patience" "$pfill" fill --patience 50
refused "hole-rounds" "$pfill" fill --hole-rounds -1
refused "site-depth" "$pfill" fill --site-depth 2
refused "birth-clearance" "$pfill" fill --birth-clearance 0.1
ls .*.tmp* >/dev/null 2>&1 && fail "temporary files left: $(ls -a)"

# SIGTERM (or Ctrl-C, SIGINT, which a script's background job ignores)
# during a fill stops it through FillOptions::cancelled: exit 128 + 15,
# one line, no output and no temporary file.
"$pfill" fill --builtin sphere -n 20000 -o interrupted.ply --frames iframes --every 50 >/dev/null 2>int_err.txt &
pid=$!
sleep 4
kill -TERM "$pid"
wait "$pid"
got=$?
[ "$got" -eq 143 ] || fail "SIGTERM during a fill exited $got, expected 143: $(cat int_err.txt)"
grep -q "interrupted: the fill stopped" int_err.txt || fail "SIGTERM during a fill: no 'interrupted' line: $(cat int_err.txt)"
[ -e interrupted.ply ] && fail "SIGTERM during a fill left its output"
ls -a iframes 2>/dev/null | grep -q '\.tmp' && fail "SIGTERM left a temporary frame: $(ls -a iframes)"
# Frames written before the signal are named, not "wrote nothing" (issue 33).
if ls iframes/frame_*.ply >/dev/null 2>&1; then
  grep -q "frames are in iframes" int_err.txt || fail "SIGTERM after frames: they are not mentioned: $(cat int_err.txt)"
fi

[ "$failures" -eq 0 ] && echo "all CLI hardening checks passed"
exit "$failures"
