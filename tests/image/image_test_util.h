#pragma once
// Small scenes for the image tests.
#include <cstdint>

#include "geometry/mesh.h"
#include "geometry/patch_mesh.h"

namespace daisy::test {

// Appends the quad p0 p1 p2 p3 (counter-clockwise seen from its front) as triangles
// (p0, p1, p2), (p0, p2, p3) with four positions of its own.
inline void addQuad(TriangleMesh& mesh, Vec3d p0, Vec3d p1, Vec3d p2, Vec3d p3,
                    uint32_t material = 0) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {p0, p1, p2, p3});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
    mesh.materials.insert(mesh.materials.end(), {material, material});
}

// The axis-aligned box [lo, hi] as 12 triangles facing inwards (a closed room).
inline TriangleMesh closedRoom(Vec3d lo, Vec3d hi) {
    TriangleMesh mesh;
    const auto p = [&](int x, int y, int z) {
        return Vec3d(x ? hi.x : lo.x, y ? hi.y : lo.y, z ? hi.z : lo.z);
    };
    addQuad(mesh, p(0, 0, 0), p(0, 0, 1), p(1, 0, 1), p(1, 0, 0));  // floor, normal +y
    addQuad(mesh, p(0, 1, 0), p(1, 1, 0), p(1, 1, 1), p(0, 1, 1));  // ceiling, -y
    addQuad(mesh, p(0, 0, 0), p(0, 1, 0), p(0, 1, 1), p(0, 0, 1));  // x = lo, +x
    addQuad(mesh, p(1, 0, 0), p(1, 0, 1), p(1, 1, 1), p(1, 1, 0));  // x = hi, -x
    addQuad(mesh, p(0, 0, 0), p(1, 0, 0), p(1, 1, 0), p(0, 1, 0));  // z = lo, +z
    addQuad(mesh, p(0, 0, 1), p(0, 1, 1), p(1, 1, 1), p(1, 0, 1));  // z = hi, -z
    return mesh;
}

inline PatchMesh patchesOf(const TriangleMesh& mesh) {
    return buildPatchMesh(mesh, 0).value();
}

}  // namespace daisy::test
