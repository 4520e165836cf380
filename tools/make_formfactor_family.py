#!/usr/bin/env python3
"""Generates assets/scenes/formfactor_family/: the view-factor benchmark family, each
scene in a full version of about 7,700 triangles (the size of assets/scenes/blacklight_box.gltf,
scene (a), which tools/make_benchmark_box.py makes) and a small version (`*_small.gltf`, a few
hundred triangles) for the cross-backend tests (tests/backend/formfactor_family_test.cpp):

- (a) blacklight_small.gltf: the black-light box's room and occluders on coarse grids (the full
  version is blacklight_box.gltf itself).
- (b) blender_room.gltf: the same room and occluders, but walls, floor and ceiling tessellated
  the way a Blender export is: an irregular triangulation (interior vertices moved in the
  plane, each quad split along a random diagonal), faces listed in a shuffled order, and every
  interior vertex ~1e-6 m off its face's plane (float rounding of rotated geometry). The runs
  stay coplanar within the driver's tolerance, so they still form clusters of 32, but each
  cluster is scattered over its whole wall: every cluster-pair shaft is as wide as the room.
  blender_shell_small.gltf: that room alone (a closed convex enclosure, ceiling lit), for the
  summation rule: every row of F sums to 1. blender_cornell.gltf (full only): a Blender-style
  Cornell box of 13,184 triangles (the room tessellated so, two blocks), the issue's second
  user scene, for the "at most 3x the black-light box" benchmark.
- (c) open.gltf: no enclosure: a floor and a ring of standing panels facing its centre, one
  panel lit; nearly every shaft is clear.
- (d) cluttered.gltf: the room on plain grids around many small boxes (floating and standing)
  with an emitter on the ceiling: many small occluders.
- (e) far_triangle.gltf: the black-light box plus one triangle at z = 1e7 m facing it (the loader refuses coordinates past 1e8); its
  small version: two facing 2 x 2 squares 1 m apart, a plate between them hiding about half,
  and the far triangle (listed last, so tests can drop it).

Everything is deterministic (a fixed LCG seed per scene). Units: metres. Materials: white (flat
reflectance 0.75) and a light (flat emission 10, reflectance 0.1).

Usage: make_formfactor_family.py [--check]   (--check: exit 1 if a committed file differs)
"""
import math
import struct
import sys
from pathlib import Path

import make_benchmark_box as bb
from gltf_writer import EXTENSION, GltfBuilder, write_or_check

ROOT = Path(__file__).resolve().parent.parent
FOLDER = ROOT / "assets" / "scenes" / "formfactor_family"
W, H, D = bb.W, bb.H, bb.D
FLAT_NM = [300, 900]


def flat(value):
    return {"wavelengths": FLAT_NM, "values": [value, value]}


MATERIALS = [
    {"name": "white", "pbrMetallicRoughness": {"baseColorFactor": [0.75, 0.75, 0.75, 1.0],
                                               "metallicFactor": 0.0, "roughnessFactor": 1.0},
     "extensions": {EXTENSION: {"reflectance": flat(0.75)}}},
    {"name": "light", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.1, 0.1, 1.0],
                                               "metallicFactor": 0.0, "roughnessFactor": 1.0},
     "emissiveFactor": [1.0, 1.0, 1.0],
     "extensions": {EXTENSION: {"reflectance": flat(0.1), "emission": flat(10.0)}}},
]
WHITE, LIGHT = 0, 1


class Lcg:
    """Numerical Recipes' 32-bit LCG: the same sequence on every Python."""

    def __init__(self, seed):
        self.state = seed & 0xFFFFFFFF

    def uniform(self):
        self.state = (1664525 * self.state + 1013904223) & 0xFFFFFFFF
        return self.state / 2.0 ** 32

    def shuffle(self, items):
        for k in range(len(items) - 1, 0, -1):
            m = int(self.uniform() * (k + 1))
            items[k], items[m] = items[m], items[k]


def room_faces(divisions, names=("floor", "ceiling", "back", "front", "left", "right")):
    """The room's six faces (inward) as (name, axis, side, u_axis, v_axis, n_u, n_v, inward sign)."""
    faces = {"floor": "-y", "ceiling": "+y", "back": "-z", "front": "+z", "left": "-x",
             "right": "+x"}
    out = []
    for name in names:
        face = faces[name]
        out.append(bb.box(name, (W / 2, H / 2, D / 2), (W, H, D), divisions, "white",
                          faces=[face], inward=True))
    return out


def blender_face(face, n_u, n_v, rng, jitter_in_plane=0.3, jitter_off_plane=1e-6):
    """One inward room face tessellated like a Blender export: a grid whose interior vertices
    move by up to jitter_in_plane of a cell in the plane and ~jitter_off_plane off it, each quad
    split along a random diagonal, quads listed in a shuffled order."""
    axis = "xyz".index(face[1])
    u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
    size = (W, H, D)
    plane = 0.0 if face[0] == "-" else size[axis]
    du, dv = size[u_axis] / n_u, size[v_axis] / n_v
    grid = {}
    for j in range(n_v + 1):
        for i in range(n_u + 1):
            p = [0.0, 0.0, 0.0]
            p[axis] = plane
            p[u_axis] = i * du
            p[v_axis] = j * dv
            if 0 < i < n_u and 0 < j < n_v:
                p[u_axis] += (rng.uniform() - 0.5) * jitter_in_plane * du
                p[v_axis] += (rng.uniform() - 0.5) * jitter_in_plane * dv
                p[axis] += (rng.uniform() - 0.5) * 2.0 * jitter_off_plane
            grid[i, j] = tuple(p)
    # Inward: the normal points away from the wall's side.
    want_plus_axis = face[0] == "-"
    quads = [(i, j) for j in range(n_v) for i in range(n_u)]
    rng.shuffle(quads)
    triangles = []
    for i, j in quads:
        p00, p10, p11, p01 = grid[i, j], grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]
        if rng.uniform() < 0.5:
            pair = [(p00, p10, p11), (p00, p11, p01)]
        else:
            pair = [(p00, p10, p01), (p10, p11, p01)]
        # cross(e_u, e_v) = +e_axis for (p00, p10, p11): flip for a -axis normal.
        triangles += [t if want_plus_axis else (t[0], t[2], t[1]) for t in pair]
    return triangles


def occluders(coarse):
    """The black-light box's occluders (bb.objects()), or coarse versions of them."""
    if not coarse:
        return [o for o in bb.objects() if o[0] not in
                ("floor", "ceiling", "back_wall", "front_wall", "left_wall", "right_wall")]
    up = ["-x", "+x", "+y", "-z", "+z"]
    return [bb.box("tall_block", (1.45, 1.0, 1.7), (1.0, 2.0, 1.0), (1, 2, 1), "white",
                   faces=up, yaw_deg=20.0),
            bb.box("short_block", (3.5, 0.5, 2.0), (1.2, 1.0, 1.2), (1, 1, 1), "white",
                   faces=up, yaw_deg=-18.0),
            bb.box("table_top", (2.4, 0.78, 3.6), (1.8, 0.06, 1.0), (2, 1, 1), "white"),
            bb.box("blacklight_0", (2.5, H - 0.04, 2.5), (0.12, 0.08, 1.4), (1, 1, 2), "light",
                   faces=["-x", "+x", "-y", "-z", "+z"])]


def small_box(rng, k):
    """One of the cluttered scene's small boxes: 0.1-0.3 m, standing or floating."""
    s = 0.1 + 0.2 * rng.uniform()
    x = 0.3 + (W - 0.6) * rng.uniform()
    z = 0.3 + (D - 0.6) * rng.uniform()
    y = s / 2 if rng.uniform() < 0.5 else 0.3 + (H - 0.8) * rng.uniform()
    faces = ["-x", "+x", "+y", "-z", "+z"] if y == s / 2 else bb.FACES
    return bb.box(f"box_{k}", (x, y, z), (s, s, s), (1, 1, 1), "white", faces=faces,
                  yaw_deg=360.0 * rng.uniform())


def scene(kind, small):
    rng = Lcg({"blacklight": 1, "blender_room": 2, "open": 3, "cluttered": 4,
               "far_triangle": 5, "blender_shell": 6, "blender_cornell": 7}[kind])
    objects = []
    if kind == "blacklight":
        objects += room_faces((6, 3, 6)) + occluders(True)
    elif kind in ("blender_room", "blender_shell", "blender_cornell"):
        n = (6, 3, 6) if small else (36, 22, 36) if kind == "blender_cornell" else (26, 15, 26)
        # The same tilt between neighbours (~5e-6 rad) at either size.
        off_plane = 4e-6 if small else 1e-6
        for name, face in [("floor", "-y"), ("ceiling", "+y"), ("back", "-z"), ("front", "+z"),
                           ("left", "-x"), ("right", "+x")]:
            axis = "xyz".index(face[1])
            u_axis, v_axis = (axis + 1) % 3, (axis + 2) % 3
            objects.append((name, "light" if name == "ceiling" else "white",
                            blender_face(face, n[u_axis], n[v_axis], rng,
                                         jitter_off_plane=off_plane)))
        if kind == "blender_room":
            objects += occluders(small)
        elif kind == "blender_cornell":
            up = ["-x", "+x", "+y", "-z", "+z"]
            objects.append(bb.box("tall_block", (1.45, 1.0, 1.7), (1.0, 2.0, 1.0), (8, 16, 8),
                                  "white", faces=up, yaw_deg=20.0))
            objects.append(bb.box("short_block", (3.5, 0.5, 2.0), (1.2, 1.0, 1.2), (8, 6, 8),
                                  "white", faces=up, yaw_deg=-18.0))
    elif kind == "open":
        n = 6 if small else 40
        objects.append(bb.box("floor", (0.0, -0.5, 0.0), (20.0, 1.0, 20.0), (n, 1, n), "white",
                              faces=["+y"]))
        panels = 6 if small else 12
        grid = (1, 2, 2) if small else (1, 12, 16)
        for k in range(panels):
            angle = 2 * math.pi * k / panels
            # A panel at radius 8 facing the centre: its -x face turned towards the origin.
            objects.append(bb.box(f"panel_{k}", (8 * math.cos(angle), 1.5, 8 * math.sin(angle)),
                                  (0.1, 3.0, 3.0), grid, "light" if k == 0 else "white",
                                  faces=["-x"], yaw_deg=-math.degrees(angle)))
    elif kind == "cluttered":
        objects += room_faces((6, 3, 6) if small else (26, 15, 26))
        objects.append(bb.box("lamp", (W / 2, H - 0.02, D / 2), (1.0, 0.04, 1.0), (1, 1, 1),
                              "light", faces=["-y"]))
        for k in range(12 if small else 190):
            objects.append(small_box(rng, k))
    elif kind == "far_triangle":
        if small:
            objects.append(bb.box("lower", (0.5, -0.5, 0.5), (1.0, 1.0, 1.0), (2, 1, 2), "light",
                                  faces=["+y"]))
            objects.append(bb.box("upper", (0.5, 1.5, 0.5), (1.0, 1.0, 1.0), (2, 1, 2), "white",
                                  faces=["-y"]))
            # A plate halfway between them over x < 0.5, seen from both sides.
            objects.append(bb.box("plate", (0.0, 0.5, 0.5), (1.0, 0.02, 1.2), (2, 1, 2),
                                  "white", faces=["-y", "+y"]))
        else:
            objects += bb.objects()
        far = 1e7  # the loader refuses coordinates past 1e8 (float32)
        objects.append(("far", "white", [((0.0, 0.0, far), (0.0, 1.0, far), (1.0, 0.0, far))]))
    return objects


def build(kind, small):
    builder = GltfBuilder()
    index = {"white": WHITE, "light": LIGHT, "blacklight": LIGHT}
    for name, mat, triangles in scene(kind, small):
        index_of, positions, indices = {}, [], []
        for tri in triangles:
            for p in tri:
                key = struct.pack("<3f", *p)
                if key not in index_of:
                    index_of[key] = len(positions)
                    positions.append(struct.unpack("<3f", key))
                indices.append(index_of[key])
        builder.add_mesh(name, positions, index.get(mat, WHITE), indices)
    target = (W / 2, 2.0, D - 0.25) if kind != "open" else (0.0, 2.0, 12.0)
    builder.add_node({"name": "camera", "camera": 0, "translation": list(target),
                      "rotation": [-0.0697565, 0.0, 0.0, 0.9975641]})
    cameras = [{"name": "front", "type": "perspective", "perspective": {
        "yfov": 1.0, "aspectRatio": 1.3333333, "znear": 0.01}}]
    return builder.document(f"{kind}{'_small' if small else ''}",
                            "DaisyRiot tools/make_formfactor_family.py", MATERIALS, cameras)


def main():
    status = 0
    for kind in ["blacklight", "blender_room", "open", "cluttered", "far_triangle",
                 "blender_shell", "blender_cornell"]:
        for small in [True, False]:
            if (kind == "blacklight" or kind == "blender_shell") and not small:
                continue
            if kind == "blender_cornell" and small:
                continue  # a benchmark only (docs/performance.md)  # assets/scenes/blacklight_box.gltf (tools/make_benchmark_box.py)
            name = f"{kind}{'_small' if small else ''}.gltf"
            status |= write_or_check(FOLDER / name, build(kind, small),
                                     "tools/make_formfactor_family.py")
    return status


if __name__ == "__main__":
    sys.exit(main())
