#!/usr/bin/env bash
# examples/lammps/bonded_impact.in: a fill with contacts as bonds falls onto
# a wall in LAMMPS and some bonds break (fix bond/break). Exits 77 (ctest:
# skipped) with a message where lmp is missing. Usage: lammps_impact.sh PFILL REPO [LMP]
set -euo pipefail
pfill="$1"
repo="$2"
lmp="${3:-}"
if [[ -z "$lmp" ]]; then lmp="$(command -v lmp || command -v lmp_serial || true)"; fi
if [[ -z "$lmp" || ! -x "$lmp" ]]; then
  echo "lammps_impact: skipped: LAMMPS (lmp) is not installed (apt-get install lammps)"
  exit 77
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
"$pfill" fill sphere -n 600 -q --contacts -o fill.data >/dev/null
"$lmp" -in "$repo/examples/lammps/bonded_impact.in" -var steps 1000 -log log.txt -screen none ||
  { tail -20 log.txt; exit 1; }
# The thermo rows: step time atoms bonds broken ke; the first and the last.
read -r first_bonds < <(awk '/^ *Step Time Atoms Bonds/ {getline; print $4; exit}' log.txt)
read -r last_bonds broken < <(awk '/^ *Step Time Atoms Bonds/ {on = 1; next} on && /^Loop time/ {print b, k; exit} on && NF == 6 {b = $4; k = $5}' log.txt)
if [[ -z "$broken" || "$broken" -le 0 || "$last_bonds" -ge "$first_bonds" ]]; then
  echo "lammps_impact: no bond broke ($first_bonds bonds, then $last_bonds; broken: $broken)"
  exit 1
fi
echo "lammps_impact: $broken of $first_bonds bonds broke in 1,000 steps of the impact"
