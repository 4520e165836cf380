#pragma once
// Scripted material edits (`daisy view --edit`, issue 15 item 6) and the editor panel's edits:
// `NAME.FIELD=VALUE`, where FIELD is a member of DAISY_materials_spectral (reflectance, emission
// or fluorescence) and VALUE is `rgb(r, g, b)` or that member's JSON (docs/scene_format.md), e.g.
//     Red.reflectance=rgb(0,1,0)
//     Lamp.emission={"blackbody": 2700, "scale": 5}
//     Paper.fluorescence={"preset": "fluorescein"}
// The value is checked by the scene loader's own parser (scene/material_extension.h); the physical
// check (reflectance + absorption <= 1) is Session::setMaterial's.
#include <cstddef>
#include <string>
#include <vector>

#include "core/expected.h"
#include "scene/material.h"
#include "scene/scene.h"

namespace daisy::viewer {

struct MaterialEdit {
    std::string text;  // as given, for messages
    std::string materialName;
    MaterialExtension extension;  // the one member FIELD sets
};

// Parses `text`; errors quote it and say what is wrong.
Expected<MaterialEdit> parseMaterialEdit(const std::string& text);

// The indices of the scene's materials named edit.materialName (names may repeat); an error that
// lists the scene's names when there is none.
Expected<std::vector<std::size_t>> editTargets(const Scene& scene, const MaterialEdit& edit);

// `material` with the edit's member overlaid (scene/material.h mergeExtension).
Material applyEdit(Material material, const MaterialEdit& edit);

}  // namespace daisy::viewer
