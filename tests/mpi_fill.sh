#!/usr/bin/env bash
# A small fill on the LAMMPS engine under mpirun -np NP (ctest: mpiNP.fill_lammps):
# every sphere inside, overlaps within the 0.1% bound, the count near what the
# OpenCL engine gives (a sphere at -n 300: about 300), one output file
# written by rank 0; and a bad option refused in one line before LAMMPS
# starts on any rank.
# Usage: mpi_fill.sh PFILL MPIRUN NP
set -euo pipefail
pfill=$1 mpirun=$2 np=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
# Ranks that wait yield the core (a shared or oversubscribed machine: busy-polling ranks starve each other)
export OMPI_MCA_mpi_yield_when_idle=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
run() { "$mpirun" --oversubscribe -np "$np" "$@"; }

run "$pfill" fill --builtin sphere -n 300 --seed 1 --engine lammps -q -o "$tmp/out.csv" --report "$tmp/r.json" \
  > "$tmp/stdout" 2> "$tmp/stderr" || { cat "$tmp/stderr"; exit 1; }
python3 - "$tmp/r.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
m = r["metrics"]
print("particles", m["particles"], "packing", round(m["packing_fraction"], 4), "largest overlap", m["max_overlap"],
      "contained", m["contained_share"], "device", r["device"])
assert m["contained_share"] == 1.0, "a sphere pokes out"
assert m["max_overlap"] <= 0.001 + 1e-9, "an overlap over the bound"
assert 255 <= m["particles"] <= 345, "count far from the OpenCL engine's"
assert all(p["pass"] != "finish" or p["steps"] > 0 for p in r["passes"]), "no finish"
assert any(p["pass"] == "finish" for p in r["passes"]), "the finish was left out"
PY
lines=$(($(wc -l < "$tmp/out.csv") - 1))
count=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["metrics"]["particles"])' "$tmp/r.json")
[ "$lines" -eq "$count" ] || { echo "out.csv has $lines rows, the report says $count"; exit 1; }
# The summary once, from rank 0 only.
[ "$(grep -c 'packing' "$tmp/stdout" || true)" -le 1 ] || { echo "more than one rank printed"; cat "$tmp/stdout"; exit 1; }

# A bad option: one line, exit 1, no LAMMPS started.
if run "$pfill" fill --builtin sphere -n 300 --engine lammps --time-step 5 -o "$tmp/bad.csv" > /dev/null 2> "$tmp/err"; then
  echo "a bad --time-step was accepted"; exit 1
fi
grep -q "time-step must be" "$tmp/err" || { echo "no one-line error:"; cat "$tmp/err"; exit 1; }
[ ! -e "$tmp/bad.csv" ] || { echo "wrote an output after an error"; exit 1; }
echo "ok: -np $np"
