# Renders a pfill particle file through the add-on, to look at the balls:
#   blender -b --factory-startup -P scripts/blender_render_particles.py -- REPO PARTICLES OUT.png [SAMPLES]
# Cycles on the CPU, a few samples; camera framed on the particles from the
# front-right, above; a sun and a soft world light.
import math
import sys

import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
repo, particles, out = args[0], args[1], args[2]
samples = int(args[3]) if len(args) > 3 else 16
sys.path.insert(0, repo + "/blender")
import pfill_import  # noqa: E402

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
obj = pfill_import.import_particles(particles)

corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
lo = Vector([min(c[k] for c in corners) for k in range(3)])
hi = Vector([max(c[k] for c in corners) for k in range(3)])
centre, size = (lo + hi) / 2, (hi - lo).length

camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
direction = Vector((1.2, 1.6, 0.7)).normalized()  # spot faces +Y once turned Z-up
camera.location = centre + direction * size * 1.6
camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
camera.data.lens = 50
scene.camera = camera

sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 3.0
sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(30))
scene.collection.objects.link(sun)
scene.world = bpy.data.worlds.new("world")
scene.world.use_nodes = True
scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False  # Debian builds Blender without OpenImageDenoise
scene.render.resolution_x, scene.render.resolution_y = 800, 600
scene.render.image_settings.file_format = "PNG"
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print(f"rendered {obj['pfill_particles']} particles to {out}")
