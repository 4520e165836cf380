#pragma once
// glTF textures for the scene model: a material's textureInfo (index, texCoord,
// KHR_texture_transform) with its texture's sampler, and the image decoded once (stb_image,
// sRGB colour). Internal to scene/ (gltf_loader.cpp). An image that cannot be read (a missing
// file, an undecodable format) is one warning line naming it, and the texture is dropped.
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/expected.h"
#include "scene/load_budget.h"
#include "scene/scene.h"

namespace tinygltf {
class Model;
struct Image;
}  // namespace tinygltf

namespace daisy {

// The tinygltf image callback: keeps the encoded bytes (decoded later, only for the images
// materials use). Signature of tinygltf::LoadImageDataFunction.
bool keepEncodedGltfImage(tinygltf::Image* image, int imageIndex, std::string* error,
                          std::string* warning, int requestedWidth, int requestedHeight,
                          const unsigned char* bytes, int size, void* userData);

struct GltfTextureRead {
    std::optional<TextureRef> ref;
    bool unreadable = false;  // the file names a texture whose image could not be read
};

class GltfTextures {
public:
    GltfTextures(const tinygltf::Model& model, const std::string& path, Scene& scene,
                 LoadBudget& budget)
        : model_(model), path_(path), scene_(scene), budget_(budget) {}

    // `info` is the raw textureInfo object at `where` ("materials[2].emissiveTexture"). Errors
    // (message without the file name) for references out of range and malformed members.
    Expected<GltfTextureRead> read(const nlohmann::json& info, const std::string& where);

private:
    Expected<int> imageTexture(int image);  // scene.textures index, or -1 when unreadable

    const tinygltf::Model& model_;
    const std::string& path_;
    Scene& scene_;
    LoadBudget& budget_;
    std::map<int, int> decoded_;  // glTF image -> scene.textures index (-1: unreadable)
};

}  // namespace daisy
