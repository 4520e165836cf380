#pragma once
// Vertex welding and conforming longest-edge bisection, the two halves of buildPatchMesh
// (geometry/patch_mesh.h), which is the public entry point; these are exposed for it and tests.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/expected.h"
#include "geometry/vec3.h"

namespace daisy {

// Gives bitwise-equal positions (after folding -0 into +0) one index, numbered in first-insertion
// order, and appends each new position to the vector it was constructed with (which it must
// outlive). Open addressing with linear probing over vertex indices: O(1) expected per insert.
class VertexWelder {
public:
    explicit VertexWelder(std::vector<Vec3d>& positions);

    uint32_t insert(const Vec3d& position);
    const std::vector<Vec3d>& positions() const { return positions_; }

private:
    void rehash(std::size_t slotCount);

    std::vector<Vec3d>& positions_;
    std::vector<uint32_t> slots_;  // vertex index, or kEmptySlot
    std::size_t mask_ = 0;
};

struct RefinedTriangles {
    std::vector<std::array<uint32_t, 3>> triangles;  // counter-clockwise, as their source
    std::vector<uint32_t> sourceTriangle;  // index into the input span
};

// Conforming longest-edge bisection (Rivara 1984, SIAM J. Numer. Anal. 21(3)): every triangle
// whose longest edge exceeds maxEdge (> 0, scene units) is bisected at that edge's midpoint,
// recursively, until no edge is longer than maxEdge. Midpoints are computed symmetrically in the
// edge's ends and welded by position through `welder`, so a split edge gets one shared midpoint
// in every triangle that contains it (no T-junctions), found in O(1) expected time.
// Output keeps input order; the children of one input triangle are consecutive, depth-first.
// Fails when more than maxPatches triangles would be produced.
Expected<RefinedTriangles> bisectLongestEdges(std::span<const std::array<uint32_t, 3>> triangles,
                                              double maxEdge, uint64_t maxPatches,
                                              VertexWelder& welder);

// Upper bound on the number of triangles bisectLongestEdges makes from these triangles for
// maxEdge > 0, without making them; UINT64_MAX when it cannot be bounded (non-finite input).
// Per triangle a proven bound (derived in subdivision.cpp from Rosenberg & Stenger 1975); where
// that is loose (slivers), tightened by following the bisection itself for a while.
uint64_t bisectionCountBound(std::span<const Vec3d> positions,
                             std::span<const std::array<uint32_t, 3>> triangles, double maxEdge);

}  // namespace daisy
