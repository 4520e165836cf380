#pragma once
// The flat BVH the shared kernels traverse (shared/bvh_traverse.h) over a PatchMesh's triangles.
// Built on the CPU with Embree 3's BVH builder (rtcBuildBVH, binned SAH at
// RTC_BUILD_QUALITY_HIGH, binary nodes, at most kFlatBvhMaxLeafSize triangles a leaf) into a
// builder tree of our own, then flattened into the shared layout (gpu_types.h): nodes depth
// first with the root at 0 and siblings adjacent, triangles in leaf order, float corners equal
// to the kernels' PatchGeometry corners. The builder tree stays inside flat_bvh.cpp.
#include <cstdint>
#include <string>
#include <vector>

#include "core/expected.h"
#include "geometry/patch_mesh.h"
#include "shared/gpu_types.h"

namespace daisy {

// Small leaves: a GPU thread tests a leaf's triangles serially; 4 matches the SAH optimum at the
// builder's default costs on our scenes while keeping divergence low.
inline constexpr int kFlatBvhMaxLeafSize = 4;

struct FlatBvh {
    std::vector<shared::BvhNode> nodes;  // empty only for a mesh without patches
    std::vector<shared::BvhTriangle> triangles;  // one per patch, in leaf order
    int depth = 0;  // levels below the root of the deepest leaf (<= DAISY_BVH_STACK_SIZE)
};

// Builds the BVH over every patch of `mesh`. Fails with a message when Embree cannot be set up or
// the tree would be deeper than the traversal stack (DAISY_BVH_STACK_SIZE).
Expected<FlatBvh> buildFlatBvh(const PatchMesh& mesh);

// Checks the structure against the mesh (for tests and DAISY_CHECKs): every patch's triangle
// exactly once with the kernels' corners, leaves of 1..kFlatBvhMaxLeafSize triangles, every
// node reached once, child boxes inside their parent's, leaf boxes holding their triangles, and
// depth within the traversal stack. Returns an empty string or what is wrong.
std::string validateFlatBvh(const FlatBvh& bvh, const PatchMesh& mesh);

}  // namespace daisy
