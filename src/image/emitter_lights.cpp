#include "image/emitter_lights.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <utility>

#include "core/check.h"
#include "core/disjoint_sets.h"
#include "geometry/bounds.h"
#include "shared/formfactor.h"

namespace daisy {

namespace {

// Corners whose boundary turns by less than this sine are collinear; triangles whose planes
// are within kPlaneTolerance of the emitters' bounding-box diagonal are coplanar.
constexpr double kCollinearSine = 1e-4;
constexpr double kPlaneTolerance = 1e-5;

// The convex loop (vertex ids, counter-clockwise about `normal`) bounding the group `members`
// (indices into `corners`), or empty when the boundary is not one simple convex loop whose area
// matches the group's.
std::vector<uint32_t> convexBoundary(const std::vector<std::array<uint32_t, 3>>& ids,
                                     const std::vector<Vec3d>& points,
                                     const std::vector<uint32_t>& members, const Vec3d& normal,
                                     double groupArea) {
    std::map<std::pair<uint32_t, uint32_t>, int> edges;  // directed edge -> count
    for (const uint32_t t : members) {
        for (int k = 0; k < 3; ++k)
            ++edges[{ids[t][k], ids[t][(k + 1) % 3]}];
    }
    std::map<uint32_t, uint32_t> next;  // boundary vertex -> the next one
    for (const auto& [edge, count] : edges) {
        if (count != 1) return {};
        if (edges.count({edge.second, edge.first}) != 0) continue;  // interior edge
        if (!next.emplace(edge.first, edge.second).second) return {};  // not a simple loop
    }
    if (next.size() < 3) return {};
    std::vector<uint32_t> loop{next.begin()->first};
    while (loop.size() <= next.size()) {
        const auto it = next.find(loop.back());
        if (it == next.end()) return {};
        if (it->second == loop.front()) break;
        loop.push_back(it->second);
    }
    if (loop.size() != next.size()) return {};  // several loops (holes, pieces)
    // Drop collinear corners (turning by under kCollinearSine: a face tessellated as Blender
    // writes it is planar only to about 1e-6 of its size), then require every remaining turn to
    // be convex.
    std::vector<uint32_t> corners;
    const std::size_t n = loop.size();
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3d& prev = points[loop[(i + n - 1) % n]];
        const Vec3d& here = points[loop[i]];
        const Vec3d& after = points[loop[(i + 1) % n]];
        const double turn = dot(cross(here - prev, after - here), normal);
        if (std::abs(turn) <= kCollinearSine * length(here - prev) * length(after - here)) continue;
        if (turn < 0) return {};
        corners.push_back(loop[i]);
    }
    if (corners.size() < 3) return {};
    double fanArea = 0;
    for (std::size_t i = 1; i + 1 < corners.size(); ++i)
        fanArea += triangleArea(points[corners[0]], points[corners[i]], points[corners[i + 1]]);
    if (std::abs(fanArea - groupArea) > 1e-6 * groupArea) return {};
    return corners;
}

}  // namespace

std::vector<LightTriangle> mergeEmitterFaces(const TriangleMesh& mesh,
                                             std::span<const uint32_t> triangles,
                                             std::span<const uint32_t> emissionClass) {
    DAISY_CHECK(triangles.size() == emissionClass.size());
    const std::size_t count = triangles.size();
    // Weld corners by exact position, so unwelded copies of a vertex still connect.
    std::map<std::array<double, 3>, uint32_t> vertexIds;
    std::vector<Vec3d> points;
    std::vector<std::array<uint32_t, 3>> ids(count);
    std::vector<Vec3d> normals(count);
    std::vector<double> areas(count);
    for (std::size_t i = 0; i < count; ++i) {
        for (int k = 0; k < 3; ++k) {
            const Vec3d p = mesh.corner(triangles[i], k);
            const auto [it, added] =
                vertexIds.emplace(std::array{p.x, p.y, p.z}, uint32_t(points.size()));
            if (added) points.push_back(p);
            ids[i][std::size_t(k)] = it->second;
        }
        const Vec3d a = points[ids[i][0]], b = points[ids[i][1]], c = points[ids[i][2]];
        const Vec3d area2 = areaVector2(a, b, c);
        areas[i] = 0.5 * length(area2);
        normals[i] = areas[i] > 0 ? area2 * (1.0 / length(area2)) : Vec3d{0, 0, 0};
    }
    // Join triangles across shared edges with the same emission and plane.
    Bounds3d bounds;
    for (const Vec3d& p : points)
        bounds.extend(p);
    const double planeTolerance = points.empty() ? 0 : kPlaneTolerance * bounds.diagonal();
    DisjointSets sets(count);
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> edgeOwner;  // undirected edge -> triangle
    for (uint32_t i = 0; i < count; ++i) {
        if (!(areas[i] > 0)) continue;
        for (int k = 0; k < 3; ++k) {
            const uint32_t u = ids[i][std::size_t(k)], v = ids[i][std::size_t((k + 1) % 3)];
            const auto [it, added] = edgeOwner.emplace(std::minmax(u, v), i);
            if (added) continue;
            const uint32_t j = it->second;
            const bool coplanar = dot(normals[i], normals[j]) >= 1 - 1e-6 &&
                std::abs(dot(normals[i], points[ids[j][0]] - points[ids[i][0]])) <= planeTolerance;
            if (coplanar && emissionClass[i] == emissionClass[j]) sets.join(i, j);
        }
    }
    std::vector<std::vector<uint32_t>> groups;
    std::vector<int> groupOf(count, -1);
    for (uint32_t i = 0; i < count; ++i) {
        const uint32_t r = sets.find(i);
        if (groupOf[r] < 0) {
            groupOf[r] = int(groups.size());
            groups.emplace_back();
        }
        groups[std::size_t(groupOf[r])].push_back(i);
    }
    std::vector<LightTriangle> lights;
    for (uint32_t group = 0; group < groups.size(); ++group) {
        const std::vector<uint32_t>& members = groups[group];
        std::vector<uint32_t> loop;
        if (members.size() >= 3) {
            double area = 0;
            for (const uint32_t t : members)
                area += areas[t];
            loop = convexBoundary(ids, points, members, normals[members.front()], area);
        }
        if (!loop.empty() && loop.size() - 2 < members.size()) {
            for (std::size_t i = 1; i + 1 < loop.size(); ++i) {
                lights.push_back({{points[loop[0]], points[loop[i]], points[loop[i + 1]]},
                                  triangles[members.front()],
                                  group});
            }
            continue;
        }
        for (const uint32_t t : members) {
            lights.push_back(
                {{points[ids[t][0]], points[ids[t][1]], points[ids[t][2]]}, triangles[t], group});
        }
    }
    return lights;
}

namespace {

// True when every corner of `corners` is below the plane through `anchor` with unit normal `n`
// by more than twice (planeEpsilon of the corners' distance from the anchor plus `reach`, and
// coordinateEpsilon of the corners and the anchor).
bool whollyBelow(const shared::vec3 (&corners)[3], shared::vec3 n, shared::vec3 anchor,
                 float reach) {
    float height = -std::numeric_limits<float>::infinity();
    float distance = 0;
    float coordinates = 0;
    for (const shared::vec3& c : corners) {
        height = std::max(height, shared::dot(n, c - anchor));
        distance = std::max(distance, shared::length(c - anchor));
        coordinates = std::max(coordinates, shared::coordinateEpsilon(c, anchor));
    }
    return height < -2.0f * (shared::planeEpsilon(distance + reach) + coordinates);
}

}  // namespace

bool lightHiddenFrom(const shared::PatchGeometry& receiver, const shared::PatchGeometry& light) {
    const shared::vec3 r[3] = {receiver.a, receiver.b, receiver.c};
    const shared::vec3 l[3] = {light.a, light.b, light.c};
    // The light's corners are clipped against the plane through x, anywhere on the receiver:
    // their distances from x reach up to the receiver's diameter beyond those from its corner a.
    const float diameter =
        std::max({shared::length(receiver.b - receiver.a), shared::length(receiver.c - receiver.b),
                  shared::length(receiver.a - receiver.c)});
    return whollyBelow(r, light.normal, light.a, 0.0f) ||
        whollyBelow(l, receiver.normal, receiver.a, diameter);
}

}  // namespace daisy
