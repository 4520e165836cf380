// The vulkan backend against the reference backend (DESIGN.md section 8): both run the shared
// pair kernel (shared/pair_kernel.h) on the same pairs with the same seed, so entries agree to
// float rounding (1e-4 relative), on analytic scenes (Howell C-11 and C-14 closed forms as a
// sanity check), an occluded scene and the Cornell box; chunking (tiny batches and dispatches,
// a tiny storage-buffer limit) must not change a bit; device selection errors are clear. The
// tests that trace rays run once per way of tracing them (VulkanRaysTest: the BVH walk in the
// shader, and ray queries through acceleration structures). Runs on whatever Vulkan device
// exists (Mesa lavapipe in CI); without one (or without ray queries, for that variant) every
// test is skipped, and fails instead when DAISY_REQUIRE_VULKAN=1 (what .ci/run sets, so CI
// cannot silently skip).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "backend/quiet_settings.h"
#include "pipeline/backend_registry.h"
#include "radiosity/matrix_compare.h"
#include "radiosity/matrix_transport.h"
#include "scene/load_scene.h"
#include "test_util.h"
#include "verify/closed_forms.h"
#include "verify/scenes.h"

#ifdef DAISY_HAVE_VULKAN
#include "vulkan/context.h"
#include "vulkan/vulkan_backend.h"
#endif

namespace daisy {
namespace {

using verify::kHowellC11;
using verify::kHowellC14;
using verify::patchesOf;
using verify::perpendicularSquares;

#ifdef DAISY_HAVE_VULKAN

// Unit squares at z = 0 (facing +z) and z = 1 (facing -z), n x n quads each; with `blocker`, a
// 0.5 x 0.5 two-sided-opaque square at z = 0.5 in the middle (facing +z).
PatchMesh parallelSquares(int n, bool blocker) {
    TriangleMesh mesh = verify::parallelSquares(n);
    if (blocker) verify::addGrid(mesh, {0.25, 0.25, 0.5}, {0.5, 0, 0}, {0, 0.5, 0}, 1, 1);
    return patchesOf(mesh);
}

PatchMesh cornellBox() {
    auto scene = loadScene(test::assetPath("scenes/cornell_box.gltf"));
    EXPECT_TRUE(scene.ok()) << scene.error().message;
    return std::move(buildPatchMesh(scene->mesh, 0).value());
}

// Area-weighted factor from patches [0, n/2) to [n/2, 2 n/2) (the first square to the second).
double firstToSecond(const PatchMesh& mesh, const SparseMatrix& f, uint32_t half) {
    return verify::groupFactor(mesh, MatrixTransport(f), 0, half, half, 2 * half);
}

// Entries of either matrix farther apart than rtol max(|a|, |b|) + 1e-7 (counted; the five worst
// reported). The 1e-7 floor (`daisy validate`'s default --atol) is for the tiny factors of
// nearly coplanar neighbours, whose float cancellation differs by ~1e-8 between the two
// compilers (measured on the Cornell box: 6.902e-6 against 6.911e-6).
uint64_t entriesOverTolerance(const SparseMatrix& a, const SparseMatrix& b, double rtol) {
    EXPECT_EQ(a.size, b.size);
    if (a.size != b.size) return 1;
    const MatrixComparison c = compareMatrices(a, b, {rtol, 1e-7, 5});
    for (const EntryDifference& d : c.worst) {
        if (d.excess > 1)
            ADD_FAILURE() << "F(" << d.row << ", " << d.column << "): " << d.a << " vs " << d.b;
    }
    return c.overTolerance;
}

class VulkanBackendTest : public ::testing::Test {
protected:
    void SetUp() override { makeBackends(BackendOptions{}); }

    void makeBackends(const BackendOptions& options) {
        auto backend = makeVulkanBackend(options);
        if (!backend) DAISY_SKIP_WITHOUT_VULKAN(backend.error().message);
        vulkan_ = std::move(*backend);
        reference_ = makeReferenceBackend();
        ASSERT_TRUE(reference_);
    }

    FormFactorResult build(Backend& backend, const PatchMesh& mesh,
                           const FormFactorSettings& settings) {
        auto result = backend.buildFormFactors(mesh, settings);
        EXPECT_TRUE(result.ok()) << backend.name() << ": " << result.error().message;
        return result.ok() ? std::move(*result) : FormFactorResult{};
    }

    // Vulkan and reference agree entry by entry for every pair method, with and without rays.
    void expectAgreement(const PatchMesh& mesh, const char* what) {
        for (FormFactorMethod method :
             {FormFactorMethod::Hybrid, FormFactorMethod::Riemann, FormFactorMethod::Nusselt}) {
            for (int rays : {0, 16}) {
                SCOPED_TRACE(std::string(what) + " " + formFactorMethodName(method) + " rays " +
                             std::to_string(rays));
                const FormFactorSettings settings = test::quietSettings(method, rays);
                const FormFactorResult gpu = build(*vulkan_, mesh, settings);
                const FormFactorResult cpu = build(*reference_, mesh, settings);
                EXPECT_EQ(entriesOverTolerance(gpu.matrix, cpu.matrix, 1e-4), 0u);
                EXPECT_GT(gpu.matrix.nonzeroCount(), 0u);
            }
        }
    }

    std::unique_ptr<Backend> vulkan_;
    std::unique_ptr<Backend> reference_;
};

// The same tests with the visibility pass's segments traced each way (--vulkan-rays software,
// --vulkan-rays query).
class VulkanRaysTest : public VulkanBackendTest, public ::testing::WithParamInterface<VulkanRays> {
protected:
    void SetUp() override { makeBackends(options()); }
    BackendOptions options() const {
        BackendOptions options;
        options.vulkanRays = GetParam();
        return options;
    }
};

TEST_P(VulkanRaysTest, AgreesWithReferenceOnAnalyticScenes) {
    expectAgreement(parallelSquares(3, false), "parallel squares");
    expectAgreement(patchesOf(perpendicularSquares(3)), "perpendicular squares");
    expectAgreement(patchesOf(verify::unitCubeRoom(2)), "unit cube room");
}

TEST_P(VulkanRaysTest, AgreesWithReferenceOnOccludedScenes) {
    expectAgreement(parallelSquares(4, true), "squares with a blocker");
    expectAgreement(cornellBox(), "Cornell box");
}

// The method and level are specialisation constants of the shader (one pipeline per method,
// level and mode, kept by the backend across builds; one visibility pipeline for all of them):
// every level agrees with reference, on one backend object that builds them one after the other
// and then the first again. riemann
// converges as O(h^2) (L = 1 ~5% high, each level ~4x better: formfactor_test.cpp), so a level
// the shader ignored would show: the levels' matrices must differ by far more than 1e-4.
TEST_P(VulkanRaysTest, EverySpecialisedLevelAgreesWithReference) {
    const PatchMesh mesh = parallelSquares(4, true);
    for (FormFactorMethod method : {FormFactorMethod::Riemann, FormFactorMethod::Hybrid}) {
        std::vector<SparseMatrix> byLevel;
        for (int level : {0, 2, 3, 0}) {
            for (int rays : {0, 4}) {
                SCOPED_TRACE(std::string(formFactorMethodName(method)) +
                             " L = " + std::to_string(level) + " rays " + std::to_string(rays));
                FormFactorSettings settings = test::quietSettings(method, rays);
                settings.quadratureLevel = level;
                FormFactorResult gpu = build(*vulkan_, mesh, settings);
                const FormFactorResult cpu = build(*reference_, mesh, settings);
                EXPECT_EQ(entriesOverTolerance(gpu.matrix, cpu.matrix, 1e-4), 0u);
                EXPECT_GT(gpu.matrix.nonzeroCount(), 0u);
                if (rays == 0) byLevel.push_back(std::move(gpu.matrix));
            }
        }
        ASSERT_EQ(byLevel.size(), 4u);
        if (method == FormFactorMethod::Riemann) {
            const MatrixComparison c02 = compareMatrices(byLevel[0], byLevel[1], {1e-4, 1e-7, 1});
            const MatrixComparison c23 = compareMatrices(byLevel[1], byLevel[2], {1e-4, 1e-7, 1});
            EXPECT_GT(c02.overTolerance, 0u);
            EXPECT_GT(c23.overTolerance, 0u);
        }
        // The first level again, from the kept pipeline: the same matrix, bit for bit.
        EXPECT_EQ(byLevel[0].values, byLevel[3].values);
    }
}

// Sanity against the closed forms at the defaults (hybrid, L = 1, K = 16); 1e-3 relative is the
// cpu backend's tolerance on the same meshes (radiosity/form_factors_test.cpp).
TEST_P(VulkanRaysTest, MatchesHowellClosedForms) {
    FormFactorSettings settings;
    settings.progress = false;
    const PatchMesh parallel = parallelSquares(4, false);
    const PatchMesh perpendicular = patchesOf(perpendicularSquares(4));
    const uint32_t half = uint32_t(parallel.patchCount() / 2);
    EXPECT_NEAR(firstToSecond(parallel, build(*vulkan_, parallel, settings).matrix, half),
                kHowellC11, 1e-3 * kHowellC11);
    EXPECT_NEAR(firstToSecond(perpendicular, build(*vulkan_, perpendicular, settings).matrix, half),
                kHowellC14, 1e-3 * kHowellC14);
}

// Tiny batches (7 pairs), dispatches (3 pairs: partial workgroups at every pairOffset) and a
// 4 KiB storage-buffer limit (512 pairs a batch) give the default run's matrix bit for bit.
TEST_P(VulkanRaysTest, ChunkingDoesNotChangeTheResult) {
    const PatchMesh mesh = cornellBox();
    const FormFactorSettings settings = test::quietSettings(FormFactorMethod::Hybrid, 16);
    const FormFactorResult whole = build(*vulkan_, mesh, settings);
    for (const VulkanBackendLimits& limits :
         {VulkanBackendLimits{7, 3, 0}, VulkanBackendLimits{0, 0, 4096},
          VulkanBackendLimits{1, 1, 0}}) {
        auto chunked = makeVulkanBackend(options(), limits);
        ASSERT_TRUE(chunked.ok()) << chunked.error().message;
        const FormFactorResult parts = build(**chunked, mesh, settings);
        EXPECT_EQ(parts.matrix.rowOffsets, whole.matrix.rowOffsets);
        EXPECT_EQ(parts.matrix.columns, whole.matrix.columns);
        EXPECT_EQ(parts.matrix.values, whole.matrix.values);
    }
}

// Patches (32 x 64 bytes) over a 1 KiB buffer limit: refused, naming the limit.
TEST_F(VulkanBackendTest, RefusesArraysOverTheStorageBufferLimit) {
    auto small = makeVulkanBackend(BackendOptions{}, VulkanBackendLimits{0, 0, 1024});
    ASSERT_TRUE(small.ok()) << small.error().message;
    auto result =
        (*small)->buildFormFactors(cornellBox(), test::quietSettings(FormFactorMethod::Hybrid, 16));
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("maxStorageBufferRange"), std::string::npos)
        << result.error().message;
}

TEST_F(VulkanBackendTest, RefusesStochastic) {
    auto result = vulkan_->buildFormFactors(cornellBox(),
                                            test::quietSettings(FormFactorMethod::Stochastic, 16));
    ASSERT_FALSE(result.ok());
    EXPECT_NE(result.error().message.find("stochastic"), std::string::npos)
        << result.error().message;
}

TEST_F(VulkanBackendTest, DeviceSelection) {
    auto missing = makeVulkanBackend(BackendOptions{"99"});
    ASSERT_FALSE(missing.ok());
    EXPECT_NE(missing.error().message.find("--device 99: there is no Vulkan device 99"),
              std::string::npos)
        << missing.error().message;
    auto unnamed = makeVulkanBackend(BackendOptions{"no-such-gpu"});
    ASSERT_FALSE(unnamed.ok());
    EXPECT_NE(unnamed.error().message.find("no Vulkan device's name contains 'no-such-gpu'"),
              std::string::npos)
        << unnamed.error().message;

    auto devices = listVulkanDevices();
    ASSERT_TRUE(devices.ok()) << devices.error().message;
    for (const VulkanDeviceInfo& device : *devices) {
        if (!device.unsupported.empty()) continue;
        EXPECT_TRUE(makeVulkanBackend(BackendOptions{std::to_string(device.index)}).ok());
        EXPECT_TRUE(makeVulkanBackend(BackendOptions{device.name.substr(0, 4)}).ok());
    }
}

TEST_F(VulkanBackendTest, TheRegistryMakesIt) {
    auto backend = makeBackend("vulkan");
    ASSERT_TRUE(backend.ok()) << backend.error().message;
    EXPECT_EQ((*backend)->name(), "vulkan");
}

INSTANTIATE_TEST_SUITE_P(Rays, VulkanRaysTest,
                         ::testing::Values(VulkanRays::Software, VulkanRays::Query),
                         [](const ::testing::TestParamInfo<VulkanRays>& param) {
                             return std::string(param.param == VulkanRays::Query ? "query"
                                                                                 : "software");
                         });

#else

TEST(VulkanBackendTest, NotBuilt) {
    DAISY_SKIP_WITHOUT_VULKAN("built with DAISY_ENABLE_VULKAN=OFF");
}

#endif

}  // namespace
}  // namespace daisy
