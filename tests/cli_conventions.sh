#!/usr/bin/env bash
# Command-line conventions: fill --json and --report - put the JSON alone on
# stdout; check's thresholds exit 3 when missed; a mistyped command is named;
# a built-in shape name works as the mesh of every subcommand; the export
# formats and options reach the files. Usage: cli_conventions.sh PFILL_BINARY
set -uo pipefail
source "$(dirname "$0")/cli_test_lib.sh" "$1"
# The particle count of a fill's JSON (no python needed: CI's Debian may lack it).
particles_of() { grep -m1 '"particles":' "$1" | tr -dc '0-9'; }
# A JSON document alone: '{' first, '}' last.
json_alone() { [ "$(head -c 1 "$1")" = "{" ] && [ "$(tail -n 1 "$1")" = "}" ]; }

# fill --json: stdout is one JSON document (progress and warnings on stderr).
"$pfill" fill sphere -n 150 --max-overlap 0.05 -o s.ply --json > fill.json 2> fill.err || fail "fill --json"
json_alone fill.json || fail "fill --json: stdout is not one JSON document: $(head -c 300 fill.json)"
[ "$(particles_of fill.json)" -gt 100 ] || fail "fill --json: no particle count: $(head -c 300 fill.json)"
grep -q "pfill: filling" fill.err || fail "fill --json: progress should stay on stderr"
# --report -: the same document on stdout.
"$pfill" fill sphere -n 150 --max-overlap 0.05 -q -o s2.ply --report - > report.json || fail "fill --report -"
json_alone report.json || fail "--report -: stdout is not one JSON document"
[ "$(particles_of report.json)" = "$(particles_of fill.json)" ] || fail "--report - and --json differ"
[ ! -e ./- ] || fail "--report - wrote a file named '-'"

# check thresholds: met -> 0, missed -> 3 with a line naming the threshold.
"$pfill" check s.ply sphere --min-inside 0.99 --max-overlap 0.06 >/dev/null || fail "check: thresholds met should exit 0"
"$pfill" check s.ply sphere --max-overlap 0.0001 > check.txt 2> check.err
[ $? -eq 3 ] || fail "check: a missed --max-overlap should exit 3"
grep -q "max-overlap" check.err || fail "check: the missed threshold is not named: $(cat check.err)"
grep -q "packing fraction" check.txt || fail "check: the metrics should still be printed"
"$pfill" fill cube -n 80 -q -o c0.ply > /dev/null || fail "fill cube"
"$pfill" check c0.ply sphere --min-inside 0.999 --json > check.json 2>/dev/null
[ $? -eq 3 ] || fail "check: particles of a cube in its inscribed sphere should miss --min-inside"
grep -q '"passed": false' check.json || fail "check --json: passed should be false"
"$pfill" check s.ply sphere --min-packing 0.9 >/dev/null 2>&1
[ $? -eq 3 ] || fail "check: a missed --min-packing should exit 3"

# A mistyped command is named; exit 2 (usage).
"$pfill" fil sphere > /dev/null 2> typo.err
[ $? -eq 2 ] || fail "a wrong command should exit 2"
grep -q "unknown command 'fil'" typo.err || fail "a wrong command is not named: $(cat typo.err)"

# Built-in names as the mesh in every subcommand.
"$pfill" info torus --json > info.json || fail "info torus"
grep -q '"genus": 1' info.json || fail "info torus: genus"
"$pfill" info --builtin torus --json | cmp -s - info.json || fail "info torus and info --builtin torus differ"
"$pfill" fill cube -n 80 -q -o c.csv > /dev/null || fail "fill cube"
"$pfill" check c.csv cube > /dev/null || fail "check c.csv cube"
"$pfill" render c.csv --mesh cube --size 32x24 -o c.png 2> /dev/null || fail "render --mesh cube"

# Exports by extension, with ids and velocities.
"$pfill" fill cube -n 80 -q --velocities -o c.data > /dev/null || fail "fill -o .data"
grep -q "^Atoms # sphere" c.data && grep -q "^Velocities" c.data || fail ".data: no Atoms or Velocities section"
"$pfill" fill cube -n 80 -q -o c.xyzr > /dev/null || fail "fill -o .xyzr"
[ "$(grep -v '^#' c.xyzr | awk '{print NF}' | sort -u)" = "5" ] || fail ".xyzr: expected x y z r id on every line"
"$pfill" fill cube -n 80 -q --velocities --attribute-names houdini -o h.csv > /dev/null || fail "houdini names"
head -1 h.csv | grep -q '^x,y,z,pscale,v.x,v.y,v.z,id$' || fail "houdini CSV header: $(head -1 h.csv)"
"$pfill" fill cube -n 80 -q --velocities -o v.csv --frames frames --every 200 > /dev/null || fail "--velocities --frames"
head -1 v.csv | grep -q ',vx,vy,vz,id$' || fail "--velocities: CSV header $(head -1 v.csv)"
head -c 400 frames/frame_000000.ply | grep -q "property float vx" || fail "--velocities: frames lack vx"
head -c 400 frames/frame_000000.ply | grep -q "property uint id" || fail "frames lack ids"
"$pfill" fill cube -n 80 -q --attribute-names maya -o m.csv > /dev/null 2>&1
[ $? -eq 2 ] || fail "--attribute-names maya should be refused (usage)"
"$pfill" fill cube -n 80 -q -o m.xyz > /dev/null 2> ext.err
grep -q ".data for LAMMPS" ext.err || fail "unknown extension: the error should list the formats: $(cat ext.err)"

if [ "$failures" -eq 0 ]; then echo "cli conventions: all passed"; else exit 1; fi
