#include "scene/gltf_features.h"

#include <algorithm>
#include <array>
#include <map>
#include <string_view>

#include "core/strings.h"
#include "scene/bounded_json.h"
#include "scene/material_extension.h"

namespace daisy {
namespace {

constexpr std::array<std::string_view, 9> kSupported = {
    "KHR_materials_emissive_strength", kSpectralExtensionName,    "KHR_mesh_quantization",
    "KHR_texture_transform",           "KHR_lights_punctual",     "EXT_mesh_gpu_instancing",
    "EXT_meshopt_compression",         "KHR_meshopt_compression", "KHR_draco_mesh_compression"};

// Material extensions a diffuse solve drops, and what the warning calls them.
constexpr std::array<std::pair<std::string_view, std::string_view>, 10> kMaterialFeatures = {{
    {"KHR_materials_transmission", "transmission"},
    {"KHR_materials_volume", "volume (refraction)"},
    {"KHR_materials_clearcoat", "clearcoat"},
    {"KHR_materials_sheen", "sheen"},
    {"KHR_materials_specular", "specular"},
    {"KHR_materials_ior", "index of refraction"},
    {"KHR_materials_iridescence", "iridescence"},
    {"KHR_materials_anisotropy", "anisotropy"},
    {"KHR_materials_unlit", "unlit shading"},
    {"KHR_materials_pbrSpecularGlossiness", "specular-glossiness"},
}};

std::string materialName(const nlohmann::json& material, std::size_t index) {
    const nlohmann::json* name = jsonMember(material, "name");
    if (name != nullptr && name->is_string() && !name->get<std::string>().empty())
        return concat("'", name->get<std::string>(), "'");
    return concat("materials[", index, "]");
}

// "'a', 'b', 'c' and 2 more".
std::string nameList(const std::vector<std::string>& names) {
    constexpr std::size_t kShown = 4;
    std::string list;
    for (std::size_t i = 0; i < names.size() && i < kShown; ++i) {
        if (i > 0) list += ", ";
        list += names[i];
    }
    if (names.size() > kShown) list += concat(" and ", names.size() - kShown, " more");
    return list;
}

std::vector<std::string> stringArray(const nlohmann::json& root, const char* key) {
    std::vector<std::string> out;
    const nlohmann::json* array = jsonMember(root, key);
    if (array == nullptr || !array->is_array()) return out;
    for (const nlohmann::json& value : *array) {
        if (value.is_string()) out.push_back(value.get<std::string>());
    }
    return out;
}

// Extensions that change nothing a diffuse solve sees, as Blender writes them on every material:
// KHR_materials_ior (it only shapes specular and transmission, warned on their own) and
// KHR_materials_specular with a zero specular colour or strength.
bool hasNoEffectOnDiffuse(const std::string& name, const nlohmann::json& value) {
    if (name == "KHR_materials_ior") return true;
    if (name != "KHR_materials_specular") return false;
    const nlohmann::json* factor = jsonMember(value, "specularFactor");
    if (factor != nullptr && factor->is_number() && factor->get<double>() == 0) return true;
    const nlohmann::json* colour = jsonMember(value, "specularColorFactor");
    if (colour == nullptr || !colour->is_array()) return false;
    return std::all_of(colour->begin(), colour->end(), [](const nlohmann::json& c) {
        return c.is_number() && c.get<double>() == 0;
    });
}

}  // namespace

bool isSupportedGltfExtension(const std::string& name) {
    return std::find(kSupported.begin(), kSupported.end(), name) != kSupported.end();
}

Expected<void> checkRequiredGltfExtensions(const nlohmann::json& root) {
    for (const std::string& name : stringArray(root, "extensionsRequired")) {
        if (isSupportedGltfExtension(name)) continue;
        return Error{concat("extensionsRequired: ", name,
                            " is not supported: the file cannot be read without it")};
    }
    return {};
}

void warnDroppedGltfFeatures(const nlohmann::json& root, const std::string& path,
                             std::vector<std::string>& warnings) {
    // Feature -> the materials that use it, in file order of first use.
    std::vector<std::pair<std::string, std::vector<std::string>>> features;
    const auto note = [&](std::string_view feature, const std::string& name) {
        auto it = std::find_if(features.begin(), features.end(),
                               [&](const auto& entry) { return entry.first == feature; });
        if (it == features.end()) {
            features.emplace_back(std::string(feature), std::vector<std::string>{});
            it = features.end() - 1;
        }
        it->second.push_back(name);
    };
    std::vector<std::string> materialExtensions;
    if (const nlohmann::json* materials = jsonMember(root, "materials");
        materials != nullptr && materials->is_array()) {
        for (std::size_t i = 0; i < materials->size(); ++i) {
            const nlohmann::json& material = (*materials)[i];
            const std::string name = materialName(material, i);
            double metallic = 1;  // glTF's default
            if (const nlohmann::json* pbr = jsonMember(material, "pbrMetallicRoughness")) {
                if (const nlohmann::json* factor = jsonMember(*pbr, "metallicFactor");
                    factor != nullptr && factor->is_number()) {
                    metallic = factor->get<double>();
                }
            }
            if (metallic > 0) note("metallic", name);
            if (const nlohmann::json* mode = jsonMember(material, "alphaMode");
                mode != nullptr && mode->is_string()) {
                if (*mode == "BLEND") note("alpha blending", name);
                if (*mode == "MASK") note("alpha masking", name);
            }
            const nlohmann::json* extensions = jsonMember(material, "extensions");
            if (extensions == nullptr || !extensions->is_object()) continue;
            for (const auto& [key, value] : extensions->items()) {
                if (isSupportedGltfExtension(key)) continue;
                materialExtensions.push_back(key);
                if (hasNoEffectOnDiffuse(key, value)) continue;
                // A structured binding is not capturable before clang 16: name it.
                const std::string& extension = key;
                const auto known =
                    std::find_if(kMaterialFeatures.begin(), kMaterialFeatures.end(),
                                 [&](const auto& entry) { return entry.first == extension; });
                note(known != kMaterialFeatures.end() ? std::string(known->second) : key, name);
            }
        }
    }
    for (const auto& [feature, names] : features) {
        const std::string users = names.size() == 1
            ? concat("material ", names[0])
            : concat(names.size(), " materials: ", nameList(names));
        warnings.push_back(concat(path, ": ", feature, " (", users,
                                  ") is not modelled: those surfaces are solved and rendered "
                                  "as diffuse"));
    }
    for (const std::string& name : stringArray(root, "extensionsUsed")) {
        if (isSupportedGltfExtension(name)) continue;
        if (std::find(materialExtensions.begin(), materialExtensions.end(), name) !=
            materialExtensions.end()) {
            continue;  // already named with its materials
        }
        warnings.push_back(
            concat(path, ": extensionsUsed: ", name, " is not supported and is ignored"));
    }
}

}  // namespace daisy
