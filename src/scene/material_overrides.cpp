#include "scene/material_overrides.h"

#include <cctype>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/strings.h"
#include "scene/bounded_json.h"
#include "scene/material_extension.h"

namespace daisy {
namespace {

// The JSON path of a top-level member: the bare name when it reads unambiguously, otherwise
// ["name"] so dots or brackets in a material name cannot be mistaken for path steps.
std::string memberPath(const std::string& name) {
    bool plain = !name.empty();
    for (char c : name) {
        plain = plain && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-');
    }
    return plain ? name : concat("[\"", name, "\"]");
}

// "a, b, c": the scene's material names, each once, in scene order.
std::string materialNames(const Scene& scene) {
    std::vector<std::string> names;
    std::string out;
    for (const Material& material : scene.materials) {
        bool seen = false;
        for (const std::string& name : names)
            seen = seen || name == material.name;
        if (seen) continue;
        names.push_back(material.name);
        if (!out.empty()) out += ", ";
        out += material.name;
    }
    return out.empty() ? "no materials" : out;
}

bool hasMaterial(const Scene& scene, const std::string& name) {
    for (const Material& material : scene.materials) {
        if (material.name == name) return true;
    }
    return false;
}

Expected<nlohmann::json> readJsonFile(const std::string& path) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) return Error{path + ": no such file"};
    if (std::filesystem::is_directory(path, ec)) return Error{path + ": is a directory"};
    // A device or pipe (/dev/zero) would be read without end: only regular files, their size
    // checked against the JSON limit before reading.
    if (!std::filesystem::is_regular_file(path, ec)) return Error{path + ": is not a regular file"};
    const uintmax_t bytes = std::filesystem::file_size(path, ec);
    if (ec) return Error{path + ": cannot read its size: " + ec.message()};
    if (bytes > kMaxJsonBytes) {
        return Error{concat(path, ": the JSON text is ", formatBytes(double(bytes)), ", over the ",
                            formatBytes(double(kMaxJsonBytes)), " limit")};
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path + ": cannot open for reading"};
    std::string text(std::size_t(bytes), '\0');
    in.read(text.data(), std::streamsize(text.size()));
    if (in.bad()) return Error{path + ": read failed"};
    text.resize(std::size_t(in.gcount()));
    auto parsed = parseBoundedJson(text, kMaxJsonDepth, JsonKeys::Unique);
    if (!parsed) return withContext(parsed.error(), path);
    return parsed;
}

}  // namespace

Expected<void> applyMaterialOverrides(Scene& scene, const std::string& jsonPath) {
    auto document = readJsonFile(jsonPath);
    if (!document) return document.error();
    if (!document->is_object()) {
        return Error{concat(jsonPath, ": expected an object mapping material names to ",
                            kSpectralExtensionName, " objects, got ", document->type_name())};
    }
    // Parse and check every entry before changing the scene, so an error leaves it untouched.
    std::vector<std::pair<std::string, MaterialExtension>> overrides;
    for (const auto& item : document->items()) {
        const std::string& name = item.key();
        if (!hasMaterial(scene, name)) {
            const std::string scenePath = scene.path.empty() ? "the scene" : scene.path;
            return Error{concat(jsonPath, ": material '", name, "' is not in ", scenePath,
                                " (it has: ", materialNames(scene), ")")};
        }
        auto extension = parseMaterialExtension(item.value(), memberPath(name));
        if (!extension) return withContext(extension.error(), jsonPath);
        overrides.emplace_back(name, std::move(*extension));
    }
    for (const auto& [name, extension] : overrides) {
        for (Material& material : scene.materials) {
            if (material.name == name) mergeExtension(material.spectral, extension);
        }
    }
    return {};
}

}  // namespace daisy
