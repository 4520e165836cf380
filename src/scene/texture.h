#pragma once
// Textures as the scene model holds them: decoded images in linear RGB and a
// material's reference to one (glTF textureInfo: the image, the TEXCOORD set, the sampler's
// wrap and filter modes, KHR_texture_transform). Sampling follows glTF 2.0 section 3.8 and the
// KHR_texture_transform specification (uv' = T R S uv).
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/expected.h"
#include "scene/load_budget.h"

namespace daisy {

// A decoded image, row 0 at the top (glTF's uv (0, 0) is the image's top-left corner).
struct TextureImage {
    std::string name;  // for messages: "images[2] 'wall.png'"
    int width = 0;
    int height = 0;
    std::vector<float> rgb;  // width x height x 3, linear (sRGB-decoded when the source is sRGB)
};

// glTF sampler wrap modes (the numbers are glTF's).
enum class TextureWrap : int { Repeat = 10497, ClampToEdge = 33071, MirroredRepeat = 33648 };

struct TextureRef {
    int image = -1;  // index into Scene::textures
    int texCoord = 0;  // TEXCOORD_<n>, 0 or 1
    // KHR_texture_transform as a 2 x 3 affine map, row-major: u' = t[0] u + t[1] v + t[2],
    // v' = t[3] u + t[4] v + t[5]. Identity without the extension.
    std::array<double, 6> transform{1, 0, 0, 0, 1, 0};
    TextureWrap wrapS = TextureWrap::Repeat;
    TextureWrap wrapT = TextureWrap::Repeat;
    bool nearest = false;  // magFilter NEAREST; else bilinear
};

// The 2 x 3 map of KHR_texture_transform's offset, rotation (radians) and scale.
std::array<double, 6> textureTransform(std::array<double, 2> offset, double rotation,
                                       std::array<double, 2> scale);

// The texel colour at (u, v) through ref's transform, wrap and filter. Precondition: `image`
// is the image ref names and has width, height >= 1.
std::array<float, 3> sampleTexture(const TextureImage& image, const TextureRef& ref, double u,
                                   double v);

// Decodes PNG or JPEG bytes (stb_image) to linear RGB; `srgb` applies the sRGB transfer curve
// (IEC 61966-2-1) as glTF colour textures require. The decoded size (read from the header
// first) is charged to `budget` before decoding. Errors say why (stb's reason).
Expected<TextureImage> decodeTextureImage(std::string_view bytes, bool srgb, LoadBudget& budget);

}  // namespace daisy
