#!/usr/bin/env bash
# The `pfill` program end to end: the main job, each subcommand, and bad
# input answered by one line on stderr with exit status 1 (usage: 2) and no
# output file left behind. Usage: cli_smoke.sh PFILL_BINARY
set -uo pipefail
source "$(dirname "$0")/cli_test_lib.sh" "$1"

# expect_error STATUS PATTERN COMMAND...: the exit status, and one error line
# on stderr that matches PATTERN (progress lines may come before it).
expect_error() {
  local want="$1" pattern="$2"
  shift 2
  "$@" >/dev/null 2>err.txt
  local got=$?
  [ "$got" -eq "$want" ] || fail "$* exited $got, expected $want"
  local lines
  lines=$(grep -c '^pfill: error: ' err.txt)
  [ "$lines" -eq 1 ] || fail "$*: expected one error line, got $lines: $(cat err.txt)"
  grep '^pfill: error: ' err.txt | grep -q -- "$pattern" || fail "$*: error does not mention '$pattern': $(cat err.txt)"
  grep -q '^$' err.txt && fail "$*: blank line on stderr"
}

"$pfill" info --builtin torus --json > info.json || fail "info --json"
grep -q '"genus": 1' info.json || fail "info: torus genus"
"$pfill" fill --builtin sphere -n 150 -q -o s.ply --report s.json > fill.txt || fail "fill"
[ -s s.ply ] && [ -s s.json ] || fail "fill wrote no PLY or report"
grep -q "packing fraction" fill.txt || fail "fill summary"
"$pfill" check s.ply sphere --json > check.json || fail "check"
grep -q '"contained_share": 1' check.json || fail "check: containment"
grep -q '"largest_hole_over_r": 0\.' check.json || fail "check: largest empty hole missing or a sphere fits"
grep -q '"min_distance_over_contact": 0\.999\|"min_distance_over_contact": 1' check.json || fail "check: closest centres over the default 0.1% bound"
grep -q "largest empty hole" fill.txt || fail "fill summary: holes"
"$pfill" fill --builtin cube -n 100 -q -o c.csv >/dev/null || fail "fill to CSV"
head -1 c.csv | grep -q '^x,y,z,radius' || fail "CSV header"
"$pfill" devices | grep -q '\*' || fail "devices: no default marked"
"$pfill" render s.ply --mesh sphere --size 64x48 -o s.png >/dev/null || fail "render"
[ -s s.png ] || fail "render wrote no PNG"

printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n' > bad.obj
expect_error 1 "missing.obj" "$pfill" fill missing.obj -o out.ply
expect_error 1 "index" "$pfill" fill bad.obj -o out.ply
expect_error 1 "no particle of radius" "$pfill" fill --builtin sphere -r 5 -o out.ply
expect_error 2 "more than pfill handles" "$pfill" fill --builtin sphere -n 2000000000 -o out.ply
expect_error 1 "outside the mesh" "$pfill" fill --builtin sphere -n 100 --birth 5,0,0 -o out.ply
expect_error 1 "no_such_dir" "$pfill" fill --builtin sphere -n 50 -q -o no_such_dir/out.ply
expect_error 2 "blocked, ke or collisions" "$pfill" fill --builtin sphere -n 50 --stop never -o out.ply
expect_error 1 "PFILL_DEVICE\|no OpenCL device\|device" "$pfill" fill --builtin sphere -n 50 --device nosuchdevice -o out.ply
[ ! -e out.ply ] || fail "a failed fill left out.ply behind"
ls -A | grep -q '^\.' && fail "temporary files left behind: $(ls -A | grep '^\.')"

"$pfill" fill --no-such-option >/dev/null 2>&1
[ $? -eq 2 ] || fail "bad usage should exit 2"

if [ "$failures" -eq 0 ]; then echo "cli smoke: all passed"; else exit 1; fi
