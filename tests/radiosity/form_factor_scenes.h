#pragma once
// Small scenes for the form-factor tests: quads meshed as grids of triangles, with the normal
// along cross(u, v).
#include <cstdint>

#include "geometry/mesh.h"
#include "geometry/patch_mesh.h"
#include "radiosity/sparse_matrix.h"

namespace daisy::test {

// Howell, "A Catalog of Radiation Heat Transfer Configuration Factors", 3rd ed.: C-11, identical
// parallel directly opposed unit squares at distance 1 (and 2); C-14, perpendicular unit squares
// sharing an edge.
inline constexpr double kHowellC11 = 0.199824895698;
inline constexpr double kHowellC11Distance2 = 0.0685895888185526;
inline constexpr double kHowellC14 = 0.200043776075;

// Adds the parallelogram origin + s u + t v (s, t in [0, 1]) as an nu x nv grid of quads, two
// triangles each, facing cross(u, v).
inline void addGrid(TriangleMesh& mesh, Vec3d origin, Vec3d u, Vec3d v, int nu, int nv,
                    uint32_t material = 0) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    for (int y = 0; y <= nv; ++y) {
        for (int x = 0; x <= nu; ++x)
            mesh.positions.push_back(origin + u * (double(x) / nu) + v * (double(y) / nv));
    }
    const auto at = [&](int x, int y) { return base + uint32_t(y * (nu + 1) + x); };
    for (int y = 0; y < nv; ++y) {
        for (int x = 0; x < nu; ++x) {
            mesh.triangles.push_back({at(x, y), at(x + 1, y), at(x + 1, y + 1)});
            mesh.triangles.push_back({at(x, y), at(x + 1, y + 1), at(x, y + 1)});
            mesh.materials.insert(mesh.materials.end(), {material, material});
        }
    }
}

// The unit cube [0, 1]^3 as a closed room: each face an n x n grid, normals pointing inwards.
inline TriangleMesh unitCubeRoom(int n) {
    TriangleMesh mesh;
    const Vec3d o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
    addGrid(mesh, o, x, y, n, n);  // floor z = 0, normal cross(x, y) = +z
    addGrid(mesh, z, y, x, n, n);  // ceiling z = 1, normal -z
    addGrid(mesh, o, z, x, n, n);  // y = 0, normal +y
    addGrid(mesh, y, x, z, n, n);  // y = 1, normal -y
    addGrid(mesh, o, y, z, n, n);  // x = 0, normal +x
    addGrid(mesh, x, z, y, n, n);  // x = 1, normal -x
    return mesh;
}

inline PatchMesh patchesOf(const TriangleMesh& mesh) {
    return std::move(buildPatchMesh(mesh, 0).value());
}

// Unit squares at z = 0 (facing +z) and z = distance (facing -z), n x n quads each (Howell
// C-11 at distance 1: 0.199824895698).
inline PatchMesh parallelSquares(int n, double distance = 1) {
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n, n);
    addGrid(mesh, {0, 0, distance}, {0, 1, 0}, {1, 0, 0}, n, n);
    return patchesOf(mesh);
}

// Unit squares z = 0 (facing +z) and x = 0 (facing +x) sharing the edge x = z = 0 (Howell
// C-14: 0.200043776075).
inline PatchMesh perpendicularSquares(int n) {
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n, n);
    addGrid(mesh, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, n, n);
    return patchesOf(mesh);
}

// Area-weighted factor from the patch range [a0, a1) to [b0, b1): F_AB = sum A_i F_ij / A_A.
inline double groupFactor(const PatchMesh& mesh, const SparseMatrix& f, uint32_t a0, uint32_t a1,
                          uint32_t b0, uint32_t b1) {
    double flux = 0, area = 0;
    for (uint32_t i = a0; i < a1; ++i) {
        area += mesh.areas[i];
        for (uint32_t j = b0; j < b1; ++j)
            flux += mesh.areas[i] * f.at(i, j);
    }
    return flux / area;
}

}  // namespace daisy::test
