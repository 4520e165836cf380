#include "scene/gltf_lights.h"

#include <cmath>
#include <numbers>
#include <string>

#include "core/strings.h"
#include "scene/bounded_json.h"
#include "scene/material_extension.h"

namespace daisy {
namespace {

Expected<double> number(const nlohmann::json& object, const char* key, double fallback, double low,
                        double high, const std::string& where) {
    const nlohmann::json* value = jsonMember(object, key);
    if (value == nullptr) return fallback;
    if (!value->is_number()) return Error{concat(where, ".", key, ": expected a number")};
    const double x = value->get<double>();
    if (!(x >= low && x <= high)) {
        return Error{concat(where, ".", key, ": ", formatNumber(x), " is outside [",
                            formatNumber(low), ", ", formatNumber(high), "]")};
    }
    return x;
}

}  // namespace

Expected<std::vector<PunctualLight>> readGltfLights(const nlohmann::json& root) {
    std::vector<PunctualLight> lights;
    const nlohmann::json* extensions = jsonMember(root, "extensions");
    const nlohmann::json* extension =
        extensions != nullptr ? jsonMember(*extensions, kLightsExtensionName) : nullptr;
    if (extension == nullptr) return lights;
    const std::string base = concat("extensions.", kLightsExtensionName, ".lights");
    const nlohmann::json* list = jsonMember(*extension, "lights");
    if (list == nullptr || !list->is_array()) return Error{base + ": expected an array"};
    constexpr double kMaxIntensity = 1e30;  // validate_scene's emission bound
    for (std::size_t k = 0; k < list->size(); ++k) {
        const nlohmann::json& object = (*list)[k];
        const std::string where = concat(base, "[", k, "]");
        if (!object.is_object()) return Error{where + ": expected an object"};
        PunctualLight light;
        const nlohmann::json* name = jsonMember(object, "name");
        light.name =
            name != nullptr && name->is_string() ? name->get<std::string>() : concat("light", k);
        const nlohmann::json* type = jsonMember(object, "type");
        if (type == nullptr || !type->is_string()) return Error{where + ".type: expected a string"};
        if (*type == "point") {
            light.type = PunctualLight::Type::Point;
        } else if (*type == "spot") {
            light.type = PunctualLight::Type::Spot;
        } else if (*type == "directional") {
            light.type = PunctualLight::Type::Directional;
        } else {
            return Error{concat(where, ".type: \"", type->get<std::string>(),
                                "\" is not point, spot or directional")};
        }
        if (const nlohmann::json* color = jsonMember(object, "color")) {
            if (!color->is_array() || color->size() != 3) {
                return Error{where + ".color: expected 3 numbers"};
            }
            for (std::size_t c = 0; c < 3; ++c) {
                const nlohmann::json& value = (*color)[c];
                if (!value.is_number() || !(value.get<double>() >= 0 && value.get<double>() <= 1)) {
                    return Error{concat(where, ".color[", c, "]: expected a number in [0, 1]")};
                }
                light.color[c] = value.get<double>();
            }
        }
        auto intensity = number(object, "intensity", 1, 0, kMaxIntensity, where);
        if (!intensity) return intensity.error();
        light.intensity = *intensity;
        auto range = number(object, "range", 0, 0, 1e30, where);
        if (!range) return range.error();
        if (jsonMember(object, "range") != nullptr && !(*range > 0)) {
            return Error{where +
                         ".range: 0 is not allowed (glTF: range > 0; leave it out for "
                         "an unlimited range)"};
        }
        light.range = *range;
        if (light.type == PunctualLight::Type::Spot) {
            const nlohmann::json* spot = jsonMember(object, "spot");
            const std::string spotWhere = where + ".spot";
            if (spot == nullptr || !spot->is_object()) {
                return Error{spotWhere + ": a spot light needs its spot object (it may be {})"};
            }
            auto outer = number(*spot, "outerConeAngle", std::numbers::pi / 4, 0,
                                std::numbers::pi / 2, spotWhere);
            if (!outer) return outer.error();
            auto inner = number(*spot, "innerConeAngle", 0, 0, *outer, spotWhere);
            if (!inner) return inner.error();
            light.innerConeRad = *inner;
            light.outerConeRad = *outer;
        }
        if (const nlohmann::json* spectral = jsonMember(object, "extensions") != nullptr
                ? jsonMember(*jsonMember(object, "extensions"), kSpectralExtensionName)
                : nullptr) {
            auto parsed = parseMaterialExtension(
                *spectral, concat(where, ".extensions.", kSpectralExtensionName));
            if (!parsed) return parsed.error();
            light.spectrum = parsed->emission;
        }
        lights.push_back(std::move(light));
    }
    return lights;
}

Expected<std::optional<PunctualLight>> placeGltfLight(const nlohmann::json& node,
                                                      const std::vector<PunctualLight>& lights,
                                                      const GltfMatrix& world) {
    const nlohmann::json* extensions = jsonMember(node, "extensions");
    const nlohmann::json* extension =
        extensions != nullptr ? jsonMember(*extensions, kLightsExtensionName) : nullptr;
    if (extension == nullptr) return std::optional<PunctualLight>{};
    const std::string where = concat("extensions.", kLightsExtensionName, ".light");
    const nlohmann::json* index = jsonMember(*extension, "light");
    if (index == nullptr || !index->is_number_integer()) {
        return Error{where + ": expected an integer"};
    }
    const long long k = index->get<long long>();
    if (k < 0 || static_cast<std::size_t>(k) >= lights.size()) {
        return Error{concat(where, ": ", gltfOutOfRange("light", k, lights.size()))};
    }
    PunctualLight light = lights[static_cast<std::size_t>(k)];
    const GltfMatrix& m = world;
    light.position = {m[12], m[13], m[14]};
    const Vec3d direction{-m[8], -m[9], -m[10]};  // the node's -z
    if (light.type != PunctualLight::Type::Point) {
        // A point light needs only its position, which a zero scale keeps.
        if (!(length(direction) > 0)) {
            return Error{where + ": the node's transform is degenerate (no direction for the " +
                         (light.type == PunctualLight::Type::Spot ? "spot" : "directional") +
                         " light)"};
        }
        light.direction = normalize(direction);
    }
    return std::optional<PunctualLight>{std::move(light)};
}

}  // namespace daisy
