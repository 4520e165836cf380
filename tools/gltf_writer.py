"""Shared by the scene generators in tools/: builds a glTF 2.0 document with one buffer and
writes it, embedded (base64 data URI) with a check that the committed file is up to date, or
binary (.gltf + .bin, or .glb) for large generated scenes.

    builder = GltfBuilder()
    builder.add_mesh("floor", positions, material=0)             # non-indexed triangles
    builder.add_mesh("box", positions, material=1, indices=[...])  # indexed (uint32)
    builder.add_node({"name": "camera", "camera": 0, "translation": [...]})
    document = builder.document("scene", "DaisyRiot tools/make_x.py", materials, cameras)
    sys.exit(write_or_check(TARGET, document, "tools/make_x.py"))
    # or: write_binary(Path("big.glb"), builder, builder.document(...))

Meshes with several primitives (one per material) and linked duplicates (one mesh, many nodes):
    mesh = builder.add_primitives("column", [(positions, material, indices), ...], node=False)
    builder.add_node({"name": "column.001", "mesh": mesh, "translation": [...]})
"""
import base64
import json
import struct
from pathlib import Path

import generated

EXTENSION = "DAISY_materials_spectral"
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
FLOAT, UNSIGNED_INT = 5126, 5125


class GltfBuilder:
    def __init__(self):
        self.blob = bytearray()
        self.accessors, self.buffer_views, self.meshes, self.nodes = [], [], [], []

    def _view(self, data, target):
        self.buffer_views.append({"buffer": 0, "byteOffset": len(self.blob),
                                  "byteLength": len(data), "target": target})
        self.blob += data
        return len(self.buffer_views) - 1

    def add_mesh(self, name, positions, material, indices=None):
        """One mesh of TRIANGLES (3 positions a triangle, or 3 indices a triangle) and a node."""
        self.add_primitives(name, [(positions, material, indices)])

    def add_primitives(self, name, primitives, node=True):
        """One mesh of one TRIANGLES primitive per (positions, material, indices or None), and a
        node for it unless `node` is false. Returns the mesh's index."""
        self.meshes.append({"name": name,
                            "primitives": [self._primitive(*p) for p in primitives]})
        if node:
            self.add_node({"name": name, "mesh": len(self.meshes) - 1})
        return len(self.meshes) - 1

    def _primitive(self, positions, material, indices):
        data = b"".join(struct.pack("<3f", *p) for p in positions)
        self.accessors.append({
            "bufferView": self._view(data, ARRAY_BUFFER), "componentType": FLOAT,
            "count": len(positions), "type": "VEC3",
            "min": [min(p[a] for p in positions) for a in range(3)],
            "max": [max(p[a] for p in positions) for a in range(3)]})
        primitive = {"attributes": {"POSITION": len(self.accessors) - 1}}
        if indices is not None:
            data = struct.pack(f"<{len(indices)}I", *indices)
            self.accessors.append({"bufferView": self._view(data, ELEMENT_ARRAY_BUFFER),
                                   "componentType": UNSIGNED_INT, "count": len(indices),
                                   "type": "SCALAR"})
            primitive["indices"] = len(self.accessors) - 1
        primitive.update({"material": material, "mode": 4})
        return primitive

    def add_node(self, node):
        self.nodes.append(node)

    def document(self, scene_name, generator, materials, cameras):
        return {
            "asset": {"version": "2.0", "generator": generator},
            "extensionsUsed": [EXTENSION],
            "scene": 0,
            "scenes": [{"name": scene_name, "nodes": list(range(len(self.nodes)))}],
            "nodes": self.nodes,
            "cameras": cameras,
            "meshes": self.meshes,
            "materials": materials,
            "accessors": self.accessors,
            "bufferViews": self.buffer_views,
            "buffers": [{"byteLength": len(self.blob),
                         "uri": "data:application/octet-stream;base64,"
                         + base64.b64encode(bytes(self.blob)).decode("ascii")}],
        }


def write_or_check(target, document, generator):
    """Writes `document` as JSON to `target`, or compares under --check (tools/generated.py)."""
    return generated.write_or_check(target, json.dumps(document, indent=1) + "\n", generator)


def write_binary(target, builder, document):
    """Writes `document` (from builder.document) with its buffer in binary: a .glb (target ends
    in .glb), or target (.gltf) and its buffer beside it as target's name with .bin."""
    target = Path(target)
    target.parent.mkdir(parents=True, exist_ok=True)
    blob = bytes(builder.blob)
    if target.suffix == ".glb":
        document["buffers"] = [{"byteLength": len(blob)}]
        text = json.dumps(document, separators=(",", ":")).encode()
        text += b" " * (-len(text) % 4)
        blob += b"\0" * (-len(blob) % 4)
        chunks = (struct.pack("<I4s", len(text), b"JSON") + text
                  + struct.pack("<I4s", len(blob), b"BIN\0") + blob)
        target.write_bytes(struct.pack("<4sII", b"glTF", 2, 12 + len(chunks)) + chunks)
    else:
        binary = target.with_suffix(".bin")
        document["buffers"] = [{"byteLength": len(blob), "uri": binary.name}]
        binary.write_bytes(blob)
        target.write_text(json.dumps(document, indent=1) + "\n")
