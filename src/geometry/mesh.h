#pragma once
// TriangleMesh: world-space triangles in scene order (DESIGN.md section 2), the geometry half
// of a Scene. Positions are in scene units (glTF: metres); triangles are counter-clockwise seen
// from their front, so the face normal is normalize(cross(b - a, c - a)).
#include <array>
#include <cstdint>
#include <vector>

#include "geometry/bounds.h"
#include "geometry/vec3.h"

namespace daisy {

struct TriangleMesh {
    std::vector<Vec3d> positions;  // world space
    std::vector<std::array<uint32_t, 3>> triangles;  // indices into positions
    std::vector<uint32_t> materials;  // per triangle, index into Scene::materials

    std::size_t triangleCount() const { return triangles.size(); }
    Vec3d corner(std::size_t triangle, int k) const { return positions[triangles[triangle][k]]; }
};

// Twice the signed area vector of triangle (a, b, c): cross(b - a, c - a); its length is 2 x area.
inline Vec3d areaVector2(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    return cross(b - a, c - a);
}

inline double triangleArea(const Vec3d& a, const Vec3d& b, const Vec3d& c) {
    return 0.5 * length(areaVector2(a, b, c));
}

Bounds3d meshBounds(const TriangleMesh& mesh);
double meshArea(const TriangleMesh& mesh);  // sum of triangle areas, scene units squared

}  // namespace daisy
