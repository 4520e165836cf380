#pragma once
// A bounding-volume hierarchy over blockers (convex planar polygons: solid faces and loose
// patches, radiosity/patch_clusters.h) in double precision, for shaft queries: which blockers
// may enter a shaft (radiosity/shaft.h). Built once per form-factor run by median splits along
// the longest axis of the centres' bounds; leaves hold up to kLeafSize blockers. This is the
// host-side helper of shaft culling, not the flat BVH the GPU backends traverse.
#include <cstdint>
#include <vector>

#include "geometry/bounds.h"
#include "radiosity/shaft.h"

namespace daisy {

// A plane whose blockers a query skips: geometry in the plane of a shaft's end polygon can only
// touch a segment at its end point, which shadow rays exclude.
struct SkipPlane {
    Vec3d normal;  // unit
    double offset = 0;
};

// What a query did, counted (the cost model prices it: form_factors_pair_loop.h).
struct BlockerQueryWork {
    uint64_t nodes = 0;  // BVH nodes tested against the shaft
    uint64_t blockers = 0;  // blockers tested
};

class BlockerBvh {
public:
    static constexpr uint32_t kLeafSize = 4;

    explicit BlockerBvh(const std::vector<ShaftPolygon>& blockers);

    // Appends to `out` every blocker that may enter the shaft's interior and does not lie in
    // either skip plane (within `tolerance`). Order: BVH order (deterministic). Adds what it
    // tested to `work`.
    void query(const Shaft& shaft, const SkipPlane& skip0, const SkipPlane& skip1, double tolerance,
               std::vector<uint32_t>& out, BlockerQueryWork& work) const;

    std::size_t nodeCount() const { return nodes_.size(); }

private:
    struct Node {
        Bounds3d bounds;
        uint32_t first = 0;  // leaf: first index into order_; inner: index of the right child
        uint32_t count = 0;  // leaf: blocker count (> 0); inner: 0 (left child = this + 1)
    };
    uint32_t build(uint32_t begin, uint32_t end, const std::vector<Vec3d>& centres);

    const std::vector<ShaftPolygon>& blockers_;
    std::vector<Node> nodes_;
    std::vector<uint32_t> order_;  // blocker indices, grouped by leaf
};

// True when the polygon lies in the plane (either orientation) within `tolerance`.
bool inSkipPlane(const ShaftPolygon& polygon, const SkipPlane& plane, double tolerance);

}  // namespace daisy
