#include "geometry/subdivision.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/strings.h"
#include "geometry/mesh.h"

namespace daisy {
namespace {

constexpr uint32_t kEmptySlot = UINT32_MAX;
constexpr std::size_t kInitialSlots = 1024;
// A bisection stack this deep means the lengths are not finite; finite input stays under ~200.
constexpr std::size_t kMaxStackDepth = 4096;

// Folds -0 into +0 (x + 0.0 is +0 for x = -0 under round-to-nearest), so both weld together.
uint64_t positionBits(double x) {
    return std::bit_cast<uint64_t>(x + 0.0);
}

// MurmurHash3's 64-bit finaliser (Appleby): every input bit affects every output bit.
uint64_t mix(uint64_t v) {
    v ^= v >> 33;
    v *= 0xff51afd7ed558ccdULL;
    v ^= v >> 33;
    v *= 0xc4ceb9fe1a85ec53ULL;
    v ^= v >> 33;
    return v;
}

uint64_t hashPosition(const Vec3d& p) {
    return mix(positionBits(p.x) ^ mix(positionBits(p.y) ^ mix(positionBits(p.z))));
}

bool sameBits(const Vec3d& a, const Vec3d& b) {
    return positionBits(a.x) == positionBits(b.x) && positionBits(a.y) == positionBits(b.y) &&
        positionBits(a.z) == positionBits(b.z);
}

using Corners = std::array<Vec3d, 3>;
using EdgeLengths = std::array<double, 3>;

// Edge k of a triangle runs from corner k to corner k + 1. Lengths and midpoints are symmetric in
// the two ends bitwise, so both triangles on an edge agree on them.
EdgeLengths edgeLengths(const Corners& corners) {
    return {length(corners[1] - corners[0]), length(corners[2] - corners[1]),
            length(corners[0] - corners[2])};
}

Vec3d midpoint(const Vec3d& a, const Vec3d& b) {
    return (a + b) * 0.5;
}

// The longest edge when it is longer than maxEdge, else -1; ties go to the lowest k; a NaN length
// never splits.
int edgeToSplit(const EdgeLengths& lengths, double maxEdge) {
    int longest = -1;
    double longestLength = maxEdge;
    for (int k = 0; k < 3; ++k) {
        if (lengths[k] > longestLength) {
            longest = k;
            longestLength = lengths[k];
        }
    }
    return longest;
}

// Let h = maxEdge and alpha0 the smallest angle of T, between its sides u and w (the two longer
// sides, meeting opposite the shortest). Longest-edge bisection never makes an angle below
// alpha0 / 2 (Rosenberg & Stenger 1975, Math. Comp. 29(130), 390-395). The parent of every leaf
// was split, so its longest edge l > h; a triangle with longest edge l and smallest angle >= beta
// (<= 60 deg) has area >= l^2 tan(beta) / 4 (the isosceles one with base angles beta is the
// least), and a leaf has half its parent's area. So leaf area >= h^2 tan(alpha0 / 2) / 8 and
//   N <= 8 area(T) / (h^2 tan(alpha0 / 2)) = 8 |u||w| cos^2(alpha0 / 2) / h^2
//      = 4 (|u||w| + dot(u, w)) / h^2,
// using area = |u||w| sin(alpha0) / 2. A relative margin covers rounding in the lengths. It is
// 2.4-4.8x the count on right isosceles triangles (whose bisection makes regular grids) but
// grows like l / h on slivers thinner than h, hence frontierBound. Infinite for non-finite input.
double rosenbergStengerBound(const Corners& corners, const EdgeLengths& lengths, double maxEdge) {
    if (!std::isfinite(lengths[0]) || !std::isfinite(lengths[1]) || !std::isfinite(lengths[2])) {
        return std::numeric_limits<double>::infinity();
    }
    if (std::max({lengths[0], lengths[1], lengths[2]}) <= maxEdge) return 1;
    const auto shortest = std::min_element(lengths.begin(), lengths.end()) - lengths.begin();
    const Vec3d& apex = corners[(shortest + 2) % 3];
    const Vec3d u = corners[shortest] - apex;
    const Vec3d w = corners[(shortest + 1) % 3] - apex;
    const double h = maxEdge * (1 - 1e-9);
    return std::ceil(4 * (length(u) * length(w) + dot(u, w)) / (h * h) * (1 + 1e-9) + 2);
}

// Bound on the leaves under one triangle: follows bisectLongestEdges' own decisions and midpoints
// (without making vertices) through the nodes whose Rosenberg-Stenger bound is loose (over
// kLooseFactor x their area over the largest leaf's, an equilateral triangle of side maxEdge),
// and adds up the bounds of the nodes where it stops (a leaf counts 1). So slivers thinner than
// maxEdge are counted exactly, thicker ones until bisection has cut them into well-shaped pieces.
// Each expanded node spends one unit of `budget`; at 0 the nodes left add their bounds.
double frontierBound(const Corners& root, double maxEdge, uint64_t& budget,
                     std::vector<Corners>& stack) {
    constexpr double kLooseFactor = 16;
    const double leafAreaMax = std::sqrt(3.0) / 4 * maxEdge * maxEdge;
    double total = 0;
    stack.assign(1, root);
    while (!stack.empty()) {
        const Corners c = stack.back();
        stack.pop_back();
        const EdgeLengths lengths = edgeLengths(c);
        const double bound = rosenbergStengerBound(c, lengths, maxEdge);
        if (!std::isfinite(bound)) return bound;
        if (bound <= 1 || budget == 0 ||
            !(bound > kLooseFactor * triangleArea(c[0], c[1], c[2]) / leafAreaMax)) {
            total += bound;
            continue;
        }
        --budget;
        const int split = edgeToSplit(lengths, maxEdge);
        DAISY_CHECK(split >= 0);
        const Vec3d m = midpoint(c[split], c[(split + 1) % 3]);
        stack.push_back({m, c[(split + 1) % 3], c[(split + 2) % 3]});
        stack.push_back({c[split], m, c[(split + 2) % 3]});
    }
    return total;
}

}  // namespace

VertexWelder::VertexWelder(std::vector<Vec3d>& positions) : positions_(positions) {
    rehash(std::max(kInitialSlots, std::bit_ceil(2 * positions.size() + 2)));
}

void VertexWelder::rehash(std::size_t slotCount) {
    slots_.assign(slotCount, kEmptySlot);
    mask_ = slotCount - 1;
    for (std::size_t v = 0; v < positions_.size(); ++v) {
        std::size_t slot = hashPosition(positions_[v]) & mask_;
        while (slots_[slot] != kEmptySlot)
            slot = (slot + 1) & mask_;
        slots_[slot] = static_cast<uint32_t>(v);
    }
}

uint32_t VertexWelder::insert(const Vec3d& position) {
    std::size_t slot = hashPosition(position) & mask_;
    while (slots_[slot] != kEmptySlot) {
        if (sameBits(positions_[slots_[slot]], position)) return slots_[slot];
        slot = (slot + 1) & mask_;
    }
    DAISY_CHECK_OP(positions_.size(), <, std::size_t{kEmptySlot});
    const auto vertex = static_cast<uint32_t>(positions_.size());
    positions_.push_back({position.x + 0.0, position.y + 0.0, position.z + 0.0});
    slots_[slot] = vertex;
    if (2 * positions_.size() > slots_.size()) rehash(2 * slots_.size());
    return vertex;
}

// Conformity: whether an edge is split depends on the edge alone (its length > maxEdge), and a
// triangle holding such an edge has a longest edge > maxEdge too, so it is split, longest edge
// first (Rivara's closure), and the child keeping that edge is split again until the edge itself
// is bisected. Every edge > maxEdge is therefore bisected in every triangle containing it, at the
// same midpoint, which the welder maps to one vertex; edges <= maxEdge are never split.
Expected<RefinedTriangles> bisectLongestEdges(std::span<const std::array<uint32_t, 3>> triangles,
                                              double maxEdge, uint64_t maxPatches,
                                              VertexWelder& welder) {
    DAISY_CHECK(maxEdge > 0);
    RefinedTriangles out;
    out.triangles.reserve(triangles.size());
    out.sourceTriangle.reserve(triangles.size());
    std::vector<std::array<uint32_t, 3>> stack;
    for (std::size_t source = 0; source < triangles.size(); ++source) {
        stack.push_back(triangles[source]);
        while (!stack.empty()) {
            const std::array<uint32_t, 3> t = stack.back();
            stack.pop_back();
            const std::vector<Vec3d>& positions = welder.positions();
            const Corners corners = {positions[t[0]], positions[t[1]], positions[t[2]]};
            const int split = edgeToSplit(edgeLengths(corners), maxEdge);
            if (split < 0) {
                if (out.triangles.size() >= maxPatches) {
                    return Error{concat("subdivision makes more than ", maxPatches, " patches")};
                }
                out.triangles.push_back(t);
                out.sourceTriangle.push_back(static_cast<uint32_t>(source));
                continue;
            }
            if (stack.size() > kMaxStackDepth) {
                return Error{concat("subdivision of triangle ", source,
                                    " does not converge (non-finite edge lengths?)")};
            }
            const uint32_t a = t[split];
            const uint32_t b = t[(split + 1) % 3];
            const uint32_t c = t[(split + 2) % 3];
            const uint32_t m = welder.insert(midpoint(corners[split], corners[(split + 1) % 3]));
            // Children (a, m, c) then (m, b, c): same winding as (a, b, c); the first pops first.
            stack.push_back({m, b, c});
            stack.push_back({a, m, c});
        }
    }
    return out;
}

// Sums frontierBound over the triangles, capped by each one's own Rosenberg-Stenger bound. A total
// budget of expanded nodes keeps the estimate fast: O(triangles) plus ~70 ms at worst.
uint64_t bisectionCountBound(std::span<const Vec3d> positions,
                             std::span<const std::array<uint32_t, 3>> triangles, double maxEdge) {
    DAISY_CHECK(maxEdge > 0);
    uint64_t budget = uint64_t{1} << 21;  // ~30 ns each
    std::vector<Corners> stack;
    double total = 0;
    for (const auto& triangle : triangles) {
        // Positions as the welder stores them (-0 folded), so decisions match bisectLongestEdges.
        Corners corners;
        for (int k = 0; k < 3; ++k) {
            DAISY_CHECK_OP(triangle[k], <, positions.size());
            const Vec3d& p = positions[triangle[k]];
            corners[k] = {p.x + 0.0, p.y + 0.0, p.z + 0.0};
        }
        total += std::min(rosenbergStengerBound(corners, edgeLengths(corners), maxEdge),
                          frontierBound(corners, maxEdge, budget, stack));
    }
    // Sums of integers, exact below 2^53, far beyond any patch limit.
    return total < 0x1p64 ? static_cast<uint64_t>(total) : UINT64_MAX;
}

}  // namespace daisy
