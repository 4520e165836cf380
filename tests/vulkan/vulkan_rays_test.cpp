// The vulkan backend's two ways of tracing the visibility pass's shadow segments
// (docs/backends.md, "Ray queries"): the flat-BVH walk in the shader, and ray queries through
// acceleration structures over the same float triangles. Oracles: the reference backend (the
// same walk on the CPU, the same segments) entry by entry on the demo scenes and the small
// form-factor family, with shaft culling off so that both backends trace every candidate pair
// and the cost model's timing-dependent choices cannot differ; the two variants against each
// other; and the limit checks of the acceleration structures. The ray-query tests skip on a
// device without ray queries (Mesa lavapipe before 25), and fail instead under
// DAISY_REQUIRE_VULKAN=1 (CI installs a lavapipe that has them: tools/install_deps.sh).
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <string>
#include <tuple>

#include "backend/quiet_settings.h"
#include "radiosity/matrix_compare.h"
#include "scene/load_scene.h"
#include "test_util.h"

#ifdef DAISY_HAVE_VULKAN
#include "vulkan/vulkan_backend.h"
#endif

namespace daisy {
namespace {

#ifdef DAISY_HAVE_VULKAN

const char* raysName(VulkanRays rays) {
    return rays == VulkanRays::Query ? "query" : "software";
}

PatchMesh sceneMesh(const std::string& relative) {
    auto scene = loadScene(test::assetPath("scenes/" + relative + ".gltf"));
    EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().message);
    if (!scene.ok()) return {};
    auto mesh = buildPatchMesh(scene->mesh, 0);
    EXPECT_TRUE(mesh.ok());
    return mesh.ok() ? std::move(*mesh) : PatchMesh{};
}

// `daisy validate`'s settings (hybrid, L = 1, K = 16, seed 1) with shaft culling off.
FormFactorSettings everyPairTraced() {
    FormFactorSettings settings = test::quietSettings(FormFactorMethod::Hybrid, 16);
    settings.shaftCulling = false;
    return settings;
}

// The vulkan backend tracing with `rays`.
Expected<std::unique_ptr<Backend>> vulkanWith(VulkanRays rays,
                                              const VulkanBackendLimits& limits = {}) {
    BackendOptions options;
    options.vulkanRays = rays;
    return makeVulkanBackend(options, limits);
}

using SceneCase = std::tuple<const char*, VulkanRays>;

class VulkanRaysScenes : public ::testing::TestWithParam<SceneCase> {};

// Every entry within 1e-4 relative plus 1e-7 absolute of the reference backend (`daisy
// validate`'s defaults), on the demo scenes (but the 7,712-patch default scene, whose small
// version is in the family) and the small family, for both variants: the walk is the
// reference's own arithmetic, and ray queries decide no segment of these scenes differently.
TEST_P(VulkanRaysScenes, AgreesWithTheReferenceEntryByEntry) {
    const auto [scene, rays] = GetParam();
    auto vulkan = vulkanWith(rays);
    if (!vulkan) DAISY_SKIP_WITHOUT_VULKAN(vulkan.error().message);
    const PatchMesh mesh = sceneMesh(scene);
    ASSERT_GT(mesh.patchCount(), 0u);
    auto gpu = (*vulkan)->buildFormFactors(mesh, everyPairTraced());
    ASSERT_TRUE(gpu.ok()) << gpu.error().message;
    auto cpu = makeReferenceBackend()->buildFormFactors(mesh, everyPairTraced());
    ASSERT_TRUE(cpu.ok()) << cpu.error().message;
    const MatrixComparison c = compareMatrices(gpu->matrix, cpu->matrix, {1e-4, 1e-7, 3});
    EXPECT_EQ(c.overTolerance, 0u) << scene << ": " << c.overTolerance << " of " << c.unionEntries;
    for (const EntryDifference& d : c.worst) {
        if (d.excess > 1)
            ADD_FAILURE() << "F(" << d.row << ", " << d.column << "): " << d.a << " vs " << d.b;
    }
    EXPECT_GT(gpu->matrix.nonzeroCount(), 0u);
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, VulkanRaysScenes,
    ::testing::Combine(::testing::Values("cornell_box", "colored_lights", "furnace_box",
                                         "parallel_plates", "perpendicular_plates",
                                         "formfactor_family/blacklight_small",
                                         "formfactor_family/blender_room_small",
                                         "formfactor_family/blender_shell_small",
                                         "formfactor_family/cluttered_small",
                                         "formfactor_family/far_triangle_small",
                                         "formfactor_family/open_small"),
                       ::testing::Values(VulkanRays::Software, VulkanRays::Query)),
    [](const ::testing::TestParamInfo<SceneCase>& param) {
        std::string name = std::get<0>(param.param);
        std::replace(name.begin(), name.end(), '/', '_');
        return name + "_" + raysName(std::get<1>(param.param));
    });

// Where the two ray tests may disagree: a segment through a blocker's edge or corner. The walk
// resolves an exact zero edge function by symbolic perturbation (shared/intersect.h), so such a
// segment hits exactly one triangle of those sharing the edge; lavapipe's ray queries count a
// zero edge function as inside (the segment hits every triangle sharing it) and compute the
// edge functions in double. Both block a segment through an inner edge; at a blocker's outline
// they may decide differently, and near-edge rounding differs by an ulp. Bound, on the scenes
// whose boxes stand on the floor (segments run along the contact edges) and the black-light
// box: at most 1 entry in 10^4 (and at most 4) differs by more than 1e-4 relative, each by at
// most 2 of the 16 segments' worth (2/16 of the unoccluded factor) -- the family test's bound
// for segments that graze an edge (tests/backend/formfactor_family_test.cpp).
TEST(VulkanRayQuery, DiffersFromTheWalkOnlyAtEdges) {
    auto query = vulkanWith(VulkanRays::Query);
    if (!query) DAISY_SKIP_WITHOUT_VULKAN(query.error().message);
    auto walk = vulkanWith(VulkanRays::Software);
    if (!walk) DAISY_SKIP_WITHOUT_VULKAN(walk.error().message);
    for (const char* scene : {"formfactor_family/cluttered_small",
                              "formfactor_family/blacklight_small", "cornell_box"}) {
        SCOPED_TRACE(scene);
        const PatchMesh mesh = sceneMesh(scene);
        auto a = (*query)->buildFormFactors(mesh, everyPairTraced());
        auto b = (*walk)->buildFormFactors(mesh, everyPairTraced());
        ASSERT_TRUE(a.ok() && b.ok());
        FormFactorSettings open = everyPairTraced();
        open.raysPerPair = 0;
        auto unoccluded = (*walk)->buildFormFactors(mesh, open);
        ASSERT_TRUE(unoccluded.ok());
        const MatrixComparison c = compareMatrices(a->matrix, b->matrix, {1e-4, 1e-7, 64});
        const uint64_t entries = unoccluded->matrix.nonzeroCount();
        EXPECT_LE(c.overTolerance, std::max<uint64_t>(4, entries / 10000))
            << c.overTolerance << " of " << entries;
        for (const EntryDifference& d : c.worst) {
            EXPECT_LE(d.absolute,
                      2.0 / 16.0 * unoccluded->matrix.at(d.row, d.column) * 1.0001 + 1e-9)
                << "F(" << d.row << ", " << d.column << "): " << d.a << " vs " << d.b;
        }
    }
}

// `auto` traces with ray queries on a GPU that has them, and with the walk on a CPU device
// (lavapipe), whose ray queries are slower than the walk; either way it says which.
TEST(VulkanRayQuery, AutoChoosesByDeviceAndSaysWhich) {
    auto query = vulkanWith(VulkanRays::Query);
    if (!query) DAISY_SKIP_WITHOUT_VULKAN(query.error().message);
    auto automatic = vulkanWith(VulkanRays::Auto);
    ASSERT_TRUE(automatic.ok()) << automatic.error().message;
    auto walk = vulkanWith(VulkanRays::Software);
    ASSERT_TRUE(walk.ok()) << walk.error().message;
    const std::string described = (*automatic)->describe();
    const bool cpuDevice = described.find("' (cpu)") != std::string::npos;
    EXPECT_NE(described.find(cpuDevice ? "shadow rays: the BVH walk in the shader (faster than "
                                         "this CPU device's ray queries"
                                       : "shadow rays: ray queries (VK_KHR_ray_query)"),
              std::string::npos)
        << described;
    EXPECT_NE((*query)->describe().find("ray queries (VK_KHR_ray_query; --vulkan-rays query)"),
              std::string::npos)
        << (*query)->describe();
    EXPECT_NE((*walk)->describe().find("the BVH walk in the shader (--vulkan-rays software)"),
              std::string::npos)
        << (*walk)->describe();
}

// Acceleration structures over a buffer limit are refused before anything is allocated, with a
// message naming the limit and the ways out.
TEST(VulkanRayQuery, StructuresOverTheBufferLimitAreRefused) {
    auto query = vulkanWith(VulkanRays::Query, VulkanBackendLimits{0, 0, 0, 1024});
    if (!query) DAISY_SKIP_WITHOUT_VULKAN(query.error().message);
    auto refused = (*query)->buildFormFactors(sceneMesh("cornell_box"), everyPairTraced());
    ASSERT_FALSE(refused.ok());
    for (const char* part : {"the vulkan backend's ray queries need a bottom-level acceleration "
                             "structure of",
                             "for 38 triangles", "buffer limit of 1.00 KiB",
                             "maxMemoryAllocationSize on '", "use --vulkan-rays software"}) {
        EXPECT_NE(refused.error().message.find(part), std::string::npos) << refused.error().message;
    }
    // The same backend then builds a scene whose structures fit (4 triangles): the refusal
    // left nothing half made.
    auto fits = (*query)->buildFormFactors(sceneMesh("parallel_plates"), everyPairTraced());
    ASSERT_TRUE(fits.ok()) << fits.error().message;
    EXPECT_GT(fits->matrix.nonzeroCount(), 0u);
}

#else

TEST(VulkanRayQuery, NotBuilt) {
    DAISY_SKIP_WITHOUT_VULKAN("built with DAISY_ENABLE_VULKAN=OFF");
}

#endif

}  // namespace
}  // namespace daisy
