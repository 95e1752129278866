#!/usr/bin/env bash
# The contact network on the command line: fill --contacts puts it in the
# output, the report and --pairs; `pfill contacts` finds the same pairs in
# the written file; bad use is refused with one line. Usage: cli_contacts.sh PFILL_BINARY
set -uo pipefail
source "$(dirname "$0")/cli_test_lib.sh" "$1"
field() { grep -m1 "\"$2\":" "$1" | tr -dc '0-9.'; }

"$pfill" fill cube -n 120 -q --contacts --pairs pairs.csv -o c.ply --report c.json > fill.txt || fail "fill --contacts"
grep -q "contacts .* pairs (gap <= 2% of the smaller radius), mean coordination" fill.txt || fail "fill --contacts: no summary line: $(cat fill.txt)"
pairs=$(field c.json pairs)
[ -n "$pairs" ] && [ "$pairs" -gt 50 ] || fail "fill --contacts: the report has no pairs: $pairs"
grep -q "\"coordination_histogram\"" c.json || fail "report: no coordination histogram"
grep -q "\"coordination_by_depth\"" c.json || fail "report: no coordination by depth"
grep -aq "^element edge $pairs$" c.ply || fail "PLY: no 'element edge $pairs'"
[ "$(awk -F, 'NR > 1 && $2 != 0' pairs.csv | wc -l)" = "$pairs" ] || fail "--pairs: not $pairs pair rows"
[ "$(awk -F, 'NR > 1 && $2 == 0' pairs.csv | wc -l)" = "$(field c.json wall_contacts)" ] || fail "--pairs: wall rows"

# The same pairs from the file (positions as floats: within rounding of the threshold, allow 1%).
"$pfill" contacts c.ply cube --json > again.json || fail "contacts --json"
again=$(field again.json pairs)
[ $((again * 100)) -ge $((pairs * 99)) ] && [ $((again * 100)) -le $((pairs * 101)) ] || fail "contacts: $again pairs, the fill $pairs"
"$pfill" contacts c.ply -o c.vtp > /dev/null || fail "contacts -o c.vtp"
grep -q "<Lines>" c.vtp || fail "VTP: no lines"
"$pfill" contacts c.ply --gap 0.2 -o wide.data > /dev/null || fail "contacts --gap 0.2"
grep -q "Atoms # hybrid sphere bond" wide.data || fail "LAMMPS data: not hybrid sphere bond"

# check --pairs: every listed pair within the gap; a pair that is not makes it exit 3.
"$pfill" check c.ply cube --pairs pairs.csv > check.txt || fail "check --pairs: listed pairs should pass"
grep -q "contacts        $pairs listed pairs, 0 beyond the gap" check.txt || fail "check --pairs: $(grep contacts check.txt)"
"$pfill" contacts c.ply --gap 0.5 --pairs wide.csv > /dev/null || fail "contacts --gap 0.5"
"$pfill" check c.ply cube --pairs wide.csv > /dev/null 2> bad.err; [ $? -eq 3 ] || fail "check --pairs with pairs 50% apart should exit 3"
grep -q "farther apart than 2% of the smaller radius" bad.err || fail "check --pairs: $(cat bad.err)"
"$pfill" check c.ply cube --pairs wide.csv --contact-gap 0.5 > /dev/null || fail "check --pairs --contact-gap 0.5"
{ head -1 pairs.csv; echo "999999,1,0,0,0,0,1,0,0"; } > unknown.csv
"$pfill" check c.ply cube --pairs unknown.csv > /dev/null 2> unknown.err; [ $? -eq 3 ] || fail "check --pairs with an unknown id should exit 3"

"$pfill" contacts c.ply > none.txt 2> none.err; [ $? -eq 1 ] || fail "contacts without an output should exit 1"
grep -q "say what to write" none.err || fail "contacts: no output named: $(cat none.err)"
"$pfill" contacts c.ply --gap 2 --json > /dev/null 2>&1; [ $? -eq 2 ] || fail "--gap 2 should be a usage error"
"$pfill" contacts c.ply -o c.ply > /dev/null 2> same.err; [ $? -eq 1 ] || fail "contacts -o over its input should exit 1"

echo "cli_contacts: $failures failures"
[ "$failures" -eq 0 ]
