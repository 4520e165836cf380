// `--vulkan-rays auto|query|software` end to end (docs/backends.md, "Ray queries"): `daisy info
// --backend vulkan` says how shadow rays are traced, `--verbose` names the acceleration
// structures (their memory and build time) or the flat BVH, both variants validate against the
// reference backend (exit 0), and `query` where no device has ray queries is one line and exit
// 2. Skips without a Vulkan device (fails under DAISY_REQUIRE_VULKAN=1, as in CI); the
// ray-query runs skip on a device without ray queries likewise.
#include <gtest/gtest.h>

#include <string>

#include "pipeline/backend_registry.h"
#include "test_util.h"

namespace daisy {
namespace {

using test::runDaisy;
using test::RunResult;

const std::string kCornellBox = test::assetPath("scenes/cornell_box.gltf");

// Empty when the vulkan backend can be made here with `rays`, else why not.
std::string vulkanUnavailable(VulkanRays rays) {
    BackendOptions options;
    options.vulkanRays = rays;
    auto backend = makeBackend("vulkan", options);
    return backend.ok() ? std::string() : backend.error().message;
}

#define DAISY_VULKAN_OR_SKIP(rays)                              \
    do {                                                        \
        const std::string reason = vulkanUnavailable(rays);     \
        if (!reason.empty()) DAISY_SKIP_WITHOUT_VULKAN(reason); \
    } while (0)

bool contains(const RunResult& run, const std::string& text) {
    return run.output.find(text) != std::string::npos;
}

TEST(VulkanRaysCli, InfoSaysHowShadowRaysAreTraced) {
    DAISY_VULKAN_OR_SKIP(VulkanRays::Query);
    RunResult run = runDaisy("info " + kCornellBox + " --backend vulkan --vulkan-rays query");
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(contains(run, "shadow rays: ray queries (VK_KHR_ray_query; --vulkan-rays query)"))
        << run.output;
    run = runDaisy("info " + kCornellBox + " --backend vulkan --vulkan-rays software");
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(contains(run, "shadow rays: the BVH walk in the shader (--vulkan-rays software)"))
        << run.output;
}

TEST(VulkanRaysCli, VerboseNamesWhatTheRaysTraverse) {
    DAISY_VULKAN_OR_SKIP(VulkanRays::Query);
    const std::string output = (test::testTempDir() / "F.mtx").string();
    RunResult run =
        runDaisy("formfactors " + kCornellBox +
                 " --backend vulkan --vulkan-rays query --no-cache --verbose -o " + output);
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(contains(run, "vulkan: acceleration structures over 38 triangles: ")) << run.output;
    EXPECT_TRUE(contains(run, " more during the build), built in ")) << run.output;
    run = runDaisy("formfactors " + kCornellBox +
                   " --backend vulkan --vulkan-rays software --no-cache --verbose -o " + output);
    EXPECT_EQ(run.status, 0) << run.output;
    EXPECT_TRUE(contains(run, "vulkan: flat BVH over 38 triangles: ")) << run.output;
    EXPECT_FALSE(contains(run, "acceleration structures")) << run.output;
}

TEST(VulkanRaysCli, BothVariantsValidateAgainstTheReference) {
    DAISY_VULKAN_OR_SKIP(VulkanRays::Query);
    for (const char* rays : {"query", "software"}) {
        const RunResult run =
            runDaisy("validate " + kCornellBox +
                     " --backend vulkan --against reference --vulkan-rays " + rays);
        EXPECT_EQ(run.status, 0) << rays << ": " << run.output;
        EXPECT_TRUE(contains(run, "within tolerance")) << run.output;
    }
}

// Asked of a device without ray queries (a lavapipe before Mesa 25, or a --device that has
// none): one error line naming what the device lacks, exit 2. Where every device has them the
// refusal is shown with a --device that matches none, which fails the same way.
TEST(VulkanRaysCli, QueryWithoutRayQueriesIsOneLineAndStatusTwo) {
    DAISY_VULKAN_OR_SKIP(VulkanRays::Software);
    const bool haveQueries = vulkanUnavailable(VulkanRays::Query).empty();
    const RunResult run = runDaisy(
        "formfactors " + kCornellBox + " --backend vulkan --no-cache " + "--vulkan-rays query -o " +
        (test::testTempDir() / "F.mtx").string() + (haveQueries ? " --device no-such-gpu" : ""));
    EXPECT_EQ(run.status, 2) << run.output;
    EXPECT_TRUE(contains(run,
                         haveQueries ? "error: --backend vulkan: --device no-such-gpu"
                                     : "no Vulkan device supports the compute backend with "
                                       "ray queries, as --vulkan-rays query asks"))
        << run.output;
}

}  // namespace
}  // namespace daisy
