#include "geometry/patch_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check.h"
#include "core/strings.h"
#include "geometry/subdivision.h"

namespace daisy {
namespace {

constexpr uint32_t kUnwelded = UINT32_MAX;

// Welds the corners of every triangle, visiting triangles in scene order, so vertices are
// numbered in first use. Fails on a non-finite position.
Expected<std::vector<std::array<uint32_t, 3>>> weldTriangles(const TriangleMesh& mesh,
                                                             VertexWelder& welder) {
    std::vector<uint32_t> welded(mesh.positions.size(), kUnwelded);
    std::vector<std::array<uint32_t, 3>> triangles(mesh.triangleCount());
    for (std::size_t t = 0; t < mesh.triangleCount(); ++t) {
        for (int k = 0; k < 3; ++k) {
            const uint32_t input = mesh.triangles[t][k];
            DAISY_CHECK_OP(input, <, mesh.positions.size());
            if (welded[input] == kUnwelded) {
                if (!isFinite(mesh.positions[input])) {
                    return Error{concat("triangle ", t, " has a non-finite vertex position ",
                                        mesh.positions[input])};
                }
                welded[input] = welder.insert(mesh.positions[input]);
            }
            triangles[t][k] = welded[input];
        }
    }
    return triangles;
}

void computePatchGeometry(PatchMesh& mesh) {
    const std::size_t patchCount = mesh.patchCount();
    mesh.normals.resize(patchCount);
    mesh.areas.resize(patchCount);
    mesh.centroids.resize(patchCount);
    for (std::size_t p = 0; p < patchCount; ++p) {
        const Vec3d& a = mesh.positions[mesh.patches[p][0]];
        const Vec3d& b = mesh.positions[mesh.patches[p][1]];
        const Vec3d& c = mesh.positions[mesh.patches[p][2]];
        const Vec3d areaVector = areaVector2(a, b, c);
        const double twiceArea = length(areaVector);
        // A zero-area patch (only from zero-area input) gets a zero normal instead of NaN.
        mesh.normals[p] = twiceArea > 0 ? areaVector / twiceArea : Vec3d{};
        mesh.areas[p] = 0.5 * twiceArea;
        mesh.centroids[p] = (a + b + c) / 3.0;
    }
}

// CSR inversion of patches -> corners; ascending patch ids per vertex since patches are visited
// in order. A corner repeated within one patch (zero-area input) is listed once.
void buildVertexAdjacency(PatchMesh& mesh) {
    mesh.vertexPatchOffsets.assign(mesh.vertexCount() + 1, 0);
    auto corners = [&](std::size_t p, auto&& visit) {
        const auto& patch = mesh.patches[p];
        visit(patch[0]);
        if (patch[1] != patch[0]) visit(patch[1]);
        if (patch[2] != patch[0] && patch[2] != patch[1]) visit(patch[2]);
    };
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        corners(p, [&](uint32_t v) { ++mesh.vertexPatchOffsets[v + 1]; });
    }
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
        mesh.vertexPatchOffsets[v + 1] += mesh.vertexPatchOffsets[v];
    }
    mesh.vertexPatches.resize(mesh.vertexPatchOffsets.back());
    std::vector<uint64_t> next(mesh.vertexPatchOffsets.begin(), mesh.vertexPatchOffsets.end() - 1);
    for (std::size_t p = 0; p < mesh.patchCount(); ++p) {
        corners(p, [&](uint32_t v) { mesh.vertexPatches[next[v]++] = static_cast<uint32_t>(p); });
    }
}

}  // namespace

uint64_t estimatePatchCount(const TriangleMesh& mesh, double maxEdge) {
    if (maxEdge == 0) return mesh.triangleCount();
    if (!(maxEdge > 0) || !std::isfinite(maxEdge)) return UINT64_MAX;
    return bisectionCountBound(mesh.positions, mesh.triangles, maxEdge);
}

Expected<PatchMesh> buildPatchMesh(const TriangleMesh& mesh, double maxEdge, uint64_t maxPatches,
                                   std::span<const uint8_t> doubleSidedMaterials) {
    if (!std::isfinite(maxEdge) || maxEdge < 0) {
        return Error{
            concat("--subdivide: the maximum edge length must be finite and >= 0 (0 = no "
                   "subdivision), got ",
                   maxEdge)};
    }
    DAISY_CHECK(mesh.materials.empty() || mesh.materials.size() == mesh.triangleCount());

    PatchMesh out;
    VertexWelder welder(out.positions);
    auto welded = weldTriangles(mesh, welder);
    if (!welded) return welded.error();
    // Patch ids are uint32 (vertexPatches, the sparse matrix's columns).
    const uint64_t limit = std::min<uint64_t>(maxPatches, UINT32_MAX);
    const uint64_t estimate = estimatePatchCount(mesh, maxEdge);
    if (estimate > limit) {
        if (maxEdge == 0) {
            return Error{concat("the scene has ", formatCount(mesh.triangleCount()),
                                " triangles, over the limit of ", formatCount(limit), " patches")};
        }
        return Error{concat("--subdivide ", maxEdge, " could make up to ", formatCount(estimate),
                            " patches from ", formatCount(mesh.triangleCount()),
                            " triangles, over the limit of ", formatCount(limit),
                            "; use a larger --subdivide (or 0 for none)")};
    }
    if (maxEdge == 0) {
        out.patches = std::move(*welded);
        out.sourceTriangle.resize(out.patches.size());
        for (std::size_t t = 0; t < out.patches.size(); ++t) {
            out.sourceTriangle[t] = static_cast<uint32_t>(t);
        }
    } else {
        auto refined = bisectLongestEdges(*welded, maxEdge, limit, welder);
        if (!refined) return refined.error();
        out.patches = std::move(refined->triangles);
        out.sourceTriangle = std::move(refined->sourceTriangle);
    }
    // Meshes built without materials (tests, tools) read as material 0 throughout.
    out.materials.resize(out.patchCount(), 0);
    if (!mesh.materials.empty()) {
        for (std::size_t p = 0; p < out.patchCount(); ++p) {
            out.materials[p] = mesh.materials[out.sourceTriangle[p]];
        }
    }
    // Back patches of double-sided materials, after every front patch.
    const std::size_t frontCount = out.patchCount();
    out.backPatch.assign(frontCount, kNoBackPatch);
    if (!doubleSidedMaterials.empty()) {
        for (std::size_t p = 0; p < frontCount; ++p) {
            const uint32_t material = out.materials[p];
            if (material >= doubleSidedMaterials.size() || !doubleSidedMaterials[material])
                continue;
            if (out.patches.size() >= limit) {
                return Error{concat("the double-sided surfaces' back patches make more than ",
                                    formatCount(limit),
                                    " patches; use a larger --subdivide or "
                                    "raise --max-memory")};
            }
            const auto& front = out.patches[p];
            const auto back = static_cast<uint32_t>(out.patches.size());
            out.patches.push_back({front[0], front[2], front[1]});
            out.sourceTriangle.push_back(out.sourceTriangle[p]);
            out.materials.push_back(material);
            out.backPatch[p] = back;
            out.backPatch.push_back(static_cast<uint32_t>(p));
        }
    }
    computePatchGeometry(out);
    buildVertexAdjacency(out);
    return out;
}

}  // namespace daisy
