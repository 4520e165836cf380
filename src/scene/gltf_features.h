#pragma once
// What a glTF file asks for that daisy does or does not model, read from the raw JSON
// (bounded_json.h) before tinygltf parses it. Internal to scene/ (gltf_loader.cpp).
// - extensionsRequired naming an extension daisy cannot read is refused in one line that names
//   it (Draco and meshopt compression are decoded first: gltf_draco.h, gltf_meshopt.h).
// - Every other unsupported extension in extensionsUsed, and each material feature a diffuse
//   radiosity solve drops (metallic, alpha blending and masking, transmission, clearcoat, ...),
//   gets one warning line naming the materials that use it.
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/expected.h"

namespace daisy {

// The extensions the loader reads (gltf_loader.h lists what each gives).
bool isSupportedGltfExtension(const std::string& name);

// Refuses (message without the file name) an extensionsRequired entry daisy does not read.
Expected<void> checkRequiredGltfExtensions(const nlohmann::json& root);

// Appends "path: ..." warning lines, one per dropped feature or ignored extension.
void warnDroppedGltfFeatures(const nlohmann::json& root, const std::string& path,
                             std::vector<std::string>& warnings);

}  // namespace daisy
