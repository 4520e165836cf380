#!/usr/bin/env python3
"""Writes a KHR_draco_mesh_compression copy of a glTF file (test data for the
Draco decoder).

Usage: tools/make_draco_fixture.py IN.gltf OUT.gltf

Runs Debian's draco_transcoder (package `draco`, 1.5.5, default quantization: 11 bits for
positions) on IN.gltf, then keeps IN's JSON and takes from the transcoder only the geometry
(meshes, accessors, bufferViews, buffers): the transcoder drops cameras and extensions it does
not know (KHR_materials_emissive_strength), which the test compares against IN. The meshes must
come back in IN's order with IN's names, so the nodes still point at the same meshes. OUT's
buffer is OUT's stem + ".bin", beside it.

tests/data/blender/cornell_draco.gltf was made with
    python3 tools/make_draco_fixture.py tests/data/blender/cornell.gltf \
        tests/data/blender/cornell_draco.gltf
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile


def main() -> int:
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    source, target = sys.argv[1], sys.argv[2]
    with open(source) as f:
        original = json.load(f)
    with tempfile.TemporaryDirectory() as tmp:
        for name in os.listdir(os.path.dirname(os.path.abspath(source))):
            if name.endswith((".bin", ".png", ".jpg")):
                shutil.copy(os.path.join(os.path.dirname(os.path.abspath(source)), name), tmp)
        shutil.copy(source, os.path.join(tmp, "in.gltf"))
        out = os.path.join(tmp, "out.gltf")
        subprocess.run(["draco_transcoder", "-i", os.path.join(tmp, "in.gltf"), "-o", out],
                       check=True)
        with open(out) as f:
            draco = json.load(f)
        with open(os.path.join(tmp, draco["buffers"][0]["uri"]), "rb") as f:
            data = f.read()
    assert len(draco["buffers"]) == 1, "expected one buffer from draco_transcoder"
    names = [m.get("name") for m in original["meshes"]]
    assert [m.get("name") for m in draco["meshes"]] == names, "meshes reordered"
    for node, old in zip(draco["nodes"], original["nodes"]):
        assert node.get("mesh") == old.get("mesh"), "nodes point at other meshes"
    result = dict(original)
    for key in ("meshes", "accessors", "bufferViews", "buffers"):
        result[key] = draco[key]
    stem = os.path.splitext(os.path.basename(target))[0]
    result["buffers"][0]["uri"] = stem + ".bin"
    ext = "KHR_draco_mesh_compression"
    result["extensionsUsed"] = [ext] + [e for e in original.get("extensionsUsed", []) if e != ext]
    result["extensionsRequired"] = [ext]
    result["asset"] = dict(original["asset"])
    result["asset"]["generator"] = (original["asset"].get("generator", "") +
                                    " + draco_transcoder 1.5.5 (tools/make_draco_fixture.py)")
    with open(target, "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    with open(os.path.join(os.path.dirname(os.path.abspath(target)), stem + ".bin"), "wb") as f:
        f.write(data)
    return 0


if __name__ == "__main__":
    sys.exit(main())
