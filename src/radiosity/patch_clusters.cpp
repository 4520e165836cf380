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

// Appends the outline of patches order[begin, end) and returns its (offset, count).
std::pair<uint32_t, uint32_t> addOutline(const PatchMesh& mesh, uint32_t begin, uint32_t end,
                                         const Vec3d& normal, PatchClusters& out) {
    const auto offset = static_cast<uint32_t>(out.outlinePoints.size());
    if (end - begin == 1) {
        for (uint32_t c : mesh.patches[out.order[begin]])
            out.outlinePoints.push_back(mesh.positions[c]);
        return {offset, 3};
    }
    std::vector<Vec3d> corners;
    for (uint32_t p = begin; p < end; ++p) {
        for (uint32_t c : mesh.patches[out.order[p]])
            corners.push_back(mesh.positions[c]);
    }
    Vec3d hull[kMaxOutlineVertices];
    const int count = planarConvexHull(corners, normal, hull);
    out.outlinePoints.insert(out.outlinePoints.end(), hull, hull + count);
    return {offset, static_cast<uint32_t>(count)};
}

Vec3d centroidOf(const PatchMesh& mesh, uint32_t patch) {
    const auto& c = mesh.patches[patch];
    return (mesh.positions[c[0]] + mesh.positions[c[1]] + mesh.positions[c[2]]) * (1.0 / 3.0);
}

// Fills node `index` for patches order[begin, end) and, below it, the halves down to single
// patches. Children are allocated as a pair so that firstChild + 1 is the second. `spatial`:
// before halving, order[begin, end) is partitioned at the median centroid along the longest
// axis of the centroids' bounds (else the halves are those of the index range).
void fillNode(const PatchMesh& mesh, uint32_t index, uint32_t begin, uint32_t end,
              const Vec3d& normal, bool spatial, PatchClusters& out) {
    const auto [offset, count] = addOutline(mesh, begin, end, normal, out);
    ClusterNode node{begin, end, offset, count, 0};
    if (end - begin > 1) {
        node.firstChild = static_cast<uint32_t>(out.nodes.size());
        out.nodes.push_back({});
        out.nodes.push_back({});
        const uint32_t middle = begin + (end - begin) / 2;
        if (spatial) {
            Vec3d lo = centroidOf(mesh, out.order[begin]), hi = lo;
            for (uint32_t p = begin + 1; p < end; ++p) {
                const Vec3d c = centroidOf(mesh, out.order[p]);
                lo = {std::min(lo.x, c.x), std::min(lo.y, c.y), std::min(lo.z, c.z)};
                hi = {std::max(hi.x, c.x), std::max(hi.y, c.y), std::max(hi.z, c.z)};
            }
            const Vec3d extent = hi - lo;
            const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0
                : extent.y >= extent.z                                    ? 1
                                                                          : 2;
            const auto key = [&](uint32_t patch) {
                const Vec3d c = centroidOf(mesh, patch);
                return axis == 0 ? c.x : axis == 1 ? c.y : c.z;
            };
            std::nth_element(out.order.begin() + begin, out.order.begin() + middle,
                             out.order.begin() + end, [&](uint32_t a, uint32_t b) {
                                 const double ka = key(a), kb = key(b);
                                 return ka < kb || (ka == kb && a < b);
                             });
        }
        fillNode(mesh, node.firstChild, begin, middle, normal, spatial, out);
        fillNode(mesh, node.firstChild + 1, middle, end, normal, spatial, out);
    }
    out.nodes[index] = node;
}

// True when the run [begin, end) cut into `piece`-long index ranges gives scattered pieces: the
// in-plane areas of the pieces' bounding boxes add up to more than 4 times the run's own (pieces
// of a mesh listed neighbour by neighbour tile the run, about 1 to 2 times; pieces of a shuffled
// run each span most of it). Runs of at most two pieces are never scattered.
bool scatteredRun(const PatchMesh& mesh, uint32_t begin, uint32_t end, uint32_t piece) {
    if (end - begin <= 2 * piece) return false;
    const auto boxArea = [&](uint32_t first, uint32_t last) {
        Vec3d lo = centroidOf(mesh, first), hi = lo;
        for (uint32_t p = first; p < last; ++p) {
            for (uint32_t c : mesh.patches[p]) {
                const Vec3d& x = mesh.positions[c];
                lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
                hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
            }
        }
        // The two largest extents of a planar box: its area in the plane, up to the tilt.
        double e[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
        std::sort(e, e + 3);
        return e[1] * e[2];
    };
    double pieces = 0;
    for (uint32_t first = begin; first < end; first += piece)
        pieces += boxArea(first, std::min(end, first + piece));
    return pieces > 4.0 * boxArea(begin, end);
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
    out.order.resize(n);
    for (uint32_t p = 0; p < n; ++p)
        out.order[p] = p;
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
        const bool spatial = scatteredRun(mesh, runBegin, runEnd, maxClusterSize);
        const uint32_t size = spatial ? kMaxScatteredClusterSize : maxClusterSize;
        for (uint32_t begin = runBegin; begin < runEnd; begin += size) {
            const uint32_t end = std::min(runEnd, begin + size);
            const auto root = static_cast<uint32_t>(out.nodes.size());
            out.nodes.push_back({});
            fillNode(mesh, root, begin, end, normal, spatial, out);
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
