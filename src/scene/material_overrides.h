#pragma once
// --materials FILE.json: a JSON object mapping material names to DAISY_materials_spectral
// objects, overlaid on the scene's materials of those names (either scene format). A name the
// scene does not have is an error that lists the names it has.
#include <string>

#include "core/expected.h"
#include "scene/scene.h"

namespace daisy {

Expected<void> applyMaterialOverrides(Scene& scene, const std::string& jsonPath);

}  // namespace daisy
