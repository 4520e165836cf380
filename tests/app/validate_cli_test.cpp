// `daisy validate` end to end (DESIGN.md sections 8, 9): exit status 0 when the backends agree,
// 1 over tolerance, 2 for bad usage, bad input or a backend that cannot run. The runs that need
// the vulkan backend skip without a Vulkan device (fail under DAISY_REQUIRE_VULKAN=1, as in CI),
// those that need the cuda backend without a CUDA device (fail under DAISY_REQUIRE_CUDA=1).
#include <gtest/gtest.h>

#include <string>

#include "pipeline/backend_registry.h"
#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

const std::string kCornellBox = test::assetPath("scenes/cornell_box.gltf");

// Empty when `daisy validate --backend vulkan` can run here, else why not.
std::string vulkanUnavailable() {
    auto backend = makeBackend("vulkan");
    return backend.ok() ? std::string() : backend.error().message;
}

#define DAISY_REQUIRE_VULKAN_OR_SKIP()                          \
    do {                                                        \
        const std::string reason = vulkanUnavailable();         \
        if (!reason.empty()) DAISY_SKIP_WITHOUT_VULKAN(reason); \
    } while (0)

TEST(ValidateCli, VulkanAgreesWithReference) {
    DAISY_REQUIRE_VULKAN_OR_SKIP();
    const RunResult run =
        runDaisy("validate " + kCornellBox + " --backend vulkan --against reference --worst 3");
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("validate: vulkan against reference"), std::string::npos)
        << run.output;
    EXPECT_NE(run.output.find("max absolute difference"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("over tolerance"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("within tolerance"), std::string::npos) << run.output;
}

// The cpu backend decides clear shafts without rays and accumulates in double: with zero
// tolerance some entry differs, which is exit status 1 and listed among the worst entries.
TEST(ValidateCli, OverToleranceIsStatusOne) {
    DAISY_REQUIRE_VULKAN_OR_SKIP();
    const RunResult run = runDaisy("validate " + kCornellBox +
                                   " --backend vulkan --against cpu --rtol 0 --atol 0 --worst 2");
    EXPECT_EQ(run.status, 1) << run.output;
    EXPECT_NE(run.output.find("worst entries"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("OVER TOLERANCE"), std::string::npos) << run.output;
}

TEST(ValidateCli, BadUsageIsStatusTwo) {
    // Only the GPU backends are validated; cpu and reference are what they are checked against.
    RunResult run = runDaisy("validate " + kCornellBox + " --backend cpu");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("--backend must be vulkan or cuda"), std::string::npos) << run.output;
    run = runDaisy("validate " + kCornellBox + " --backend vulkan --against opencl");
    EXPECT_EQ(run.status, 2) << run.output;
    run = runDaisy("validate " + kCornellBox + " --backend vulkan --rtol -1");
    EXPECT_EQ(run.status, 2) << run.output;
    run = runDaisy("validate " + test::testTempDir().string() + "/missing.gltf --backend vulkan");
    EXPECT_EQ(run.status, 2) << run.output;
}

TEST(ValidateCli, MissingDeviceIsStatusTwo) {
    const RunResult run = runDaisy("validate " + kCornellBox + " --backend vulkan --device 99");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("--backend vulkan"), std::string::npos) << run.output;
}

TEST(ValidateCli, StochasticIsStatusTwo) {
    DAISY_REQUIRE_VULKAN_OR_SKIP();
    const RunResult run =
        runDaisy("validate " + kCornellBox + " --backend vulkan --method stochastic");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("stochastic"), std::string::npos) << run.output;
}

// What a user on an NVIDIA machine runs (docs/gpu.md): cuda against the reference backend, then
// against cpu. Skips without a CUDA device (fails under DAISY_REQUIRE_CUDA=1).
TEST(ValidateCli, CudaAgreesWithReference) {
    auto backend = makeBackend("cuda");
    if (!backend) DAISY_SKIP_WITHOUT_CUDA(backend.error().message);
    RunResult run =
        runDaisy("validate " + kCornellBox + " --backend cuda --against reference --worst 3");
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_NE(run.output.find("validate: cuda against reference"), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("within tolerance"), std::string::npos) << run.output;
    run = runDaisy("validate " + kCornellBox + " --backend cuda --against cpu --rtol 0 --atol 0");
    EXPECT_EQ(run.status, 1) << run.output;
    EXPECT_NE(run.output.find("validate: cuda against cpu"), std::string::npos) << run.output;
}

// Without a device (or with --device 99 on a one-GPU box) validate cannot run: status 2.
TEST(ValidateCli, CudaWithoutADeviceIsStatusTwo) {
    const RunResult run = runDaisy("validate " + kCornellBox + " --backend cuda --device 99");
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_NE(run.output.find("--backend cuda"), std::string::npos) << run.output;
}

}  // namespace
}  // namespace daisy
