#!/usr/bin/env python3
"""Fills Spot (or any mesh) with about 500 spheres and writes them as
whitespace `x y z r` text, with a progress line while it runs.

    PYTHONPATH=build/python /usr/bin/python3 python/examples/fill_spot.py [MESH] [COUNT] [OUT]

Ctrl-C stops the fill (KeyboardInterrupt) and writes nothing.
"""
import sys

import numpy as np

import pfill


def show(p):
    left = f", ~{p['remaining']:.0f}s left" if p["remaining"] is not None else ""
    print(f"\r{p['phase']:8} {p['particles']:6} particles (~{p['target']} when full){left}   ",
          end="", file=sys.stderr, flush=True)


def main():
    mesh = sys.argv[1] if len(sys.argv) > 1 else "../shared/meshes/spot.obj"
    count = int(sys.argv[2]) if len(sys.argv) > 2 else 500
    out = sys.argv[3] if len(sys.argv) > 3 else "spot_particles.xyzr"
    try:
        r = pfill.fill(mesh, count=count, seed=1, progress=show)
    except pfill.Error as e:  # one line naming the problem, as the command line prints it
        sys.exit(f"\nfill_spot: {e}")
    except KeyboardInterrupt:  # Ctrl-C: the fill stopped at its next sync
        print("\nfill_spot: cancelled; nothing written", file=sys.stderr)
        sys.exit(130)
    print(file=sys.stderr)
    np.savetxt(out, np.column_stack([r.positions, r.radii]), fmt="%.9g")
    m = r.metrics
    print(f"{len(r)} spheres of radius {r.radius:.4g} -> {out}")
    print(f"packing fraction {m['packing_fraction']:.4f}, {100 * m['contained_share']:.2f}% inside, "
          f"largest overlap {100 * m['max_overlap']:.2f}% of r")


if __name__ == "__main__":
    main()
