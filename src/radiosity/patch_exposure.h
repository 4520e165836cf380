#pragma once
// Exposed parts of patches (docs/rendering.md). A floor subdivided without
// regard to the blocks standing on it has patches that run under a block: their buried part
// sees only the inside of the block, so F_ij from its points is 0 (blocked). The session
// solves for the exposed parts (radiosity/exposed_system.h) and stores B_i - E_i as the
// exposed part's value times phi_i; the gather divides it back, and the smooth image weights
// vertex means by exposed area so fully buried patches do not blacken the block's base.
//
// A point counts as buried when it is inside a closed object: all five probe rays from it
// (along the patch normal and four tilted 45 degrees from it) hit the back of a single-sided
// surface, or those five and four more at 80 degrees all hit the authored back (the side its
// normal leaves from) of one small piece of connected surfaces (patches joined by shared
// vertices): a closed double-sided object, such as a column's base standing on a floor, seen
// from within (Blender writes every material double-sided, so a closed object's faces have no
// back to tell). Such a piece's own inner faces (its back patches) are buried with it. A piece
// over half the scene's size (a room's shell modelled facing out) never buries; nor does one
// that encloses a light (a point or spot light, or an emitting patch's centroid: a lamp's shade
// over its bulb); nor is an emitting patch's own point buried by a piece. The 80-degree probes
// leave from under a table.
// phi_i is the exposed share of the 16 equal-area points patchQuadraturePoint gives.
#include <cstdint>
#include <span>
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

// Probes every patch's 16 points, in parallel: 16 rays a patch along its normal, the four
// tilted ones only from the points those leave unsettled, the four at 80 degrees only from
// points then still enclosed by one piece. `emitters`: per patch, 1 when it emits light of its
// own (empty: none); `lightPositions`: the point and spot lights'. Fails (no crash) when the
// ray caster cannot build the scene.
Expected<PatchExposure> patchExposure(const PatchMesh& patches,
                                      std::span<const uint8_t> emitters = {},
                                      std::span<const Vec3d> lightPositions = {});

// Per patch, its area times phi: the area weights of the smooth image's vertex means
// (vertex_radiance.h), so fully buried patches do not darken the exposed ones at a shared vertex.
std::vector<double> exposedAreas(const PatchMesh& patches, const PatchExposure& exposure);

}  // namespace daisy
