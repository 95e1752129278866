#!/usr/bin/env bash
# A fill's contacts as LAMMPS bonds: `pfill fill --contacts -o fill.data`
# (atom_style hybrid sphere bond, one bond per contact pair) is read by
# LAMMPS (Debian's `lmp`) with read_data, every bond arrives, and 100 steps
# of a bonded granular run (bond_style harmonic, pair gran/hooke, fix
# nve/sphere) run without error. Exits 77 (ctest: skipped) with a message
# where lmp is not installed. Usage: lammps_bonds.sh PFILL [LMP]
set -euo pipefail
pfill="$1"
lmp="${2:-}"
if [[ -z "$lmp" ]]; then lmp="$(command -v lmp || command -v lmp_serial || true)"; fi
if [[ -z "$lmp" || ! -x "$lmp" ]]; then
  echo "lammps_bonds: skipped: LAMMPS (lmp) is not installed (apt-get install lammps)"
  exit 77
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
"$pfill" fill cube -n 150 -q --contacts --pairs pairs.csv -o fill.data --report report.json >/dev/null
pairs=$(/usr/bin/python3 -c 'import json; print(json.load(open("report.json"))["contacts"]["pairs"])')
diameter=$(awk '/^Atoms/ {getline; getline; print $6; exit}' fill.data)
cat > in.bonds <<LAMMPS
units lj
atom_style hybrid sphere bond
boundary f f f
comm_modify vel yes
read_data fill.data
variable nb equal bonds
print "bonds read: \${nb}"
bond_style harmonic
bond_coeff 1 1000 ${diameter}
special_bonds lj 0 1 1
pair_style gran/hooke 2000 NULL 50 NULL 0.5 0
pair_coeff * *
fix 1 all nve/sphere
velocity all set 0 0 -0.5
timestep 0.0005
thermo 50
run 100
LAMMPS
"$lmp" -in in.bonds -log log.lammps -screen screen.txt || { tail -20 screen.txt; exit 1; }
read=$(awk '/^bonds read:/ {print $3}' screen.txt)
rows=$(($(wc -l < pairs.csv) - 1))
wall=$(awk -F, 'NR > 1 && $2 == 0' pairs.csv | wc -l)
if [[ "$read" != "$pairs" || $((rows - wall)) != "$pairs" ]]; then
  echo "lammps_bonds: the fill has $pairs contact pairs, pairs.csv $((rows - wall)), LAMMPS read $read bonds"
  exit 1
fi
grep -q '^Loop time' screen.txt || { echo "lammps_bonds: the run did not finish"; tail -20 screen.txt; exit 1; }
echo "lammps_bonds: LAMMPS read all $pairs bonds of the fill and ran 100 steps of bond_style harmonic"
