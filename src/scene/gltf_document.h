#pragma once
// The checks a glTF file gets before tinygltf parses it, on the raw bytes and the
// raw JSON (bounded_json.h): the GLB container (header, chunk lengths and types), the asset
// version, and every buffer and image uri (a folder or a missing file would otherwise reach
// tinygltf as a std::bad_alloc). Internal to scene/ (gltf_loader.cpp). Messages name the field,
// the value and what was expected, without the file name (the caller adds it).
#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/expected.h"
#include "scene/load_budget.h"

namespace daisy {

// The chunks of a GLB file (glTF 2.0 section 4.4), as views into its bytes.
struct GlbChunks {
    std::string_view json;
    std::string_view bin;
    bool hasBin = false;
};

// Checks the 12-byte header (magic "glTF", version 2, length = the file's size) and the chunk
// headers (the first is JSON, the optional second BIN, each within the file).
Expected<GlbChunks> splitGlb(std::string_view bytes);

// asset.version must be "2.<minor>" and asset.minVersion, when given, at most 2.0: daisy reads
// glTF 2.0.
Expected<void> checkGltfAsset(const nlohmann::json& root);

// Each buffers[k]: byteLength an integer >= 0; a uri that is empty (the GLB BIN chunk), a data:
// uri, or a regular file beside the scene holding at least byteLength bytes; and the sum charged
// to `budget`. Each images[k].uri that names a file must not be a folder. `folder` is the
// scene's folder; `binBytes` the size of the GLB BIN chunk (0 for .gltf).
Expected<void> checkGltfResources(const nlohmann::json& root, const std::string& folder,
                                  uint64_t binBytes, bool isGlb, LoadBudget& budget);

}  // namespace daisy
