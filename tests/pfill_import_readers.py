# The Blender add-on's file readers (blender/pfill_import.py) outside Blender,
# with Debian's python3 and numpy, so they are tested where Blender is not:
#   python3 tests/pfill_import_readers.py REPO REFERENCE.csv FILE...
# Each FILE is the same fill as REFERENCE.csv (pfill's CSV, read here with
# the csv module): the same ids, radii, colours (8-bit sRGB within one step)
# and positions (a .glb turned Y-up to Z-up). Exit status 1 on any miss.
import csv
import sys

import numpy as np

repo, reference, files = sys.argv[1], sys.argv[2], sys.argv[3:]
sys.path.insert(0, repo + "/blender")
import pfill_import  # noqa: E402

with open(reference, newline="") as f:
    rows = sorted(csv.DictReader(f), key=lambda r: int(r["id"]))
ids = np.array([int(r["id"]) for r in rows])
positions = np.array([[float(r[a]) for a in "xyz"] for r in rows])
radii = np.array([float(r["radius"]) for r in rows])
colours = np.array([[int(r[c]) for c in "rgb"] for r in rows])
failed = 0
for path in files:
    p = pfill_import.read_particles(path)
    order = np.argsort(p["ids"])
    expected = pfill_import.y_up_to_z_up(positions) if path.endswith(".glb") else positions
    checks = {
        "ids": np.array_equal(p["ids"][order], ids),
        "radii": np.allclose(p["radii"][order], radii, rtol=1e-6, atol=0),
        "positions": np.allclose(p["positions"][order], expected, rtol=0, atol=1e-6),
        "colours": p["colours"] is not None and np.abs(np.rint(p["colours"][order] * 255) - colours).max() <= 1,
    }
    for name, ok in checks.items():
        if not ok:
            print(f"FAILED: {path}: {name} differ from {reference}")
            failed += 1
    print(f"{path}: {len(p['ids'])} particles, " + ", ".join(checks))
try:
    pfill_import.read_particles(reference + ".xyz")
    print("FAILED: an unknown extension was read")
    failed += 1
except pfill_import.PfillFileError as e:
    print(f"refused as expected: {e}")
print("pfill_import readers: " + ("all passed" if not failed else f"{failed} FAILED"))
sys.exit(1 if failed else 0)
