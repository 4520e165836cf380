#include "scene/gltf_textures.h"

#include <tiny_gltf.h>

#include <cmath>
#include <filesystem>
#include <string_view>

#include "core/strings.h"
#include "scene/bounded_json.h"

namespace daisy {
namespace {

// Numbers array member `key` of `object` of length `size`, or `fallback` when absent.
template <std::size_t N>
Expected<std::array<double, N>> readArray(const nlohmann::json& object, const char* key,
                                          std::array<double, N> fallback,
                                          const std::string& where) {
    const nlohmann::json* value = jsonMember(object, key);
    if (value == nullptr) return fallback;
    if (!value->is_array() || value->size() != N) {
        return Error{concat(where, ".", key, ": expected an array of ", N, " numbers")};
    }
    std::array<double, N> out{};
    for (std::size_t k = 0; k < N; ++k) {
        if (!(*value)[k].is_number() || !std::isfinite((*value)[k].get<double>())) {
            return Error{concat(where, ".", key, "[", k, "]: expected a finite number")};
        }
        out[k] = (*value)[k].get<double>();
    }
    return out;
}

Expected<int> readTexCoord(const nlohmann::json& object, int fallback, const std::string& where) {
    const nlohmann::json* value = jsonMember(object, "texCoord");
    if (value == nullptr) return fallback;
    if (!value->is_number_integer() || value->get<long long>() < 0) {
        return Error{concat(where, ".texCoord: expected an integer >= 0")};
    }
    return static_cast<int>(std::min<long long>(value->get<long long>(), 1 << 20));
}

TextureWrap wrapOf(int mode) {
    if (mode == static_cast<int>(TextureWrap::ClampToEdge)) return TextureWrap::ClampToEdge;
    if (mode == static_cast<int>(TextureWrap::MirroredRepeat)) return TextureWrap::MirroredRepeat;
    return TextureWrap::Repeat;
}

// Why tinygltf handed over no bytes for `image`.
std::string unreadableImage(const tinygltf::Image& image, const std::string& scenePath) {
    if (!image.uri.empty() && !image.uri.starts_with("data:")) {
        const std::filesystem::path file =
            std::filesystem::path(scenePath).parent_path() / image.uri;
        std::error_code error;
        if (!std::filesystem::exists(file, error)) return "the image file does not exist";
        if (std::filesystem::file_size(file, error) == 0 && !error) {
            return "the image file is empty (0 bytes)";
        }
    }
    return "the image cannot be read (no data)";
}

}  // namespace

bool keepEncodedGltfImage(tinygltf::Image* target, int, std::string*, std::string*, int, int,
                          const unsigned char* bytes, int size, void*) {
    target->image.assign(bytes, bytes + (size > 0 ? size : 0));
    target->as_is = true;  // encoded bytes, not pixels
    return true;
}

Expected<int> GltfTextures::imageTexture(int image) {
    if (const auto it = decoded_.find(image); it != decoded_.end()) return it->second;
    const tinygltf::Image& source = model_.images[static_cast<std::size_t>(image)];
    const std::string name =
        concat("images[", image, "]",
               !source.uri.empty() && source.uri.rfind("data:", 0) != 0 ? " '" + source.uri + "'"
                   : !source.name.empty()                               ? " '" + source.name + "'"
                                                                        : std::string());
    int index = -1;
    if (source.image.empty()) {
        scene_.warnings.push_back(concat(path_, ": ", name, ": ", unreadableImage(source, path_),
                                         "; the textures using it are dropped"));
    } else {
        const std::string_view bytes(reinterpret_cast<const char*>(source.image.data()),
                                     source.image.size());
        auto decoded = decodeTextureImage(bytes, true, budget_);
        if (!decoded) {
            if (decoded.error().message.find("--max-memory") != std::string::npos) {
                return withContext(decoded.error(), name);
            }
            scene_.warnings.push_back(concat(path_, ": ", name, ": ", decoded.error().message,
                                             "; the textures using it are dropped"));
        } else {
            decoded->name = name;
            index = static_cast<int>(scene_.textures.size());
            scene_.textures.push_back(std::move(*decoded));
        }
    }
    decoded_[image] = index;
    return index;
}

Expected<GltfTextureRead> GltfTextures::read(const nlohmann::json& info, const std::string& where) {
    if (!info.is_object()) return Error{where + ": expected an object"};
    const nlohmann::json* indexValue = jsonMember(info, "index");
    if (indexValue == nullptr || !indexValue->is_number_integer()) {
        return Error{where + ".index: expected an integer"};
    }
    const long long textureIndex = indexValue->get<long long>();
    if (textureIndex < 0 || static_cast<std::size_t>(textureIndex) >= model_.textures.size()) {
        return Error{concat(where, ".index: texture ", textureIndex,
                            " is out of range (the file has ", model_.textures.size(), ")")};
    }
    const tinygltf::Texture& texture = model_.textures[static_cast<std::size_t>(textureIndex)];
    const std::string textureWhere = concat("textures[", textureIndex, "]");
    GltfTextureRead result;
    if (texture.source < 0) {
        // Only an extension's image (KHR_texture_basisu, EXT_texture_webp): not read.
        scene_.warnings.push_back(concat(path_, ": ", textureWhere,
                                         " has no PNG or JPEG source; the texture is dropped"));
        result.unreadable = true;
        return result;
    }
    if (static_cast<std::size_t>(texture.source) >= model_.images.size()) {
        return Error{concat(textureWhere, ".source: image ", texture.source,
                            " is out of range (the file has ", model_.images.size(), ")")};
    }
    auto image = imageTexture(texture.source);
    if (!image) return image.error();
    if (*image < 0) {
        result.unreadable = true;
        return result;
    }
    TextureRef ref;
    ref.image = *image;
    auto texCoord = readTexCoord(info, 0, where);
    if (!texCoord) return texCoord.error();
    ref.texCoord = *texCoord;
    const nlohmann::json* extensions = jsonMember(info, "extensions");
    if (const nlohmann::json* transform =
            extensions != nullptr ? jsonMember(*extensions, "KHR_texture_transform") : nullptr) {
        const std::string transformWhere = where + ".extensions.KHR_texture_transform";
        auto offset = readArray<2>(*transform, "offset", {0, 0}, transformWhere);
        if (!offset) return offset.error();
        auto scale = readArray<2>(*transform, "scale", {1, 1}, transformWhere);
        if (!scale) return scale.error();
        double rotation = 0;
        if (const nlohmann::json* value = jsonMember(*transform, "rotation")) {
            if (!value->is_number() || !std::isfinite(value->get<double>())) {
                return Error{transformWhere + ".rotation: expected a finite number"};
            }
            rotation = value->get<double>();
        }
        auto overridden = readTexCoord(*transform, ref.texCoord, transformWhere);
        if (!overridden) return overridden.error();
        ref.texCoord = *overridden;
        ref.transform = textureTransform(*offset, rotation, *scale);
    }
    if (ref.texCoord > 1) {
        scene_.warnings.push_back(concat(path_, ": ", where, " uses TEXCOORD_", ref.texCoord,
                                         "; only TEXCOORD_0 and TEXCOORD_1 are read, so the "
                                         "texture is dropped"));
        result.unreadable = true;
        return result;
    }
    if (texture.sampler >= 0) {
        if (static_cast<std::size_t>(texture.sampler) >= model_.samplers.size()) {
            return Error{concat(textureWhere, ".sampler: sampler ", texture.sampler,
                                " is out of range (the file has ", model_.samplers.size(), ")")};
        }
        const tinygltf::Sampler& sampler =
            model_.samplers[static_cast<std::size_t>(texture.sampler)];
        ref.wrapS = wrapOf(sampler.wrapS);
        ref.wrapT = wrapOf(sampler.wrapT);
        ref.nearest = sampler.magFilter == TINYGLTF_TEXTURE_FILTER_NEAREST;
    }
    result.ref = ref;
    return result;
}

}  // namespace daisy
