#pragma once
// Wavefront OBJ + MTL through tinyobjloader. Internal to scene/; use loadScene().
// Polygons triangulated; Kd -> baseColor, Ke -> emissiveRgb; with MtlConvention::DaisyRiot also
// Ks -> FluorescentColor and black Kd with non-zero Ke -> blacklight emission.
#include <string>

#include "core/expected.h"
#include "scene/load_scene.h"
#include "scene/scene.h"

namespace daisy {

Expected<Scene> loadObj(const std::string& path, MtlConvention convention);

}  // namespace daisy
