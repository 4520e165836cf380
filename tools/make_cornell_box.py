#!/usr/bin/env python3
"""Generates assets/scenes/cornell_box.gltf from assets/reference/cornell_box.json.

The measured Cornell box (Cornell Program of Computer Graphics, "Cornell Box Data"): geometry in
millimetres converted to metres, tabulated reflectances and the light's relative spectrum written
as DAISY_materials_spectral (DESIGN.md section 10). Every face is wound so its normal points into
the room: walls face the room's centre, block faces face away from their block's centre.
The measured light lies in the ceiling's plane (y = 548.8 mm) inside the ceiling quad; so that
no two surfaces overlap, the ceiling is written as a ring of eight triangles around the light's
opening (the light's corners are the ring's inner corners, so the two share vertices).
The RGB fallback colours (for viewers without the extension) are band means of the reflectance
(R 600-700 nm, G 500-600 nm, B 400-500 nm), not a colorimetric conversion.

Usage: make_cornell_box.py [--check]   (--check: exit 1 if the committed file differs)
"""
import json
import math
import sys
from pathlib import Path

from gltf_writer import EXTENSION, GltfBuilder, write_or_check

ROOT = Path(__file__).resolve().parent.parent
SOURCE = ROOT / "assets" / "reference" / "cornell_box.json"
TARGET = ROOT / "assets" / "scenes" / "cornell_box.gltf"
MM = 0.001


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def dot(a, b):
    return sum(a[i] * b[i] for i in range(3))


def centre(points):
    return [sum(p[i] for p in points) / len(points) for i in range(3)]


def band_mean(wavelengths, values, lo, hi):
    picked = [v for w, v in zip(wavelengths, values) if lo <= w <= hi]
    return round(sum(picked) / len(picked), 4)


def oriented_quad(quad, inside_point, outward):
    """Returns the quad wound so its normal points towards inside_point (or away, if outward)."""
    normal = cross(sub(quad[1], quad[0]), sub(quad[2], quad[0]))
    towards = dot(normal, sub(inside_point, centre(quad)))
    if (towards < 0) != outward:
        return [quad[0], quad[3], quad[2], quad[1]]
    return quad


def ring(outer, hole, inside_point):
    """Triangles of quad `outer` minus the quad `hole` inside it (same plane), each wound so
    its normal points towards inside_point: two triangles between each outer edge and the hole
    corners nearest its ends."""
    nearest = [min(hole, key=lambda h: sum((h[i] - o[i]) ** 2 for i in range(3))) for o in outer]
    triangles = []
    for k in range(4):
        o0, o1, h0, h1 = outer[k], outer[(k + 1) % 4], nearest[k], nearest[(k + 1) % 4]
        for tri in ((o0, o1, h1), (o0, h1, h0)):
            normal = cross(sub(tri[1], tri[0]), sub(tri[2], tri[0]))
            if dot(normal, sub(inside_point, tri[0])) < 0:
                tri = (tri[0], tri[2], tri[1])
            triangles.append(tri)
    return triangles


def build():
    data = json.loads(SOURCE.read_text())
    surfaces = data["surfaces"]
    room = [s for s in surfaces if not s["name"].startswith(("short_block", "tall_block"))]
    room_centre = centre([p for s in room for p in s["quad"]])
    block_centres = {}
    for prefix in ("short_block", "tall_block"):
        block_centres[prefix] = centre(
            [p for s in surfaces if s["name"].startswith(prefix) for p in s["quad"]])

    reflectance = data["reflectance"]
    wavelengths = reflectance["wavelength_nm"]
    material_names = ["white", "red", "green", "emitter"]
    materials = []
    for name in material_names:
        values = reflectance[name if name != "emitter" else "white"]
        material = {
            "name": name,
            "pbrMetallicRoughness": {
                "baseColorFactor": [band_mean(wavelengths, values, 600, 700),
                                    band_mean(wavelengths, values, 500, 600),
                                    band_mean(wavelengths, values, 400, 500), 1.0],
                "metallicFactor": 0.0, "roughnessFactor": 1.0},
            "extensions": {EXTENSION: {
                "reflectance": {"wavelengths": wavelengths, "values": values}}},
        }
        if name == "emitter":
            light = data["light_emission"]
            material["emissiveFactor"] = [1.0, 0.85, 0.65]
            material["extensions"][EXTENSION]["emission"] = {
                "wavelengths": light["wavelength_nm"], "values": light["relative_radiance"],
                "scale": 1.0}
        materials.append(material)

    builder = GltfBuilder()
    light = next(s["quad"] for s in surfaces if s["name"] == "light")
    for surface in surfaces:
        prefix = next((p for p in block_centres if surface["name"].startswith(p)), None)
        if prefix is None:
            quad = oriented_quad(surface["quad"], room_centre, outward=False)
        else:
            quad = oriented_quad(surface["quad"], block_centres[prefix], outward=True)
        if surface["name"] == "ceiling":
            triangles = ring(quad, light, room_centre)
        else:
            triangles = [(quad[0], quad[1], quad[2]), (quad[0], quad[2], quad[3])]
        positions = [[c * MM for c in p] for triangle in triangles for p in triangle]
        builder.add_mesh(surface["name"], positions, material_names.index(surface["material"]))

    camera = data["camera"]
    film_height = camera["film_size_m"][1]
    yfov = 2 * math.atan(0.5 * film_height / camera["focal_length_m"])
    # glTF cameras look down their local -Z; the measured camera looks along +Z: turn 180 deg
    # about +Y (quaternion x, y, z, w).
    builder.add_node({"name": "camera", "camera": 0,
                      "translation": [c * MM for c in camera["position"]],
                      "rotation": [0.0, 1.0, 0.0, 0.0]})
    cameras = [{"name": "measured", "type": "perspective", "perspective": {
        "yfov": round(yfov, 9), "aspectRatio": 1.0, "znear": 0.01}}]
    return builder.document("cornell_box", "DaisyRiot tools/make_cornell_box.py", materials,
                            cameras)


def main():
    return write_or_check(TARGET, build(), "tools/make_cornell_box.py")


if __name__ == "__main__":
    sys.exit(main())
