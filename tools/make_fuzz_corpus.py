#!/usr/bin/env python3
"""Writes the fuzz targets' seed corpora, tests/fuzz/corpus/<target>/: every committed
.gltf scene (assets/scenes, tests/data) as .gltf and converted to .glb; the Blender exports of
tests/data/blender made self-contained (their .bin and .png inlined), which bring punctual
lights, textures, COLOR_0, quantization, instancing, Draco and meshopt, plus small variants of
them (a JPEG texture, TEXCOORD_1, a directional light); hand-made OBJ+MTL scenes; every
DAISY_materials_spectral object in those scenes plus one of each form the extension allows;
--materials files built from them, up to one naming all 64 materials of the target's scene;
option strings; and tiny scenes for the whole pipeline. Each seed starts with the byte its
target reads first (tests/fuzz/*_fuzz.cpp). With --check, only compares with the committed files
(the ctest generator.fuzz_corpus_up_to_date)."""
import base64
import json
import struct
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "tests" / "fuzz" / "corpus"
# tests/data/blender holds exporter output with side .bin and .png files (Blender's own output),
# not self-contained seeds.
SCENES = sorted((ROOT / "assets" / "scenes").glob("*.gltf")) + sorted(
    p for p in (ROOT / "tests" / "data").rglob("*.gltf") if "blender" not in p.parts)


def to_glb(document):
    """The same scene as GLB: the first data: buffer becomes the BIN chunk (a buffer without a
    uri stays as it is: a meshopt fallback buffer)."""
    document = json.loads(json.dumps(document))
    binary = b""
    buffers = document.get("buffers", [])
    if buffers and buffers[0].get("uri", "").startswith("data:"):
        binary = base64.b64decode(buffers[0]["uri"].split(",", 1)[1])
        del buffers[0]["uri"]
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary += b"\0" * (-len(binary) % 4)
    chunks = struct.pack("<II", len(text), 0x4E4F534A) + text
    if binary:
        chunks += struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<III", 0x46546C67, 2, 12 + len(chunks)) + chunks


BLENDER = ROOT / "tests" / "data" / "blender"
# Written by Blender's exporter, gltfpack and draco_transcoder (tools/make_blender_corpus.py,
# tools/make_draco_fixture.py): Draco and meshopt seeds are real compressed streams.
BLENDER_SCENES = ["cornell.gltf", "cornell_draco.gltf", "room.gltf", "room_packed.gltf"]


def data_uri(mime, data):
    return f"data:{mime};base64," + base64.b64encode(data).decode()


def inlined(path):
    """A glTF document with its external buffers and images read into data: URIs."""
    document = json.loads(path.read_text())
    for buffer in document.get("buffers", []):
        if "uri" in buffer and not buffer["uri"].startswith("data:"):
            buffer["uri"] = data_uri("application/octet-stream",
                                     (path.parent / buffer["uri"]).read_bytes())
    for image in document.get("images", []):
        if "uri" in image and not image["uri"].startswith("data:"):
            image["uri"] = data_uri(image.get("mimeType", "image/png"),
                                    (path.parent / image["uri"]).read_bytes())
    return document


def from_glb(data):
    """A GLB's JSON with its BIN chunk as the first buffer's data: URI."""
    length = struct.unpack_from("<I", data, 12)[0]
    document = json.loads(data[20:20 + length])
    at = 20 + length
    if at + 8 <= len(data):
        size = struct.unpack_from("<I", data, at)[0]
        document["buffers"][0]["uri"] = data_uri("application/octet-stream",
                                                 data[at + 8:at + 8 + size])
    return document


def gray_jpeg():
    """An 8 x 8 baseline JPEG of one grey block (DC difference 0, then end of block): the
    smallest stream stb_image's JPEG decoder reads through."""
    def segment(marker, body):
        return struct.pack(">BBH", 0xFF, marker, len(body) + 2) + body
    quantization = segment(0xDB, b"\x00" + b"\x01" * 64)
    frame = segment(0xC0, struct.pack(">BHHB", 8, 8, 8, 1) + b"\x01\x11\x00")
    # One code of length 1 in each table: DC category 0, AC end of block.
    dc = segment(0xC4, b"\x00" + b"\x01" + b"\x00" * 15 + b"\x00")
    ac = segment(0xC4, b"\x10" + b"\x01" + b"\x00" * 15 + b"\x00")
    scan = segment(0xDA, b"\x01\x01\x00\x00\x3f\x00")
    return b"\xff\xd8" + quantization + frame + dc + ac + scan + b"\x3f\xff\xd9"


def blender_variants(room):
    """(name, document): small changes to the Blender room that reach paths its export does
    not: a JPEG texture, the texture on TEXCOORD_1, a directional light, a light without a
    name or colour."""
    def variant(change):
        document = json.loads(json.dumps(room))
        change(document)
        return document

    def jpeg(document):
        document["images"][0] = {"uri": data_uri("image/jpeg", gray_jpeg()),
                                 "mimeType": "image/jpeg"}

    def texcoord1(document):
        primitive = document["meshes"][0]["primitives"][0]
        primitive["attributes"]["TEXCOORD_1"] = primitive["attributes"]["TEXCOORD_0"]
        texture = document["materials"][primitive["material"]]["pbrMetallicRoughness"]
        texture["baseColorTexture"]["texCoord"] = 1
        texture["baseColorTexture"]["extensions"] = {
            "KHR_texture_transform": {"offset": [0.5, 0], "rotation": 0.3, "scale": [4, 4]}}

    def directional(document):
        document["extensions"]["KHR_lights_punctual"]["lights"] = [
            {"type": "directional", "intensity": 3},
            {"type": "spot", "intensity": 100, "range": 10, "color": [0.2, 0.4, 1],
             "spot": {"outerConeAngle": 0.7}}]

    return [("room_jpeg", variant(jpeg)), ("room_texcoord1", variant(texcoord1)),
            ("room_directional", variant(directional))]


# The materials_json target's scene (tests/fuzz/materials_json_fuzz.cpp): one triangle each for
# "lamp", "wall" and m02 .. m63.
MATERIAL_NAMES = ["lamp", "wall"] + [f"m{k:02d}" for k in range(2, 64)]


CUBE_OBJ = """# a closed unit room with a ceiling lamp
mtllib s.mtl
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
vn 0 0 1
vt 0.5 0.5
usemtl wall
f 1 2 3 4
f 5 8 7 6
f 1 5 6 2
f 2 6 7 3
usemtl lamp
f 3 7 8 4
usemtl green
f 1/1/1 4/1/1 8/1/1 5/1/1
"""
CUBE_MTL = """newmtl wall
Kd 0.8 0.8 0.8
newmtl lamp
Kd 0 0 0
Ke 5 5 5
newmtl green
Kd 0.1 0.6 0.1
Ks 0.2 0.9 0.3
Ns 10
d 1
"""
PLATES_OBJ = """mtllib s.mtl
o plates
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
v 1 0 1
v 1 1 1
v 0 1 1
usemtl lamp
f -8 -7 -6 -5
usemtl wall
f 5 8 7 6
"""
RELATIVE_OBJ = "v 0 0 0\nv 1 0 0 1\nv 0 1 0\nf -3 -2 -1\nl 1 2\np 3\n"

EXTENSIONS = [
    {"reflectance": {"rgb": [0.2, 0.5, 0.8]}},
    {"reflectance": {"wavelengths": [400, 500, 600, 700], "values": [0.1, 0.5, 0.6, 0.2],
                     "scale": 0.9}},
    {"reflectance": {"gaussian": {"peak": 550, "fwhm": 40}}},
    {"emission": {"preset": "D65", "scale": 2}},
    {"emission": {"blackbody": 3000}},
    {"emission": {"preset": "blacklight", "scale": 10}},
    {"emission": {"wavelengths": [350, 400], "values": [1, 0]}},
    {"fluorescence": {"preset": "fluorescein"}},
    {"fluorescence": {"absorption": {"gaussian": {"peak": 360, "fwhm": 30}},
                      "emission": {"gaussian": {"peak": 440, "fwhm": 50}}, "quantumYield": 0.8}},
    {"fluorescence": {"matrix": {"wavelengths": [400, 500, 600],
                                 "values": [[0.5, 0, 0], [0.2, 0.6, 0], [0.1, 0.1, 0.7]]}}},
    {"reflectance": {"rgb": [0.5, 0.5, 0.5]}, "emission": {"rgb": [1, 1, 1]},
     "fluorescence": {"preset": "optical-brightener"}},
]

OPTIONS = [
    (0, "daisyriot"), (0, "meyer4"), (0, "visible"), (0, "auto"), (0, "fine"),
    (0, "400:700:50"), (0, "380,450,550,650"), (0, "300:800:0.5"), (1, "4G"), (1, "512MiB"),
    (1, "1000000"), (1, "1.5GiB"), (2, "auto"), (2, "-1.5"), (3, "hybrid"), (3, "gauss-seidel"),
    (4, "D65"), (4, "F11"), (4, "blacklight"), (5, "fluorescein"), (5, "rhodamine-6g"),
]


def seeds():
    """(target, name, bytes) of every seed."""
    extensions = list(EXTENSIONS)
    for path in SCENES:
        document = json.loads(path.read_text())
        yield "gltf", path.stem + ".gltf", b"\0" + path.read_bytes()
        yield "gltf", path.stem + ".glb", b"\1" + to_glb(document)
        for material in document.get("materials", []):
            extension = material.get("extensions", {}).get("DAISY_materials_spectral")
            if extension is not None and extension not in extensions:
                extensions.append(extension)
        triangles = sum(a.get("count", 0) for a in document.get("accessors", [])
                        if a.get("type") == "SCALAR") // 3
        if triangles <= 64:
            yield "pipeline", path.stem + ".gltf", b"\0" + path.read_bytes()
            yield "pipeline", path.stem + "_subdivided.gltf", b"\2" + path.read_bytes()
    room = None
    for name in BLENDER_SCENES:
        document = inlined(BLENDER / name)
        stem = Path(name).stem
        room = document if stem == "room" else room
        yield "gltf", stem + ".gltf", b"\0" + json.dumps(document).encode()
        yield "gltf", stem + ".glb", b"\1" + to_glb(document)
        yield "pipeline", stem + ".gltf", b"\0" + json.dumps(document).encode()
    meshopt = (BLENDER / "room_meshopt.glb").read_bytes()
    yield "gltf", "room_meshopt.glb", b"\1" + meshopt
    yield "gltf", "room_meshopt.gltf", b"\0" + json.dumps(from_glb(meshopt)).encode()
    yield "pipeline", "room_meshopt.gltf", b"\0" + json.dumps(from_glb(meshopt)).encode()
    for name, document in blender_variants(room):
        yield "gltf", name + ".gltf", b"\0" + json.dumps(document).encode()
        yield "pipeline", name + ".gltf", b"\0" + json.dumps(document).encode()
    separator = b"\n#---MTL---\n"
    for name, obj, mtl in [("cube", CUBE_OBJ, CUBE_MTL), ("plates", PLATES_OBJ, CUBE_MTL),
                           ("relative", RELATIVE_OBJ, "")]:
        body = obj.replace("mtllib s.mtl\n", "").encode() + separator + mtl.encode()
        yield "obj", name + ".obj", b"\0" + body
        yield "obj", name + "_daisyriot.obj", b"\1" + body
        yield "pipeline", name + ".obj", b"\1" + obj.encode()
    for k, extension in enumerate(extensions):
        text = json.dumps(extension, indent=1).encode()
        yield "material_extension", f"extension{k:02d}.json", text
        yield "materials_json", f"materials{k:02d}.json", json.dumps(
            {"lamp": extension, "wall": extensions[(k + 1) % len(extensions)]}).encode()
    # Many members: every material of the target's scene, each a different form.
    many = {name: extensions[k % len(extensions)] for k, name in enumerate(MATERIAL_NAMES)}
    yield "materials_json", "materials_all64.json", json.dumps(many, indent=1).encode()
    yield "materials_json", "materials_1000.json", json.dumps(
        {f"m{k:03d}": extensions[k % 3] for k in range(1000)}).encode()
    for k, (parser, text) in enumerate(OPTIONS):
        yield "options", f"option{k:02d}", bytes([parser]) + text.encode()


def regressions():
    """(target, name, bytes): the inputs known to have crashed daisy or failed silently, kept in
    tests/fuzz/crashes/<target>/ so ctest replays them."""
    room = json.loads((ROOT / "tests" / "data" / "gltf" / "lamp_room.gltf").read_text())

    def variant(change):
        document = json.loads(json.dumps(room))
        change(document)
        return b"\0" + json.dumps(document).encode()

    deep = json.dumps(room).replace('"asset"', '"extras": ' + "[" * 15000 + "]" * 15000 + ', "asset"', 1)
    yield "gltf", "issue14-deep-extras.gltf", b"\0" + deep.encode()
    yield "material_extension", "issue14-deep.json", ("[" * 15000 + "]" * 15000).encode()
    yield "materials_json", "issue14-deep.json", ('{"lamp": ' + "[" * 15000 + "]" * 15000 + "}").encode()

    def huge_count(document):
        document["accessors"].append({"componentType": 5126, "count": 4294967295, "type": "VEC3"})
        document["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = len(document["accessors"]) - 1

    def sparse_bomb(document):
        document["accessors"].append({"componentType": 5126, "count": 30000000, "type": "VEC3",
                                      "sparse": {"count": 0, "indices": {"bufferView": 0, "componentType": 5125},
                                                 "values": {"bufferView": 0}}})
        document["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = len(document["accessors"]) - 1

    def dot_uri(document):
        document["buffers"][0]["uri"] = "."

    def far_camera(document):
        document["cameras"] = [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}]
        document["nodes"].append({"camera": 0, "translation": [1e18, 0, 0]})
        document["scenes"][0]["nodes"].append(len(document["nodes"]) - 1)

    def far_geometry(document):
        roots = document["scenes"][0]["nodes"]
        document["nodes"].append({"scale": [1e18, 1e18, 1e18], "children": roots})
        document["scenes"][0]["nodes"] = [len(document["nodes"]) - 1]

    yield "gltf", "issue14-count-4294967295.gltf", variant(huge_count)
    yield "gltf", "issue14-sparse-bomb.gltf", variant(sparse_bomb)
    yield "gltf", "issue14-buffer-uri-dot.gltf", variant(dot_uri)
    yield "pipeline", "issue14-camera-1e18.gltf", variant(far_camera)
    yield "pipeline", "issue14-geometry-1e18.gltf", variant(far_geometry)
    glb = to_glb(room)
    yield "gltf", "issue14-glb-truncated.glb", b"\1" + glb[: len(glb) // 2]
    yield "gltf", "issue14-glb-chunk-length.glb", b"\1" + glb[:12] + struct.pack("<I", 1 << 30) + glb[16:]
    yield "obj", "issue14-nan.obj", b"\0v nan 0 0\nv hello 1 0\nv 0 0 1\nf 1 2 3\n"


def main():
    check = "--check" in sys.argv[1:]
    stale = 0
    crashes = ROOT / "tests" / "fuzz" / "crashes"
    for (target, name, data), folder in [(seed, OUT) for seed in seeds()] + [
            (seed, crashes) for seed in regressions()]:
        path = folder / target / name
        if check:
            if not path.exists() or path.read_bytes() != data:
                print(f"{path} is out of date: run tools/make_fuzz_corpus.py", file=sys.stderr)
                stale = 1
            continue
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(data)
    if not check:
        print(f"wrote {OUT}")
    return stale


if __name__ == "__main__":
    sys.exit(main())
