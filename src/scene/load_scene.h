#pragma once
// Entry point for scene files: picks the loader by extension (.gltf, .glb, .obj), applies a
// --materials override file, then validates (validate_scene.h). Every error message starts
// with the file's path and names the place in it.
#include <cstdint>
#include <string>

#include "core/expected.h"
#include "scene/scene.h"

namespace daisy {

enum class MtlConvention {
    Standard,  // Kd reflectance, Ke emission
    DaisyRiot,  // also: Ks = fluorescent colour; black Kd with non-zero Ke = UV lamp (blacklight)
};

struct SceneLoadOptions {
    MtlConvention mtlConvention = MtlConvention::Standard;
    std::string materialsPath;  // --materials FILE.json; empty = none
    uint64_t maxMemoryBytes = 0;  // --max-memory: bounds what loading allocates; 0 = no limit
};

Expected<Scene> loadScene(const std::string& path, const SceneLoadOptions& options = {});

}  // namespace daisy
