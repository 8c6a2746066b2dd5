"""The Collada duck of Debian's assimp-testmodels (the duck the Khronos glTF samples were made
from) as a binary glTF, converted by Blender itself, for tools/vs-threejs:

    blender --background --factory-startup --python tools/data/make_duck.py -- \
        /usr/share/assimp/models/Collada/duck.dae out/vs-threejs/duck.glb

(Debian 12's blender 3.4: its Collada importer turns the duck's Phong material into a Principled
BSDF with the duckCM texture, which its glTF add-on writes as a metallic-roughness material.)
Nothing is downloaded; the output is not committed.
"""
import sys

import bpy

source, target = sys.argv[sys.argv.index("--") + 1:][:2]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.wm.collada_import(filepath=source)
bpy.ops.export_scene.gltf(filepath=target, export_format="GLB", export_lights=False, export_cameras=False)
