#!/usr/bin/env bash
# The shatter script (blender/pfill_shatter.py): a 1,000-sphere fill with
# contacts (PLY edges) becomes rigid bodies joined by one breakable
# constraint per contact, and a few frames of the rigid-body simulation run
# headless. Its contact reader is checked with Debian's python3 first; the
# Blender part exits 77 (ctest: skipped) with a message where blender is
# missing. Usage: blender_shatter.sh PFILL_BINARY REPO_DIR
set -euo pipefail
pfill="$1"
repo="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"
"$pfill" fill sphere -n 1000 -q --contacts -o fill.ply --pairs pairs.csv --report report.json >/dev/null
pairs=$(grep -m1 '"pairs":' report.json | tr -dc '0-9')
/usr/bin/python3 - "$repo/blender" fill.ply "$pairs" <<'PY'
import sys
sys.path.insert(0, sys.argv[1])
import pfill_shatter, pfill_import
edges = pfill_shatter.read_contacts(sys.argv[2])
p = pfill_import.read_particles(sys.argv[2])
assert len(edges) == int(sys.argv[3]), f"{len(edges)} edges read, the fill has {sys.argv[3]} contacts"
assert edges.min() >= 0 and edges.max() < len(p["positions"]) and (edges[:, 0] < edges[:, 1]).all()
print(f"blender_shatter: read {len(edges)} contacts of {len(p['positions'])} particles")
PY
if ! command -v blender >/dev/null; then
  echo "blender_shatter: skipped: Blender is not installed (apt-get install blender)"
  exit 77
fi
cat > check.py <<PY
import sys, bpy
sys.path.insert(0, "$repo/blender")
import pfill_shatter
spheres, bonds = pfill_shatter.build("fill.ply")
scene = bpy.context.scene
bodies = [o for o in scene.objects if o.rigid_body is not None and o.rigid_body.type == "ACTIVE"]
constraints = [o for o in scene.objects if o.rigid_body_constraint is not None]
assert len(bodies) == len(spheres), f"{len(bodies)} rigid bodies for {len(spheres)} spheres"
assert len(constraints) == $pairs, f"{len(constraints)} constraints for $pairs contacts"
assert all(c.rigid_body_constraint.use_breaking for c in constraints)
z0 = min(o.matrix_world.translation.z for o in spheres)
for f in range(1, 7):
    scene.frame_set(f)
z1 = min(o.matrix_world.translation.z for o in spheres)
assert z1 < z0, f"nothing fell: lowest sphere at {z0} then {z1}"
print(f"blender_shatter: {len(bodies)} rigid bodies, {len(constraints)} breakable constraints; 6 frames run, fell {z0 - z1:.4f}")
PY
blender -b --factory-startup --python-exit-code 1 -P check.py 2>&1 | grep -E "blender_shatter|Error|Traceback|line [0-9]"
