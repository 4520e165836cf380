#include "radiosity/patch_clusters.h"

#include <algorithm>
#include <cmath>

#include "radiosity/shaft.h"

namespace daisy {
namespace {

double magnitude(const Vec3d& v) {
    return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

bool inPlane(const PatchMesh& mesh, uint32_t patch, const Vec3d& normal, double offset,
             const Vec3d& anchor, double relativeTolerance) {
    if (dot(mesh.normals[patch], normal) < 1 - 1e-9) return false;
    for (uint32_t c : mesh.patches[patch]) {
        const Vec3d& p = mesh.positions[c];
        const double tolerance =
            relativeTolerance * (length(p - anchor) + magnitude(p) + magnitude(anchor));
        if (std::fabs(dot(normal, p) - offset) > tolerance) return false;
    }
    return true;
}

// Appends the outline of patches [begin, end) and returns its (offset, count).
std::pair<uint32_t, uint32_t> addOutline(const PatchMesh& mesh, uint32_t begin, uint32_t end,
                                         const Vec3d& normal, PatchClusters& out) {
    const auto offset = static_cast<uint32_t>(out.outlinePoints.size());
    if (end - begin == 1) {
        for (uint32_t c : mesh.patches[begin])
            out.outlinePoints.push_back(mesh.positions[c]);
        return {offset, 3};
    }
    std::vector<Vec3d> corners;
    for (uint32_t p = begin; p < end; ++p) {
        for (uint32_t c : mesh.patches[p])
            corners.push_back(mesh.positions[c]);
    }
    Vec3d hull[kMaxOutlineVertices];
    const int count = planarConvexHull(corners, normal, hull);
    out.outlinePoints.insert(out.outlinePoints.end(), hull, hull + count);
    return {offset, static_cast<uint32_t>(count)};
}

// Fills node `index` for patches [begin, end) and, below it, the halves down to single patches.
// Children are allocated as a pair so that firstChild + 1 is the second.
void fillNode(const PatchMesh& mesh, uint32_t index, uint32_t begin, uint32_t end,
              const Vec3d& normal, PatchClusters& out) {
    const auto [offset, count] = addOutline(mesh, begin, end, normal, out);
    ClusterNode node{begin, end, offset, count, 0};
    if (end - begin > 1) {
        node.firstChild = static_cast<uint32_t>(out.nodes.size());
        out.nodes.push_back({});
        out.nodes.push_back({});
        const uint32_t middle = begin + (end - begin) / 2;
        fillNode(mesh, node.firstChild, begin, middle, normal, out);
        fillNode(mesh, node.firstChild + 1, middle, end, normal, out);
    }
    out.nodes[index] = node;
}

void addSolidFace(const PatchMesh& mesh, uint32_t begin, uint32_t end, const Vec3d& normal,
                  double offset, PatchClusters& out) {
    std::vector<Vec3d> corners;
    double area = 0;
    for (uint32_t p = begin; p < end; ++p) {
        area += mesh.areas[p];
        for (uint32_t c : mesh.patches[p])
            corners.push_back(mesh.positions[c]);
    }
    Vec3d hull[kMaxOutlineVertices + 1];
    // One spare slot: a hull that does not fit comes back as a rectangle, which is not exact.
    const int count =
        planarConvexHull(corners, normal, std::span<Vec3d>(hull, kMaxOutlineVertices));
    if (count < 3) return;
    double hullArea = 0;
    for (int k = 1; k + 1 < count; ++k)
        hullArea += 0.5 * dot(normal, cross(hull[k] - hull[0], hull[k + 1] - hull[0]));
    if (!(std::fabs(hullArea - area) <= 1e-6 * area)) return;  // holes, or a rectangle fallback
    SolidFace face;
    face.normal = normal;
    face.offset = offset;
    face.outline.assign(hull, hull + count);
    for (int k = 0; k < count; ++k) {
        const Vec3d edge = hull[(k + 1) % count] - hull[k];
        face.inwardEdgeNormals.push_back(normalize(cross(normal, edge)));
    }
    const auto index = static_cast<uint32_t>(out.faces.size());
    out.blockers.emplace_back(face.outline, normal);
    out.blockerFace.push_back(index);
    out.faces.push_back(std::move(face));
    for (uint32_t p = begin; p < end; ++p)
        out.patchFace[p] = index;
}

}  // namespace

PatchClusters buildPatchClusters(const PatchMesh& mesh, double relativeTolerance,
                                 uint32_t maxClusterSize) {
    PatchClusters out;
    const auto n = static_cast<uint32_t>(mesh.patchCount());
    out.patchFace.assign(n, kNoFace);
    uint32_t runBegin = 0;
    while (runBegin < n) {
        // One coplanar run; faces take it whole, clusters cut it into pieces.
        const Vec3d normal = mesh.normals[runBegin];
        const Vec3d& anchor = mesh.positions[mesh.patches[runBegin][0]];
        const double offset = dot(normal, anchor);
        uint32_t runEnd = runBegin + 1;
        while (runEnd < n && inPlane(mesh, runEnd, normal, offset, anchor, relativeTolerance))
            ++runEnd;
        addSolidFace(mesh, runBegin, runEnd, normal, offset, out);
        for (uint32_t begin = runBegin; begin < runEnd; begin += maxClusterSize) {
            const uint32_t end = std::min(runEnd, begin + maxClusterSize);
            const auto root = static_cast<uint32_t>(out.nodes.size());
            out.nodes.push_back({});
            fillNode(mesh, root, begin, end, normal, out);
            out.clusterRoot.push_back(root);
        }
        runBegin = runEnd;
    }
    for (uint32_t p = 0; p < n; ++p) {
        if (out.patchFace[p] != kNoFace) continue;
        const Vec3d corners[3] = {mesh.positions[mesh.patches[p][0]],
                                  mesh.positions[mesh.patches[p][1]],
                                  mesh.positions[mesh.patches[p][2]]};
        out.blockers.emplace_back(corners, mesh.normals[p]);
        out.blockerFace.push_back(kNoFace);
    }
    return out;
}

bool faceCoversShaft(const SolidFace& face, std::span<const Vec3d> p, std::span<const Vec3d> q,
                     double margin) {
    double dp[Shaft::kMaxPoints], dq[Shaft::kMaxPoints];
    if (p.size() > std::size_t(Shaft::kMaxPoints) || q.size() > std::size_t(Shaft::kMaxPoints)) {
        return false;
    }
    const double side = dot(face.normal, p[0]) - face.offset > 0 ? 1.0 : -1.0;
    for (std::size_t a = 0; a < p.size(); ++a) {
        dp[a] = side * (dot(face.normal, p[a]) - face.offset);
        if (!(dp[a] > margin)) return false;
    }
    for (std::size_t b = 0; b < q.size(); ++b) {
        dq[b] = side * (dot(face.normal, q[b]) - face.offset);
        if (!(dq[b] < -margin)) return false;
    }
    for (std::size_t a = 0; a < p.size(); ++a) {
        for (std::size_t b = 0; b < q.size(); ++b) {
            const Vec3d x = p[a] + (q[b] - p[a]) * (dp[a] / (dp[a] - dq[b]));
            for (std::size_t k = 0; k < face.outline.size(); ++k) {
                if (!(dot(face.inwardEdgeNormals[k], x - face.outline[k]) > margin)) return false;
            }
        }
    }
    return true;
}

}  // namespace daisy
