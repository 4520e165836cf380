#pragma once
// Test scenes built in code, shared by the tests, the tools, the micro-benchmarks and
// `daisy bench --stress`. Triangles are counter-clockwise seen from their front (mesh.h); every
// builder appends in a fixed order, so patch indices are stable and documented here.
#include <cstdint>
#include <string>

#include "geometry/mesh.h"
#include "geometry/patch_mesh.h"
#include "radiosity/transport.h"
#include "scene/scene.h"

namespace daisy::verify {

// Appends the parallelogram origin + s u + t v (s, t in [0, 1]) as an nu x nv grid of quads, row
// by row along u, two triangles each ((x, y), (x+1, y), (x+1, y+1)) and ((x, y), (x+1, y+1),
// (x, y+1)), facing cross(u, v); (nu + 1)(nv + 1) shared positions.
void addGrid(TriangleMesh& mesh, Vec3d origin, Vec3d u, Vec3d v, int nu, int nv,
             uint32_t material = 0);

// Appends the quad p0 p1 p2 p3 (counter-clockwise seen from its front) as the triangles
// (p0, p1, p2), (p0, p2, p3) with four positions of its own, so shared corners only meet
// through welding.
void addQuad(TriangleMesh& mesh, Vec3d p0, Vec3d p1, Vec3d p2, Vec3d p3, uint32_t material = 0);

// Appends the box origin + [0, size] as a closed room, faces facing inwards, each an n x n grid
// (addGrid), in the order floor (z = 0), ceiling, y = 0, y = max, x = 0, x = max; face f gets
// material f.
void addRoom(TriangleMesh& mesh, Vec3d origin, Vec3d size, int n);

// A material of flat spectra over 300..900 nm: reflectance `reflectance`, and emission
// `emission` (W m^-2 nm^-1) when positive. Named `name`.
Material flatMaterial(const std::string& name, double reflectance, double emission);

// The unit room of addRoom(n) as a Scene at path "room": material f is `base` named "face<f>"
// (origin "room: material <f>"), and face 1 (the ceiling) emits the preset spectrum `emission`
// at scale 1.
Scene unitRoomScene(int n, const std::string& emission, const Material& base = {});

// The unit cube [0, 1]^3 as a closed room: the faces of addRoom (same order and triangles),
// all material 0; 12 n^2 triangles.
TriangleMesh unitCubeRoom(int n);

// Appends the solid box origin + [0, size], faces facing outwards, each an n x n grid, in the
// order z = 0, z = max, y = 0, y = max, x = 0, x = max.
void addSolidBox(TriangleMesh& mesh, Vec3d origin, Vec3d size, int n = 1);

// The white furnace (unitCubeRoom(8), E = 1, rho = 0.5, B = 2 everywhere in view) with a closed
// 0.3 m box standing on its floor: the floor patches along the base run partly under it.
Scene furnaceWithABoxOnItsFloor();

// Appends the cube [lo, hi]^3 as 12 triangles (addQuad), facing inwards (a room) or outwards
// (an object); faces in the order x = lo, x = hi, y = lo, y = hi, z = lo, z = hi.
void addCube(TriangleMesh& mesh, double lo, double hi, bool inward);

// The axis-aligned box [lo, hi] as 12 triangles (addQuad) facing inwards, in the order
// y = lo (floor, +y), y = hi, x = lo, x = hi, z = lo, z = hi.
TriangleMesh closedRoom(Vec3d lo, Vec3d hi);

// Unit squares at z = 0 (facing +z) and z = distance (facing -z), n x n quads each: patches
// [0, 2 n^2) and [2 n^2, 4 n^2). Howell C-11 (at distance 1: kHowellC11).
TriangleMesh parallelSquares(int n, double distance = 1);

// Unit squares z = 0 (facing +z) and x = 0 (facing +x) sharing the edge x = z = 0, n x n quads
// each. Howell C-14 (kHowellC14).
TriangleMesh perpendicularSquares(int n);

// parallelSquares(8, 2) with a plate at z = 1 covering x < 0.5 (two triangles, patches 256 and
// 257, facing +z). The reflection x -> 1 - x swaps blocked and open segments and preserves the
// kernel, so F between the squares is exactly half of kHowellC11Distance2.
TriangleMesh halfOccludedSquares();

// The patch mesh of `mesh` without subdivision; the mesh must be valid (DAISY_CHECK).
PatchMesh patchesOf(const TriangleMesh& mesh);

// Area-weighted factor from the patch range [a0, a1) to [b0, b1): F_AB = sum A_i F_ij / A_A,
// the factor between the two unions.
double groupFactor(const PatchMesh& mesh, const Transport& transport, uint32_t a0, uint32_t a1,
                   uint32_t b0, uint32_t b1);

}  // namespace daisy::verify
