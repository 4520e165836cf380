#include "scene/surface_appearance.h"

#include <algorithm>
#include <cmath>

namespace daisy {
namespace {

constexpr int kMaxSamplesPerSide = 16;

// Centroids of the K x K sub-triangles of the unit barycentric triangle, as (s, t) with the
// point c0 + s (c1 - c0) + t (c2 - c0): K^2 points of equal area weight.
std::vector<std::array<double, 2>> subTriangleCentroids(int k) {
    std::vector<std::array<double, 2>> points;
    points.reserve(std::size_t(k) * k);
    for (int i = 0; i < k; ++i) {
        for (int j = 0; i + j < k; ++j) {
            points.push_back({(i + 1.0 / 3) / k, (j + 1.0 / 3) / k});
            if (i + j < k - 1) points.push_back({(i + 2.0 / 3) / k, (j + 2.0 / 3) / k});
        }
    }
    return points;
}

bool textured(const Material& m) {
    return m.baseColorTexture.has_value() || m.emissiveTexture.has_value();
}

}  // namespace

std::array<double, 3> barycentricWeights(const Vec3d& a, const Vec3d& b, const Vec3d& c,
                                         const Vec3d& p) {
    const Vec3d e1 = b - a, e2 = c - a, d = p - a;
    const double d11 = dot(e1, e1), d12 = dot(e1, e2), d22 = dot(e2, e2);
    const double d1 = dot(d, e1), d2 = dot(d, e2);
    const double det = d11 * d22 - d12 * d12;
    if (!(det > 0)) return {1, 0, 0};
    const double v = (d22 * d1 - d12 * d2) / det;
    const double w = (d11 * d2 - d12 * d1) / det;
    return {1 - v - w, v, w};
}

bool SurfaceSampler::reflectanceVaries(uint32_t material) const {
    const Material& m = scene_.materials[material];
    return m.baseColorTexture.has_value() || !scene_.vertexColors.empty();
}

bool SurfaceSampler::emissionVaries(uint32_t material) const {
    return scene_.materials[material].emissiveTexture.has_value();
}

std::array<double, 2> SurfaceSampler::uv(uint32_t t, int set,
                                         const std::array<double, 3>& w) const {
    const auto& coords = scene_.texCoords[static_cast<std::size_t>(set)];
    if (coords.empty()) return {0, 0};
    std::array<double, 2> out{0, 0};
    for (int k = 0; k < 3; ++k) {
        const auto& c = coords[scene_.mesh.triangles[t][k]];
        out[0] += w[k] * c[0];
        out[1] += w[k] * c[1];
    }
    return out;
}

Rgb3 SurfaceSampler::reflectance(uint32_t t, const std::array<double, 3>& w) const {
    const Material& m = scene_.materials[scene_.mesh.materials[t]];
    Rgb3 out{float(m.baseColor[0]), float(m.baseColor[1]), float(m.baseColor[2])};
    if (m.baseColorTexture) {
        const auto [u, v] = uv(t, m.baseColorTexture->texCoord, w);
        const Rgb3 texel =
            sampleTexture(scene_.textures[static_cast<std::size_t>(m.baseColorTexture->image)],
                          *m.baseColorTexture, u, v);
        for (int c = 0; c < 3; ++c)
            out[c] *= texel[c];
    }
    if (!scene_.vertexColors.empty()) {
        for (int c = 0; c < 3; ++c) {
            double colour = 0;
            for (int k = 0; k < 3; ++k)
                colour += w[k] * scene_.vertexColors[scene_.mesh.triangles[t][k]][c];
            out[c] *= static_cast<float>(std::clamp(colour, 0.0, 1.0));
        }
    }
    return out;
}

Rgb3 SurfaceSampler::emission(uint32_t t, const std::array<double, 3>& w) const {
    const Material& m = scene_.materials[scene_.mesh.materials[t]];
    Rgb3 out{float(m.emissiveRgb[0]), float(m.emissiveRgb[1]), float(m.emissiveRgb[2])};
    if (m.emissiveTexture) {
        const auto [u, v] = uv(t, m.emissiveTexture->texCoord, w);
        const Rgb3 texel =
            sampleTexture(scene_.textures[static_cast<std::size_t>(m.emissiveTexture->image)],
                          *m.emissiveTexture, u, v);
        for (int c = 0; c < 3; ++c)
            out[c] *= texel[c];
    }
    return out;
}

double SurfaceSampler::texelsCovered(uint32_t t, const TextureRef& ref) const {
    const auto a = uv(t, ref.texCoord, {1, 0, 0});
    const auto b = uv(t, ref.texCoord, {0, 1, 0});
    const auto c = uv(t, ref.texCoord, {0, 0, 1});
    const auto& m = ref.transform;
    const double det = std::abs(m[0] * m[4] - m[1] * m[3]);
    const double uvArea =
        0.5 * std::abs((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])) * det;
    const TextureImage& image = scene_.textures[static_cast<std::size_t>(ref.image)];
    return uvArea * image.width * image.height;
}

PatchAppearance patchAppearance(const Scene& scene, const PatchMesh& patches) {
    PatchAppearance out;
    const SurfaceSampler sampler(scene);
    bool any = false;
    for (std::size_t m = 0; m < scene.materials.size() && !any; ++m) {
        any = sampler.reflectanceVaries(uint32_t(m)) || sampler.emissionVaries(uint32_t(m));
    }
    if (!any) return out;
    const std::size_t n = patches.patchCount();
    out.reflectance.assign(n, {0, 0, 0});
    out.emission.assign(n, {0, 0, 0});
    out.reflectanceVaries.assign(n, 0);
    out.emissionVaries.assign(n, 0);
    out.cornerWeights.resize(n);
    std::vector<std::vector<std::array<double, 2>>> grids(kMaxSamplesPerSide + 1);
    for (std::size_t i = 0; i < n; ++i) {
        const uint32_t t = patches.sourceTriangle[i];
        const uint32_t material = patches.materials[i];
        const bool reflectance = sampler.reflectanceVaries(material);
        const bool emission = sampler.emissionVaries(material);
        const Vec3d a = scene.mesh.corner(t, 0), b = scene.mesh.corner(t, 1),
                    c = scene.mesh.corner(t, 2);
        auto& corners = out.cornerWeights[i];
        for (int k = 0; k < 3; ++k)
            corners[k] = barycentricWeights(a, b, c, patches.positions[patches.patches[i][k]]);
        if (!reflectance && !emission) continue;
        // Samples per side from the texels this patch covers (its share of the triangle's).
        double texels = 0;
        const Material& mat = scene.materials[material];
        const double share = patches.areas[i] / std::max(triangleArea(a, b, c), 1e-300);
        for (const auto& ref : {mat.baseColorTexture, mat.emissiveTexture}) {
            if (ref) texels = std::max(texels, share * sampler.texelsCovered(t, *ref));
        }
        // About two samples per texel along each side (bilinear texels vary on that scale).
        const int k = textured(mat)
            ? std::clamp(int(std::ceil(2 * std::sqrt(texels))), 2, kMaxSamplesPerSide)
            : 1;
        if (grids[k].empty()) grids[k] = subTriangleCentroids(k);
        std::array<double, 3> sumR{0, 0, 0}, sumE{0, 0, 0};
        for (const auto& [s, q] : grids[k]) {
            std::array<double, 3> w{};
            for (int j = 0; j < 3; ++j)
                w[j] = corners[0][j] + s * (corners[1][j] - corners[0][j]) +
                    q * (corners[2][j] - corners[0][j]);
            if (reflectance) {
                const Rgb3 r = sampler.reflectance(t, w);
                for (int ch = 0; ch < 3; ++ch)
                    sumR[ch] += r[ch];
            }
            if (emission) {
                const Rgb3 e = sampler.emission(t, w);
                for (int ch = 0; ch < 3; ++ch)
                    sumE[ch] += e[ch];
            }
        }
        const double count = double(grids[k].size());
        for (int ch = 0; ch < 3; ++ch) {
            out.reflectance[i][ch] = static_cast<float>(sumR[ch] / count);
            out.emission[i][ch] = static_cast<float>(sumE[ch] / count);
        }
        out.reflectanceVaries[i] = reflectance;
        out.emissionVaries[i] = emission;
    }
    return out;
}

}  // namespace daisy
