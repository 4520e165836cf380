#include "image/texture_detail.h"

#include <algorithm>

#include "spectral/color.h"

namespace daisy {
namespace {

double luminance(const Rgb3& rgb) {
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];  // Rec. 709 Y weights
}

}  // namespace

SurfaceDetail::SurfaceDetail(const Scene& scene, const PatchMesh& patches,
                             const PatchAppearance& appearance, std::size_t spectralChannels)
    : sampler_(scene),
      patches_(patches),
      appearance_(appearance),
      spectralChannels_(spectralChannels) {
    hasBackPatches_ = std::any_of(patches.backPatch.begin(), patches.backPatch.end(),
                                  [](uint32_t back) { return back != kNoBackPatch; });
}

bool SurfaceDetail::empty() const {
    return appearance_.empty() && !hasBackPatches_;
}

void resolveBackFace(const PatchMesh& patches, const Ray& ray, SurfaceHit& hit) {
    if (hit.patch >= patches.backPatch.size()) return;
    const uint32_t back = patches.backPatch[hit.patch];
    if (back == kNoBackPatch) return;
    const Vec3d& n = patches.normals[hit.patch];
    const double facing = n.x * ray.direction[0] + n.y * ray.direction[1] + n.z * ray.direction[2];
    if (facing <= 0) return;  // seen from the front
    // Corner weights on the other patch: its corners are the same vertices, permuted.
    const auto& from = patches.patches[hit.patch];
    const auto& to = patches.patches[back];
    const double weights[3] = {1.0 - hit.u - hit.v, hit.u, hit.v};
    double mapped[3] = {0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 3; ++j) {
            if (to[j] == from[k]) mapped[j] = weights[k];
        }
    }
    hit.patch = back;
    hit.u = static_cast<float>(mapped[1]);
    hit.v = static_cast<float>(mapped[2]);
}

DetailSource detailSource(const PatchAppearance& appearance, uint32_t i) {
    if (appearance.emissionVaries[i] && luminance(appearance.emission[i]) > kSmallestDetailMean)
        return DetailSource::Emission;
    return appearance.reflectanceVaries[i] ? DetailSource::Reflectance : DetailSource::None;
}

void SurfaceDetail::resolve(const Ray& ray, SurfaceHit& hit) const {
    if (hasBackPatches_) resolveBackFace(patches_, ray, hit);
}

void SurfaceDetail::shade(const SurfaceHit& hit, std::span<double> values) const {
    if (appearance_.empty()) return;
    const uint32_t i = hit.patch;
    const DetailSource follows = detailSource(appearance_, i);
    if (follows == DetailSource::None) return;
    const bool emits = follows == DetailSource::Emission;
    const auto& corners = appearance_.cornerWeights[i];
    const double w[3] = {1.0 - hit.u - hit.v, hit.u, hit.v};
    std::array<double, 3> source{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
        for (int j = 0; j < 3; ++j)
            source[j] += w[k] * corners[k][j];
    }
    const uint32_t t = patches_.sourceTriangle[i];
    const Rgb3 point = emits ? sampler_.emission(t, source) : sampler_.reflectance(t, source);
    const Rgb3& mean = emits ? appearance_.emission[i] : appearance_.reflectance[i];
    Rgb ratio{1, 1, 1};
    for (int c = 0; c < 3; ++c) {
        if (mean[c] > kSmallestDetailMean) ratio[c] = point[c] / mean[c];
    }
    const double meanY = luminance(mean);
    const double yRatio = meanY > kSmallestDetailMean ? luminance(point) / meanY : 1.0;
    for (std::size_t k = 0; k < spectralChannels_; ++k)
        values[k] *= yRatio;
    double* xyz = values.data() + spectralChannels_;
    Rgb rgb = xyzToLinearSrgb(Xyz{xyz[0], xyz[1], xyz[2]});
    for (int c = 0; c < 3; ++c)
        rgb[c] *= ratio[c];
    const Xyz out = linearSrgbToXyz(rgb);
    for (int c = 0; c < 3; ++c)
        xyz[c] = out[c];
}

}  // namespace daisy
