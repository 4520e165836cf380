#pragma once
// Exposed parts of patches (docs/rendering.md). A floor subdivided without
// regard to the blocks standing on it has patches that run under a block: their buried part
// sees only the inside of the block, so F_ij from its points is 0 (blocked). The session
// solves for the exposed parts (radiosity/exposed_system.h) and stores B_i - E_i as the
// exposed part's value times phi_i; the gather divides it back, and the smooth image weights
// vertex means by exposed area so fully buried patches do not blacken the block's base.
//
// A point counts as buried when all five probe rays from it (along the patch normal and four
// tilted 45 degrees from it) hit the back of a single-sided surface: it is inside a closed
// object. phi_i is the exposed share of the 16 equal-area points patchQuadraturePoint gives.
#include <cstdint>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "shared/gpu_types.h"

namespace daisy {

inline constexpr int kPatchQuadraturePoints = 16;

// Point q (0..15) of the equal-area rule on triangle (a, b, c): the centroid of child q of its
// level-2 midpoint subdivision.
shared::vec3 patchQuadraturePoint(const shared::PatchGeometry& t, int q);

// An area-uniform point of child q (0..15) of triangle (a, b, c)'s level-2 midpoint subdivision,
// the child whose centroid patchQuadraturePoint gives, for u uniform in [0, 1)^2: a point of a
// patch's exposed part when q is one of its exposed points.
shared::vec3 pointInPatchChild(shared::vec3 a, shared::vec3 b, shared::vec3 c, int q,
                               shared::vec2 u);

struct PatchExposure {
    std::vector<float> fraction;  // phi per patch, in [0, 1]
    std::vector<uint16_t> exposedPoints;  // per patch: bit q set when point q is exposed
};

// Probes every patch's 16 points, in parallel: 16 rays a patch along its normal, and the four
// tilted ones only from the points those leave unsettled. Fails (no crash) when the ray caster
// cannot build the scene.
Expected<PatchExposure> patchExposure(const PatchMesh& patches);

// Per patch, its area times phi: the area weights of the smooth image's vertex means
// (vertex_radiance.h), so fully buried patches do not darken the exposed ones at a shared vertex.
std::vector<double> exposedAreas(const PatchMesh& patches, const PatchExposure& exposure);

}  // namespace daisy
