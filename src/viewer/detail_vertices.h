#pragma once
// The viewer's texture detail: per vertex, what the fragment shader needs to multiply the smooth
// radiance by texel / patch mean as `daisy render` does (image/texture_detail.h). The texture
// coordinates come with the TEXCOORD set chosen and KHR_texture_transform applied (both affine
// over a triangle, so the rasteriser's interpolation of them is exact); the factor turns the
// sampled texel into the ratio: baseColor x COLOR_0 / patch mean (reflectance) or
// emissiveRgb / patch mean (emission), per linear sRGB channel.
#include <cstdint>
#include <vector>

#include "geometry/patch_mesh.h"
#include "scene/scene.h"
#include "scene/surface_appearance.h"

namespace daisy::viewer {

// Floats per vertex: u, v, then the factor of R, G, B (negative: the ratio is 1, no detail).
inline constexpr int kDetailFloats = 5;

// One texture as the shader samples it: an image and the sampler's wrap and filter.
struct DetailTexture {
    int image = -1;  // into Scene::textures; -1 = one white texel (COLOR_0 alone, or no detail)
    TextureWrap wrapS = TextureWrap::Repeat;
    TextureWrap wrapT = TextureWrap::Repeat;
    bool nearest = false;
    bool operator==(const DetailTexture&) const = default;
};

// Consecutive patches drawn with one texture bound.
struct DetailRun {
    uint32_t firstPatch = 0;
    uint32_t patchCount = 0;
    uint32_t texture = 0;  // into DetailVertices::textures
};

struct DetailVertices {
    std::vector<float> vertices;  // 3 x patches x kDetailFloats, in patch order
    std::vector<DetailTexture> textures;  // those the runs read, the white texel first
    std::vector<DetailRun> runs;  // in patch order, covering every patch
    bool empty() const { return vertices.empty(); }
};

// The detail of `patches` from the session's patch means; empty when `appearance` is (no
// material's colour varies: the viewer draws as before, without textures).
DetailVertices detailVertices(const Scene& scene, const PatchMesh& patches,
                              const PatchAppearance& appearance);

}  // namespace daisy::viewer
