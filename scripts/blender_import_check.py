# Imports pfill outputs into Blender (3.4, run headless) and checks that
# each particle became one point: blender -b -P scripts/blender_import_check.py -- COUNT FILE...
# Exit status 0 when every file imported with COUNT points, 1 otherwise.
import sys

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
expected = int(args[0])
ok = True
for path in args[1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path.endswith(".ply"):
        bpy.ops.import_mesh.ply(filepath=path)
    elif path.endswith(".glb") or path.endswith(".gltf"):
        # Debian 12's Blender 3.4 glTF importer uses numpy.bool, which Debian's
        # numpy 1.24 no longer has, on its default "NORMALS" shading path;
        # FLAT shading avoids it (points have no faces to shade anyway).
        bpy.ops.import_scene.gltf(filepath=path, import_shading="FLAT")
    else:
        print(f"{path}: not a PLY or glTF file")
        ok = False
        continue
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    points = sum(len(o.data.vertices) for o in meshes if len(o.data.polygons) == 0)
    # What survived, as values (not only names): Blender 3.4's importers keep
    # the points but lose colours and radii (see the README's Blender section).
    colours = []
    for o in meshes:
        for a in getattr(o.data, "color_attributes", []):
            colours.append(f"{a.name} ({a.domain}, {len(a.data)} values)")
    attributes = sorted({a.name for o in meshes for a in o.data.attributes if not a.name.startswith(".")})
    print(f"{path}: {len(meshes)} mesh objects, {points} points, colour attributes {colours}, "
          f"attributes {attributes}")
    if points != expected:
        print(f"{path}: expected {expected} points")
        ok = False
sys.exit(0 if ok else 1)
