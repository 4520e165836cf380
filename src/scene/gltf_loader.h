#pragma once
// glTF 2.0 (.gltf and .glb) through tinygltf. Internal to scene/; use loadScene().
// Node hierarchy (matrix or TRS) flattened depth-first in scene order; TRIANGLES, STRIP and
// FAN primitives (indexed or not) triangulated; points and lines refused; baseColorFactor,
// emissiveFactor x KHR_materials_emissive_strength, DAISY_materials_spectral; perspective
// cameras. Returns the scene before validate_scene's checks.
#include <string>

#include "core/expected.h"
#include "scene/scene.h"

namespace daisy {

Expected<Scene> loadGltf(const std::string& path);

}  // namespace daisy
