#pragma once
// Where a material's colour varies over its surface: baseColorFactor x the
// baseColorTexture texel x COLOR_0, and emissive x the emissiveTexture texel. The solve takes
// each patch's mean over its area (patchAppearance); the image takes the point value against
// that mean (image/texture_detail.h): the classic split of texture x illumination, so the image
// of a patch averages to what the solve gave it.
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/patch_mesh.h"
#include "scene/scene.h"

namespace daisy {

using Rgb3 = std::array<float, 3>;

// Barycentric weights of `p` in triangle (a, b, c) (of p's projection onto its plane).
std::array<double, 3> barycentricWeights(const Vec3d& a, const Vec3d& b, const Vec3d& c,
                                         const Vec3d& p);

class SurfaceSampler {
public:
    explicit SurfaceSampler(const Scene& scene) : scene_(scene) {}

    // The material's reflectance (emission) varies over its triangles: a texture, or vertex
    // colours in the scene (reflectance only).
    bool reflectanceVaries(uint32_t material) const;
    bool emissionVaries(uint32_t material) const;
    // At the point of triangle `t` with corner weights `w`: linear RGB reflectance
    // (baseColor x texel x COLOR_0) and exitance (emissiveRgb x texel).
    Rgb3 reflectance(uint32_t t, const std::array<double, 3>& w) const;
    Rgb3 emission(uint32_t t, const std::array<double, 3>& w) const;
    // Texels the triangle's uv image covers for `ref` (to size a patch's sampling).
    double texelsCovered(uint32_t t, const TextureRef& ref) const;
    const Scene& scene() const { return scene_; }
    // TEXCOORD_<set> at the point of triangle `t` with corner weights `w` ((0, 0) when the mesh
    // has no such set), before the texture's transform.
    std::array<double, 2> uv(uint32_t t, int set, const std::array<double, 3>& w) const;

private:
    const Scene& scene_;
};

// Per patch means for the solve. `reflectance[i]` / `emission[i]` are meaningful where the
// `...Varies[i]` flag is 1 (then they replace the material's baseColor / emissiveRgb for the
// patch); all four are empty when nothing varies in the scene.
struct PatchAppearance {
    std::vector<Rgb3> reflectance;
    std::vector<Rgb3> emission;
    std::vector<uint8_t> reflectanceVaries;
    std::vector<uint8_t> emissionVaries;
    // Per patch: the source-triangle weights of its 3 corners (row k = corner k).
    std::vector<std::array<std::array<double, 3>, 3>> cornerWeights;
    bool empty() const { return reflectanceVaries.empty(); }
};

// The patch means: the mean over a K x K sub-triangle grid of the patch (K about twice the
// texels it covers along a side, 2..16; K = 1 without a texture, exact for vertex colours,
// which are affine over the patch).
PatchAppearance patchAppearance(const Scene& scene, const PatchMesh& patches);

}  // namespace daisy
