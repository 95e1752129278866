#!/usr/bin/env python3
"""Round trip (issue 33): `pfill check` on each particle format pfill writes
(.ply .glb .csv .vtp .data .xyzr) measures what the fill's own summary says
(count, share inside, largest overlap), for a mesh at the origin and the
same mesh 1e6, 1e9 and 1e14 away (where the fill must refuse: doubles there
are spaced by a fifth of the radius) (survey and CAD coordinates: float32 positions
once put 29% of the spheres outside). Usage: cli_roundtrip.py PFILL_BINARY"""
import json
import os
import subprocess
import sys
import tempfile

PFILL = os.path.abspath(sys.argv[1])
FORMATS = [".ply", ".glb", ".csv", ".vtp", ".data", ".xyzr"]
failures = []


def write_box(path, shift):
    """A 2 x 1 x 1 box, outward faces, moved by `shift` on every axis."""
    v = [(x, y, z) for x in (-1, 1) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
             (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    with open(path, "w") as f:
        for p in v:
            f.write("v %.17g %.17g %.17g\n" % tuple(c + shift for c in p))
        for t in faces:
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))


def main():
    work = tempfile.mkdtemp(prefix="pfill-roundtrip-")
    compared = 0
    for shift in (0.0, 1e6, 1e9, 1e14):
        mesh = os.path.join(work, f"box_{shift:g}.obj")
        write_box(mesh, shift)
        for ext in FORMATS:
            out = os.path.join(work, f"out_{shift:g}{ext}")
            fill = subprocess.run([PFILL, "fill", mesh, "-n", "150", "-q", "--json", "-o", out],
                                  capture_output=True, text=True, timeout=300)
            label = f"shift {shift:g} {ext}"
            if fill.returncode != 0:
                lines = fill.stderr.strip().splitlines()
                # Far out, a one-line refusal is an answer too (the issue allows it at 1e9).
                if shift >= 1e9 and fill.returncode == 1 and len(lines) == 1 and "origin" in lines[0]:
                    print(f"{label}: refused: {lines[0]}")
                    continue
                failures.append(f"{label}: the fill exited {fill.returncode}: {fill.stderr[-300:]}")
                continue
            summary = json.loads(fill.stdout)["metrics"]
            check = subprocess.run([PFILL, "check", out, mesh, "--json"], capture_output=True, text=True, timeout=300)
            if check.returncode != 0:
                failures.append(f"{label}: check exited {check.returncode}: {check.stderr[-300:]}")
                continue
            measured = json.loads(check.stdout)["metrics"]
            compared += 1
            print(f"{label}: fill {summary['particles']} spheres, {summary['contained_share']:.4f} inside, "
                  f"overlap {summary['max_overlap']:.5f}; check {measured['particles']}, "
                  f"{measured['contained_share']:.4f}, {measured['max_overlap']:.5f}")
            if measured["particles"] != summary["particles"]:
                failures.append(f"{label}: check counts {measured['particles']}, the summary {summary['particles']}")
            if measured["contained_share"] != summary["contained_share"]:
                failures.append(f"{label}: check finds {measured['contained_share']} inside, the summary "
                                f"{summary['contained_share']}")
            if abs(measured["max_overlap"] - summary["max_overlap"]) > 2e-4:
                failures.append(f"{label}: check finds overlaps up to {measured['max_overlap']}, the summary "
                                f"{summary['max_overlap']}")
    for f in failures:
        print("FAIL:", f)
    print(f"{compared} files compared, {len(failures)} failures")
    return 1 if failures or compared < 12 else 0


if __name__ == "__main__":
    sys.exit(main())
