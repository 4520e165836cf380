"""Round-trips a glTF scene through Blender: imports it into an empty scene and exports it with
Blender's glTF exporter at its default settings plus cameras and lights (which the defaults
leave out), so that daisy reads what Blender itself writes (normals, its vertex splitting, its
node and material layout, its light units). Debian's blender 3.4 (not a build dependency):

    blender --background --factory-startup --python tools/blender_reexport.py -- IN.gltf OUT.glb

OUT ending in .gltf is written as .gltf + .bin (GLTF_SEPARATE), else as .glb (the default).
Used for the Blender-exported large interior (tools/make_large_interior.py, docs/performance.md)
and its committed small version, tests/data/blender/interior_small.glb.
"""
import os
import sys

import bpy

arguments = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(arguments) != 2:
    sys.exit("usage: blender -b --factory-startup --python blender_reexport.py -- IN OUT")
source, target = (os.path.abspath(a) for a in arguments)
bpy.ops.wm.read_factory_settings(use_empty=True)
# Shading FLAT: what the default ("NORMALS") makes of a file without normals (every face flat),
# without its guess, which calls numpy.bool, gone since NumPy 1.24 (Debian's is newer).
bpy.ops.import_scene.gltf(filepath=source, import_shading="FLAT")
os.makedirs(os.path.dirname(target), exist_ok=True)
bpy.ops.export_scene.gltf(filepath=target, export_cameras=True, export_lights=True,
                          export_format="GLTF_SEPARATE" if target.endswith(".gltf") else "GLB")
print(f"blender_reexport: {source} -> {target}")
