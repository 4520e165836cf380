#!/usr/bin/env python3
"""Generates assets/scenes/blacklight_box.gltf: the view-factor benchmark scene.

A closed Cornell-style room (red left wall, green right wall, white elsewhere) lit only by two
UV "black light" tubes on the ceiling (emission preset `blacklight`), with occluders (a tall
and a short rotated block, a bench, a table on four legs, a shelf on the back wall) and a row
of eight poster panels on the back wall: each fluorescent material (the `brightener` preset,
and green, pink and yellow UV-excited day-glo paints, uv_paint below) hangs next to a
non-fluorescent twin of the same RGB colour, and the short block (pink paint) is the fluorescent
twin of the pink tall block, so renders show what fluorescence adds (the original paper's
Figures 4c and 4d). The visible-band presets (fluorescein, rhodamine6g, neon) are not used:
they absorb blue and green light, not the black lights' UV, so they would hardly glow here. 7,712
triangles, the size of the original DaisyRiot renderer's benchmark scene (docs/performance.md).

Every surface is an axis-aligned or y-rotated box face meshed as a regular grid, row by row;
vertices come from per-axis coordinate tables, so shared edges are bitwise equal. Room faces are wound so
their normals point into the room; object faces so theirs point out of the object. Faces that
lie against another surface (the bottoms of blocks and legs, the backs of panels, shelf and
lamps) are left out: they could never exchange light. Units: metres.

Usage: make_benchmark_box.py [--check]   (--check: exit 1 if the committed file differs)
"""
import math
import struct
import sys
from pathlib import Path

from gltf_writer import EXTENSION, GltfBuilder, write_or_check

ROOT = Path(__file__).resolve().parent.parent
TARGET = ROOT / "assets" / "scenes" / "blacklight_box.gltf"
TRIANGLES = 7712  # the original renderer's benchmark scene

W, H, D = 5.0, 3.0, 5.0  # room: x in [0, W], y (up) in [0, H], z in [0, D]


def uv_paint(peak_nm):
    """A day-glo paint as black-light posters use: absorbs UV-A and the violet edge (0.8 from
    250 to 400 nm, falling to 0 at 420 nm, the original DaisyRiot's fluorescent-colour model,
    docs/materials.md) and re-emits a 40 nm wide band at peak_nm (pink: a red band with a
    weaker blue one) with quantum yield 0.9."""
    if peak_nm == "pink":
        emission = {"wavelengths": [400, 440, 470, 520, 580, 620, 660, 720],
                    "values": [0.0, 0.5, 0.3, 0.05, 0.3, 1.0, 0.5, 0.0]}
    else:
        emission = {"gaussian": {"peak": peak_nm, "fwhm": 40}}
    return {"absorption": {"wavelengths": [250, 400, 420, 900], "values": [0.8, 0.8, 0.0, 0.0]},
            "emission": emission, "quantumYield": 0.9}


# Reflectances of the painted posters and blocks (nm, value), shared by each fluorescent paint
# and its twin so both have the same colour: 0.15 in the UV, where the paint absorbs (rho + a
# <= 1 with uv_paint's 0.8), then a smooth visible curve close to the RGB fallback colour.
PAINTS = {
    "green": ([250, 400, 420, 450, 500, 530, 560, 600, 650, 700],
              [0.15, 0.15, 0.2, 0.25, 0.6, 0.75, 0.6, 0.3, 0.3, 0.35]),
    "pink": ([250, 400, 420, 450, 500, 550, 600, 650, 700],
             [0.15, 0.15, 0.45, 0.45, 0.3, 0.3, 0.8, 0.9, 0.9]),
    "yellow": ([250, 400, 420, 450, 500, 540, 600, 700],
               [0.15, 0.15, 0.15, 0.15, 0.5, 0.85, 0.9, 0.9]),
}


def material(name, rgb, fluorescence=None, emission=None, emissive_rgb=None, paint=None):
    m = {"name": name,
         "pbrMetallicRoughness": {"baseColorFactor": list(rgb) + [1.0], "metallicFactor": 0.0,
                                  "roughnessFactor": 1.0}}
    ext = {}
    if paint:
        wavelengths, values = PAINTS[paint]
        ext["reflectance"] = {"wavelengths": wavelengths, "values": values}
    if fluorescence:
        ext["fluorescence"] = (fluorescence if isinstance(fluorescence, dict)
                               else {"preset": fluorescence})
    if emission:
        ext["emission"] = emission
        m["emissiveFactor"] = list(emissive_rgb)
    if ext:
        m["extensions"] = {EXTENSION: ext}
    return m


MATERIALS = [
    material("white", [0.75, 0.75, 0.75]),
    material("red", [0.63, 0.065, 0.05]),
    material("green", [0.14, 0.45, 0.09]),
    material("block_glow_pink", [0.9, 0.35, 0.45], fluorescence=uv_paint("pink"), paint="pink"),
    material("block_pink", [0.9, 0.35, 0.45], paint="pink"),
    material("wood", [0.45, 0.3, 0.18]),
    material("blacklight", [0.05, 0.05, 0.05],
             emission={"preset": "blacklight", "scale": 20}, emissive_rgb=[0.3, 0.0, 0.5]),
    material("poster_brightener", [0.85, 0.85, 0.85], fluorescence="brightener"),
    material("poster_white", [0.85, 0.85, 0.85]),
    material("poster_glow_green", [0.35, 0.75, 0.25], fluorescence=uv_paint(520), paint="green"),
    material("poster_green", [0.35, 0.75, 0.25], paint="green"),
    material("poster_glow_pink", [0.9, 0.35, 0.45], fluorescence=uv_paint("pink"), paint="pink"),
    material("poster_pink", [0.9, 0.35, 0.45], paint="pink"),
    material("poster_glow_yellow", [0.8, 0.9, 0.2], fluorescence=uv_paint(570), paint="yellow"),
    material("poster_yellow", [0.8, 0.9, 0.2], paint="yellow"),
]
MATERIAL_INDEX = {m["name"]: k for k, m in enumerate(MATERIALS)}

# Face names: the axis and side of the box face, e.g. "-y" is the bottom.
FACES = ["-x", "+x", "-y", "+y", "-z", "+z"]


def box(name, centre, size, divisions, mat, faces=FACES, inward=False, yaw_deg=0.0):
    """Triangles of the chosen faces of a box, in face order, each face row by row.

    centre, size: (x, y, z); divisions: grid cells per axis; yaw_deg: rotation about +y.
    Returns (name, material, [(p0, p1, p2), ...]).
    """
    coords = [[-0.5 * size[a] + size[a] * k / divisions[a] for k in range(divisions[a] + 1)]
              for a in range(3)]
    yaw = math.radians(yaw_deg)
    cos_y, sin_y = math.cos(yaw), math.sin(yaw)

    def world(local):
        x, y, z = local
        return (centre[0] + cos_y * x + sin_y * z, centre[1] + y, centre[2] - sin_y * x + cos_y * z)

    triangles = []
    for face in faces:
        axis = "xyz".index(face[1])
        side = 0 if face[0] == "-" else divisions[axis]
        u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
        # cross(e_u, e_v) = +e_axis; the face's outward normal is sign(face) e_axis.
        outward_sign = 1 if face[0] == "+" else -1
        want_plus_axis = (outward_sign > 0) != inward
        for j in range(divisions[v_axis]):
            for i in range(divisions[u_axis]):
                def corner(di, dj):
                    local = [0.0, 0.0, 0.0]
                    local[axis] = coords[axis][side]
                    local[u_axis] = coords[u_axis][i + di]
                    local[v_axis] = coords[v_axis][j + dj]
                    return world(local)
                p00, p10, p11, p01 = corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)
                if want_plus_axis:
                    triangles += [(p00, p10, p11), (p00, p11, p01)]
                else:
                    triangles += [(p00, p11, p10), (p00, p01, p11)]
    return name, mat, triangles


def objects():
    out = []
    # The room: walls face inwards. Left (x = 0) red, right (x = W) green.
    room = dict(centre=(W / 2, H / 2, D / 2), size=(W, H, D), divisions=(26, 15, 26),
                inward=True)
    out.append(box("floor", mat="white", faces=["-y"], **room))
    out.append(box("ceiling", mat="white", faces=["+y"], **room))
    out.append(box("back_wall", mat="white", faces=["-z"], **room))
    out.append(box("front_wall", mat="white", faces=["+z"], **room))
    out.append(box("left_wall", mat="red", faces=["-x"], **room))
    out.append(box("right_wall", mat="green", faces=["+x"], **room))
    # Occluders standing on the floor (no bottom faces).
    up = ["-x", "+x", "+y", "-z", "+z"]
    out.append(box("tall_block", (1.45, 1.0, 1.7), (1.0, 2.0, 1.0), (4, 8, 4), "block_pink",
                   faces=up, yaw_deg=20.0))
    out.append(box("short_block", (3.5, 0.5, 2.0), (1.2, 1.0, 1.2), (5, 4, 5), "block_glow_pink",
                   faces=up, yaw_deg=-18.0))
    out.append(box("bench", (0.7, 0.225, 3.75), (0.5, 0.45, 1.5), (3, 3, 15), "wood", faces=up))
    out.append(box("table_top", (2.4, 0.78, 3.6), (1.8, 0.06, 1.0), (9, 1, 5), "wood"))
    sides = ["-x", "+x", "-z", "+z"]
    for k, (dx, dz) in enumerate([(-0.8, -0.42), (0.8, -0.42), (-0.8, 0.42), (0.8, 0.42)]):
        out.append(box(f"table_leg_{k}", (2.4 + dx, 0.375, 3.6 + dz), (0.08, 0.75, 0.08),
                       (1, 4, 1), "wood", faces=sides))
    out.append(box("shelf", (2.5, 1.9, 0.175), (2.4, 0.05, 0.35), (12, 1, 2), "wood",
                   faces=["-x", "+x", "-y", "+y", "+z"]))
    # Black lights against the ceiling (no top faces).
    for k, x in enumerate([1.6, 3.4]):
        out.append(box(f"blacklight_{k}", (x, H - 0.04, 2.5), (0.12, 0.08, 1.4), (1, 1, 14),
                       "blacklight", faces=["-x", "+x", "-y", "-z", "+z"]))
    # Poster panels 2 cm thick on the back wall above the shelf (no back faces), in a row of
    # four pairs, each fluorescent poster next to its non-fluorescent twin.
    pairs = [("poster_brightener", "poster_white"), ("poster_glow_green", "poster_green"),
             ("poster_glow_pink", "poster_pink"), ("poster_glow_yellow", "poster_yellow")]
    for k, (fluorescent, twin) in enumerate(pairs):
        x0 = 0.425 + 1.2 * k
        for m, (mat, dx) in enumerate([(fluorescent, 0.0), (twin, 0.55)]):
            out.append(box(f"panel_{mat}", (x0 + dx, 2.4, 0.01), (0.5, 0.6, 0.02), (3, 4, 1),
                           mat, faces=["+z", "-x", "+x", "-y", "+y"]))
    return out


def build():
    builder = GltfBuilder()
    total = 0
    for name, mat, triangles in objects():
        # Indexed: each distinct corner once per object, in first-use order.
        index_of, positions, indices = {}, [], []
        for tri in triangles:
            for p in tri:
                key = struct.pack("<3f", *p)
                if key not in index_of:
                    index_of[key] = len(positions)
                    positions.append(struct.unpack("<3f", key))
                indices.append(index_of[key])
        total += len(triangles)
        builder.add_mesh(name, positions, MATERIAL_INDEX[mat], indices)
    if total != TRIANGLES:
        raise SystemExit(f"generated {total} triangles, expected {TRIANGLES}")
    # glTF cameras look down their local -Z: from near the front wall towards the back wall.
    # Eye height 2 m, tilted down 8 degrees (quaternion about +x), so the posters show above
    # the tall block.
    builder.add_node({"name": "camera", "camera": 0, "translation": [W / 2, 2.0, D - 0.25],
                      "rotation": [-0.0697565, 0.0, 0.0, 0.9975641]})
    cameras = [{"name": "front", "type": "perspective", "perspective": {
        "yfov": 1.0, "aspectRatio": 1.3333333, "znear": 0.01}}]
    return builder.document("blacklight_box", "DaisyRiot tools/make_benchmark_box.py", MATERIALS,
                            cameras)


def main():
    return write_or_check(TARGET, build(), "tools/make_benchmark_box.py")


if __name__ == "__main__":
    sys.exit(main())
