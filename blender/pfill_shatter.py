# pfill fills as breakable bodies in Blender 3.4 and later: every particle of
# a fill written with contacts (`pfill fill MESH -n 1000 --contacts -o
# fill.ply`: PLY `edge` elements) becomes a rigid-body sphere, and every
# contact pair a breakable FIXED rigid-body constraint between its two
# spheres, so a filled object dropped on the ground shatters.
#
# Headless:  blender -b -P blender/pfill_shatter.py -- fill.ply [--threshold T]
#                   [--drop H] [--frames F] [--save out.blend]
# From Python (with blender/ on sys.path):
#            import pfill_shatter; spheres, bonds = pfill_shatter.build(path)
#
# The particles are read by pfill_import.read_particles (beside this file);
# the contacts here, from the PLY's `edge` element (vertex1 vertex2 in file
# order, as pfill writes them). Breaking thresholds are impulses: each
# bond breaks above `threshold` x the mean sphere mass x 1 m/s (Blender's
# units), so the default (2.0) breaks a body dropped from a metre or two.
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pfill_import  # noqa: E402

try:
    import bpy
except ImportError:  # read_contacts works outside Blender
    bpy = None


def read_contacts(path):
    """The (M, 2) int64 vertex index pairs of a PLY's `edge` element (empty when it has none)."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise pfill_import.PfillFileError(f"{path}: not a PLY file")
    body = data.index(b"\n", end) + 1
    fmt, elements = None, []
    for line in data[:body].decode("ascii", "replace").splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property" and elements:
            if w[1] == "list":
                raise pfill_import.PfillFileError(f"{path}: list properties: not a pfill particle file")
            elements[-1][2].append((w[2], pfill_import._PLY_TYPES[w[1]]))
    if fmt == "ascii":
        lines = data[body:].decode("ascii", "replace").split("\n")
        at = 0
        for name, count, props in elements:
            if name == "edge":
                names = [p for p, _ in props]
                rows = np.array([l.split() for l in lines[at:at + count]], dtype=np.float64).reshape(count, len(names))
                return rows[:, [names.index("vertex1"), names.index("vertex2")]].astype(np.int64)
            at += count
        return np.zeros((0, 2), dtype=np.int64)
    order = "<" if fmt == "binary_little_endian" else ">"
    offset = body
    for name, count, props in elements:
        dtype = np.dtype([(p, order + t) for p, t in props])
        if name == "edge":
            table = np.frombuffer(data, dtype=dtype, count=count, offset=offset)
            return np.stack([table["vertex1"], table["vertex2"]], axis=1).astype(np.int64)
        offset += count * dtype.itemsize
    return np.zeros((0, 2), dtype=np.int64)


def build(path, threshold=2.0, drop=1.0, ground=True, density=1000.0, name=None):
    """Builds the rigid bodies and bonds of a fill with contacts (PLY with
    edges); returns (spheres, bonds): the sphere objects and the constraint empties.
    drop: the body's lowest point this far above the ground plane."""
    if bpy is None:
        raise RuntimeError("build runs inside Blender; read_contacts works anywhere")
    path = os.path.abspath(path)
    p = pfill_import.read_particles(path)
    pairs = read_contacts(path)
    n = len(p["positions"])
    if len(pairs) and (pairs.min() < 0 or pairs.max() >= n):
        raise pfill_import.PfillFileError(f"{path}: an edge names a vertex past the {n} particles")
    scene = bpy.context.scene
    if scene.rigidbody_world is None:
        bpy.ops.rigidbody.world_add()
    name = name or os.path.splitext(os.path.basename(path))[0]
    coll = bpy.data.collections.new(name + " shatter")
    scene.collection.children.link(coll)

    positions = p["positions"].copy()
    lift = drop - (positions[:, 2] - p["radii"]).min()
    positions[:, 2] += lift
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=1.0)
    unit = bpy.context.active_object
    sphere_mesh = unit.data
    bpy.data.objects.remove(unit, do_unlink=True)
    spheres = []
    for i in range(n):
        o = bpy.data.objects.new(f"{name} {int(p['ids'][i])}", sphere_mesh)
        o.location = positions[i]
        o.scale = (p["radii"][i],) * 3
        coll.objects.link(o)
        spheres.append(o)
    with bpy.context.temp_override(selected_objects=spheres, selected_editable_objects=spheres,
                                   active_object=spheres[0], object=spheres[0]):
        bpy.ops.rigidbody.objects_add(type="ACTIVE")
    masses = density * 4.0 / 3.0 * np.pi * p["radii"] ** 3
    for o, m in zip(spheres, masses):
        o.rigid_body.collision_shape = "SPHERE"
        o.rigid_body.mass = float(m)
    impulse = threshold * float(masses.mean())

    # The bonds: empties in a collection that becomes (or joins) the rigid-body
    # world's constraints collection, which gives each a FIXED constraint in
    # one go (an operator call per bond crashed Blender 3.4 after ~1,200).
    bonds_coll = bpy.data.collections.new(name + " bonds")
    coll.children.link(bonds_coll)
    bonds = []
    for k, (a, b) in enumerate(pairs):
        e = bpy.data.objects.new(f"{name} bond {k}", None)
        e.location = (positions[a] + positions[b]) / 2
        e.empty_display_size = float(p["radii"][a]) * 0.5
        bonds_coll.objects.link(e)
        bonds.append(e)
    world = scene.rigidbody_world
    if world.constraints is None:
        world.constraints = bonds_coll
    else:  # another fill's bonds are there: add these to its collection
        for e in bonds:
            world.constraints.objects.link(e)
        world.constraints = world.constraints
    for e, (a, b) in zip(bonds, pairs):
        c = e.rigid_body_constraint
        c.type = "FIXED"
        c.object1, c.object2 = spheres[a], spheres[b]
        c.use_breaking = True
        c.breaking_threshold = impulse
        c.disable_collisions = True

    if ground:
        size = float(np.ptp(positions, axis=0).max()) * 4 + 1
        bpy.ops.mesh.primitive_plane_add(size=size, location=(float(positions[:, 0].mean()), float(positions[:, 1].mean()), 0))
        plane = bpy.context.active_object
        plane.name = name + " ground"
        with bpy.context.temp_override(selected_objects=[plane], selected_editable_objects=[plane],
                                       active_object=plane, object=plane):
            bpy.ops.rigidbody.objects_add(type="PASSIVE")
    return spheres, bonds


def _main(argv):
    import argparse
    ap = argparse.ArgumentParser(prog="blender -b -P pfill_shatter.py --")
    ap.add_argument("path", help="a fill written with --contacts as .ply")
    ap.add_argument("--threshold", type=float, default=2.0, help="bond breaking impulse, in mean sphere masses x 1 m/s")
    ap.add_argument("--drop", type=float, default=1.0, help="height of the body's lowest point above the ground")
    ap.add_argument("--frames", type=int, default=0, help="simulate this many frames")
    ap.add_argument("--save", help="save the scene to this .blend")
    a = ap.parse_args(argv)
    spheres, bonds = build(a.path, threshold=a.threshold, drop=a.drop)
    print(f"pfill_shatter: {len(spheres)} rigid bodies, {len(bonds)} breakable constraints")
    scene = bpy.context.scene
    if a.frames > 0:
        scene.frame_end = max(scene.frame_end, a.frames + 1)
        scene.rigidbody_world.point_cache.frame_end = scene.frame_end
        for f in range(scene.frame_start, scene.frame_start + a.frames + 1):
            scene.frame_set(f)
        print(f"pfill_shatter: simulated {a.frames} frames")
    if a.save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(a.save))


if __name__ == "__main__" and bpy is not None:
    _main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
