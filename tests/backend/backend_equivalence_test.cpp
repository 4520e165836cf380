// Every backend against the analytic oracles (STYLE.md rule 12: one TEST_P over backends; a
// backend without a device or build skips with the reason), and the reference backend against
// the cpu backend entry by entry. Oracles: Howell, "A Catalog of Radiation Heat Transfer
// Configuration Factors", 3rd ed.: C-11 (identical parallel directly opposed squares, side 1 at
// distance 1: 0.199824895698; at distance 2: 0.0685895888185526) and C-14 (perpendicular squares
// with a common edge, side 1: 0.200043776075); the summation rule (rows of a closed enclosure
// sum to 1) and reciprocity A_i F_ij = A_j F_ji (Howell, Menguc & Siegel, "Thermal Radiation Heat
// Transfer", 6th ed., eqs. 4.20 and 4.22); a symmetric occluder that hides exactly half.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "pipeline/backend_registry.h"
#include "radiosity/matrix_compare.h"
#include "radiosity/matrix_transport.h"
#include "radiosity/sparse_matrix.h"
#include "test_util.h"
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

// Parallel 8 x 8 squares at distance 2 with a plate at z = 1 that hides exactly half
// (verify/scenes.h).
PatchMesh halfOccludedSquares() {
    return patchesOf(verify::halfOccludedSquares());
}

// A closed cube with a tilted plate floating inside: shared edges, occlusion, all orientations.
PatchMesh cubeWithPlate() {
    TriangleMesh mesh = verify::unitCubeRoom(3);
    verify::addGrid(mesh, {0.3, 0.3, 0.4}, {0.5, 0, 0}, {0, 0.2, 0.1}, 2, 1);
    return patchesOf(mesh);
}

// The unit cube room (3 x 3 quads a face) around a solid box [0.35, 0.65] x [0.35, 0.65] x
// [0.2, 0.5] with outward faces: a closed enclosure with an obstacle, so every row of both the
// room and the box sums to 1 (the box hides part of the room from itself).
PatchMesh cubeAroundBox() {
    TriangleMesh mesh = verify::unitCubeRoom(3);
    verify::addSolidBox(mesh, {0.35, 0.35, 0.2}, {0.3, 0.3, 0.3}, 2);
    return patchesOf(mesh);
}

class BackendEquivalence : public testing::TestWithParam<const char*> {
protected:
    void SetUp() override {
        auto backend = makeBackend(GetParam());
        if (!backend && std::string(GetParam()) == "vulkan")
            DAISY_SKIP_WITHOUT_VULKAN(backend.error().message);
        if (!backend && std::string(GetParam()) == "cuda")
            DAISY_SKIP_WITHOUT_CUDA(backend.error().message);
        ASSERT_TRUE(backend.ok()) << backend.error().message;
        backend_ = std::move(*backend);
    }
    FormFactorResult build(const PatchMesh& mesh, FormFactorSettings settings = {}) {
        settings.progress = false;
        auto result = backend_->buildFormFactors(mesh, settings);
        EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
        if (!result.ok()) return {};
        EXPECT_EQ(validateStructure(result->matrix), "");
        return std::move(*result);
    }
    std::unique_ptr<Backend> backend_;
};

// Defaults (hybrid, L = 1, K = 16): within 0.1% of both closed forms, as the cpu driver's tests
// require (radiosity/form_factors_test.cpp).
TEST_P(BackendEquivalence, HowellClosedForms) {
    const PatchMesh c11 = patchesOf(parallelSquares(4));
    EXPECT_NEAR(groupFactor(c11, MatrixTransport(build(c11).matrix), 0, 32, 32, 64), kHowellC11,
                1e-3 * kHowellC11);
    const PatchMesh c14 = patchesOf(perpendicularSquares(4));
    EXPECT_NEAR(groupFactor(c14, MatrixTransport(build(c14).matrix), 0, 32, 32, 64), kHowellC14,
                1e-3 * kHowellC14);
}

// The simple rules reach the tolerances the cpu driver's tests give them on a 4 x 4 mesh.
TEST_P(BackendEquivalence, RiemannAndNusseltConverge) {
    const PatchMesh c11 = patchesOf(parallelSquares(4));
    FormFactorSettings riemann;
    riemann.method = FormFactorMethod::Riemann;
    riemann.quadratureLevel = 2;
    EXPECT_NEAR(groupFactor(c11, MatrixTransport(build(c11, riemann).matrix), 0, 32, 32, 64),
                kHowellC11, 2e-3 * kHowellC11);
    FormFactorSettings nusselt;
    nusselt.method = FormFactorMethod::Nusselt;
    nusselt.quadratureLevel = 0;
    EXPECT_NEAR(groupFactor(c11, MatrixTransport(build(c11, nusselt).matrix), 0, 32, 32, 64),
                kHowellC11, 1e-2 * kHowellC11);
}

// Summation rule in a closed cube (hybrid: exact up to its refinement tolerance), and around a
// solid box inside it, where visibility enters: every row of the room and the box sums to 1.
// At the default K = 4 rows stray by up to ~2% (sampling); at K = 256 by 0.2%. Without
// kernel-weighted visibility they fell short by up to 3.4% at any K: a room patch straddling
// the plane of a box face got shadow samples on its part behind that plane, blocked by the
// box's other faces, and the plain open fraction counted them. Reciprocity entry by entry.
TEST_P(BackendEquivalence, ClosedEnclosureRowsSumToOneAndReciprocityHolds) {
    const PatchMesh cube = patchesOf(verify::unitCubeRoom(2));
    for (double sum : rowSums(build(cube).matrix))
        ASSERT_NEAR(sum, 1.0, 1e-4);
    const PatchMesh occluded = cubeAroundBox();
    const SparseMatrix f = build(occluded).matrix;
    const std::vector<double> sums = rowSums(f);
    for (std::size_t i = 0; i < sums.size(); ++i)
        EXPECT_NEAR(sums[i], 1.0, 2.5e-2) << i;
    // Converges with K: the kernel-weighted visibility has no bias left to stall at (the plain
    // open fraction stayed 3.4% off at every K from 4 to 256).
    FormFactorSettings many;
    many.raysPerPair = 256;
    for (double sum : rowSums(build(occluded, many).matrix))
        EXPECT_NEAR(sum, 1.0, 3e-3);
    for (uint32_t i = 0; i < f.size; ++i) {
        for (std::size_t k = 0; k < f.rowLength(i); ++k) {
            const uint32_t j = f.rowColumns(i)[k];
            const double forward = occluded.areas[i] * f.rowValues(i)[k];
            ASSERT_NEAR(forward, occluded.areas[j] * f.at(j, i), 2.5e-7 * forward)
                << i << ", " << j;
        }
    }
}

TEST_P(BackendEquivalence, OccluderHalfwayHidesExactlyHalf) {
    const PatchMesh mesh = halfOccludedSquares();
    const double occluded =
        groupFactor(mesh, MatrixTransport(build(mesh).matrix), 0, 128, 128, 256);
    EXPECT_NEAR(occluded / kHowellC11Distance2, 0.5, 0.003);
}

INSTANTIATE_TEST_SUITE_P(Backends, BackendEquivalence,
                         testing::Values("cpu", "reference", "vulkan", "cuda"),
                         [](const testing::TestParamInfo<const char*>& param) {
                             return std::string(param.param);
                         });

FormFactorResult buildOn(const char* backendName, const PatchMesh& mesh,
                         FormFactorSettings settings) {
    settings.progress = false;
    auto backend = makeBackend(backendName);
    EXPECT_TRUE(backend.ok());
    auto result = (*backend)->buildFormFactors(mesh, settings);
    EXPECT_TRUE(result.ok()) << (result.ok() ? "" : result.error().message);
    return std::move(*result);
}

// Without visibility both backends run the same shared factor code on the same float geometry
// and store the mirror entry the same way: the matrices are identical, bit for bit.
TEST(ReferenceBackend, UnoccludedMatrixEqualsCpuBitForBit) {
    const PatchMesh mesh = cubeWithPlate();
    for (FormFactorMethod method :
         {FormFactorMethod::Hybrid, FormFactorMethod::Riemann, FormFactorMethod::Nusselt}) {
        FormFactorSettings settings;
        settings.method = method;
        settings.raysPerPair = 0;
        const SparseMatrix cpu = buildOn("cpu", mesh, settings).matrix;
        const SparseMatrix reference = buildOn("reference", mesh, settings).matrix;
        EXPECT_EQ(reference.rowOffsets, cpu.rowOffsets) << formFactorMethodName(method);
        EXPECT_EQ(reference.columns, cpu.columns);
        EXPECT_EQ(reference.values, cpu.values);
    }
}

// With visibility and culling off, both backends trace every candidate pair with the same
// segments, decided by the same watertight test (the cpu backend's Embree only proposes
// candidates, raycast/ray_caster.h): the matrices are identical, bit for bit.
TEST(ReferenceBackend, OccludedMatrixEqualsCpuBitForBitWithoutCulling) {
    for (const PatchMesh& mesh : {cubeWithPlate(), cubeAroundBox(), halfOccludedSquares()}) {
        FormFactorSettings settings;
        settings.shaftCulling = false;
        const SparseMatrix cpu = buildOn("cpu", mesh, settings).matrix;
        const SparseMatrix reference = buildOn("reference", mesh, settings).matrix;
        EXPECT_GT(cpu.nonzeroCount(), 0u);
        EXPECT_EQ(reference.rowOffsets, cpu.rowOffsets);
        EXPECT_EQ(reference.columns, cpu.columns);
        EXPECT_EQ(reference.values, cpu.values);
    }
}

// With culling the two backends' cost models price a segment differently (the reference's rays
// are dearer), so they may cull different pairs, and a clear or covered shaft can differ from
// the rays on a pair that grazes an edge or crosses the other's plane: nearly every entry must
// be identical and the rest within a few rays' worth (0.3 of the unoccluded factor: V is
// kernel-weighted, so 4 of 16 segments can weigh a little more than 4 / 16 of the pair).
TEST(ReferenceBackend, OccludedMatrixAgreesWithCpu) {
    for (const PatchMesh& mesh : {cubeWithPlate(), cubeAroundBox(), halfOccludedSquares()}) {
        FormFactorSettings settings;
        const SparseMatrix cpu = buildOn("cpu", mesh, settings).matrix;
        const SparseMatrix reference = buildOn("reference", mesh, settings).matrix;
        settings.raysPerPair = 0;
        const SparseMatrix open = buildOn("reference", mesh, settings).matrix;
        // Tolerances 0: every differing entry is over, and all of them are kept.
        const uint64_t entries = open.nonzeroCount();
        const MatrixComparison c = compareMatrices(cpu, reference, {0, 0, int(entries)});
        for (const EntryDifference& d : c.worst)
            EXPECT_LE(d.absolute, 0.3 * open.at(d.row, d.column)) << d.row << ", " << d.column;
        EXPECT_LE(c.overTolerance, entries / 100) << c.overTolerance << " of " << entries;
    }
}

TEST(ReferenceBackend, DeterministicAcrossThreadCounts) {
    const PatchMesh mesh = cubeWithPlate();
    FormFactorSettings one;
    one.threads = 1;
    FormFactorSettings two;
    two.threads = 2;
    const SparseMatrix a = buildOn("reference", mesh, one).matrix;
    const SparseMatrix b = buildOn("reference", mesh, two).matrix;
    EXPECT_EQ(a.columns, b.columns);
    EXPECT_EQ(a.values, b.values);
}

TEST(ReferenceBackend, RefusesStochasticAndOverMaxMemory) {
    auto backend = makeBackend("reference");
    ASSERT_TRUE(backend.ok());
    const PatchMesh mesh = cubeWithPlate();
    FormFactorSettings stochastic;
    stochastic.method = FormFactorMethod::Stochastic;
    auto refused = (*backend)->buildFormFactors(mesh, stochastic);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("backend 'reference' has no stochastic method"),
              std::string::npos);
    FormFactorSettings tiny;
    tiny.maxMemoryBytes = 1000;
    tiny.progress = false;
    auto tooBig = (*backend)->buildFormFactors(mesh, tiny);
    ASSERT_FALSE(tooBig.ok());
    EXPECT_NE(tooBig.error().message.find("--max-memory"), std::string::npos);
}

}  // namespace
}  // namespace daisy
