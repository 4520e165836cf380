// The backend registry (DESIGN.md section 8): names, the automatic choice and unbuilt backends.
#include "pipeline/backend_registry.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace daisy
