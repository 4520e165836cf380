#pragma once
// Wavefront OBJ + MTL through tinyobjloader. Internal to scene/; use loadScene().
// Polygons triangulated; Kd -> baseColor, Ke -> emissiveRgb; with MtlConvention::DaisyRiot also
// Ks -> FluorescentColor and black Kd with non-zero Ke -> blacklight emission.
#include <cstdint>
#include <string>

#include "core/expected.h"
#include "scene/load_scene.h"
#include "scene/scene.h"

namespace daisy {

// Coordinates, face references and MTL numbers are checked with their line first
// (obj_syntax.h); `maxMemoryBytes` bounds what loading may allocate (0 = no limit).
Expected<Scene> loadObj(const std::string& path, MtlConvention convention,
                        uint64_t maxMemoryBytes = 0);

}  // namespace daisy
