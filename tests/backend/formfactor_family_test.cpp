// The view-factor benchmark family (tools/make_formfactor_family.py), small versions,
// on every backend through the one driver. Oracle: the reference backend with shaft culling
// off, which traces every candidate pair (the driver's only ray-free decision left is facing
// away). Culling and the cost model only skip work, so every backend must give the same matrix
// up to segments that graze an edge; rows of nearly coplanar neighbours must not exceed 1
// (summation rule, Howell, Menguc & Siegel, "Thermal Radiation Heat Transfer", 6th ed., eq.
// 4.22: a row sums to at most 1); and one far triangle must not change the nearby pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <tuple>

#include "pipeline/backend_registry.h"
#include "radiosity/matrix_compare.h"
#include "radiosity/sparse_matrix.h"
#include "scene/load_scene.h"
#include "test_util.h"

namespace daisy {
namespace {

PatchMesh familyMesh(const std::string& name) {
    auto scene = loadScene(test::assetPath("scenes/formfactor_family/" + name + ".gltf"));
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
    if (!scene.ok()) return {};
    auto mesh = buildPatchMesh(scene->mesh, 0);
    EXPECT_TRUE(mesh.ok());
    return std::move(*mesh);
}

Expected<FormFactorResult> buildWith(const std::string& backendName, const PatchMesh& mesh,
                                     FormFactorSettings settings) {
    settings.progress = false;
    auto backend = makeBackend(backendName);
    if (!backend) return backend.error();
    return (*backend)->buildFormFactors(mesh, settings);
}

// The oracle: every candidate traced, K = 16.
const SparseMatrix& oracle(const std::string& scene) {
    static std::map<std::string, SparseMatrix> cache;
    auto found = cache.find(scene);
    if (found != cache.end()) return found->second;
    FormFactorSettings settings;
    settings.raysPerPair = 16;
    settings.shaftCulling = false;
    auto result = buildWith("reference", familyMesh(scene), settings);
    EXPECT_TRUE(result.ok());
    return cache[scene] = result.ok() ? std::move(result->matrix) : SparseMatrix{};
}

using FamilyCase = std::tuple<const char*, const char*>;  // scene, backend

class FormFactorFamily : public testing::TestWithParam<FamilyCase> {
protected:
    void SetUp() override {
        const std::string backend = std::get<1>(GetParam());
        auto made = makeBackend(backend);
        if (!made && backend == "vulkan") DAISY_SKIP_WITHOUT_VULKAN(made.error().message);
        if (!made && backend == "cuda") DAISY_SKIP_WITHOUT_CUDA(made.error().message);
        ASSERT_TRUE(made.ok()) << made.error().message;
    }
};

// Culling with the cost model against the oracle, entry by entry. The cpu backend decides every
// segment with the oracle's own watertight test and computes the oracle's kernel bit for bit, so
// on these scenes it agrees on every entry, on every instruction set (ctest runs this again with
// DAISY_ISA=avx2 and sse2): with Embree's coherent packets it had 838 (AVX-512), 1,324 (AVX2) and
// 1,198 (SSE2) entries of the cluttered scene apart. The GPU backends may differ by kernel
// rounding (1e-4 relative: their float arithmetic differs from the CPU's in the last bits) and,
// for segments that graze an edge, on at most 1% of entries, nearly all within 2 of the 16 rays'
// worth (F_unoccluded / 8). Boxes standing on the floor (scene (d)) have pairs whose segments run
// through the contact edge, where a compiler's rounding decides: at most 4 entries (2 pairs) or
// 1 in 10^4 may differ by more.
TEST_P(FormFactorFamily, AgreesWithTheReferenceEntryByEntry) {
    const std::string scene = std::get<0>(GetParam());
    const PatchMesh mesh = familyMesh(scene);
    FormFactorSettings settings;
    settings.raysPerPair = 16;
    auto result = buildWith(std::get<1>(GetParam()), mesh, settings);
    ASSERT_TRUE(result.ok()) << result.error().message;
    EXPECT_EQ(validateStructure(result->matrix), "");
    FormFactorSettings open = settings;
    open.raysPerPair = 0;
    auto unoccluded = buildWith("reference", mesh, open);
    ASSERT_TRUE(unoccluded.ok());
    const uint64_t entries = unoccluded->matrix.nonzeroCount();
    ASSERT_GT(entries, 0u);
    const MatrixComparison c = compareMatrices(result->matrix, oracle(scene), {1e-4, 0, 64});
    if (std::get<1>(GetParam()) == std::string("cpu")) {
        EXPECT_EQ(c.overTolerance, 0u) << c.overTolerance << " of " << entries;
    }
    EXPECT_LE(c.overTolerance, entries / 100) << c.overTolerance << " of " << entries;
    uint64_t beyondTwoRays = 0;
    for (const EntryDifference& d : c.worst) {
        const double bound = unoccluded->matrix.at(d.row, d.column);
        EXPECT_LE(d.absolute, bound * 1.0001 + 1e-9)
            << scene << " F(" << d.row << ", " << d.column << ")";
        beyondTwoRays += d.absolute > 2.0 / 16.0 * bound * 1.0001 + 1e-9 ? 1 : 0;
    }
    EXPECT_LE(beyondTwoRays, std::max<uint64_t>(4, entries / 10000)) << scene;
}

INSTANTIATE_TEST_SUITE_P(SmallScenes, FormFactorFamily,
                         testing::Combine(testing::Values("blacklight_small", "blender_room_small",
                                                          "open_small", "cluttered_small",
                                                          "far_triangle_small"),
                                          testing::Values("cpu", "reference", "vulkan", "cuda")),
                         [](const testing::TestParamInfo<FamilyCase>& param) {
                             return std::string(std::get<0>(param.param)) + "_" +
                                 std::get<1>(param.param);
                         });

class FormFactorFamilyBackend : public testing::TestWithParam<const char*> {
protected:
    void SetUp() override {
        auto made = makeBackend(GetParam());
        if (!made && std::string(GetParam()) == "vulkan")
            DAISY_SKIP_WITHOUT_VULKAN(made.error().message);
        if (!made && std::string(GetParam()) == "cuda")
            DAISY_SKIP_WITHOUT_CUDA(made.error().message);
        ASSERT_TRUE(made.ok()) << made.error().message;
    }
};

// Scene (b)'s room alone, a closed convex enclosure tessellated like a Blender export: nearly
// coplanar neighbours (corners ~5e-6 of their size off each other's planes) see each other as
// coplanar, F = 0, so every row sums to 1 (summation rule; hybrid's own error is ~1e-4) and
// none above 1 + 1e-3.
TEST_P(FormFactorFamilyBackend, NearlyCoplanarRowsSumToOne) {
    auto result = buildWith(GetParam(), familyMesh("blender_shell_small"), {});
    ASSERT_TRUE(result.ok());
    const std::vector<double> sums = rowSums(result->matrix);
    for (std::size_t i = 0; i < sums.size(); ++i)
        ASSERT_NEAR(sums[i], 1.0, 1e-3) << "row " << i;
}

// Scene (e): one triangle at z = 1e7 beside two facing squares and a plate that hides part of
// them changes nothing near them: every tolerance is relative to the patches involved, so the
// matrix restricted to the near patches equals, bit for bit, the one of the scene without the
// far triangle (the last one), and it has the reference backend's non-zeros (every pair traced).
TEST_P(FormFactorFamilyBackend, FarTriangleKeepsTheNearbyPairs) {
    auto scene = loadScene(test::assetPath("scenes/formfactor_family/far_triangle_small.gltf"));
    ASSERT_TRUE(scene.ok());
    auto mesh = buildPatchMesh(scene->mesh, 0);
    ASSERT_TRUE(mesh.ok());
    TriangleMesh nearOnly = scene->mesh;
    // The far triangle and its three corners come last.
    for (uint32_t corner : nearOnly.triangles.back())
        ASSERT_GE(corner + 3, nearOnly.positions.size());
    nearOnly.positions.resize(nearOnly.positions.size() - 3);
    nearOnly.triangles.pop_back();
    nearOnly.materials.pop_back();
    auto nearMesh = buildPatchMesh(nearOnly, 0);
    ASSERT_TRUE(nearMesh.ok());
    auto with = buildWith(GetParam(), *mesh, {});
    auto without = buildWith(GetParam(), *nearMesh, {});
    FormFactorSettings traced;
    traced.shaftCulling = false;
    auto reference = buildWith("reference", *mesh, traced);
    ASSERT_TRUE(with.ok() && without.ok() && reference.ok());
    const uint32_t n = without->matrix.size;
    ASSERT_EQ(with->matrix.size, n + 1);
    uint64_t nearEntries = 0;
    for (uint32_t i = 0; i < n; ++i) {
        for (uint32_t j = 0; j < n; ++j) {
            ASSERT_EQ(with->matrix.at(i, j), without->matrix.at(i, j)) << i << ", " << j;
            nearEntries += without->matrix.at(i, j) != 0.0f ? 1 : 0;
        }
    }
    EXPECT_GE(nearEntries, 32u);
    EXPECT_EQ(with->matrix.nonzeroCount(), reference->matrix.nonzeroCount());
    EXPECT_EQ(with->matrix.columns, reference->matrix.columns);
}

INSTANTIATE_TEST_SUITE_P(Backends, FormFactorFamilyBackend,
                         testing::Values("cpu", "reference", "vulkan", "cuda"),
                         [](const testing::TestParamInfo<const char*>& param) {
                             return std::string(param.param);
                         });

}  // namespace
}  // namespace daisy
