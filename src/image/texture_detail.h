#pragma once
// The image's surface detail: what the per-patch solve averages away, put back per
// sample by the renderer (image/renderer.h's SampleShader).
// - Texture detail: the interpolated radiosity times texel / patch mean (the classic texture x
//   illumination split), the texel being baseColor x texture x COLOR_0 (or, on an emitting
//   patch, the emission's), so a patch's image still averages to its solved radiance. The XYZ
//   channels are scaled in linear sRGB per channel; spectral channels by the luminance ratio.
// - Double-sided surfaces: a hit on a patch seen from behind is moved to its back patch
//   (PatchMesh::backPatch), whatever the ray caster returned for the two coincident triangles.
#include <cstddef>
#include <span>

#include "geometry/patch_mesh.h"
#include "image/renderer.h"
#include "scene/surface_appearance.h"

namespace daisy {

// A mean channel at or below this has ratio 1 (no detail).
inline constexpr double kSmallestDetailMean = 1e-6;

// Which of patch `i`'s colours the image's texture detail follows: its emission where that varies
// and the patch emits, else its reflectance where that varies, else neither. `appearance` is not
// empty. The viewer's texture detail (viewer/detail_vertices.h) makes the same choice.
enum class DetailSource { None, Reflectance, Emission };
DetailSource detailSource(const PatchAppearance& appearance, uint32_t i);

// Moves a hit on a double-sided surface seen from behind to its back patch, the corner weights
// permuted to match (the two patches share their vertices). One-sided patches stay as they are.
void resolveBackFace(const PatchMesh& patches, const Ray& ray, SurfaceHit& hit);

class SurfaceDetail final : public SampleShader {
public:
    // `wavelengthCount` spectral channels precede X, Y, Z (Session::patchChannels's layout;
    // 0 when not spectral). The referenced objects must outlive this one.
    SurfaceDetail(const Scene& scene, const PatchMesh& patches, const PatchAppearance& appearance,
                  std::size_t spectralChannels);

    // True when neither detail applies (the renderer can skip the shader).
    bool empty() const;

    void resolve(const Ray& ray, SurfaceHit& hit) const override;
    void shade(const SurfaceHit& hit, std::span<double> values) const override;

private:
    SurfaceSampler sampler_;
    const PatchMesh& patches_;
    const PatchAppearance& appearance_;
    std::size_t spectralChannels_;
    bool hasBackPatches_ = false;
};

}  // namespace daisy
