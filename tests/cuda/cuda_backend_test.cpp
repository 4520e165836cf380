// The cuda backend. Without a device: the missing-device and --device errors are one
// clear line. On an NVIDIA device (tools/gpu_check.sh, DAISY_REQUIRE_CUDA=1): cuda against the
// reference backend entry by entry, as tests/vulkan/vulkan_backend_test.cpp checks vulkan: both
// run the shared pair kernel on the same pairs with the same seed, so entries agree to float
// rounding (1e-4 relative plus 1e-7 absolute, `daisy validate`'s defaults), and tiny launches and
// batches (every partial block, many double-buffer rounds) must not change a bit.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "backend/quiet_settings.h"
#include "cuda/cuda_backend.h"
#include "pipeline/backend_registry.h"
#include "radiosity/matrix_compare.h"
#include "scene/load_scene.h"
#include "test_util.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

using verify::patchesOf;

TEST(CudaBackend, MissingDeviceIsOneClearLine) {
    auto backend = makeCudaBackend(BackendOptions{});
    if (cudaDevicePresent()) {
        EXPECT_TRUE(backend.ok()) << backend.error().message;
        return;
    }
    ASSERT_FALSE(backend.ok());
    const std::string& message = backend.error().message;
    EXPECT_EQ(message.rfind("no CUDA device (cudaGetDeviceCount", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    // auto then falls through to vulkan or cpu.
    const std::string resolved = resolveBackendName("auto");
    EXPECT_TRUE(resolved == "vulkan" || resolved == "cpu") << resolved;
}

TEST(CudaBackend, DeviceSelectorsThatMatchNothingAreErrors) {
    for (const char* selector : {"99", "no such gpu"}) {
        auto backend = makeCudaBackend(BackendOptions{selector});
        ASSERT_FALSE(backend.ok()) << selector;
        const std::string& message = backend.error().message;
        if (cudaDevicePresent()) {
            EXPECT_NE(message.find(std::string("--device ") + selector), std::string::npos)
                << message;
            EXPECT_NE(message.find("found: 0: '"), std::string::npos) << message;
        } else {
            EXPECT_EQ(message.rfind("no CUDA device", 0), 0u) << message;
        }
    }
}

class CudaBackendTest : public ::testing::Test {
protected:
    void SetUp() override {
        auto backend = makeCudaBackend(BackendOptions{});
        if (!backend) DAISY_SKIP_WITHOUT_CUDA(backend.error().message);
        cuda_ = std::move(*backend);
        reference_ = makeReferenceBackend();
    }

    SparseMatrix build(Backend& backend, const PatchMesh& mesh,
                       const FormFactorSettings& settings) {
        auto result = backend.buildFormFactors(mesh, settings);
        EXPECT_TRUE(result.ok()) << backend.name() << ": " << result.error().message;
        return result.ok() ? std::move(result->matrix) : SparseMatrix{};
    }

    // Entries farther apart than 1e-4 max(|a|, |b|) + 1e-7.
    uint64_t overTolerance(const SparseMatrix& a, const SparseMatrix& b) {
        EXPECT_EQ(a.size, b.size);
        const MatrixComparison c = compareMatrices(a, b, {1e-4, 1e-7, 5});
        for (const EntryDifference& d : c.worst) {
            if (d.excess > 1)
                ADD_FAILURE() << "F(" << d.row << ", " << d.column << "): " << d.a << " vs " << d.b;
        }
        return c.overTolerance;
    }

    void expectAgreement(const PatchMesh& mesh, const char* what) {
        for (FormFactorMethod method :
             {FormFactorMethod::Hybrid, FormFactorMethod::Riemann, FormFactorMethod::Nusselt}) {
            for (int rays : {0, 16}) {
                SCOPED_TRACE(std::string(what) + " " + formFactorMethodName(method) + " rays " +
                             std::to_string(rays));
                const FormFactorSettings settings = test::quietSettings(method, rays);
                const SparseMatrix gpu = build(*cuda_, mesh, settings);
                const SparseMatrix cpu = build(*reference_, mesh, settings);
                EXPECT_EQ(overTolerance(gpu, cpu), 0u);
                EXPECT_GT(gpu.nonzeroCount(), 0u);
            }
        }
    }

    std::unique_ptr<Backend> cuda_;
    std::unique_ptr<Backend> reference_;
};

TEST_F(CudaBackendTest, AgreesWithReferenceOnAnalyticScenes) {
    expectAgreement(patchesOf(verify::parallelSquares(3)), "parallel squares");
    expectAgreement(patchesOf(verify::perpendicularSquares(3)), "perpendicular squares");
    expectAgreement(patchesOf(verify::halfOccludedSquares()), "half-occluded squares");
}

TEST_F(CudaBackendTest, AgreesWithReferenceOnTheCornellBox) {
    auto scene = loadScene(test::assetPath("scenes/cornell_box.gltf"));
    ASSERT_TRUE(scene.ok()) << scene.error().message;
    expectAgreement(buildPatchMesh(scene->mesh, 0).value(), "cornell box");
}

TEST_F(CudaBackendTest, TinyLaunchesAndBatchesChangeNoBit) {
    const PatchMesh mesh = patchesOf(verify::halfOccludedSquares());
    const FormFactorSettings settings = test::quietSettings(FormFactorMethod::Hybrid, 16);
    const SparseMatrix whole = build(*cuda_, mesh, settings);
    for (const CudaBatchLimits limits :
         {CudaBatchLimits{1, 1}, CudaBatchLimits{3, 7}, CudaBatchLimits{65, 1000}}) {
        auto tiny = makeCudaBackend(BackendOptions{}, limits);
        ASSERT_TRUE(tiny.ok()) << tiny.error().message;
        const SparseMatrix chunked = build(**tiny, mesh, settings);
        EXPECT_EQ(chunked.columns, whole.columns) << limits.launchPairs;
        EXPECT_EQ(chunked.values, whole.values) << limits.launchPairs;
    }
}

TEST_F(CudaBackendTest, RefusesStochastic) {
    auto refused = cuda_->buildFormFactors(patchesOf(verify::unitCubeRoom(2)),
                                           test::quietSettings(FormFactorMethod::Stochastic, 16));
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().message.find("backend 'cuda' has no stochastic method"),
              std::string::npos);
}

}  // namespace
}  // namespace daisy
