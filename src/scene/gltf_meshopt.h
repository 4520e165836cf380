#pragma once
// EXT_meshopt_compression (and its KHR_ successor's identical layout) through
// libmeshoptimizer: every compressed bufferView is decoded (vertex or index codec,
// then the octahedral, quaternion or exponential filter) into one new buffer, the views are
// pointed at it and the extension removed, so tinygltf and the accessor readers see plain glTF.
// Internal to scene/ (gltf_loader.cpp). Messages name the bufferView without the file.
#include <initializer_list>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/expected.h"
#include "scene/load_budget.h"

namespace daisy {

// A data: uri (base64) holding `bytes`.
std::string gltfDataUri(std::string_view bytes);

// What the decoders (this one and gltf_draco.cpp) do last, so that the result parses as a
// .gltf: every buffer without a uri gets a data: uri, buffer 0 the GLB BIN chunk `glbBin` when
// there is one and any other 4 zero bytes no view reads (tinygltf refuses an empty data: uri);
// then the extension `names` leave extensionsUsed and extensionsRequired.
void inlineBuffersAndDropExtensions(nlohmann::json& root, std::string_view glbBin,
                                    std::initializer_list<const char*> names);

// The bytes of buffers[index]: the GLB BIN chunk (`glbBin`, buffer 0 without a uri), a data:
// uri, or a file beside the scene in `folder`. Shared with gltf_draco.cpp.
Expected<std::string> gltfBufferBytes(const nlohmann::json& buffer, std::size_t index,
                                      const std::string& folder, std::string_view glbBin);

// True when some bufferView of `root` carries the compression extension.
bool usesMeshoptCompression(const nlohmann::json& root);

// Decodes in place: `root` gains a buffer with a data: uri holding the decoded views, and loses
// the extension from extensionsUsed and extensionsRequired. Fallback buffers (no uri) become
// 4-byte data: buffers no view reads. `folder` is the scene's folder (for buffers in files),
// `glbBin` the GLB BIN chunk (buffer 0 without a uri), which becomes a data: uri too, so the result
// is parsed as a .gltf.
Expected<void> decodeMeshoptViews(nlohmann::json& root, const std::string& folder,
                                  std::string_view glbBin, LoadBudget& budget);

}  // namespace daisy
