#pragma once
// PatchMesh: the radiosity patches. Patches are the mesh's triangles in scene order (DESIGN.md
// section 2), each optionally subdivided until no edge is longer than maxEdge; the children of
// one source triangle are consecutive. Vertices are welded (bitwise-equal positions are one
// vertex) and subdivision is conforming, so neighbouring patches share their corners: no
// T-junctions. Normals, areas and centroids are computed in double precision from the corners.
// Double-sided surfaces add a back patch per front patch, after all the front patches.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/expected.h"
#include "geometry/mesh.h"

namespace daisy {

inline constexpr uint32_t kNoBackPatch = 0xffffffffu;

struct PatchMesh {
    std::vector<Vec3d> positions;  // welded vertices, world space
    std::vector<std::array<uint32_t, 3>> patches;  // corner indices, counter-clockwise
    std::vector<uint32_t> sourceTriangle;  // per patch: triangle index in scene order
    std::vector<uint32_t> materials;  // per patch: material index
    std::vector<Vec3d> normals;  // per patch: unit geometric (face) normal
    std::vector<double> areas;  // per patch: area, scene units squared
    std::vector<Vec3d> centroids;  // per patch
    // Per patch: the other face of a double-sided surface (same corners, reversed), or
    // kNoBackPatch. Back patches follow all front patches, in the order of their fronts.
    std::vector<uint32_t> backPatch;
    // Vertex -> patch adjacency (CSR): the patches touching vertex v are
    // vertexPatches[vertexPatchOffsets[v] .. vertexPatchOffsets[v + 1]), in ascending order.
    std::vector<uint64_t> vertexPatchOffsets;
    std::vector<uint32_t> vertexPatches;

    std::size_t patchCount() const { return patches.size(); }
    std::size_t vertexCount() const { return positions.size(); }
    std::span<const uint32_t> patchesAtVertex(uint32_t vertex) const {
        return {vertexPatches.data() + vertexPatchOffsets[vertex],
                vertexPatches.data() + vertexPatchOffsets[vertex + 1]};
    }
};

// Memory one patch costs in a PatchMesh, rounded up: corners 12, source triangle and material 8,
// normal, centroid and area 56, adjacency 12, and about half a welded vertex with its offsets
// and weld table 20; 128 leaves room for the subdivision's working stack.
inline constexpr uint64_t kPatchMeshBytesPerPatch = 128;

// Upper bound on the patch count buildPatchMesh would produce for maxEdge (0 = no subdivision),
// computed without subdividing, so absurd settings can be refused before memory is spent.
uint64_t estimatePatchCount(const TriangleMesh& mesh, double maxEdge);

// Builds the patches. maxEdge = 0 keeps the input triangles. Fails (no crash) when maxEdge is
// negative or non-finite, or when the result would exceed maxPatches patches.
// doubleSidedMaterials[m] != 0 gives each patch of material m a back patch (glTF doubleSided).
Expected<PatchMesh> buildPatchMesh(const TriangleMesh& mesh, double maxEdge,
                                   uint64_t maxPatches = UINT32_MAX,
                                   std::span<const uint8_t> doubleSidedMaterials = {});

}  // namespace daisy
