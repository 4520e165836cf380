#pragma once
// KHR_lights_punctual, read from the raw JSON (bounded_json.h): the file's light
// list, checked, and a node's light placed in world space. Internal to scene/ (gltf_loader.cpp).
// Messages name the place ("extensions.KHR_lights_punctual.lights[1].intensity") without the
// file (the caller adds it).
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/expected.h"
#include "scene/gltf_accessors.h"
#include "scene/scene.h"

namespace daisy {

inline constexpr const char* kLightsExtensionName = "KHR_lights_punctual";

// The lights of root.extensions.KHR_lights_punctual.lights (empty without the extension), in
// their node-local frame (position 0, direction -z).
Expected<std::vector<PunctualLight>> readGltfLights(const nlohmann::json& root);

// The light node `node` (raw JSON) carries, placed by `world`; nullopt when it has none.
Expected<std::optional<PunctualLight>> placeGltfLight(const nlohmann::json& node,
                                                      const std::vector<PunctualLight>& lights,
                                                      const GltfMatrix& world);

}  // namespace daisy
