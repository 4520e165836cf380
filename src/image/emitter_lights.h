#pragma once
// The final gather's lights (image/final_gather.h): emitting source triangles with merged
// faces. A lamp modelled as a finely tessellated box (the black-light tubes: 176 triangles, five
// faces of 28 each per tube) is, for a point receiver, a few flat convex faces: the exact factor
// of a face is the sum of its triangles' factors (Lambert's contour formula is additive over a
// partition; the interior edges cancel), and a uniform point on the face is a uniform point on
// its triangles. So each connected group of coplanar triangles with the same emission whose union
// is one convex polygon is replaced by a fan of (corners - 2) triangles over that polygon, which
// leaves every factor and the gather's expectation unchanged and makes the per-sample light loop
// proportional to faces, not triangles.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "geometry/mesh.h"
#include "geometry/vec3.h"

namespace daisy {

struct LightTriangle {
    std::array<Vec3d, 3> corners;  // counter-clockwise seen from the front, as in the mesh
    uint32_t sourceTriangle;  // a triangle of the group it came from (its emission)
};

// The triangles of `mesh` listed in `triangles`, with `emissionClass[i]` equal for two of them
// exactly when their emission is equal. Groups of at least 3 triangles sharing edges (corners
// at equal positions), in one plane (normals within 1e-6, offsets within 1e-6 of the group's
// size) and with one emission class, whose boundary is a single convex loop enclosing their
// area (1e-6 relative), become a fan over that loop with collinear corners dropped when that
// has fewer triangles; everything else is kept as it is. Deterministic: lights come in the order
// of their groups' first triangles.
std::vector<LightTriangle> mergeEmitterFaces(const TriangleMesh& mesh,
                                             std::span<const uint32_t> triangles,
                                             std::span<const uint32_t> emissionClass);

}  // namespace daisy
