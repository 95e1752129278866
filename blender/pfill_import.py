# pfill particles for Blender 3.4 and later: File > Import > pfill particles
# (.ply, .glb, .csv) makes one mesh object whose vertices are the particle
# centres, with point attributes `radius` (float), `colour` (float colour,
# scene linear) and `id` (int), and a geometry-nodes modifier that puts an
# ico sphere of the particle's radius on every point, coloured by a material
# that reads `colour`.
#
# From Python:   import pfill_import; obj = pfill_import.import_particles(path)
#
# The files are parsed here, with numpy, not by Blender's importers: Blender
# 3.4's PLY importer drops point colours and radii, and its glTF importer
# loses the point colours (a `Col` attribute with no values), drops _RADIUS
# and does not know EXT_mesh_gpu_instancing.
#
# Axes: glTF is Y-up, Blender Z-up. A .glb is converted as Blender's glTF
# importer converts it, (x, y, z) -> (x, -z, y), so the particles line up with
# their mesh imported by File > Import > glTF. PLY and CSV hold the mesh's own
# coordinates and are kept as they are (as Blender's PLY and STL importers
# keep theirs); pass y_up=True (the "Y up" box in the import dialog) for a
# fill of a Y-up mesh (glTF, OBJ) to line up with it imported by Blender.
import json
import os
import struct

import numpy as np

try:
    import bpy
    from bpy.props import BoolProperty, IntProperty, StringProperty
    from bpy_extras.io_utils import ImportHelper
except ImportError:  # the readers also work outside Blender (tests, scripts)
    bpy = None

bl_info = {
    "name": "pfill particles",
    "author": "pfill",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "File > Import > pfill particles (.ply, .glb, .csv)",
    "description": "Import pfill's particle files as coloured spheres of the right radius",
    "category": "Import-Export",
}


class PfillFileError(Exception):
    """A particle file this add-on cannot read; the message names the file and why."""


# ---------------------------------------------------------------- readers
# Each returns a dict of numpy arrays: positions (N, 3) float64, radii (N),
# colours (N, 3) float sRGB 0..1 or None, velocities (N, 3) or None, ids (N)
# int64 (1..N when the file has none).

_PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def _first(names, available):
    for name in names:
        if name in available:
            return name
    return None


def _particles(path, columns, radius, colour, velocity, id_, colour_max):
    """Assembles the result dict from a name -> column array mapping."""
    n = len(columns["x"])
    out = {"positions": np.stack([columns[a] for a in ("x", "y", "z")], axis=1).astype(np.float64)}
    if radius is None:
        raise PfillFileError(f"{path}: no radius (or pscale) per particle; pfill's files have one")
    out["radii"] = np.asarray(columns[radius], dtype=np.float64)
    out["colours"] = None
    if colour is not None:
        out["colours"] = np.clip(np.stack([columns[c] for c in colour], axis=1).astype(np.float64) / colour_max, 0, 1)
    out["velocities"] = None
    if velocity is not None:
        out["velocities"] = np.stack([columns[v] for v in velocity], axis=1).astype(np.float64)
    out["ids"] = np.asarray(columns[id_], dtype=np.int64) if id_ else np.arange(1, n + 1, dtype=np.int64)
    return out


def _named_columns(path, names, get, colour_max_of):
    """Finds pfill's and Houdini's attribute names among `names`."""
    radius = _first(("radius", "pscale"), names)
    colour = None
    for triple in (("red", "green", "blue"), ("r", "g", "b"), ("Cd.r", "Cd.g", "Cd.b"), ("cd.r", "cd.g", "cd.b")):
        if all(c in names for c in triple):
            colour = triple
            break
    velocity = None
    for triple in (("vx", "vy", "vz"), ("v.x", "v.y", "v.z")):
        if all(v in names for v in triple):
            velocity = triple
            break
    for axis in ("x", "y", "z"):
        if axis not in names:
            raise PfillFileError(f"{path}: no '{axis}' column/property")
    id_ = _first(("id",), names)
    wanted = ["x", "y", "z"] + [c for c in (radius, id_) if c] + list(colour or ()) + list(velocity or ())
    columns = {name: get(name) for name in wanted}
    return _particles(path, columns, radius, colour, velocity, id_, colour_max_of(colour))


def read_ply(path):
    """PLY (binary little/big endian or ascii) whose first element is `vertex`."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header")
    if not data.startswith(b"ply") or end < 0:
        raise PfillFileError(f"{path}: not a PLY file (no 'ply' ... 'end_header' header)")
    body = data.index(b"\n", end) + 1
    header = data[:body].decode("ascii", "replace").splitlines()
    fmt, elements = None, []
    for line in header:
        words = line.split()
        if not words:
            continue
        if words[0] == "format":
            fmt = words[1]
        elif words[0] == "element":
            elements.append((words[1], int(words[2]), []))
        elif words[0] == "property":
            if not elements:
                raise PfillFileError(f"{path}: a property before any element")
            if words[1] == "list":
                elements[-1][2].append((words[4], None))
            else:
                if words[1] not in _PLY_TYPES:
                    raise PfillFileError(f"{path}: unknown PLY type '{words[1]}'")
                elements[-1][2].append((words[2], _PLY_TYPES[words[1]]))
    if not elements or elements[0][0] != "vertex":
        raise PfillFileError(f"{path}: the first element is not 'vertex'")
    _, n, properties = elements[0]
    if any(t is None for _, t in properties):
        raise PfillFileError(f"{path}: list properties on vertices are not particles")
    names = [p for p, _ in properties]
    if fmt == "ascii":
        text = data[body:].decode("ascii", "replace").split("\n")[:n]
        table = np.array([line.split()[: len(names)] for line in text], dtype=np.float64).reshape(n, len(names))
        get = lambda name: table[:, names.index(name)]  # noqa: E731
        types = {p: t for p, t in properties}
    elif fmt in ("binary_little_endian", "binary_big_endian"):
        order = "<" if fmt == "binary_little_endian" else ">"
        dtype = np.dtype([(p, order + t) for p, t in properties])
        if len(data) - body < n * dtype.itemsize:
            raise PfillFileError(f"{path}: truncated: {n} vertices need {n * dtype.itemsize} bytes")
        table = np.frombuffer(data, dtype=dtype, count=n, offset=body)
        get = lambda name: table[name]  # noqa: E731
        types = {p: t for p, t in properties}
    else:
        raise PfillFileError(f"{path}: unknown PLY format '{fmt}'")
    # uchar colours are 0..255, float ones 0..1 (Houdini's Cd).
    colour_max = lambda colour: 255.0 if colour and types[colour[0]] == "u1" else 1.0  # noqa: E731
    return _named_columns(path, set(names), get, colour_max)


def read_csv(path):
    """pfill's CSV: a header naming the columns, comma separated."""
    with open(path, "r", encoding="utf-8") as f:
        header = f.readline().strip()
    names = [c.strip().strip('"') for c in header.split(",")]
    lowered = [c.lower() for c in names]
    try:
        table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, dtype=np.float64)
    except ValueError as e:
        raise PfillFileError(f"{path}: {e}") from None
    if table.size == 0:
        table = np.zeros((0, len(names)))
    get = lambda name: table[:, lowered.index(name)]  # noqa: E731
    colour_max = lambda colour: 1.0 if colour and colour[0].startswith("cd.") else 255.0  # noqa: E731
    return _named_columns(path, set(lowered), get, colour_max)


_GLTF_COMPONENTS = {5120: "i1", 5121: "u1", 5122: "i2", 5123: "u2", 5125: "u4", 5126: "f4"}
_GLTF_WIDTH = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}


def _srgb_from_linear(c):
    c = np.clip(c, 0, 1)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * np.power(c, 1 / 2.4) - 0.055)


def _linear_from_srgb(c):
    c = np.clip(c, 0, 1)
    return np.where(c <= 0.04045, c / 12.92, np.power((c + 0.055) / 1.055, 2.4))


def read_glb(path):
    """pfill's GLB: the POINTS primitive of node "particles" (POSITION,
    COLOR_0 linear, _RADIUS, _ID, _VELOCITY), converted Y-up -> Z-up."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 20 or data[:4] != b"glTF":
        raise PfillFileError(f"{path}: not a binary glTF (.glb) file")
    offset, gltf, binary = 12, None, b""
    while offset + 8 <= len(data):
        length, kind = struct.unpack_from("<II", data, offset)
        chunk = data[offset + 8: offset + 8 + length]
        if kind == 0x4E4F534A:
            gltf = json.loads(chunk.decode("utf-8"))
        elif kind == 0x004E4942:
            binary = chunk
        offset += 8 + length
    if gltf is None:
        raise PfillFileError(f"{path}: no JSON chunk")

    def accessor(index):
        a = gltf["accessors"][index]
        view = gltf["bufferViews"][a["bufferView"]]
        width = _GLTF_WIDTH[a["type"]]
        dtype = np.dtype("<" + _GLTF_COMPONENTS[a["componentType"]])
        start = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        count, row = a["count"], dtype.itemsize * width
        stride = view.get("byteStride", 0) or row
        if start + stride * max(count - 1, 0) + row * (count > 0) > len(binary):
            raise PfillFileError(f"{path}: accessor {index} runs past the binary chunk")
        if stride == row:
            values = np.frombuffer(binary, dtype=dtype, count=count * width, offset=start).reshape(count, width)
        else:  # interleaved: row by row
            values = np.array([np.frombuffer(binary, dtype=dtype, count=width, offset=start + i * stride)
                               for i in range(count)]).reshape(count, width)
        values = np.array(values, dtype=np.float64)
        if a.get("normalized"):
            values /= float(np.iinfo(dtype).max)
        return values

    primitive = None
    for mesh in gltf.get("meshes", []):
        for p in mesh.get("primitives", []):
            if p.get("mode", 4) == 0 and "POSITION" in p["attributes"]:
                primitive = primitive or p
    if primitive is None:
        if not gltf.get("meshes"):  # pfill's GLB of no particles: a scene with no nodes
            empty = np.zeros((0, 3))
            return {"positions": empty, "radii": np.zeros(0), "colours": None, "velocities": None,
                    "ids": np.zeros(0, np.int64)}
        raise PfillFileError(f"{path}: no POINTS primitive (is it a pfill particle file?)")
    attributes = primitive["attributes"]
    if "_RADIUS" not in attributes:
        raise PfillFileError(f"{path}: the points have no _RADIUS attribute (is it a pfill particle file?)")
    y_up = accessor(attributes["POSITION"])
    # Far from the origin pfill stores the points about their centre, the node's translation.
    mesh_index = next(i for i, m in enumerate(gltf["meshes"]) if any(q is primitive for q in m.get("primitives", [])))
    for node in gltf.get("nodes", []):
        if node.get("mesh") == mesh_index and "translation" in node:
            y_up = y_up + np.asarray(node["translation"], dtype=np.float64)
            break
    out = {"positions": y_up, "radii": accessor(attributes["_RADIUS"])[:, 0], "colours": None, "velocities": None}
    if "COLOR_0" in attributes:
        out["colours"] = _srgb_from_linear(accessor(attributes["COLOR_0"])[:, :3])
    if "_VELOCITY" in attributes:
        out["velocities"] = accessor(attributes["_VELOCITY"])
    n = len(y_up)
    out["ids"] = (np.rint(accessor(attributes["_ID"])[:, 0]).astype(np.int64) if "_ID" in attributes
                  else np.arange(1, n + 1, dtype=np.int64))
    for key in ("positions", "velocities"):
        if out[key] is not None:
            out[key] = y_up_to_z_up(out[key])
    return out


def y_up_to_z_up(v):
    """glTF's Y-up to Blender's Z-up, as Blender's glTF importer: (x, y, z) -> (x, -z, y)."""
    v = np.asarray(v, dtype=np.float64)
    return np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1)


def read_particles(path):
    """The particles of a .ply, .glb or .csv file written by pfill, as numpy arrays
    (positions in Blender's frame: see the axes note at the top)."""
    extension = os.path.splitext(path)[1].lower()
    readers = {".ply": read_ply, ".csv": read_csv, ".glb": read_glb}
    if extension not in readers:
        raise PfillFileError(f"{path}: pfill_import reads .ply, .glb and .csv particle files")
    if not os.path.isfile(path):
        raise PfillFileError(f"{path}: no such file")
    p = readers[extension](path)
    n = len(p["positions"])
    if len(p["radii"]) != n or not np.all(np.isfinite(p["positions"])) or np.any(~(p["radii"] > 0)):
        raise PfillFileError(f"{path}: positions and radii must be finite, radii > 0")
    return p


# ---------------------------------------------------------------- Blender side

def _add_socket(group, in_out, socket_type, name):
    """A group input or output: Blender 4.0 moved them to group.interface."""
    if hasattr(group, "interface"):
        return group.interface.new_socket(name, in_out=in_out, socket_type=socket_type)
    return (group.inputs if in_out == "INPUT" else group.outputs).new(socket_type, name)


def _sphere_node_group(subdivisions):
    """Geometry nodes: an ico sphere on each vertex, scaled by `radius`, with the material.
    Instance on Points takes the mesh's vertices directly (Mesh to Points would
    overwrite the `radius` attribute with its own Radius input)."""
    name = f"pfill spheres (subdivisions {subdivisions})"
    group = bpy.data.node_groups.get(name)
    if group is not None:
        return group
    group = bpy.data.node_groups.new(name, "GeometryNodeTree")
    _add_socket(group, "INPUT", "NodeSocketGeometry", "Geometry")
    _add_socket(group, "INPUT", "NodeSocketMaterial", "Material")
    _add_socket(group, "OUTPUT", "NodeSocketGeometry", "Geometry")
    nodes, links = group.nodes, group.links
    group_in = nodes.new("NodeGroupInput")
    group_out = nodes.new("NodeGroupOutput")
    sphere = nodes.new("GeometryNodeMeshIcoSphere")
    sphere.inputs["Radius"].default_value = 1.0
    sphere.inputs["Subdivisions"].default_value = subdivisions
    smooth = nodes.new("GeometryNodeSetShadeSmooth")
    radius = nodes.new("GeometryNodeInputNamedAttribute")
    radius.data_type = "FLOAT"
    radius.inputs["Name"].default_value = "radius"
    instance = nodes.new("GeometryNodeInstanceOnPoints")
    material = nodes.new("GeometryNodeSetMaterial")
    links.new(group_in.outputs["Geometry"], instance.inputs["Points"])
    links.new(sphere.outputs["Mesh"], smooth.inputs["Geometry"])
    links.new(smooth.outputs["Geometry"], material.inputs["Geometry"])
    links.new(group_in.outputs["Material"], material.inputs["Material"])
    links.new(material.outputs["Geometry"], instance.inputs["Instance"])
    # Named Attribute has one "Attribute" output per data type; only the FLOAT one is enabled.
    links.new(next(o for o in radius.outputs if o.enabled and o.type == "VALUE"), instance.inputs["Scale"])
    links.new(instance.outputs["Instances"], group_out.inputs["Geometry"])
    for k, node in enumerate((group_in, instance, group_out)):
        node.location = (250 * k, 0)
    for k, node in enumerate((sphere, smooth, material, radius)):
        node.location = (250 + 200 * k, -300)
    return group


def _colour_material(has_colours):
    """Principled BSDF whose base colour is the `colour` attribute of each
    instance's point (read through the instancer), or a light grey."""
    name = "pfill particle" if has_colours else "pfill particle (no colours)"
    material = bpy.data.materials.get(name)
    if material is not None:
        return material
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    bsdf = nodes.get("Principled BSDF")
    bsdf.inputs["Roughness"].default_value = 0.5
    if has_colours:
        attribute = nodes.new("ShaderNodeAttribute")
        attribute.attribute_type = "INSTANCER"  # the instance's own attribute, from its point
        attribute.attribute_name = "colour"
        attribute.location = (-300, 200)
        material.node_tree.links.new(attribute.outputs["Color"], bsdf.inputs["Base Color"])
    else:
        bsdf.inputs["Base Color"].default_value = (0.7, 0.7, 0.7, 1.0)
    material.diffuse_color = (0.7, 0.7, 0.7, 1.0)
    return material


def import_particles(path, name=None, subdivisions=2, y_up=False, collection=None):
    """Imports a pfill particle file (.ply, .glb, .csv) and returns the new object:
    a mesh of one vertex per particle with point attributes `radius`, `colour`
    (FLOAT_COLOR, scene linear; absent when the file has none), `id` and, when the
    file has them, `velocity`, and a geometry-nodes modifier "pfill spheres" that
    shows an ico sphere of that radius and colour on every point.
    y_up: the PLY/CSV holds a Y-up mesh's coordinates (see the note at the top)."""
    if bpy is None:
        raise RuntimeError("import_particles runs inside Blender; read_particles works anywhere")
    path = os.path.abspath(bpy.path.abspath(path))
    p = read_particles(path)
    if y_up and not path.lower().endswith(".glb"):
        p["positions"] = y_up_to_z_up(p["positions"])
        if p["velocities"] is not None:
            p["velocities"] = y_up_to_z_up(p["velocities"])
    n = len(p["positions"])
    name = name or os.path.splitext(os.path.basename(path))[0]
    mesh = bpy.data.meshes.new(name)
    mesh.vertices.add(n)
    mesh.vertices.foreach_set("co", p["positions"].astype(np.float32).ravel())
    mesh.attributes.new("radius", "FLOAT", "POINT").data.foreach_set("value", p["radii"].astype(np.float32))
    ids = np.clip(p["ids"], -2**31, 2**31 - 1).astype(np.int32)
    mesh.attributes.new("id", "INT", "POINT").data.foreach_set("value", ids)
    if p["colours"] is not None:
        rgba = np.ones((n, 4), dtype=np.float32)
        rgba[:, :3] = _linear_from_srgb(p["colours"])
        mesh.attributes.new("colour", "FLOAT_COLOR", "POINT").data.foreach_set("color", rgba.ravel())
    if p["velocities"] is not None:
        mesh.attributes.new("velocity", "FLOAT_VECTOR", "POINT").data.foreach_set(
            "vector", p["velocities"].astype(np.float32).ravel())
    mesh.update()
    obj = bpy.data.objects.new(name, mesh)
    (collection or bpy.context.scene.collection).objects.link(obj)
    modifier = obj.modifiers.new("pfill spheres", "NODES")
    modifier.node_group = _sphere_node_group(subdivisions)
    material = _colour_material(p["colours"] is not None)
    # The group's Material input: the modifier's property named by the socket's identifier.
    group = modifier.node_group
    socket = group.interface.items_tree["Material"] if hasattr(group, "interface") else group.inputs["Material"]
    modifier[socket.identifier] = material
    obj.data.materials.append(material)
    obj["pfill_source"] = path
    obj["pfill_particles"] = n
    return obj


if bpy is not None:

    class IMPORT_OT_pfill_particles(bpy.types.Operator, ImportHelper):
        """Import a pfill particle file (.ply, .glb, .csv) as spheres of the file's radii and colours"""
        bl_idname = "import_scene.pfill_particles"
        bl_label = "Import pfill particles"
        bl_options = {"REGISTER", "UNDO"}

        filter_glob: StringProperty(default="*.ply;*.glb;*.csv", options={"HIDDEN"})
        subdivisions: IntProperty(name="Sphere subdivisions", default=2, min=1, max=5,
                                  description="Ico sphere level of each particle (2: 80 triangles)")
        y_up: BoolProperty(name="Y up (PLY, CSV)", default=False,
                           description="The file holds a Y-up mesh's coordinates (a fill of a glTF or OBJ): "
                                       "turn them to Blender's Z up, as its glTF and OBJ importers do")

        def execute(self, context):
            try:
                obj = import_particles(self.filepath, subdivisions=self.subdivisions, y_up=self.y_up)
            except (PfillFileError, OSError, ValueError) as e:
                self.report({"ERROR"}, str(e))
                return {"CANCELLED"}
            for other in context.selected_objects:
                other.select_set(False)
            obj.select_set(True)
            context.view_layer.objects.active = obj
            self.report({"INFO"}, f"pfill: {obj['pfill_particles']} particles from {os.path.basename(self.filepath)}")
            return {"FINISHED"}

    def _menu(self, context):
        self.layout.operator(IMPORT_OT_pfill_particles.bl_idname, text="pfill particles (.ply, .glb, .csv)")

    def register():
        bpy.utils.register_class(IMPORT_OT_pfill_particles)
        bpy.types.TOPBAR_MT_file_import.append(_menu)

    def unregister():
        bpy.types.TOPBAR_MT_file_import.remove(_menu)
        bpy.utils.unregister_class(IMPORT_OT_pfill_particles)
