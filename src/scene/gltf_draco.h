#pragma once
// KHR_draco_mesh_compression through libdraco: every primitive carrying the extension
// has its bufferView decoded with draco::Decoder, and the indices and the attributes the
// extension names (POSITION, NORMAL, TEXCOORD_n, COLOR_n, ...) are written as plain glTF into one
// new buffer: uint32 indices and float attributes, with the primitive's accessors pointed at
// them. The extension is then removed, so tinygltf and the accessor readers see plain glTF.
// Internal to scene/ (gltf_loader.cpp). Messages name the mesh and the primitive without the file.
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/expected.h"
#include "scene/load_budget.h"

namespace daisy {

// True when some mesh primitive of `root` carries KHR_draco_mesh_compression.
bool usesDracoCompression(const nlohmann::json& root);

// Decodes in place, like decodeMeshoptViews (gltf_meshopt.h): `root` gains a data: buffer with
// the decoded data and loses the extension; buffers without a uri (the GLB BIN chunk) become
// data: uris, so the result is parsed as a .gltf. Every accessor count, the attribute ids and
// the component counts are checked against the decoded mesh.
Expected<void> decodeDracoPrimitives(nlohmann::json& root, const std::string& folder,
                                     std::string_view glbBin, LoadBudget& budget);

}  // namespace daisy
