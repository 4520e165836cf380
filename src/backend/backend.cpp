#include "backend/backend.h"

#include "core/strings.h"

#if DAISY_HAVE_VULKAN
#include "vulkan/vulkan_backend.h"
#endif

namespace daisy {

std::vector<std::string> backendNames() {
    return {"auto", "cpu", "reference", "vulkan", "cuda"};
}

Expected<std::unique_ptr<Backend>> makeBackend(const std::string& name,
                                               const BackendOptions& options) {
    if (name == "cpu") return makeCpuBackend();
    if (name == "reference") return makeReferenceBackend();
    if (name == "vulkan") {
#if DAISY_HAVE_VULKAN
        return makeVulkanBackend(options);
#else
        return Error{
            "backend 'vulkan' is not built into this binary (configure with "
            "-DDAISY_ENABLE_VULKAN=ON)"};
#endif
    }
    if (name == "cuda") {
        return Error{"backend 'cuda' is not built yet (available: cpu, reference, vulkan)"};
    }
    if (name == "auto") {
#if DAISY_HAVE_VULKAN
        if (vulkanHardwareGpuPresent()) return makeVulkanBackend(options);
#endif
        return makeCpuBackend();
    }
    (void)options;
    return Error{
        concat("unknown backend '", name, "' (expected auto, cpu, reference, vulkan or cuda)")};
}

}  // namespace daisy
