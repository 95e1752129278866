# Checks the pfill add-on (blender/pfill_import.py) in Blender, headless:
#   blender -b --factory-startup --python-exit-code 1 -P scripts/blender_pfill_import_check.py -- \
#       REPO REFERENCE.csv FILE...
# REFERENCE.csv is the same fill written by pfill as CSV (read here with
# Python's csv module, not by the add-on). For every FILE (.ply, .glb, .csv):
# import_particles gives one object whose evaluated depsgraph holds one
# instance per particle, each scaled to the file's radius; the `radius`
# attribute equals the file's radii; the `colour` attribute holds the file's
# colours (scene linear, so back to sRGB 8-bit within one step); the ids and
# positions match (a .glb turned from Y-up to Z-up). Exit status 1 on any miss.
import csv
import sys

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:]
repo, reference_path, files = args[0], args[1], args[2:]
sys.path.insert(0, repo + "/blender")
import pfill_import  # noqa: E402

with open(reference_path, newline="") as f:
    rows = list(csv.DictReader(f))
ref_ids = np.array([int(r["id"]) for r in rows])
order = np.argsort(ref_ids)
ref = {
    "ids": ref_ids[order],
    "positions": np.array([[float(r[a]) for a in "xyz"] for r in rows])[order],
    "radii": np.array([float(r["radius"]) for r in rows])[order],
    "colours": np.array([[int(r[c]) for c in "rgb"] for r in rows])[order] if "r" in rows[0] else None,
}
n = len(rows)
failures = []


def check(ok, what):
    print(("  ok: " if ok else "  FAILED: ") + what)
    if not ok:
        failures.append(what)


def attribute(mesh, name, field, width):
    data = mesh.attributes[name].data
    integer = mesh.attributes[name].data_type == "INT"
    buffer = np.zeros(len(data) * width, dtype=np.int32 if integer else np.float32)
    data.foreach_get(field, buffer)
    values = buffer.astype(np.float64)
    return values.reshape(len(data), width) if width > 1 else values


for path in files:
    print(path)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = pfill_import.import_particles(path)
    mesh = obj.data
    check(len(mesh.vertices) == n, f"{len(mesh.vertices)} points for {n} particles")
    ids = attribute(mesh, "id", "value", 1).astype(np.int64)
    by_id = np.argsort(ids)
    check(np.array_equal(ids[by_id], ref["ids"]), "the ids are the file's")

    radii = attribute(mesh, "radius", "value", 1)[by_id]
    check(np.allclose(radii, ref["radii"], rtol=1e-6, atol=0), f"radius attribute = the file's radii "
          f"(largest difference {np.max(np.abs(radii - ref['radii'])):.3g})")

    positions = np.zeros(n * 3, dtype=np.float32)
    mesh.vertices.foreach_get("co", positions)
    positions = positions.reshape(n, 3)[by_id]
    expected = pfill_import.y_up_to_z_up(ref["positions"]) if path.endswith(".glb") else ref["positions"]
    check(np.allclose(positions, expected, rtol=0, atol=1e-5 * np.abs(expected).max()),
          "positions = the file's" + (" turned Y-up to Z-up" if path.endswith(".glb") else ""))

    if ref["colours"] is not None:
        check("colour" in mesh.attributes and mesh.attributes["colour"].data_type == "FLOAT_COLOR"
              and mesh.attributes["colour"].domain == "POINT", "a FLOAT_COLOR point attribute 'colour'")
        linear = attribute(mesh, "colour", "color", 4)[by_id, :3]
        srgb8 = np.rint(pfill_import._srgb_from_linear(linear) * 255)
        check(np.max(np.abs(srgb8 - ref["colours"])) <= 1, "colour attribute = the file's colours "
              f"(largest difference {np.max(np.abs(srgb8 - ref['colours'])):.0f}/255; "
              f"{len(np.unique(ref['colours'], axis=0))} distinct colours)")

    # The evaluated object: one sphere instance per particle, scaled to its radius.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    scales = []
    for inst in depsgraph.object_instances:
        if inst.is_instance and inst.parent and inst.parent.original == obj:
            scales.append(inst.matrix_world.to_scale()[0])
    check(len(scales) == n, f"{len(scales)} sphere instances in the evaluated depsgraph for {n} particles")
    if len(scales) == n:
        check(np.allclose(np.sort(scales), np.sort(ref["radii"]), rtol=1e-5),
              "each instance's scale is a particle's radius (the sphere has radius 1)")
    nodes = obj.modifiers["pfill spheres"].node_group.nodes
    check(any(node.type == "INSTANCE_ON_POINTS" for node in nodes), "geometry nodes: Instance on Points")
    if ref["colours"] is not None:
        shader = obj.active_material.node_tree.nodes
        check(any(node.type == "ATTRIBUTE" and node.attribute_name == "colour" and node.outputs["Color"].is_linked
                  for node in shader), "the material's base colour comes from the 'colour' attribute")

# The File > Import operator (registered as an add-on would be) on the first file.
print("the operator import_scene.pfill_particles")
bpy.ops.wm.read_factory_settings(use_empty=True)
pfill_import.register()
check(bpy.ops.import_scene.pfill_particles(filepath=files[0]) == {"FINISHED"}, "the operator finished")
imported = [o for o in bpy.context.scene.objects if o.get("pfill_particles") == n]
check(len(imported) == 1 and bpy.context.view_layer.objects.active == imported[0],
      "it made one active object of all the particles")
try:
    bpy.ops.import_scene.pfill_particles(filepath=files[0] + ".missing.ply")
    check(False, "a missing file should cancel the import with an error")
except RuntimeError as e:
    check("no such file" in str(e), f"a missing file is refused: {str(e).strip()}")
pfill_import.unregister()

print("blender pfill_import: " + ("all passed" if not failures else f"{len(failures)} FAILED"))
sys.exit(1 if failures else 0)
