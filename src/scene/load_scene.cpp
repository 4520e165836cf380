#include "scene/load_scene.h"

#include <filesystem>

#include "core/strings.h"
#include "scene/gltf_loader.h"
#include "scene/material_overrides.h"
#include "scene/obj_loader.h"
#include "scene/validate_scene.h"

namespace daisy {

Expected<Scene> loadScene(const std::string& path, const SceneLoadOptions& options) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
        return Error{concat(path, ": no such file")};
    }
    const std::string extension = toLower(std::filesystem::path(path).extension().string());
    Expected<Scene> scene = Error{};
    if (extension == ".gltf" || extension == ".glb") {
        scene = loadGltf(path, options.maxMemoryBytes);
    } else if (extension == ".obj") {
        scene = loadObj(path, options.mtlConvention, options.maxMemoryBytes);
    } else {
        return Error{concat(path, ": unknown scene format '", extension,
                            "' (expected .gltf, .glb or .obj)")};
    }
    if (!scene) return scene;
    if (!options.materialsPath.empty()) {
        if (auto ok = applyMaterialOverrides(*scene, options.materialsPath); !ok) return ok.error();
    }
    if (auto ok = validateScene(*scene); !ok) return ok.error();
    return scene;
}

}  // namespace daisy
