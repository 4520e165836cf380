#include "geometry/mesh.h"

namespace daisy {

Bounds3d meshBounds(const TriangleMesh& mesh) {
    Bounds3d bounds;
    for (const auto& triangle : mesh.triangles) {
        for (uint32_t v : triangle)
            bounds.extend(mesh.positions[v]);
    }
    return bounds;
}

double meshArea(const TriangleMesh& mesh) {
    double area = 0;
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        area += triangleArea(mesh.corner(t, 0), mesh.corner(t, 1), mesh.corner(t, 2));
    }
    return area;
}

}  // namespace daisy
