// The backend registry (DESIGN.md section 8) and the cpu backend's Embree ray caster. Oracles:
// segments whose occlusion is evident by construction.
#include "pipeline/backend_registry.h"

#include <gtest/gtest.h>

#include "backend/embree_ray_caster.h"
#include "verify/scenes.h"

namespace daisy {
namespace {

TEST(Backend, NamedBackendsAreThemselves) {
    for (const char* name : {"cpu", "reference"}) {
        auto backend = makeBackend(name);
        ASSERT_TRUE(backend.ok()) << name << ": " << backend.error().message;
        EXPECT_EQ((*backend)->name(), name);
    }
}

// auto: cuda on an NVIDIA device, then vulkan on a hardware GPU when built in, else cpu
// (DESIGN.md section 8). This machine class has no GPU, but a GPU box may legitimately pick cuda
// or vulkan.
TEST(Backend, AutoIsCpuVulkanOrCuda) {
    auto backend = makeBackend("auto");
    ASSERT_TRUE(backend.ok()) << backend.error().message;
    const std::string name = (*backend)->name();
    EXPECT_TRUE(name == "cpu" || name == "vulkan" || name == "cuda") << name;
#if !DAISY_HAVE_VULKAN && !DAISY_HAVE_CUDA
    EXPECT_EQ(name, "cpu");
#endif
}

TEST(Backend, UnbuiltAndUnknownBackendsAreErrors) {
#if !DAISY_HAVE_CUDA
    auto cuda = makeBackend("cuda");
    ASSERT_FALSE(cuda.ok());
    EXPECT_NE(cuda.error().message.find("backend 'cuda' is not built into this binary"),
              std::string::npos);
#endif
#if !DAISY_HAVE_VULKAN
    auto vulkan = makeBackend("vulkan");
    ASSERT_FALSE(vulkan.ok());
    EXPECT_NE(vulkan.error().message.find("not built into this binary"), std::string::npos);
    EXPECT_NE(vulkan.error().message.find("-DDAISY_ENABLE_VULKAN=ON"), std::string::npos);
#endif
    auto unknown = makeBackend("opencl");
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("unknown backend 'opencl'"), std::string::npos);
}

// A unit square at z = 1 (two triangles): segments through it are blocked, beside it not,
// ending on it not (the end point's own patch is excluded), empty never.
TEST(EmbreeRayCaster, OcclusionInEveryPacketMode) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    const PatchMesh patches = verify::patchesOf(mesh);
    auto caster = EmbreeRayCaster::create(patches);
    ASSERT_TRUE(caster.ok()) << caster.error().message;
    SegmentArrays segments;
    segments.resize(39);
    std::vector<uint8_t> expected;
    for (int k = 0; k < 37; ++k) {  // more than two packets, a partial one at the end
        const float x = 0.05f + 0.025f * float(k);
        segments.set(k, x, 0.5f, 0, x, 0.5f, 2);
        expected.push_back(x < 1.0f ? 1 : 0);
    }
    segments.set(37, 0.5f, 0.5f, 0, 0.5f, 0.5f, 1);  // ends on the square
    expected.push_back(0);
    segments.set(38, 0.5f, 0.5f, 0, 0.5f, 0.5f, 0);  // empty
    expected.push_back(0);
    for (PacketMode mode : {PacketMode::Single, PacketMode::Packet4, PacketMode::Packet8,
                            PacketMode::Packet16, PacketMode::Stream}) {
        (*caster)->setPacketMode(mode);
        std::vector<uint8_t> blocked(segments.size(), 7);
        (*caster)->occluded(segments, blocked);
        EXPECT_EQ(blocked, expected) << packetModeName(mode);
    }
}

TEST(EmbreeRayCaster, ClosestHitReportsThePatch) {
    TriangleMesh mesh;
    verify::addGrid(mesh, {0, 0, 1}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    verify::addGrid(mesh, {0, 0, 2}, {1, 0, 0}, {0, 1, 0}, 1, 1);
    auto caster = EmbreeRayCaster::create(verify::patchesOf(mesh));
    ASSERT_TRUE(caster.ok());
    const Ray rays[] = {
        {{0.7f, 0.2f, 0}, {0, 0, 1}}, {{0.2f, 0.7f, 0}, {0, 0, 1}}, {{0.5f, 0.5f, 0}, {0, 0, -1}}};
    uint32_t hits[3];
    (*caster)->closestHits(rays, hits);
    EXPECT_EQ(hits[0], 0u);  // (0.7, 0.2) is in the first triangle of the nearer square
    EXPECT_EQ(hits[1], 1u);
    EXPECT_EQ(hits[2], kNoPatch);
}

}  // namespace
}  // namespace daisy
