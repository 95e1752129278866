#!/usr/bin/env bash
# What issue 33 found the program doing wrong with exit 0 or after a whole
# fill: NaN thresholds in `check`, stale frames, unwritable outputs found
# late, FIFOs and bad OFF indices as meshes, PFILL_DEVICE=bogus in
# `pfill devices`, a 120 KB argument echoed whole, range errors with exit 1,
# options that do nothing, a JPEG name for PNG data, a replaced symlink.
# Usage: cli_issue33.sh PFILL_BINARY
set -uo pipefail
source "$(dirname "$0")/cli_test_lib.sh" "$1"

# refused STATUS PATTERN COMMAND...: that exit status within seconds, one
# line on stderr mentioning PATTERN.
refused() {
  local want="$1" pattern="$2"
  shift 2
  timeout 30 "$@" >out.txt 2>err.txt
  local got=$?
  [ "$got" -eq "$want" ] || fail "$* exited $got, expected $want: $(head -c 300 err.txt)"
  grep -q -- "$pattern" err.txt || fail "$*: stderr does not mention '$pattern': $(head -c 300 err.txt)"
  [ "$(grep -c . err.txt)" -eq 1 ] || fail "$*: not one line on stderr: $(head -c 600 err.txt)"
  [ "$(wc -c < err.txt)" -lt 1000 ] || fail "$*: $(wc -c < err.txt) bytes on stderr"
}

small=(--builtin sphere -n 60 -q --hole-rounds 0)
"$pfill" fill "${small[@]}" -o p.ply >/dev/null || fail "a small fill"

# 9: a NaN or negative threshold can never fail: refused as bad usage.
refused 2 "tolerance" "$pfill" check p.ply sphere --tolerance nan
refused 2 "tolerance" "$pfill" check p.ply sphere --tolerance -1
refused 2 "min-inside" "$pfill" check p.ply sphere --min-inside nan
refused 2 "max-overlap" "$pfill" check p.ply sphere --max-overlap nan
refused 2 "min-packing" "$pfill" check p.ply sphere --min-packing inf

# 8: a frames folder holding an earlier fill's frames is refused before the fill.
mkdir old_frames
for i in 000000 000001 000002; do cp p.ply old_frames/frame_$i.ply; done
refused 1 "already holds 3 frames" "$pfill" fill "${small[@]}" -o f.ply --frames old_frames
[ ! -e f.ply ] || fail "a fill ran although its frames folder was refused"

# 13: outputs that cannot be written fail before the fill.
mkdir a_folder.ply
refused 1 "it is a folder" "$pfill" fill "${small[@]}" -o a_folder.ply
refused 1 "not writable" "$pfill" fill "${small[@]}" -o /proc/x.ply
refused 2 "density" "$pfill" fill "${small[@]}" -o x.data --density nan

# 14: a FIFO as the mesh, an OFF index out of range, PFILL_DEVICE=bogus.
mkfifo pipe.obj
refused 1 "not a regular file" "$pfill" fill pipe.obj -n 60 -o x.ply
refused 1 "not a regular file" "$pfill" info pipe.obj
printf 'OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 -7 2\n3 1 2 3\n' > neg.off
refused 1 "vertex index -7 out of range" "$pfill" fill neg.off -n 60 -o x.ply
PFILL_DEVICE=bogus "$pfill" devices >devices.txt 2>devices_err.txt || fail "PFILL_DEVICE=bogus pfill devices failed: $(cat devices_err.txt)"
grep -q "0: " devices.txt || fail "PFILL_DEVICE=bogus pfill devices listed nothing"
grep -q "bogus" devices_err.txt || fail "PFILL_DEVICE=bogus: no warning naming it"

# 15: parse errors capped; range errors are bad usage (2); -1 for an unsigned count.
long=$(head -c 120000 /dev/zero | tr '\0' 'x')
refused 2 "more bytes" "$pfill" fill --stop-share "$long"
refused 2 "sync-every" "$pfill" fill "${small[@]}" --sync-every 0
refused 2 "max-steps" "$pfill" fill "${small[@]}" --max-steps -1
refused 2 "rest-distance" "$pfill" fill "${small[@]}" --rest-distance 1e300
refused 2 "exponents" "$pfill" fill "${small[@]}" --exponents 1e300,6
refused 2 "birth-speed" "$pfill" fill "${small[@]}" --birth-speed 0,0
refused 1 "PNG" "$pfill" fill "${small[@]}" -o y.ply --preview y.jpg
# Options that do nothing for the chosen output say so.
"$pfill" fill "${small[@]}" -o w.ply --density 2 --every 10 --spheres >/dev/null 2>warn.txt || fail "a fill with idle options"
for option in --density --every --spheres; do
  grep -q -- "warning: $option" warn.txt || fail "$option with .ply and no --frames passed silently: $(cat warn.txt)"
done
# A symbolic link as the output stays a link; the file it points to is written.
"$pfill" fill "${small[@]}" -o target.ply >/dev/null
ln -s target.ply link.ply
"$pfill" fill "${small[@]}" --seed 7 -o link.ply >/dev/null || fail "writing through a link"
[ -L link.ply ] || fail "-o link.ply replaced the symbolic link by a file"
cmp -s link.ply target.ply || fail "the link's target was not written"

# A birth point outside a box at (9..11)^3 is not echoed shifted by the box's centre.
printf 'v 9 9 9\nv 11 9 9\nv 9 11 9\nv 11 11 9\nv 9 9 11\nv 11 9 11\nv 9 11 11\nv 11 11 11\n' > box.obj
printf 'f 1 3 4\nf 1 4 2\nf 5 6 8\nf 5 8 7\nf 1 2 6\nf 1 6 5\nf 3 7 8\nf 3 8 4\nf 1 5 7\nf 1 7 3\nf 2 4 8\nf 2 8 6\n' >> box.obj
refused 1 "outside the mesh" "$pfill" fill box.obj -n 60 -q --birth=0,0,0 -o b.ply
grep -q -- "-10" err.txt && fail "--birth=0,0,0 echoed shifted: $(cat err.txt)"
# A fill whose pass 1 ran out of --max-steps says so, not "the mesh may be thinner".
"$pfill" fill --builtin sphere -n 400 -q --hole-rounds 0 --max-steps 100 -o m.ply >/dev/null 2>steps.txt
grep -q -- "--max-steps" steps.txt || fail "a fill cut short by --max-steps does not name it: $(cat steps.txt)"

# A temporary file a SIGKILL left during the final rename (its process gone) is cleaned up by the next write.
touch .k.ply.tmp4194303-0
"$pfill" fill "${small[@]}" -o k.ply >/dev/null || fail "a fill beside a stale temporary"
[ ! -e .k.ply.tmp4194303-0 ] || fail "the stale temporary .k.ply.tmp4194303-0 was left"

[ "$failures" -eq 0 ] && echo "all issue-33 CLI checks passed"
exit "$failures"
