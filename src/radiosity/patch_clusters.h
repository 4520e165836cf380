#pragma once
// Patch groups for shaft culling (radiosity/shaft.h).
//
// Clusters: maximal runs of consecutive patches (in patch order) lying in one plane, at most
// kMaxClusterSize long. A cluster is a contiguous index range, so a block of rows or columns of
// F; because its patches are coplanar, none can block a ray leaving another (rays leave the
// plane at once), so shaft queries for a cluster pair skip both clusters' own patches. Each
// cluster carries a binary tree down to single patches, each node with a convex outline
// enclosing its patches, so a partly blocked cluster pair can be refined into smaller shafts.
// A node holds the patches order[begin, end) (a cluster's root: its whole index range). Typical
// meshes list neighbouring triangles together, so runs cut into kMaxClusterSize pieces are
// spatially compact, and a node's children halve its index range (order is the identity there).
// A run in scattered order (a Blender export lists a wall's triangles shuffled: every piece of
// it would span the whole wall, and so would every shaft) is cut into clusters of up to
// kMaxScatteredClusterSize patches instead (by index, so each still spans the run), and their
// trees split the patches in space (median of the centroids along the longest axis), so that
// nodes below the first levels are compact again.
//
// Solid faces: maximal coplanar runs (any length) whose triangles exactly tile their convex
// outline (areas add up), e.g. a subdivided box face. A shaft that crosses a solid face
// entirely (every segment from one end to the other passes through its interior) is blocked.
//
// Blockers: what shaft queries test, each a convex polygon: every solid face as one polygon
// (it enters a shaft exactly when one of its patches does, so it replaces them all), and every
// patch outside solid faces as its own triangle.
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/patch_mesh.h"
#include "radiosity/shaft.h"

namespace daisy {

inline constexpr uint32_t kMaxClusterSize = 32;
inline constexpr uint32_t kMaxScatteredClusterSize = 256;
inline constexpr int kMaxOutlineVertices = kMaxPolygonVertices;
inline constexpr uint32_t kNoFace = 0xffffffffu;

struct ClusterNode {
    uint32_t begin = 0;  // first position in PatchClusters::order
    uint32_t end = 0;  // one past the last position
    uint32_t outlineBegin = 0;  // into PatchClusters::outlinePoints
    uint32_t outlineCount = 0;
    uint32_t firstChild = 0;  // the two children are nodes firstChild, firstChild + 1; 0 = leaf
};

struct SolidFace {
    Vec3d normal;  // unit
    double offset = 0;  // plane: dot(normal, x) = offset
    std::vector<Vec3d> outline;  // convex, counter-clockwise about normal
    std::vector<Vec3d> inwardEdgeNormals;  // unit, in the plane, one per outline edge
};

struct PatchClusters {
    std::vector<uint32_t> order;  // patches by tree position; a permutation within each cluster
    std::vector<uint32_t> clusterRoot;  // per cluster: its root node
    std::vector<ClusterNode> nodes;
    std::vector<Vec3d> outlinePoints;
    std::vector<SolidFace> faces;
    std::vector<uint32_t> patchFace;  // per patch: its solid face, or kNoFace
    std::vector<ShaftPolygon> blockers;
    std::vector<uint32_t> blockerFace;  // per blocker: its solid face, or kNoFace (a patch)

    std::size_t clusterCount() const { return clusterRoot.size(); }
    const ClusterNode& cluster(std::size_t c) const { return nodes[clusterRoot[c]]; }
    std::span<const Vec3d> outline(const ClusterNode& node) const {
        return {outlinePoints.data() + node.outlineBegin, node.outlineCount};
    }
};

// How far a corner may lie off a run's plane and still count as in it: `relativeTolerance`
// times (its distance from the run's first corner plus its own coordinates' magnitude), i.e.
// relative to the patches involved, never to the scene.
PatchClusters buildPatchClusters(const PatchMesh& mesh, double relativeTolerance,
                                 uint32_t maxClusterSize = kMaxClusterSize);

// True when every segment from a point of conv(p) to a point of conv(q) crosses the interior of
// `face`: p and q lie strictly on opposite sides of its plane (by more than `margin`), and the
// crossing points of all vertex-to-vertex segments, whose convex hull holds every crossing,
// lie inside its outline by more than `margin`.
bool faceCoversShaft(const SolidFace& face, std::span<const Vec3d> p, std::span<const Vec3d> q,
                     double margin);

}  // namespace daisy
