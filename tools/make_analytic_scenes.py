#!/usr/bin/env python3
"""Generates the analytic test scenes in assets/scenes/, whose answers are known in closed form:

- furnace_box.gltf: a closed unit cube, inside faces all of one material with a flat
  reflectance rho = 0.5 and a flat emission E = 1 (W m^-2 nm^-1) at every sample. Every row of F
  sums to 1, so B = E + rho B everywhere: B = E / (1 - rho) = 2 exactly, and the radiance of
  every pixel of a render from inside is B / pi (the "white furnace" test). A camera at the
  centre looks along -z.
- parallel_plates.gltf: two directly opposed unit squares 1 m apart (x, z in [0, 1], at y = 0
  facing up and y = 1 facing down). F between them = 0.19982 (Howell's catalogue, C-11: X = Y = 1).
- perpendicular_plates.gltf: two unit squares sharing an edge at 90 degrees (the floor
  x, z in [0, 1] facing up, the wall x = 0 facing +x). F = 0.20004 (Howell, C-14: H = W = 1).

In the plate scenes the lower plate emits (flat 1) and both reflect nothing, so B of the other
plate is zero and the solve is trivial; they exist for their view factors. Each square is two
triangles; tests subdivide them.

Usage: make_analytic_scenes.py [--check]   (--check: exit 1 if a committed file differs)
"""
import sys
from pathlib import Path

from gltf_writer import EXTENSION, GltfBuilder, write_or_check

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "assets" / "scenes"
FLAT_NM = [300, 900]  # covers every wavelength set's samples


def flat(value):
    return {"wavelengths": FLAT_NM, "values": [value, value]}


def material(name, reflectance, emission=None):
    m = {"name": name,
         "pbrMetallicRoughness": {"baseColorFactor": [reflectance] * 3 + [1.0],
                                  "metallicFactor": 0.0, "roughnessFactor": 1.0},
         "extensions": {EXTENSION: {"reflectance": flat(reflectance)}}}
    if emission is not None:
        m["emissiveFactor"] = [emission] * 3
        m["extensions"][EXTENSION]["emission"] = flat(emission)
    return m


def square(corners):
    """Two triangles of the quad p0 p1 p2 p3 (counter-clockwise seen from its front)."""
    p0, p1, p2, p3 = corners
    return [p0, p1, p2, p0, p2, p3]


def furnace_box():
    builder = GltfBuilder()
    # Inward-facing faces of [0, 1]^3, each counter-clockwise seen from inside.
    faces = {
        "floor": [(0, 0, 0), (0, 0, 1), (1, 0, 1), (1, 0, 0)],
        "ceiling": [(0, 1, 0), (1, 1, 0), (1, 1, 1), (0, 1, 1)],
        "back": [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0)],
        "front": [(0, 0, 1), (0, 1, 1), (1, 1, 1), (1, 0, 1)],
        "left": [(0, 0, 0), (0, 1, 0), (0, 1, 1), (0, 0, 1)],
        "right": [(1, 0, 0), (1, 0, 1), (1, 1, 1), (1, 1, 0)],
    }
    for name, corners in faces.items():
        builder.add_mesh(name, square([tuple(float(c) for c in p) for p in corners]), 0)
    builder.add_node({"name": "camera", "camera": 0, "translation": [0.5, 0.5, 0.5]})
    cameras = [{"name": "centre", "type": "perspective",
                "perspective": {"yfov": 1.2, "znear": 0.01}}]
    return builder.document("furnace_box", "DaisyRiot tools/make_analytic_scenes.py",
                            [material("furnace", 0.5, emission=1.0)], cameras)


def plates(name, second):
    builder = GltfBuilder()
    builder.add_mesh("source", square([(0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 1.0),
                                       (1.0, 0.0, 0.0)]), 0)
    builder.add_mesh("target", square(second), 1)
    materials = [material("source", 0.0, emission=1.0), material("target", 0.0)]
    return builder.document(name, "DaisyRiot tools/make_analytic_scenes.py", materials, [])


def build():
    return {
        "furnace_box.gltf": furnace_box(),
        # At y = 1 facing down: counter-clockwise seen from below.
        "parallel_plates.gltf": plates("parallel_plates", [(0.0, 1.0, 0.0), (1.0, 1.0, 0.0),
                                                           (1.0, 1.0, 1.0), (0.0, 1.0, 1.0)]),
        # At x = 0 facing +x.
        "perpendicular_plates.gltf": plates("perpendicular_plates",
                                            [(0.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 1.0, 1.0),
                                             (0.0, 0.0, 1.0)]),
    }


def main():
    status = 0
    for file_name, document in build().items():
        status = max(status, write_or_check(SCENES / file_name, document,
                                            "tools/make_analytic_scenes.py"))
    return status


if __name__ == "__main__":
    sys.exit(main())
