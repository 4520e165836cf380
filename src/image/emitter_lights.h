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
#include "shared/gpu_types.h"

namespace daisy {

struct LightTriangle {
    std::array<Vec3d, 3> corners;  // counter-clockwise seen from the front, as in the mesh
    uint32_t sourceTriangle;  // a triangle of the group it came from (its emission)
    // Its group: the connected coplanar triangles of one emission it was merged from (or a
    // group that stayed as it was), numbered 0, 1, ... in order; a group's lights are
    // consecutive.
    uint32_t group;
};

// The triangles of `mesh` listed in `triangles`, with `emissionClass[i]` equal for two of them
// exactly when their emission is equal. Groups of at least 3 triangles sharing edges (corners
// at equal positions), in one plane (normals within 1e-6, offsets within 1e-5 of the emitters'
// bounding-box diagonal: exporters leave faces flat only to rounding) and with one emission
// class, whose boundary is a single convex loop enclosing their area (1e-6 relative), become a
// fan over that loop with corners turning by under 1e-4 radians dropped when that has fewer
// triangles; everything else is kept as it is. Deterministic: lights come in the order
// of their groups' first triangles.
std::vector<LightTriangle> mergeEmitterFaces(const TriangleMesh& mesh,
                                             std::span<const uint32_t> triangles,
                                             std::span<const uint32_t> emissionClass);

// True when shared::pointToTriangleFactor(x, receiver.normal, light) is exactly 0 at every point
// x of the receiver triangle (its float corners; x may be rounded to float from a point inside):
// the receiver lies wholly behind the light's plane (the factor's first test fails), or the
// light wholly behind the receiver's plane (its clip to x's front half-space is empty). Each
// side must clear the plane by twice the tolerances the factor applies and the rounding of the
// coordinates (shared/formfactor.h: planeEpsilon over the distances that can occur,
// coordinateEpsilon), so a grazing pair is never called hidden. receiver.normal is the normal
// the caller passes to the factor. For skipping lights a patch cannot see (the final gather).
bool lightHiddenFrom(const shared::PatchGeometry& receiver, const shared::PatchGeometry& light);

}  // namespace daisy
