#pragma once
// The vulkan backend (DESIGN.md section 8): the shared pair kernel (shared/pair_kernel.h) as a
// headless compute shader over our flat BVH, on any Vulkan 1.2 device (Mesa lavapipe in CI).
#include <cstddef>
#include <cstdint>
#include <memory>

#include "backend/backend.h"
#include "core/expected.h"

namespace daisy {

// Sizes the backend normally derives from the device (vulkan_backend.cpp says how); tests set
// small ones to exercise the chunking. 0 = automatic.
struct VulkanBackendLimits {
    std::size_t batchPairs = 0;  // pairs uploaded (and results downloaded) per batch
    std::size_t dispatchPairs = 0;  // pairs per vkCmdDispatch
    uint64_t storageBufferBytes = 0;  // largest buffer, bytes; 0 = maxStorageBufferRange
    // largest acceleration-structure, scratch or corner buffer of the ray queries, bytes;
    // 0 = maxMemoryAllocationSize
    uint64_t accelerationBufferBytes = 0;
};

// The backend on the device options.device selects (index or part of its name; empty = the
// first discrete GPU, else integrated, else any). Shadow segments are traced as
// options.vulkanRays says (backend/backend.h; docs/backends.md, "Ray queries"). Error with a
// clear message when Vulkan or a matching device is missing, or when VulkanRays::Query is asked
// and no device has ray queries.
Expected<std::unique_ptr<Backend>> makeVulkanBackend(const BackendOptions& options);
Expected<std::unique_ptr<Backend>> makeVulkanBackend(const BackendOptions& options,
                                                     const VulkanBackendLimits& limits);

// True when a discrete or integrated GPU offers Vulkan 1.2 (what `--backend auto` asks).
bool vulkanHardwareGpuPresent();

}  // namespace daisy
