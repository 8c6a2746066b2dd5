"""Blender's own glTF exports with lights, the files tests/data/blender/*.glb, made by Blender itself:

    blender --background --factory-startup --python tools/data/make_blender_exports.py -- tests/data/blender

(Debian 12's blender 3.4 and its glTF add-on). Each file is one small scene as a Blender user
would set it up: a subject on a floor, a camera, and lights in Blender's units (point and spot
lights in watts, suns in W/m^2), which the exporter writes into KHR_lights_punctual as candela and
lux (a 1000 W point light becomes 54.35 cd: W / (4 pi) x 683 / 1000 at the add-on's default
"standard" light units). They are what docs/color.md's exposure and tone mapping are for: GL
read these numbers as intensities of 50 and more and drew white silhouettes.
"""
import math
import os
import sys

import bpy
from mathutils import Vector

out_dir = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else "."
os.makedirs(out_dir, exist_ok=True)


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def material(name, colour, metallic=0.0, roughness=0.5):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    return m


def add(obj, mat):
    obj.data.materials.append(mat)
    return obj


def floor(colour=(0.6, 0.6, 0.6)):
    bpy.ops.mesh.primitive_plane_add(size=8, location=(0, 0, 0))
    add(bpy.context.object, material("floor", colour))


def camera(location=(7.36, -6.93, 4.96), target=(0, 0, 0.8)):  # Blender's default camera, aimed at the subject
    bpy.ops.object.camera_add(location=location)
    cam = bpy.context.object
    cam.rotation_mode = "QUATERNION"
    cam.rotation_quaternion = (Vector(target) - Vector(location)).to_track_quat("-Z", "Y")
    bpy.context.scene.camera = cam


def light(kind, energy, location, rotation=(0, 0, 0), colour=(1, 1, 1), spot_deg=45):
    data = bpy.data.lights.new(kind + "_light", kind)
    data.energy = energy
    data.color = colour
    if kind == "SPOT":
        data.spot_size = math.radians(spot_deg)
    obj = bpy.data.objects.new(kind.lower(), data)
    obj.location = location
    obj.rotation_euler = rotation
    bpy.context.collection.objects.link(obj)


def export(name):
    bpy.ops.export_scene.gltf(filepath=os.path.join(out_dir, name + ".glb"), export_format="GLB", export_lights=True,
                              export_cameras=True, export_apply=True)


def subject(shape, colour, metallic=0.0, roughness=0.5, z=1.0):
    if shape == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(radius=1, location=(0, 0, z), segments=32, ring_count=16)
        bpy.ops.object.shade_smooth()
    elif shape == "monkey":
        bpy.ops.mesh.primitive_monkey_add(location=(0, 0, z))
        bpy.ops.object.shade_smooth()
    elif shape == "torus":
        bpy.ops.mesh.primitive_torus_add(location=(0, 0, z))
        bpy.ops.object.shade_smooth()
    else:
        bpy.ops.mesh.primitive_cube_add(size=1.6, location=(0, 0, z))
    add(bpy.context.object, material(shape, colour, metallic, roughness))


# Ten scenes: Blender's default lights (a 1000 W point light), suns, spots, several lights, colours.
scenes = [
    ("point_1000w_cube", "cube", (0.8, 0.8, 0.8), [("POINT", 1000, (4.1, 1.0, 5.9))]),
    ("point_1000w_sphere_red", "sphere", (0.8, 0.1, 0.1), [("POINT", 1000, (4.1, -1.0, 5.9))]),
    ("sun_3_monkey", "monkey", (0.7, 0.6, 0.4), [("SUN", 3, (0, 0, 6), (0.6, 0.2, 0.4))]),
    ("sun_1_torus_blue", "torus", (0.1, 0.3, 0.8), [("SUN", 1, (0, 0, 6), (0.5, -0.3, 0.2))]),
    ("spot_500w_sphere", "sphere", (0.9, 0.9, 0.9), [("SPOT", 500, (0, -3, 5), (0.55, 0, 0))]),
    ("two_points_monkey", "monkey", (0.5, 0.5, 0.5), [("POINT", 800, (3, -3, 4)), ("POINT", 300, (-4, 2, 3))]),
    ("point_100w_cube_small", "cube", (0.9, 0.7, 0.2), [("POINT", 100, (2, -2, 3))]),
    ("sun_and_point_torus", "torus", (0.2, 0.7, 0.3), [("SUN", 2, (0, 0, 6), (0.3, 0.3, 0)), ("POINT", 500, (-3, -3, 3))]),
    ("metal_sphere_point", "sphere", (0.9, 0.8, 0.6), [("POINT", 1000, (3, -4, 4))], 1.0, 0.3),
    ("warm_spot_cube", "cube", (0.6, 0.6, 0.7), [("SPOT", 1000, (2, -3, 4), (0.7, 0, 0.6)), ("SUN", 0.5, (0, 0, 5))]),
]
for entry in scenes:
    name, shape, colour, lights = entry[:4]
    metallic, roughness = (entry[4], entry[5]) if len(entry) > 4 else (0.0, 0.5)
    reset()
    floor()
    subject(shape, colour, metallic, roughness)
    camera()
    for spec in lights:
        kind, energy, location = spec[:3]
        rotation = spec[3] if len(spec) > 3 else (0, 0, 0)
        light(kind, energy, location, rotation, colour=(1.0, 0.95, 0.9) if name.startswith("warm") else (1, 1, 1))
    export(name)
print("wrote %d files to %s" % (len(scenes), out_dir))
