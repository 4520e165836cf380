#!/usr/bin/env python3
"""Generates assets/scenes/colored_lights.gltf: coloured light patterns on white walls.

After the original DaisyRiot paper's Figure 4f: a white room (3.6 x 2.6 x 3.6 m) divided by a
white partition 1.5 m high with two windows; behind it stand a pink and a green light box, so
the camera in front sees only their tops over the partition. Their light reaches the back wall,
the ceiling and the side walls over the partition (pink on the left, green on the right, mixing
in the middle) and falls through the windows onto the floor in front of it as coloured pools,
with the partition's shadows between them. The lights are RGB emitters (a bounded spectrum times
D65, docs/scene_format.md); every other surface is the same white.

Surfaces are rectangles meshed as two triangles, the partition's faces as grids of cells around
its windows so neighbouring cells share corners; `daisy render` subdivides them automatically.
Room faces are wound so their normals point into the room, the partition's and the lights' so
theirs point out of them. Faces that touch another surface (the lights' bottoms, the partition's
bottom) are left out. Units: metres.

Usage: make_colored_lights.py [--check]   (--check: exit 1 if the committed file differs)
"""
import sys
from pathlib import Path

from gltf_writer import EXTENSION, GltfBuilder, write_or_check

ROOT = Path(__file__).resolve().parent.parent
TARGET = ROOT / "assets" / "scenes" / "colored_lights.gltf"

W, H, D = 3.6, 2.6, 3.6  # room: x in [0, W], y (up) in [0, H], z in [0, D]
PARTITION_Z = (1.15, 1.25)  # its back and front faces
PARTITION_X = (0.45, 3.15)
PARTITION_TOP = 1.5
WINDOWS_X = [(0.9, 1.5), (2.1, 2.7)]  # two windows, each 0.6 m wide
WINDOWS_Y = (0.3, 1.15)
LIGHT_SIZE = 0.4
LIGHTS = [("pink_light", 1.2), ("green_light", 2.4)]  # name, x of the centre
LIGHT_Y = (1.1, 1.5)  # bottom and top of the light boxes (on stands hidden by the partition)
LIGHT_Z = 0.6  # centre


def material(name, rgb, emission_rgb=None, scale=1.0):
    m = {"name": name,
         "pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 1.0}}
    if emission_rgb is not None:
        m["emissiveFactor"] = list(emission_rgb)
        m["extensions"] = {EXTENSION: {"emission": {"rgb": list(emission_rgb), "scale": scale}}}
    return m


MATERIALS = [
    material("white", [0.8, 0.8, 0.8]),
    material("pink_light", [0.8, 0.8, 0.8], emission_rgb=[1.0, 0.22, 0.55], scale=8.0),
    material("green_light", [0.8, 0.8, 0.8], emission_rgb=[0.2, 1.0, 0.25], scale=8.0),
    material("stand", [0.8, 0.8, 0.8]),
]
MATERIAL_INDEX = {m["name"]: k for k, m in enumerate(MATERIALS)}


def grid_face(axis, level, u_coords, v_coords, positive, skip=lambda i, j: False):
    """Quads of the plane coordinate[axis] = level over the cells of u_coords x v_coords (u, v the
    next two axes in cyclic order), as triangles whose normal is +axis if `positive` else -axis.
    Cells for which skip(i, j) is true are left out (openings)."""
    u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
    triangles = []
    for j in range(len(v_coords) - 1):
        for i in range(len(u_coords) - 1):
            if skip(i, j):
                continue

            def corner(di, dj):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u_axis], p[v_axis] = level, u_coords[i + di], v_coords[j + dj]
                return tuple(p)
            p00, p10, p11, p01 = corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)
            # cross(e_u, e_v) = +e_axis
            if positive:
                triangles += [(p00, p10, p11), (p00, p11, p01)]
            else:
                triangles += [(p00, p11, p10), (p00, p01, p11)]
    return triangles


def box_faces(lo, hi, faces):
    """The named faces ("-x", "+y", ...) of an axis-aligned box, each two triangles facing out."""
    triangles = []
    for face in faces:
        axis = "xyz".index(face[1])
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        level = hi[axis] if face[0] == "+" else lo[axis]
        triangles += grid_face(axis, level, [lo[u_axis], hi[u_axis]], [lo[v_axis], hi[v_axis]],
                               positive=face[0] == "+")
    return triangles


def partition():
    """The partition with its two windows: front, back, top, ends and the windows' reveals."""
    (z0, z1), (x0, x1) = PARTITION_Z, PARTITION_X
    xs = sorted({x0, x1, *[x for w in WINDOWS_X for x in w]})
    ys = [0.0, WINDOWS_Y[0], WINDOWS_Y[1], PARTITION_TOP]
    windows = {(xs.index(a), 1) for a, _ in WINDOWS_X}

    # z faces: u = x, v = y
    def opening(i, j):
        return (i, j) in windows
    triangles = grid_face(2, z1, xs, ys, True, opening) + grid_face(2, z0, xs, ys, False, opening)
    zs = [z0, z1]
    triangles += grid_face(1, PARTITION_TOP, zs, xs, True)  # top (u = z, v = x)
    triangles += grid_face(0, x0, ys, zs, False) + grid_face(0, x1, ys, zs, True)  # ends
    for a, b in WINDOWS_X:
        triangles += grid_face(1, WINDOWS_Y[0], zs, [a, b], True)  # sill, facing up
        triangles += grid_face(1, WINDOWS_Y[1], zs, [a, b], False)  # lintel, facing down
        triangles += grid_face(0, a, list(WINDOWS_Y), zs, True)  # left reveal, facing +x
        triangles += grid_face(0, b, list(WINDOWS_Y), zs, False)  # right reveal, facing -x
    return triangles


def objects():
    out = []
    # The room: every face looks inwards.
    out.append(("floor", "white", grid_face(1, 0.0, [0.0, D], [0.0, W], True)))
    out.append(("ceiling", "white", grid_face(1, H, [0.0, D], [0.0, W], False)))
    out.append(("back_wall", "white", grid_face(2, 0.0, [0.0, W], [0.0, H], True)))
    out.append(("front_wall", "white", grid_face(2, D, [0.0, W], [0.0, H], False)))
    out.append(("left_wall", "white", grid_face(0, 0.0, [0.0, H], [0.0, D], True)))
    out.append(("right_wall", "white", grid_face(0, W, [0.0, H], [0.0, D], False)))
    out.append(("partition", "white", partition()))
    half = LIGHT_SIZE / 2
    for name, x in LIGHTS:
        lo = (x - half, LIGHT_Y[0], LIGHT_Z - half)
        hi = (x + half, LIGHT_Y[1], LIGHT_Z + half)
        out.append((name, name, box_faces(lo, hi, ["-x", "+x", "+y", "-z", "+z"])))
        # A thin stand under the light box, 8 cm square, from the floor.
        lo = (x - 0.04, 0.0, LIGHT_Z - 0.04)
        hi = (x + 0.04, LIGHT_Y[0], LIGHT_Z + 0.04)
        out.append((name + "_stand", "stand", box_faces(lo, hi, ["-x", "+x", "-z", "+z"])))
    return out


def build():
    builder = GltfBuilder()
    for name, mat, triangles in objects():
        positions = [p for triangle in triangles for p in triangle]
        builder.add_mesh(name, positions, MATERIAL_INDEX[mat])
    # glTF cameras look down their local -Z: from high up near the front wall towards the
    # partition, tilted down by 22 degrees (quaternion about +x) to take in the floor in front.
    builder.add_node({"name": "camera", "camera": 0, "translation": [W / 2, 2.1, D - 0.1],
                      "rotation": [-0.190809, 0.0, 0.0, 0.981627]})
    cameras = [{"name": "front", "type": "perspective", "perspective": {
        "yfov": 1.05, "aspectRatio": 1.3333333, "znear": 0.01}}]
    return builder.document("colored_lights", "DaisyRiot tools/make_colored_lights.py", MATERIALS,
                            cameras)


def main():
    return write_or_check(TARGET, build(), "tools/make_colored_lights.py")


if __name__ == "__main__":
    sys.exit(main())
