#include "viewer/detail_vertices.h"

#include <algorithm>
#include <optional>

#include "image/texture_detail.h"

namespace daisy::viewer {
namespace {

// The index of `texture` in `textures`, added when new.
uint32_t textureIndex(std::vector<DetailTexture>& textures, const DetailTexture& texture) {
    const auto found = std::find(textures.begin(), textures.end(), texture);
    if (found != textures.end()) return uint32_t(found - textures.begin());
    textures.push_back(texture);
    return uint32_t(textures.size() - 1);
}

}  // namespace

DetailVertices detailVertices(const Scene& scene, const PatchMesh& patches,
                              const PatchAppearance& appearance) {
    DetailVertices out;
    if (appearance.empty()) return out;
    const SurfaceSampler sampler(scene);
    out.textures.push_back(DetailTexture{});
    out.vertices.reserve(patches.patchCount() * 3 * kDetailFloats);
    for (uint32_t i = 0; i < uint32_t(patches.patchCount()); ++i) {
        const DetailSource follows = detailSource(appearance, i);
        const Material& material = scene.materials[patches.materials[i]];
        const bool emits = follows == DetailSource::Emission;
        const std::optional<TextureRef>& ref =
            emits ? material.emissiveTexture : material.baseColorTexture;
        const std::array<double, 3>& factor = emits ? material.emissiveRgb : material.baseColor;
        const Rgb3& mean = emits ? appearance.emission[i] : appearance.reflectance[i];
        const bool colours = follows == DetailSource::Reflectance && !scene.vertexColors.empty();
        const uint32_t t = patches.sourceTriangle[i];
        for (int k = 0; k < 3; ++k) {
            const std::array<double, 3>& w = appearance.cornerWeights[i][std::size_t(k)];
            std::array<double, 2> uv{0, 0};
            if (ref) {
                const auto [u, v] = sampler.uv(t, ref->texCoord, w);
                const auto& m = ref->transform;
                uv = {m[0] * u + m[1] * v + m[2], m[3] * u + m[4] * v + m[5]};
            }
            out.vertices.push_back(float(uv[0]));
            out.vertices.push_back(float(uv[1]));
            for (std::size_t c = 0; c < 3; ++c) {
                double scale = -1;
                if (follows != DetailSource::None && mean[c] > kSmallestDetailMean) {
                    double colour = 1;
                    if (colours) {
                        colour = 0;
                        for (std::size_t j = 0; j < 3; ++j)
                            colour += w[j] * scene.vertexColors[scene.mesh.triangles[t][j]][c];
                        colour = std::clamp(colour, 0.0, 1.0);
                    }
                    scale = factor[c] * colour / mean[c];
                }
                out.vertices.push_back(float(scale));
            }
        }
        // A patch without detail draws with whatever texture is bound: it joins the last run.
        std::optional<uint32_t> texture;
        if (follows != DetailSource::None) {
            texture = ref
                ? textureIndex(out.textures, {ref->image, ref->wrapS, ref->wrapT, ref->nearest})
                : 0;
        }
        if (out.runs.empty() || (texture && *texture != out.runs.back().texture)) {
            out.runs.push_back({i, 0, texture.value_or(0)});
        }
        ++out.runs.back().patchCount;
    }
    return out;
}

}  // namespace daisy::viewer
