"""Generates tests/data/blender/: real glTF files written by Blender's own exporter.

Run once with Debian's blender 3.4 (not a build dependency; the outputs are committed):
    blender --background --factory-startup --python tools/make_blender_corpus.py -- tests/data/blender
It writes
- room.gltf (+ room.bin, floor_checker.png): a closed 4 x 5 x 3 m room (Blender z-up, so glTF
  4 (x) x 3 (y) x 5 (z)) whose floor has a checkerboard baseColorTexture, the wall at Blender
  x = 0 a vertex-coloured gradient (COLOR_0), the other walls plain colours, every material
  doubleSided (Blender's default), an emissive ceiling panel, a point light and a spot light
  (KHR_lights_punctual), three linked duplicates of one cube (one mesh, three nodes) and a
  camera;
- cornell.gltf (+ cornell.bin): a diffuse Cornell box (red, green and white walls, a one-sided
  emissive ceiling quad, two boxes) and its camera, and cornell_cycles.exr, the same scene rendered by
  Cycles with Lambertian (Diffuse BSDF) copies of the materials (64 x 64 pixels, 1024 samples,
  32 bounces, no denoising, Standard view transform, linear EXR), which
  tests/scene/blender_corpus_test.cpp compares daisy's render with.
Then, for the quantized, instanced and compressed paths, gltfpack 1.3 (`npm install -g gltfpack`):
    cd tests/data/blender && gltfpack -i room.gltf -o room_packed.gltf -mi \
        && gltfpack -i room.gltf -o room_meshopt.glb -mi -cc
"""
import math
import os
import sys

import bpy

out = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else "tests/data/blender"
os.makedirs(out, exist_ok=True)


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)


def material(name, rgb, emission=None, strength=1.0):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*rgb, 1)
    bsdf.inputs["Metallic"].default_value = 0
    bsdf.inputs["Specular"].default_value = 0
    bsdf.inputs["Roughness"].default_value = 1
    if emission is not None:
        bsdf.inputs["Emission"].default_value = (*emission, 1)
        bsdf.inputs["Emission Strength"].default_value = strength
    return m


def quad(name, corners, mat):
    """A one-face mesh, corners counter-clockwise seen from its front."""
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def box(name, lo, hi, mat, inward):
    (x0, y0, z0), (x1, y1, z1) = lo, hi
    v = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
         (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (3, 0, 4, 7)]
    if inward:
        faces = [tuple(reversed(f)) for f in faces]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(v, [], faces)
    mesh.materials.append(mat)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def camera(location, look_at, lens_fov_deg):
    cam = bpy.data.cameras.new("camera")
    cam.angle = math.radians(lens_fov_deg)
    cam.sensor_fit = "VERTICAL"
    obj = bpy.data.objects.new("camera", cam)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    direction = [b - a for a, b in zip(location, look_at)]
    import mathutils
    obj.rotation_euler = mathutils.Vector(direction).to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.camera = obj
    return obj


def export(path):
    bpy.ops.export_scene.gltf(filepath=path, export_format="GLTF_SEPARATE", export_lights=True,
                              export_cameras=True, export_colors=True, export_normals=False,
                              export_yup=True)


def make_room():
    reset()
    w, d, h = 4.0, 5.0, 3.0
    # Checkerboard texture, 8 x 8 squares of 8 texels. A byte image stores the values assigned
    # as sRGB codes (so the PNG's 0.8 decodes to linear 0.60).
    image = bpy.data.images.new("floor_checker", 64, 64)
    pixels = []
    for y in range(64):
        for x in range(64):
            on = ((x // 8) + (y // 8)) % 2 == 0
            pixels += [0.8, 0.8, 0.8, 1] if on else [0.1, 0.3, 0.6, 1]
    image.pixels = pixels
    image.filepath_raw = os.path.join(out, "floor_checker.png")
    image.file_format = "PNG"
    image.save()
    floor = material("floor", (1, 1, 1))
    tex = floor.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image = image
    floor.node_tree.links.new(tex.outputs["Color"], floor.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    quad("floor", [(0, 0, 0), (w, 0, 0), (w, d, 0), (0, d, 0)], floor)
    obj = bpy.context.scene.objects["floor"]
    uv = obj.data.uv_layers.new(name="UVMap")
    for loop, (u, v) in zip(obj.data.loops, [(0, 0), (1, 0), (1, 1), (0, 1)]):
        uv.data[loop.index].uv = (u, v)
    # The x = 0 wall: a vertex-colour gradient (red at the floor, blue at the ceiling).
    painted = material("painted", (1, 1, 1))
    attr_node = painted.node_tree.nodes.new("ShaderNodeVertexColor")
    attr_node.layer_name = "Col"
    painted.node_tree.links.new(attr_node.outputs["Color"], painted.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
    wall = quad("painted_wall", [(0, 0, 0), (0, d, 0), (0, d, h), (0, 0, h)], painted)
    colours = wall.data.color_attributes.new("Col", "FLOAT_COLOR", "POINT")
    for k, c in enumerate([(0.8, 0.1, 0.1, 1), (0.8, 0.1, 0.1, 1), (0.1, 0.1, 0.8, 1), (0.1, 0.1, 0.8, 1)]):
        colours.data[k].color = c
    white = material("white", (0.7, 0.7, 0.7))
    quad("ceiling", [(0, 0, h), (0, d, h), (w, d, h), (w, 0, h)], white)
    quad("wall_x", [(w, 0, 0), (w, 0, h), (w, d, h), (w, d, 0)], material("yellow", (0.7, 0.6, 0.2)))
    quad("wall_y0", [(0, 0, 0), (0, 0, h), (w, 0, h), (w, 0, 0)], white)
    quad("wall_y1", [(0, d, 0), (w, d, 0), (w, d, h), (0, d, h)], white)
    panel = material("panel", (0, 0, 0), emission=(1, 0.9, 0.8), strength=5)
    quad("panel", [(1.5, 2, h - 0.01), (1.5, 3, h - 0.01), (2.5, 3, h - 0.01), (2.5, 2, h - 0.01)], panel)
    # One cube mesh, three nodes (linked duplicates).
    grey = material("grey", (0.5, 0.5, 0.5))
    cube = box("cube", (-0.25, -0.25, 0), (0.25, 0.25, 0.5), grey, inward=False)
    cube.location = (1, 1, 0)
    for k, x in enumerate([2, 3]):
        twin = bpy.data.objects.new(f"cube.{k + 1}", cube.data)
        bpy.context.scene.collection.objects.link(twin)
        twin.location = (x, 1, 0)
    point = bpy.data.lights.new("point", "POINT")
    point.energy = 100  # W (Blender)
    point.color = (1, 0.8, 0.6)
    obj = bpy.data.objects.new("point", point)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = (1, 4, 2)
    spot = bpy.data.lights.new("spot", "SPOT")
    spot.energy = 200
    spot.spot_size = math.radians(60)
    spot.spot_blend = 0.2
    obj = bpy.data.objects.new("spot", spot)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = (3, 4, 2.5)
    obj.rotation_euler = (math.radians(30), 0, 0)
    camera((2, 0.3, 1.5), (2, 4, 1.0), 70)
    export(os.path.join(out, "room.gltf"))


def lambertian_for_cycles():
    """After the export: each material as a Diffuse BSDF (Lambertian at roughness 0) or an
    Emission shader of the same colour, so Cycles solves what daisy solves (the Principled BSDF's
    diffuse lobe is not Lambertian)."""
    for m in bpy.data.materials:
        nodes, links = m.node_tree.nodes, m.node_tree.links
        bsdf = nodes["Principled BSDF"]
        output = nodes["Material Output"]
        strength = bsdf.inputs["Emission Strength"].default_value
        emission = bsdf.inputs["Emission"].default_value
        if strength > 0 and max(emission[:3]) > 0:
            shader = nodes.new("ShaderNodeEmission")
            shader.inputs["Color"].default_value = emission
            shader.inputs["Strength"].default_value = strength
            # One-sided like the exported (doubleSided false) light: black from behind.
            black = nodes.new("ShaderNodeBsdfDiffuse")
            black.inputs["Color"].default_value = (0, 0, 0, 1)
            mix = nodes.new("ShaderNodeMixShader")
            links.new(nodes.new("ShaderNodeNewGeometry").outputs["Backfacing"], mix.inputs["Fac"])
            links.new(shader.outputs["Emission"], mix.inputs[1])
            links.new(black.outputs["BSDF"], mix.inputs[2])
            links.new(mix.outputs["Shader"], output.inputs["Surface"])
        else:
            shader = nodes.new("ShaderNodeBsdfDiffuse")
            shader.inputs["Color"].default_value = bsdf.inputs["Base Color"].default_value
            shader.inputs["Roughness"].default_value = 0
            links.new(shader.outputs["BSDF"], output.inputs["Surface"])


def make_cornell():
    reset()
    red = material("red", (0.63, 0.065, 0.05))
    green = material("green", (0.14, 0.45, 0.091))
    white = material("white", (0.725, 0.71, 0.68))
    light = material("light", (0, 0, 0), emission=(1, 1, 1), strength=10)
    light.use_backface_culling = True  # exported doubleSided false: emits downwards only
    s = 1.0
    quad("floor", [(0, 0, 0), (s, 0, 0), (s, s, 0), (0, s, 0)], white)
    quad("ceiling", [(0, 0, s), (0, s, s), (s, s, s), (s, 0, s)], white)
    quad("back", [(0, s, 0), (s, s, 0), (s, s, s), (0, s, s)], white)
    quad("left", [(0, 0, 0), (0, s, 0), (0, s, s), (0, 0, s)], red)
    quad("right", [(s, 0, 0), (s, 0, s), (s, s, s), (s, s, 0)], green)
    quad("light", [(0.4, 0.4, s - 0.001), (0.4, 0.6, s - 0.001), (0.6, 0.6, s - 0.001), (0.6, 0.4, s - 0.001)], light)
    box("tall", (0.55, 0.45, 0), (0.8, 0.7, 0.6), white, inward=False)
    box("short", (0.2, 0.15, 0), (0.45, 0.4, 0.3), white, inward=False)
    camera((0.5, -1.4, 0.5), (0.5, 0.5, 0.5), 40)
    export(os.path.join(out, "cornell.gltf"))
    lambertian_for_cycles()
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 1024
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = 32
    scene.cycles.diffuse_bounces = 32
    scene.render.resolution_x = 64
    scene.render.resolution_y = 64
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = os.path.join(out, "cornell_cycles.exr")
    world = bpy.data.worlds.new("black")
    world.color = (0, 0, 0)
    scene.world = world
    bpy.ops.render.render(write_still=True)


make_room()
make_cornell()
