#!/usr/bin/env bash
# A real client: LAMMPS (Debian's `lmp`) reads a fill written as a LAMMPS
# data file (-o fill.data, atom_style sphere) with read_data, and every
# particle arrives with its id, diameter, position and velocity; the fill
# is of unequal spheres (--radii, issue 29), so every diameter is its own. Registered
# with ctest only where lmp is installed. Usage: lammps_read_data.sh PFILL LMP
set -euo pipefail
pfill="$1"
lmp="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
"$pfill" fill cube -n 150 --radii discrete:1:0.5,2:0.5 -q --velocities --density 2.5 -o fill.data --report report.json >/dev/null
cat > in.check <<'LAMMPS'
units lj
atom_style sphere
boundary f f f
read_data fill.data
variable n equal count(all)
print "atoms read: ${n}"
write_dump all custom dump.txt id diameter mass x y z vx vy vz modify sort id format float %.17g
LAMMPS
"$lmp" -in in.check -log none -screen none
/usr/bin/python3 - <<'PY'
import json, math
count = json.load(open("report.json"))["metrics"]["particles"]
lines = open("fill.data").read().split("\n")
atoms_at = lines.index("Atoms # sphere") + 2
written = {}
for line in lines[atoms_at:atoms_at + count]:
    id_, type_, diameter, density, x, y, z = line.split()
    written[int(id_)] = (float(diameter), float(density), float(x), float(y), float(z))
vel_at = lines.index("Velocities") + 2
velocity = {int(l.split()[0]): tuple(map(float, l.split()[1:4])) for l in lines[vel_at:vel_at + count]}
dump = open("dump.txt").read().split("\n")
rows = [l.split() for l in dump[dump.index("ITEM: ATOMS id diameter mass x y z vx vy vz") + 1:] if l]
assert len(written) == count, f"the data file holds {len(written)} atoms, the fill {count}"
assert len(rows) == count, f"LAMMPS read {len(rows)} atoms of {count}"
for r in rows:
    id_, d, m, x, y, z, vx, vy, vz = int(r[0]), *map(float, r[1:])
    wd, rho, wx, wy, wz = written[id_]
    assert d == wd, f"atom {id_}: diameter {d}, written {wd}"
    assert math.isclose(m, rho * math.pi / 6 * d ** 3, rel_tol=1e-12), f"atom {id_}: mass {m}"
    assert (x, y, z) == (wx, wy, wz), f"atom {id_}: position {(x, y, z)}, written {(wx, wy, wz)}"
    assert (vx, vy, vz) == velocity[id_], f"atom {id_}: velocity"
sizes = sorted({float(r[1]) for r in rows})
assert len(sizes) == 2 and math.isclose(sizes[1], 2 * sizes[0], rel_tol=1e-6), f"diameters {sizes[:5]}: expected two, 1:2"
print(f"lammps read_data: all {count} atoms read with their diameters ({sizes[0]:.4g} and {sizes[1]:.4g}), positions and velocities")
PY
