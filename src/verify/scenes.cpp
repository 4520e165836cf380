#include "verify/scenes.h"

#include <utility>

#include "core/strings.h"

namespace daisy::verify {

void addGrid(TriangleMesh& mesh, Vec3d origin, Vec3d u, Vec3d v, int nu, int nv,
             uint32_t material) {
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

void addQuad(TriangleMesh& mesh, Vec3d p0, Vec3d p1, Vec3d p2, Vec3d p3, uint32_t material) {
    const auto base = static_cast<uint32_t>(mesh.positions.size());
    mesh.positions.insert(mesh.positions.end(), {p0, p1, p2, p3});
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
    mesh.materials.insert(mesh.materials.end(), {material, material});
}

namespace {

// The six faces of addRoom, face f with material faceMaterial[f].
void addRoomFaces(TriangleMesh& mesh, Vec3d origin, Vec3d size, int n,
                  const uint32_t (&faceMaterial)[6]) {
    const Vec3d x{size.x, 0, 0}, y{0, size.y, 0}, z{0, 0, size.z};
    addGrid(mesh, origin, x, y, n, n, faceMaterial[0]);  // floor z = 0, normal cross(x, y) = +z
    addGrid(mesh, origin + z, y, x, n, n, faceMaterial[1]);  // ceiling, -z
    addGrid(mesh, origin, z, x, n, n, faceMaterial[2]);  // y = 0, +y
    addGrid(mesh, origin + y, x, z, n, n, faceMaterial[3]);  // y = max, -y
    addGrid(mesh, origin, y, z, n, n, faceMaterial[4]);  // x = 0, +x
    addGrid(mesh, origin + x, z, y, n, n, faceMaterial[5]);  // x = max, -x
}

}  // namespace

void addRoom(TriangleMesh& mesh, Vec3d origin, Vec3d size, int n) {
    addRoomFaces(mesh, origin, size, n, {0, 1, 2, 3, 4, 5});
}

Material flatMaterial(const std::string& name, double reflectance, double emission) {
    Material m;
    m.name = name;
    m.spectral.reflectance =
        SpectrumSpec{TabulatedSpectrum{{300, 900}, {reflectance, reflectance}}};
    if (emission > 0)
        m.spectral.emission = SpectrumSpec{TabulatedSpectrum{{300, 900}, {emission, emission}}};
    return m;
}

Scene unitRoomScene(int n, const std::string& emission, const Material& base) {
    Scene scene;
    scene.path = "room";
    addRoom(scene.mesh, {0, 0, 0}, {1, 1, 1}, n);
    for (int face = 0; face < 6; ++face) {
        Material material = base;
        material.name = concat("face", face);
        material.origin = concat("room: material ", face);
        scene.materials.push_back(material);
    }
    scene.materials[1].spectral.emission = SpectrumSpec{PresetSpectrum{emission}, 1.0};
    return scene;
}

TriangleMesh unitCubeRoom(int n) {
    TriangleMesh mesh;
    addRoomFaces(mesh, {0, 0, 0}, {1, 1, 1}, n, {0, 0, 0, 0, 0, 0});
    return mesh;
}

void addSolidBox(TriangleMesh& mesh, Vec3d origin, Vec3d size, int n) {
    const Vec3d x{size.x, 0, 0}, y{0, size.y, 0}, z{0, 0, size.z};
    addGrid(mesh, origin, y, x, n, n);  // z = 0, normal -z
    addGrid(mesh, origin + z, x, y, n, n);  // z = max, +z
    addGrid(mesh, origin, x, z, n, n);  // y = 0, -y
    addGrid(mesh, origin + y, z, x, n, n);  // y = max, +y
    addGrid(mesh, origin, z, y, n, n);  // x = 0, -x
    addGrid(mesh, origin + x, y, z, n, n);  // x = max, +x
}

void addCube(TriangleMesh& mesh, double lo, double hi, bool inward) {
    for (int axis = 0; axis < 3; ++axis) {
        for (int side = 0; side < 2; ++side) {
            Vec3d c[4];
            const double uv[4][2] = {{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}};
            for (int k = 0; k < 4; ++k) {
                c[k][axis] = side == 0 ? lo : hi;
                c[k][(axis + 1) % 3] = uv[k][0];
                c[k][(axis + 2) % 3] = uv[k][1];
            }
            // This order's normal is +axis, which points inward on side 0.
            if ((side == 0) == inward) {
                addQuad(mesh, c[0], c[1], c[2], c[3]);
            } else {
                addQuad(mesh, c[0], c[3], c[2], c[1]);
            }
        }
    }
}

TriangleMesh closedRoom(Vec3d lo, Vec3d hi) {
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

TriangleMesh parallelSquares(int n, double distance) {
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n, n);
    addGrid(mesh, {0, 0, distance}, {0, 1, 0}, {1, 0, 0}, n, n);
    return mesh;
}

TriangleMesh perpendicularSquares(int n) {
    TriangleMesh mesh;
    addGrid(mesh, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, n, n);
    addGrid(mesh, {0, 0, 0}, {0, 1, 0}, {0, 0, 1}, n, n);
    return mesh;
}

TriangleMesh halfOccludedSquares() {
    TriangleMesh mesh = parallelSquares(8, 2);
    addGrid(mesh, {-1, -1, 1}, {1.5, 0, 0}, {0, 3, 0}, 1, 1);
    return mesh;
}

Scene furnaceWithABoxOnItsFloor() {
    Scene scene;
    scene.path = "furnace-box";
    scene.mesh = unitCubeRoom(8);
    addSolidBox(scene.mesh, {0.35, 0.35, 0}, {0.3, 0.3, 0.3});
    scene.materials = {flatMaterial("flat", 0.5, 1)};
    return scene;
}

PatchMesh patchesOf(const TriangleMesh& mesh) {
    return std::move(buildPatchMesh(mesh, 0).value());
}

double groupFactor(const PatchMesh& mesh, const Transport& transport, uint32_t a0, uint32_t a1,
                   uint32_t b0, uint32_t b1) {
    double flux = 0, area = 0;
    std::vector<TransportEntry> row;
    for (uint32_t i = a0; i < a1; ++i) {
        area += mesh.areas[i];
        transport.row(i, row);
        for (const TransportEntry& entry : row)
            if (entry.patch >= b0 && entry.patch < b1) flux += mesh.areas[i] * entry.factor;
    }
    return flux / area;
}

}  // namespace daisy::verify
