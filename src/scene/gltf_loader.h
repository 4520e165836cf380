#pragma once
// glTF 2.0 (.gltf and .glb) through tinygltf. Internal to scene/; use loadScene().
// Node hierarchy (matrix or TRS) flattened depth-first in scene order; TRIANGLES, STRIP and
// FAN primitives (indexed or not) triangulated; points and lines refused; baseColorFactor,
// emissiveFactor x KHR_materials_emissive_strength, DAISY_materials_spectral; perspective
// cameras. Returns the scene before validate_scene's checks. Before tinygltf parses anything, the
// JSON is read by a bounded, non-recursive parser and the GLB container, asset version and
// buffer uris are checked (gltf_document.h); the spectral and emissive-strength extensions are
// read from that raw JSON.
#include <cstdint>
#include <string>

#include "core/expected.h"
#include "scene/scene.h"

namespace daisy {

// `maxMemoryBytes` bounds what the file can make the loader allocate (load_budget.h); 0 = none.
Expected<Scene> loadGltf(const std::string& path, uint64_t maxMemoryBytes = 0);

}  // namespace daisy
