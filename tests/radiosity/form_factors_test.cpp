// The view-factor driver end to end (cpu backend rays), against closed forms and conservation
// laws. Oracles: Howell, "A Catalog of Radiation Heat Transfer Configuration Factors", 3rd ed.
// (http://www.thermalradiation.net/indexCat.html): C-11 (identical parallel directly opposed
// rectangles) at a = b = c = 1: 0.199824895698; C-14 (perpendicular rectangles with a common
// edge) at h = w = l = 1: 0.200043776075. Summation rule: in a closed enclosure every row of F
// sums to 1 (Howell, Menguc & Siegel, "Thermal Radiation Heat Transfer", 6th ed., eq. 4.22).
// Reciprocity A_i F_ij = A_j F_ji (ibid., eq. 4.20).
#include "radiosity/form_factors.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>

#include "radiosity/kernel_inputs.h"
#include "radiosity/matrix_compare.h"
#include "radiosity/matrix_transport.h"
#include "raycast/ray_caster.h"
#include "shared/formfactor.h"
#include "verify/closed_forms.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using verify::groupFactor;
using verify::kHowellC11;
using verify::kHowellC11Distance2;
using verify::kHowellC14;
using verify::parallelSquares;
using verify::patchesOf;
using verify::perpendicularSquares;

FormFactorResult build(const PatchMesh& mesh, FormFactorSettings settings) {
    settings.progress = false;
    // The cpu backend's ray caster.
    auto caster =
        makeRayCaster(mesh, {.packetMode = PacketMode::Stream, .watertightSegments = true});
    EXPECT_TRUE(caster.ok());
    auto result = computeFormFactors(mesh, settings, **caster);
    EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
    return std::move(*result);
}

double halfToHalf(const PatchMesh& mesh, const SparseMatrix& f) {
    const auto half = static_cast<uint32_t>(mesh.patchCount() / 2);
    return groupFactor(mesh, MatrixTransport(f), 0, half, half, 2 * half);
}

// Default settings (hybrid, L = 1, K = 16): within 0.1% of both closed forms (measured: ~1e-5,
// docs/formfactors.md), from two triangles a square to a fine mesh.
TEST(FormFactors, HowellC11ParallelSquaresAtDefaults) {
    for (int n : {1, 4}) {
        const PatchMesh mesh = patchesOf(parallelSquares(n));
        const FormFactorResult result = build(mesh, {});
        EXPECT_NEAR(halfToHalf(mesh, result.matrix), kHowellC11, 1e-3 * kHowellC11) << n;
        // Nothing can block: every pair's shaft is clear, no ray is cast.
        EXPECT_EQ(result.stats.raysCast, 0u);
    }
}

TEST(FormFactors, HowellC14PerpendicularSquaresAtDefaults) {
    for (int n : {1, 4}) {
        const PatchMesh mesh = patchesOf(perpendicularSquares(n));
        const FormFactorResult result = build(mesh, {});
        EXPECT_NEAR(halfToHalf(mesh, result.matrix), kHowellC14, 1e-3 * kHowellC14) << n;
    }
}

// The simple rules against the same oracles, with the tolerance each reaches on a 4 x 4 mesh
// (docs/formfactors.md has the full table): they converge, but slowly at the shared edge.
TEST(FormFactors, OtherMethodsConvergeTowardsTheClosedForms) {
    struct Case {
        FormFactorMethod method;
        int level;
        double c11Tolerance, c14Tolerance;  // relative
    };
    for (const Case& c : {Case{FormFactorMethod::Riemann, 2, 2e-3, 5e-2},
                          Case{FormFactorMethod::Nusselt, 0, 1e-2, 2e-2},
                          Case{FormFactorMethod::Stochastic, 0, 1e-2, 1e-2}}) {
        FormFactorSettings settings;
        settings.method = c.method;
        settings.quadratureLevel = c.level;
        settings.stochasticRays = 4096;
        const PatchMesh c11 = patchesOf(parallelSquares(4));
        const PatchMesh c14 = patchesOf(perpendicularSquares(4));
        EXPECT_NEAR(halfToHalf(c11, build(c11, settings).matrix), kHowellC11,
                    c.c11Tolerance * kHowellC11)
            << formFactorMethodName(c.method);
        EXPECT_NEAR(halfToHalf(c14, build(c14, settings).matrix), kHowellC14,
                    c.c14Tolerance * kHowellC14)
            << formFactorMethodName(c.method);
    }
}

// Summation rule in a closed cube of 2 x 2 quads a face (48 triangles, shared edges and
// corners everywhere). Tolerances per method: hybrid is exact up to its refinement tolerance;
// the 4x4 riemann rule overshoots next to shared edges (rows up to ~1.12, the original
// renderer's behaviour); stochastic rows are 1 only in expectation once made reciprocal.
TEST(FormFactors, ClosedCubeRowsSumToOne) {
    const PatchMesh cube = patchesOf(verify::unitCubeRoom(2));
    struct Case {
        FormFactorMethod method;
        int level;
        double tolerance;
    };
    for (const Case& c :
         {Case{FormFactorMethod::Hybrid, 1, 1e-4}, Case{FormFactorMethod::Riemann, 1, 0.15},
          Case{FormFactorMethod::Nusselt, 0, 0.1}, Case{FormFactorMethod::Stochastic, 0, 0.03}}) {
        FormFactorSettings settings;
        settings.method = c.method;
        settings.quadratureLevel = c.level;
        settings.stochasticRays = 4096;
        const std::vector<double> sums = rowSums(build(cube, settings).matrix);
        for (std::size_t i = 0; i < sums.size(); ++i)
            ASSERT_NEAR(sums[i], 1.0, c.tolerance)
                << formFactorMethodName(c.method) << " row " << i;
    }
}

TEST(FormFactors, DefaultRowsInACubeMeetTheIssueTolerance) {
    const std::vector<double> sums = rowSums(build(patchesOf(verify::unitCubeRoom(3)), {}).matrix);
    for (double sum : sums)
        EXPECT_NEAR(sum, 1.0, 1e-3);
}

// Reciprocity holds by construction: the mirror entry is F_ij A_i / A_j, rounded once to float.
TEST(FormFactors, ReciprocityIsExactUpToFloatRounding) {
    TriangleMesh mesh = verify::unitCubeRoom(2);
    verify::addGrid(mesh, {0.3, 0.3, 0.4}, {0.5, 0, 0}, {0, 0.2, 0.1}, 2, 1);  // a tilted plate
    const PatchMesh patches = patchesOf(mesh);
    for (FormFactorMethod method : {FormFactorMethod::Hybrid, FormFactorMethod::Stochastic}) {
        FormFactorSettings settings;
        settings.method = method;
        const SparseMatrix f = build(patches, settings).matrix;
        ASSERT_EQ(validateStructure(f), "");
        for (uint32_t i = 0; i < f.size; ++i) {
            for (std::size_t k = 0; k < f.rowLength(i); ++k) {
                const uint32_t j = f.rowColumns(i)[k];
                const double forward = patches.areas[i] * f.rowValues(i)[k];
                const double backward = patches.areas[j] * f.at(j, i);
                ASSERT_NEAR(forward, backward, 2.5e-7 * forward) << i << ", " << j;
            }
        }
    }
}

// A plate halfway between two parallel unit squares, covering x < 0.5 at z = 1, blocks the
// segment from (xs, ys, 0) to (xr, yr, 2) exactly when (xs + xr) / 2 < 0.5. The reflection
// x -> 1 - x of both squares swaps blocked and open pairs and preserves the kernel, so exactly
// half of the unoccluded factor remains: F = F_C11(distance 2) / 2.
TEST(FormFactors, OccluderHalfwayHidesExactlyHalf) {
    const PatchMesh open = patchesOf(parallelSquares(8, 2));
    const PatchMesh blocked = patchesOf(verify::halfOccludedSquares());
    const double unoccluded =
        groupFactor(open, MatrixTransport(build(open, {}).matrix), 0, 128, 128, 256);
    const FormFactorResult result = build(blocked, {});
    const double occluded = groupFactor(blocked, MatrixTransport(result.matrix), 0, 128, 128, 256);
    // Howell C-11 with a = b = 1, c = 2 (X = Y = 0.5): 0.0685895888185526.
    EXPECT_NEAR(unoccluded, kHowellC11Distance2, 5e-4 * kHowellC11Distance2);
    EXPECT_NEAR(occluded / unoccluded, 0.5, 0.002);
    // Shaft culling settles most pairs exactly: fully hidden (the plate covers the shaft) or
    // clear; only pairs straddling the shadow edge need rays.
    EXPECT_GT(result.stats.coveredPairs, 0u);
    EXPECT_GT(result.stats.clearClusterShafts + result.stats.clearPairShafts, 0u);
    EXPECT_LT(result.stats.tracedPairs, 128u * 128u);
}

// Same matrix, bit for bit, for 1 and 2 threads (each value depends only on its pair).
TEST(FormFactors, DeterministicAcrossThreadCounts) {
    TriangleMesh mesh = verify::unitCubeRoom(3);
    verify::addGrid(mesh, {0.2, 0.2, 0.5}, {0.6, 0, 0}, {0, 0.6, 0}, 3, 3);  // a floating plate
    const PatchMesh patches = patchesOf(mesh);
    for (FormFactorMethod method : {FormFactorMethod::Hybrid, FormFactorMethod::Stochastic}) {
        FormFactorSettings one, two;
        one.method = two.method = method;
        one.threads = 1;
        two.threads = 2;
        const SparseMatrix a = build(patches, one).matrix;
        const SparseMatrix b = build(patches, two).matrix;
        EXPECT_EQ(a.rowOffsets, b.rowOffsets);
        EXPECT_EQ(a.columns, b.columns);
        ASSERT_EQ(a.values.size(), b.values.size());
        EXPECT_EQ(std::memcmp(a.values.data(), b.values.data(), a.values.size() * sizeof(float)),
                  0);
    }
}

// Shaft culling only skips work: with it off every candidate pair is traced, and the matrix
// agrees except for segments that graze a surface within float rounding (tiny values).
TEST(FormFactors, ShaftCullingDoesNotChangeTheAnswer) {
    TriangleMesh mesh = verify::unitCubeRoom(3);
    verify::addGrid(mesh, {0.2, 0.2, 0.5}, {0.6, 0, 0}, {0, 0.6, 0}, 3, 3);
    verify::addGrid(mesh, {0.2, 0.8, 0.5}, {0.6, 0, 0}, {0, -0.6, 0}, 3, 3);  // its other side
    const PatchMesh patches = patchesOf(mesh);
    FormFactorSettings culled, traced;
    traced.shaftCulling = false;
    const FormFactorResult a = build(patches, culled);
    const FormFactorResult b = build(patches, traced);
    EXPECT_LT(a.stats.raysCast, b.stats.raysCast);
    const MatrixComparison c = compareMatrices(a.matrix, b.matrix, {0, 1e-6, 1});
    EXPECT_EQ(c.overTolerance, 0u)
        << "worst F(" << c.maxAbsolute.row << ", " << c.maxAbsolute.column
        << "): " << c.maxAbsolute.a << " vs " << c.maxAbsolute.b;
}

// A room whose floor lists its triangles shuffled (a Blender export's order), with a plate
// standing over it: the floor's clusters are split in space (patch_clusters.h), and culling
// still changes no entry against tracing every pair, while it now decides most floor pairs
// without rays (with index-range pieces every floor shaft spans the floor and holds the plate).
TEST(FormFactors, ShaftCullingOnAShuffledFloorDoesNotChangeTheAnswer) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 0}, {4, 0, 0}, {0, 4, 0}, 24, 24);  // floor facing +z, 1,152
    std::mt19937 rng(7);
    std::shuffle(mesh.triangles.begin(), mesh.triangles.end(), rng);
    verify::addGrid(mesh, {0, 0, 2}, {0, 4, 0}, {4, 0, 0}, 3, 3);  // ceiling facing -z
    verify::addGrid(mesh, {1.5, 1.5, 0.5}, {1, 0, 0}, {0, 0, 1}, 2, 2);  // plate facing -y
    verify::addGrid(mesh, {1.5, 1.5, 0.5}, {0, 0, 1}, {1, 0, 0}, 2, 2);  // and its back
    const PatchMesh patches = patchesOf(mesh);
    FormFactorSettings culled, traced;
    culled.costModel = false;  // cull wherever it can, to compare every decision with rays
    traced.shaftCulling = false;
    const FormFactorResult a = build(patches, culled);
    const FormFactorResult b = build(patches, traced);
    EXPECT_LT(a.stats.raysCast * 3, b.stats.raysCast);  // index-range clusters: 0.42 of it
    EXPECT_GT(a.stats.coveredPairs, 0u);
    const MatrixComparison c = compareMatrices(a.matrix, b.matrix, {0, 1e-6, 1});
    EXPECT_EQ(c.overTolerance, 0u)
        << "worst F(" << c.maxAbsolute.row << ", " << c.maxAbsolute.column
        << "): " << c.maxAbsolute.a << " vs " << c.maxAbsolute.b;
}

// Pairs facing away are skipped without rays and store nothing: two back-to-back squares.
TEST(FormFactors, FacingAwayPairsAreSkipped) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 2, 2);  // facing +z, away from
    verify::addGrid(mesh, {0, 0, 0}, {0, 1, 0}, {1, 0, 0}, 2, 2);  // this one, facing -z
    const FormFactorResult result = build(patchesOf(mesh), {});
    EXPECT_EQ(result.matrix.nonzeroCount(), 0u);
    EXPECT_EQ(result.stats.facingAway, result.stats.pairs);
    EXPECT_EQ(result.stats.raysCast, 0u);
}

// The candidate pass skips the per-pair test for cluster pairs that face each other by a wide
// margin (the room's opposite walls) and runs it elsewhere (a tilted plate that some patches see
// edge-on or from behind): its facing-away count is shared::facingAway over every pair.
TEST(FormFactors, FacingAwayCountIsThePerPairTestOverEveryPair) {
    TriangleMesh mesh = verify::unitCubeRoom(4);
    verify::addGrid(mesh, {0.2, 0.3, 0.2}, {0.6, 0, 0}, {0, 0.3, 0.5}, 3, 3);  // tilted plate
    verify::addGrid(mesh, {0.2, 0.6, 0.7}, {0.6, 0, 0}, {0, -0.3, -0.5}, 3, 3);  // its back
    const PatchMesh patches = patchesOf(mesh);
    const std::vector<shared::PatchGeometry> geometry = kernelPatches(patches);
    uint64_t facingAway = 0;
    for (std::size_t i = 0; i < geometry.size(); ++i) {
        for (std::size_t j = i + 1; j < geometry.size(); ++j)
            facingAway += shared::facingAway(geometry[i], geometry[j]) ? 1 : 0;
    }
    for (const bool culling : {true, false}) {
        FormFactorSettings settings;
        settings.shaftCulling = culling;
        const FormFactorResult result = build(patches, settings);
        EXPECT_EQ(result.stats.facingAway, facingAway) << "culling " << culling;
        EXPECT_GT(result.stats.facingAway, 0u);
        EXPECT_LT(result.stats.facingAway, result.stats.pairs);
    }
}

// Degenerate sizes: one patch has no pairs, an empty row, and still a valid 1 x 1 matrix.
TEST(FormFactors, SinglePatch) {
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    mesh.materials = {0};
    for (FormFactorMethod method : {FormFactorMethod::Hybrid, FormFactorMethod::Stochastic}) {
        FormFactorSettings settings;
        settings.method = method;
        const FormFactorResult result = build(patchesOf(mesh), settings);
        EXPECT_EQ(result.matrix.size, 1u);
        EXPECT_EQ(result.matrix.nonzeroCount(), 0u);
        EXPECT_EQ(validateStructure(result.matrix), "");
    }
}

TEST(FormFactors, RefusesABuildOverMaxMemory) {
    FormFactorSettings settings;
    settings.maxMemoryBytes = 1000;
    settings.progress = false;
    const PatchMesh cube = patchesOf(verify::unitCubeRoom(3));
    auto caster = makeRayCaster(cube);
    auto result = computeFormFactors(cube, settings, **caster);
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("--max-memory"), std::string::npos);
}

// Without visibility (K = 0) the factors are the unoccluded kernel: a closed cube still sums
// to one (nothing is hidden inside a convex room).
TEST(FormFactors, NoVisibilityMeansNoRays) {
    FormFactorSettings settings;
    settings.raysPerPair = 0;
    const FormFactorResult result = build(patchesOf(verify::unitCubeRoom(2)), settings);
    EXPECT_EQ(result.stats.raysCast, 0u);
    for (double sum : rowSums(result.matrix))
        EXPECT_NEAR(sum, 1.0, 1e-4);
}

}  // namespace
}  // namespace daisy
